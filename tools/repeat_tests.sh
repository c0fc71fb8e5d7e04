#!/usr/bin/env bash
# Runs the README's tests matching a ctest regex N times in a row on an existing build and counts the passes (how the
# ROS 2 tests' flakiness is measured: tools/repeat_tests.sh 30 ros). Each failing run's log is kept in the output
# folder, the others are removed.
#   tools/repeat_tests.sh N REGEX [build dir, default build] [log folder, default /tmp/lidarsgm_repeat]
# BUSY=1: with the machine busy, a build beside the tests: the C++ sources of the CUDA build tree's lidarsgm target
# (OpenCV's and the module's, about 370) compiled again and again, one compiler per core, without ccache and without
# touching a build tree (the objects go to /dev/null).
set -uo pipefail
cd "$(dirname "$0")/.."
N=${1:?runs}; R=${2:?ctest regex}; B=${3:-build}; L=${4:-/tmp/lidarsgm_repeat}
mkdir -p "$L"
if [ -n "${BUSY:-}" ]; then
  T=${BUSY_TREE:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}/build-cuda90}
  mapfile -t cmds < <(ninja -C "$T" -t commands opencv_lidarsgm | grep " -c " | grep "lidarsgm" | grep "\.cpp" |
                      sed -E 's#^/usr/bin/ccache ##; s# -o [^ ]+# -o /dev/null#')
  [ "${#cmds[@]}" -gt 0 ] || { echo "BUSY: no compile commands in $T" >&2; exit 2; }
  busy=()
  for ((c = 0; c < $(nproc); c++)); do
    ( cd "$T" && while :; do for cmd in "${cmds[@]}"; do eval "$cmd" 2>/dev/null; done; done ) &
    busy+=($!)
  done
  trap 'kill "${busy[@]}" 2>/dev/null; pkill -P $$ 2>/dev/null' EXIT
  echo "busy: $(nproc) compilers over ${#cmds[@]} sources of $T"
fi
pass=0
for ((i = 1; i <= N; i++)); do
  log="$L/run_$i.log"
  if ctest --test-dir "$B" -R "$R" --output-on-failure > "$log" 2>&1; then
    pass=$((pass + 1)); echo "run $i passed ($(grep -o 'Total Test time (real) = *[0-9.]* sec' "$log"))"; rm -f "$log"
  else
    echo "run $i FAILED: $log"
  fi
done
echo "passed $pass of $N"
[ "$pass" = "$N" ]
