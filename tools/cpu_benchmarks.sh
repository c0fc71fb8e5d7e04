#!/usr/bin/env bash
# Rewrites doc/benchmarks/cpu_<name>.txt: SDSGM on KITTI 000002 against every cv::StereoSGBM mode in the same process
# (the tool's --timing: alternating runs, medians), 8 and 4 paths, at the given thread count, and the working memory.
# Run it on an otherwise idle machine.
#   tools/cpu_benchmarks.sh NAME THREADS [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [runs, default 15]
set -eo pipefail
cd "$(dirname "$0")/.."
NAME=${1:?name: cores-machine, e.g. 2core-epyc}; THREADS=${2:?thread count}
T=${3:-$HOME/.cache/lidarsgm/build-cuda90}/bin/lidarsgm_fuse
RUNS=${4:-15}
C=$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src src_cuda include samples || echo " + uncommitted changes")
f=doc/benchmarks/cpu_$NAME.txt
{ echo "# $(date -u +%Y-%m-%d), commit $C, $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
  for paths in 8 4; do
    echo "# Command: lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --timing $RUNS --threads $THREADS --paths $paths"
    "$T" --kitti-frame testdata/kitti --id 000002 --timing "$RUNS" --threads "$THREADS" --paths "$paths"
  done; } > "$f" 2>&1
echo "wrote $f"
