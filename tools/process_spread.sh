#!/usr/bin/env bash
# Runs N fresh processes of the tool's CPU timing, one after another, and prints each process's median SDSGM time (and
# MODE_SGBM_3WAY's in the same process), then the spread: the slowest process against the fastest. A state fixed at
# a process's start-up (thread pool, scheduling, placement) shows as processes that stay slow for their whole life.
# Run it on an otherwise idle machine.
#   tools/process_spread.sh N THREADS PATHS [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [runs per process, default 5]
# TOOL_ARGS: further tool options for every process, e.g. "--params doc/params/kitti_best.yml --search-window 4".
set -eo pipefail
cd "$(dirname "$0")/.."
N=${1:?number of processes}; THREADS=${2:?threads}; PATHS=${3:?4 or 8}
T=${4:-$HOME/.cache/lidarsgm/build-cuda90}/bin/lidarsgm_fuse
RUNS=${5:-5}
echo "# $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD 2>/dev/null || echo "unknown (no git checkout)"), $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
read -r -a extra <<< "${TOOL_ARGS:-}"
echo "# Command: TOOL_ARGS=\"${TOOL_ARGS:-}\" tools/process_spread.sh $N $THREADS $PATHS, each process: lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --timing $RUNS --threads $THREADS --paths $PATHS ${TOOL_ARGS:-}"
times=()
ratios=()
for i in $(seq 1 "$N"); do
  out=$("$T" --kitti-frame testdata/kitti --id 000002 --timing "$RUNS" --threads "$THREADS" --paths "$PATHS" "${extra[@]}")
  ours=$(echo "$out" | awk -F'|' '/lidarsgm SDSGM/ && !/confidence/ {gsub(/[ ms]/, "", $3); print $3}')
  ref=$(echo "$out" | awk -F'|' '/MODE_SGBM_3WAY/ {gsub(/[ ms]/, "", $3); print $3}')
  awk -v i="$i" -v a="$ours" -v b="$ref" \
    'BEGIN { printf "process %2d: SDSGM %7.1f ms, MODE_SGBM_3WAY %7.1f ms, ratio %.2f\n", i, a, b, a / b }'
  times+=("$ours")
  ratios+=("$(awk -v a="$ours" -v b="$ref" 'BEGIN { print a / b }')")
  [ $i = 1 ] && echo "$out" | grep -m1 "cells searched" || true
done
printf "%s\n" "${ratios[@]}" | sort -g | awk '{ v[NR] = $1 } END {
    printf "SDSGM / MODE_SGBM_3WAY per process: median %.2f (%.2f to %.2f)\n",
           (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2, v[1], v[NR] }'
printf "%s\n" "${times[@]}" | sort -g | awk -v t="$THREADS" -v p="$PATHS" '
  { v[NR] = $1 } END {
    med = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    printf "%d processes, %d threads, %d paths: fastest %.1f ms, median %.1f ms, slowest %.1f ms; slowest / fastest %.3f\n",
           NR, t, p, v[1], med, v[NR], v[NR] / v[1] }'
