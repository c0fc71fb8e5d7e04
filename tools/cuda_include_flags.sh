#!/usr/bin/env bash
# The -I flags with which the README's CUDA build compiles src_cuda/ (from its generated rules for aggregation.cu), for
# the tools that compile the kernels' sources by hand (tools/sass_counts.sh, tools/emulate_kernel.sh), with this
# checkout's directories of the module.
#   tools/cuda_include_flags.sh [cache dir, default ~/.cache/lidarsgm]
# LIDARSGM_CUDA_BUILD: the CUDA build's folder, if not the cache's build-cuda90.
set -eo pipefail
CACHE=${1:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}}
BUILD=${LIDARSGM_CUDA_BUILD:-$CACHE/build-cuda90}
RULES=$(ls "$BUILD"/modules/lidarsgm/CMakeFiles/cuda_compile_*.dir/__/__/src_cuda/*generated_aggregation.cu.o.Release.cmake 2>/dev/null | head -1 || true)
[ -f "$RULES" ] || { echo "no CUDA build in $BUILD (run the README's build first)" >&2; exit 2; }
# The build's own copies of the module's directories (the checkout it was configured from, maybe another one) are
# replaced by this checkout's, so that the headers are those of the sources being compiled.
ROOT=$(cd "$(dirname "$0")/.." && pwd)
sed -n 's/^set(CUDA_NVCC_INCLUDE_DIRS \[==\[\(.*\)\]==\]).*/\1/p' "$RULES" | tr ';' '\n' |
  sed -E "s#^.*/modules/lidarsgm/include\$#$ROOT/modules/lidarsgm/include#; s#^.*/(src|src_cuda)\$#$ROOT/\1#" |
  awk '!seen[$0]++' | sed 's/^/-I/' | tr '\n' ' '
