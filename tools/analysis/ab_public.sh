#!/usr/bin/env bash
# A CPU change against the library before it, through the public API only (where the Python bindings of the new build
# no longer load the old library: tools/analysis/ab_cpu.sh needs them to): ab_public.cpp built against the build,
# ROUNDS alternating fresh processes with BASE's libopencv_lidarsgm preloaded and without; prints each pair and the
# mean of the medians. CALLGRIND=1: instead, the instructions of one process each (valgrind --tool=callgrind, RUNS
# calls, 1 thread).
#   cp <build>/lib/libopencv_lidarsgm.so.* BASE/   (built at the commit before the change)
#   tools/analysis/ab_public.sh BASE ROUNDS [RUNS per process, default 15] [OpenCV build dir, default ~/.cache/lidarsgm/build-cpu-opencv5.0.0.93]
set -eo pipefail
cd "$(dirname "$0")/../.."
BASE=${1:?folder with the base libopencv_lidarsgm.so.*}; ROUNDS=${2:?rounds}; RUNS=${3:-15}
B=${4:-$HOME/.cache/lidarsgm/build-cpu-opencv5.0.0.93}
lib=$(ls "$BASE"/libopencv_lidarsgm.so.* | head -1)
src=$(sed -n 's/^OpenCV_SOURCE_DIR:STATIC=//p' "$B/CMakeCache.txt")
exe=$(mktemp -d)/ab_public
incs=$(ls -d "$src"/modules/*/include | sed 's/^/-I/')
# shellcheck disable=SC2086
g++ -O2 -std=c++17 -o "$exe" tools/analysis/ab_public.cpp -Iinclude -I"$B" $incs -L"$B/lib" -lopencv_lidarsgm \
  -lopencv_core -Wl,-rpath,"$B/lib"
if [ "${CALLGRIND:-0}" = 1 ]; then
  for side in base new; do
    pre=""; [ $side = base ] && pre=$lib
    echo "$side $(LD_PRELOAD=$pre valgrind --tool=callgrind --callgrind-out-file=/dev/null "$exe" testdata/kitti "$RUNS" 1 \
      2>&1 | sed -n 's/.*Collected : //p') instructions"
  done
  exit 0
fi
for r in $(seq 1 "$ROUNDS"); do
  if [ $((r % 2)) = 1 ]; then a=$(LD_PRELOAD=$lib "$exe" testdata/kitti "$RUNS" 2); b=$("$exe" testdata/kitti "$RUNS" 2)
  else b=$("$exe" testdata/kitti "$RUNS" 2); a=$(LD_PRELOAD=$lib "$exe" testdata/kitti "$RUNS" 2); fi
  echo "base $a ms, new $b ms"
done | awk '{ print; sb += $2; sn += $5; n++ }
  END { printf "mean of the medians: base %.1f ms, new %.1f ms (new / base %.3f)\n", sb / n, sn / n, sn / sb }'
