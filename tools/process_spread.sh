#!/usr/bin/env bash
# Runs N fresh processes of the tool's CPU timing, one after another, and prints each process's median SDSGM time (and
# MODE_SGBM_3WAY's in the same process), then the spread: the slowest process against the fastest. A state fixed at
# a process's start-up (thread pool, scheduling, placement) shows as processes that stay slow for their whole life.
# Run it on an otherwise idle machine.
#   tools/process_spread.sh N THREADS PATHS [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [runs per process, default 5]
set -eo pipefail
cd "$(dirname "$0")/.."
N=${1:?number of processes}; THREADS=${2:?threads}; PATHS=${3:?4 or 8}
T=${4:-$HOME/.cache/lidarsgm/build-cuda90}/bin/lidarsgm_lidarsgm_fuse
RUNS=${5:-5}
echo "# $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD 2>/dev/null || echo "unknown (no git checkout)"), $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
echo "# Command: tools/process_spread.sh $N $THREADS $PATHS, each process: lidarsgm_lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --timing $RUNS --threads $THREADS --paths $PATHS"
times=()
for i in $(seq 1 "$N"); do
  out=$("$T" --kitti-frame testdata/kitti --id 000002 --timing "$RUNS" --threads "$THREADS" --paths "$PATHS")
  ours=$(echo "$out" | awk -F'|' '/lidarsgm SDSGM/ {gsub(/[ ms]/, "", $3); print $3}')
  ref=$(echo "$out" | awk -F'|' '/MODE_SGBM_3WAY/ {gsub(/[ ms]/, "", $3); print $3}')
  awk -v i="$i" -v a="$ours" -v b="$ref" \
    'BEGIN { printf "process %2d: SDSGM %7.1f ms, MODE_SGBM_3WAY %7.1f ms, ratio %.2f\n", i, a, b, a / b }'
  times+=("$ours")
done
printf "%s\n" "${times[@]}" | sort -g | awk -v t="$THREADS" -v p="$PATHS" '
  { v[NR] = $1 } END {
    med = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    printf "%d processes, %d threads, %d paths: fastest %.1f ms, median %.1f ms, slowest %.1f ms; slowest / fastest %.3f\n",
           NR, t, p, v[1], med, v[NR], v[NR] / v[1] }'
