#!/usr/bin/env bash
# Whether a rewrite of the packed windows' path kernel (packedWindowPathKernel in src_cuda/aggregation.cu) keeps its
# sums, with no GPU: tools/emulate/packed_walk.cpp runs the old and the new version under a SIMT emulation on the CPU
# (AddressSanitizer and UBSan on: its 8- and 16-byte accesses must be aligned) on one random case a seed, and compares
# their sum volumes word for word. Prints one line a case; exits 1 if any case differs. Needs g++ with C++20, the CUDA
# toolkit's headers and the README's CUDA build (its include directories).
#   tools/emulate_packed_walk.sh [old revision, default HEAD~1] [new revision, default the working tree] [seeds, 40]
set -eo pipefail
cd "$(dirname "$0")/.."
OLD=${1:-HEAD~1}; NEW=${2:-}; SEEDS=${3:-40}
inc=$(bash tools/cuda_include_flags.sh)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
git show "$OLD:src_cuda/aggregation.cu" > "$tmp/old.cu"
if [ -n "$NEW" ]; then git show "$NEW:src_cuda/aggregation.cu" > "$tmp/new.cu"; else cp src_cuda/aggregation.cu "$tmp/new.cu"; fi
python3 tools/emulate/extract_walk.py "$tmp/old.cu" "$tmp/old.inc"
python3 tools/emulate/extract_walk.py "$tmp/new.cu" "$tmp/new.inc"
g++ -std=c++20 -O1 -fsanitize=address,undefined -fno-sanitize-recover=undefined -Isrc -Isrc_cuda -I"$tmp" $inc \
  tools/emulate/packed_walk.cpp -o "$tmp/emulate" -lpthread
seq 1 "$SEEDS" | xargs -P "$(nproc)" -I{} "$tmp/emulate" {} > "$tmp/cases.txt" 2>&1 || true
sort -t' ' -k2n "$tmp/cases.txt"
total=$(grep -c "^seed" "$tmp/cases.txt" || true); same=$(grep -c " 0 differ$" "$tmp/cases.txt" || true)
echo "$OLD against ${NEW:-the working tree}: $same of $SEEDS cases the same word for word ($total ran)"
[ "$same" = "$SEEDS" ]
