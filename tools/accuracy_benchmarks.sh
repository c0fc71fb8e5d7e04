#!/usr/bin/env bash
# Rewrites the accuracy outputs in doc/benchmarks/ (the figures of doc/accuracy.md and the README) with the tool of an
# OpenCV build made by the README's commands: the 20 shared KITTI frames (every mode and check; DSGM and SDSGM at
# 64, 32 and 16 LiDAR lines, and SDSGM with the other ring offsets) and the Middlebury scenes, with the create()
# defaults and with kitti_best.yml (which searches disparity windows, searchWindow 4).
# Then kitti_best.yml over the full disparity range (--search-window 0) at 64, 32 and 16 lines and on Middlebury.
#   tools/accuracy_benchmarks.sh [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [shared data dir]
# FULL_RANGE_ONLY=1: the full-range runs only.
set -eo pipefail
cd "$(dirname "$0")/.."
T=${1:-$HOME/.cache/lidarsgm/build-cuda90}/bin/lidarsgm_fuse
DATA=${2:-../shared/data}
C=$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src src_cuda include samples || echo " + uncommitted changes")
header() { echo "# $(date -u +%Y-%m-%d), commit $C, $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), CPU path"; }
tool() { echo "# Command: lidarsgm_fuse $*"; "$T" "$@"; }   # the command line, then its output
run() {  # output file, then the tool's arguments
  local f=doc/benchmarks/$1; shift
  { header; tool "$@"; } > "$f" 2>&1
  echo "wrote $f"
}
for cfg in defaults best; do
  [ -n "${FULL_RANGE_ONLY:-}" ] && break
  P=(); [ $cfg = best ] && P=(--params doc/params/kitti_best.yml)
  run accuracy_kitti20_$cfg.txt --kitti "$DATA/kitti2015_lidar" --table5 --quiet "${P[@]}"
  run accuracy_kitti20_lines_$cfg.txt --kitti "$DATA/kitti2015_lidar" --modes dsgm,sdsgm --lidar-lines 64,32,16 \
    --quiet "${P[@]}"
  run accuracy_middlebury_$cfg.txt --middlebury "$DATA/middlebury" "${P[@]}"
  # Which rings simulate the sparser sensors (the paper does not say): SDSGM with the other ring offsets.
  f=doc/benchmarks/accuracy_kitti20_ring_offsets_$cfg.txt
  { header
    for a in "32 1" "16 1" "16 2" "16 3"; do
      set -- $a
      tool --kitti "$DATA/kitti2015_lidar" --modes sdsgm --lidar-lines $1 --lidar-ring-offset $2 --quiet "${P[@]}"
    done; } > "$f" 2>&1
  echo "wrote $f"
done
P=(--params doc/params/kitti_best.yml --search-window 0)
run accuracy_kitti20_lines_best_full_range.txt --kitti "$DATA/kitti2015_lidar" --modes dsgm,sdsgm \
  --lidar-lines 64,32,16 --quiet "${P[@]}"
run accuracy_middlebury_best_full_range.txt --middlebury "$DATA/middlebury" "${P[@]}"
