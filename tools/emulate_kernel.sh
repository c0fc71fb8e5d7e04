#!/usr/bin/env bash
# Whether a rewrite of a CUDA kernel keeps its output, with no GPU: tools/emulate/<kernel>.cpp runs the old and the new
# version of the kernel's source under a SIMT emulation on the CPU (tools/emulate/simt.hpp; AddressSanitizer and UBSan
# on: 8- and 16-byte accesses must be aligned) on one random case a seed, and compares their outputs word for word.
# Prints one line a case; exits 1 if any case differs. Needs g++ with C++20, the CUDA toolkit's headers and the
# README's CUDA build (its include directories). Kernels:
#   packed_walk       packedWindowPathKernel (src_cuda/aggregation.cu): the sum volumes
#   winner_takes_all  wtaKernel (src_cuda/winner_takes_all.cu): the disparity maps and the right view's keys
#   matching_cost     windowCostsKernel (src_cuda/matching_cost.cu): the stored costs and the zeroed sums
#   scan_gaps         scanGapHistogramKernel (src_cuda/visibility_filter.cu): the scan test's histograms, also
#                     against the CPU's
#   tile_points       listSparseRowsKernel and listTilePoints (src_cuda/sparse_input.cu, sparse_window.cuh): every
#                     block's tile list, also against a direct listing of the tile's pixels
#   ring_fill         ringFillKernel (src_cuda/ring_interpolation.cu): the filled semidense map, also against the
#                     CPU's rule
#   visibility        visibilityKernel (src_cuda/visibility_filter.cu): the filtered sparse map, also against a
#                     direct search of hiddenBy's window
#   consistency_check checkKernel (src_cuda/consistency_check.cu): the output (both types) and the confidence
#   tools/emulate_kernel.sh KERNEL [old revision, default HEAD~1] [new revision, default the working tree] [seeds, 40]
# ("." for a revision: the working tree. With both ".", the kernels whose cases also compare with the CPU's rule or a
# direct search are tested as they are: the test suite's cuda_kernels_emulated.)
set -eo pipefail
cd "$(dirname "$0")/.."
USAGE="usage: tools/emulate_kernel.sh packed_walk|winner_takes_all|matching_cost|scan_gaps|tile_points|ring_fill|visibility|consistency_check [old] [new]"
KERNEL=${1:?"$USAGE [seeds]"}
OLD=${2:-HEAD~1}; NEW=${3:-}; SEEDS=${4:-40}
case $KERNEL in
  packed_walk) SRC=src_cuda/aggregation.cu ;;
  winner_takes_all) SRC=src_cuda/winner_takes_all.cu ;;
  matching_cost) SRC=src_cuda/matching_cost.cu ;;
  scan_gaps) SRC=src_cuda/visibility_filter.cu ;;
  tile_points) SRC="src_cuda/sparse_window.cuh src_cuda/sparse_input.cu" ;;
  ring_fill) SRC=src_cuda/ring_interpolation.cu ;;
  visibility) SRC=src_cuda/visibility_filter.cu ;;
  consistency_check) SRC=src_cuda/consistency_check.cu ;;
  *) echo "emulate_kernel.sh: unknown kernel $KERNEL (packed_walk, winner_takes_all, matching_cost, scan_gaps," \
          "tile_points, ring_fill, visibility, consistency_check)" >&2
     exit 2 ;;
esac
inc=$(bash tools/cuda_include_flags.sh)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# A revision's files, or the working tree's ("" or "."; no git needed then).
version() { for f in $SRC; do if [ -n "$1" ] && [ "$1" != . ]; then git show "$1:$f"; else cat "$f"; fi; done; }
version "$OLD" > "$tmp/old.cu"   # (a kernel of two files: one after the other)
version "$NEW" > "$tmp/new.cu"
python3 tools/emulate/extract.py "$KERNEL" "$tmp/old.cu" "$tmp/old.inc"
python3 tools/emulate/extract.py "$KERNEL" "$tmp/new.cu" "$tmp/new.inc"
g++ -std=c++20 -O1 -fsanitize=address,undefined -fno-sanitize-recover=undefined -Isrc -Isrc_cuda -I"$tmp" $inc \
  "tools/emulate/$KERNEL.cpp" -o "$tmp/emulate" -lpthread
seq 1 "$SEEDS" | xargs -P "$(nproc)" -I{} "$tmp/emulate" {} > "$tmp/cases.txt" 2>&1 || true
sort -t' ' -k2n "$tmp/cases.txt"
total=$(grep -c "^seed" "$tmp/cases.txt" || true); same=$(grep -c " 0 differ$" "$tmp/cases.txt" || true)
label() { if [ -z "$1" ] || [ "$1" = . ]; then echo "the working tree"; else echo "$1"; fi; }
echo "$KERNEL, $(label "$OLD") against $(label "$NEW"): $same of $SEEDS cases the same word for word ($total ran)"
[ "$same" = "$SEEDS" ]
