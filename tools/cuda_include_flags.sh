#!/usr/bin/env bash
# The -I flags with which the README's CUDA build compiles src_cuda/ (from its generated rules for aggregation.cu), for
# the tools that compile the kernels' sources by hand (tools/sass_counts.sh, tools/emulate_packed_walk.sh).
#   tools/cuda_include_flags.sh [cache dir, default ~/.cache/lidarsgm]
set -eo pipefail
CACHE=${1:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}}
RULES=$(ls "$CACHE"/build-cuda90/modules/lidarsgm/CMakeFiles/cuda_compile_*.dir/__/__/src_cuda/*generated_aggregation.cu.o.Release.cmake 2>/dev/null | head -1 || true)
[ -f "$RULES" ] || { echo "no CUDA build in $CACHE/build-cuda90 (run the README's build first)" >&2; exit 2; }
sed -n 's/^set(CUDA_NVCC_INCLUDE_DIRS \[==\[\(.*\)\]==\]).*/\1/p' "$RULES" | tr ';' '\n' | sed 's/^/-I/' | tr '\n' ' '
