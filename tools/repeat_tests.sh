#!/usr/bin/env bash
# Runs the README's tests matching a ctest regex N times in a row on an existing build and counts the passes (how the
# ROS 2 tests' flakiness is measured: tools/repeat_tests.sh 30 ros). Each failing run's log is kept in the output
# folder, the others are removed.
#   tools/repeat_tests.sh N REGEX [build dir, default build] [log folder, default /tmp/lidarsgm_repeat]
set -uo pipefail
cd "$(dirname "$0")/.."
N=${1:?runs}; R=${2:?ctest regex}; B=${3:-build}; L=${4:-/tmp/lidarsgm_repeat}
mkdir -p "$L"
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
