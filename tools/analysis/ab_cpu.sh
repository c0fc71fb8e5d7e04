#!/usr/bin/env bash
# A CPU change against the library before it, in alternating fresh processes (the machine's speed drifts within
# minutes, so only processes run side by side compare): bench_cpu.py with the module library of BASE preloaded and
# with the build's own, ROUNDS times (use an even number); prints each run and the mean of the medians per side.
#   cp <build>/lib/libopencv_lidarsgm.so.* BASE/   (built at the commit before the change)
#   tools/analysis/ab_cpu.sh BASE PATHS ROUNDS [RUNS per process, default 15] [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90]
set -eo pipefail
cd "$(dirname "$0")/../.."
BASE=${1:?folder with the base libopencv_lidarsgm.so.*}; PATHS=${2:?4 or 8}; ROUNDS=${3:?rounds}
RUNS=${4:-15}; B=${5:-$HOME/.cache/lidarsgm/build-cuda90}
PY=python3
for p in "$B/../pyenv-"*/bin/python; do [ -x "$p" ] && PY=$p; done
lib=$(ls "$BASE"/libopencv_lidarsgm.so.* | head -1)
[ -f "$lib" ] || { echo "no libopencv_lidarsgm.so.* in $BASE" >&2; exit 2; }
# The preloaded library has the module's soname, so the loader takes it instead of the build's.
# The order alternates between rounds: the first process of a pair ran about 1.3 % slower in an A/A test (the same
# library on both sides, 2-core Xeon, 2026-11-25), which a fixed order adds to every difference.
for r in $(seq 1 "$ROUNDS"); do
  order="base new"; [ $((r % 2)) = 0 ] && order="new base"
  for side in $order; do
    pre=""; [ "$side" = base ] && pre=$lib
    echo "$side $(LD_PRELOAD=$pre PYTHONPATH="$B/python_loader" OPENBLAS_NUM_THREADS=1 "$PY" tools/analysis/bench_cpu.py \
      "$PATHS" "$RUNS" 2 | tail -1)"
  done
done | awk '{ print } { split($0, a, "median "); s[$1] += a[2]; n[$1]++ }
  END { printf "mean of the lidarsgm medians: base %.1f ms, new %.1f ms (new / base %.3f)\n",
               s["base"] / n["base"], s["new"] / n["new"], (s["new"] / n["new"]) / (s["base"] / n["base"]) }'
