#!/usr/bin/env bash
# Where SDSGM's CPU time goes: perf over a loop of calls on KITTI 000002 (tools/analysis/bench_cpu.py, which also
# runs MODE_SGBM_3WAY), the share of each lidarsgm function in the module's own samples. Needs Linux perf.
#   tools/analysis/profile_cpu.sh [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [paths, default 8]
set -eo pipefail
cd "$(dirname "$0")/../.."
B=${1:-$HOME/.cache/lidarsgm/build-cuda90}
PY=python3
for p in "$B/../pyenv-"*/bin/python; do [ -x "$p" ] && PY=$p; done
data=$(mktemp)
PYTHONPATH="$B/python_loader" OPENBLAS_NUM_THREADS=1 perf record -q -o "$data" -- "$PY" tools/analysis/bench_cpu.py \
  "${2:-8}" 30 2
perf report -i "$data" --no-children --stdio --sort dso,sym 2>/dev/null \
  | awk '/libopencv_lidarsgm/ { gsub(/%/, "", $1); t += $1; n[NR] = $1; sub(/^.*\[\.\] /, ""); s[NR] = $0 }
         END { for (i in n) if (n[i] / t >= 0.01) printf "%5.1f %%  %s\n", 100 * n[i] / t, s[i] }' | sort -rn
rm -f "$data"
