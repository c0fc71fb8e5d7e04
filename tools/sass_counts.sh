#!/usr/bin/env bash
# SASS instruction counts that doc/perf.md and doc/design.md quote (no GPU needed): what one packed minimum or add
# costs for sm_87 (Jetson Orin) and sm_90 (H100, H200), and the main loop of the packed path kernel
# (pathKernel<8, 8, ...>: two steps of four lines, KITTI's 128 disparities with DDC and the edge rule) for both; and
# the packed windows' path kernel (packedWindowPathKernel, no edge rule) per step for each K rows of 16 disparities, with the
# costs stored (the few-SMs kernel) and computed with DDC, where every line owns its pairs and where some are masked;
# the winner-takes-all's loop over a chunk of 16 disparities (wtaKernel), with and without the uniqueness check; the
# stored matching costs' loop (windowCostsKernel) per disparity, with and without DDC.
# Needs nvcc and cuobjdump (the CUDA toolkit's, or PyPI's nvidia-cuda-cuobjdump: CUOBJDUMP=path/to/cuobjdump), and the
# README's CUDA build (its include directories for src_cuda/aggregation.cu).
#   tools/sass_counts.sh [cache dir, default ~/.cache/lidarsgm]
set -eo pipefail
cd "$(dirname "$0")/.."
CACHE=${1:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}}
CUOBJDUMP=${CUOBJDUMP:-$(command -v cuobjdump || true)}
[ -x "$CUOBJDUMP" ] || { echo "no cuobjdump: set CUOBJDUMP (pip install nvidia-cuda-cuobjdump ships one)"; exit 2; }
inc=$(bash tools/cuda_include_flags.sh "$CACHE")
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# One operation on loaded words, stored: its count minus the XOR baseline's is what the operation takes.
for op in base __vminu2 __vminu4 __vaddus4 __vadd4 __vsub4; do
  e="a[1] ^ a[2]"; [ $op = base ] || e="$op(a[1], a[2])"
  echo "__global__ void k(unsigned* a) { a[0] = $e; }" > "$tmp/$op.cu"
done
count() { "$CUOBJDUMP" -sass "$1" | grep -E '^\s+/\*[0-9a-f]{4}\*/' | grep -vc -E 'NOP|BRA 0x' || true; }
printf "%-10s %6s %6s   (SASS instructions of one operation)\n" op sm_87 sm_90
for arch in 87 90; do
  for op in base __vminu2 __vminu4 __vaddus4 __vadd4 __vsub4; do
    nvcc -cubin -arch=sm_$arch -o "$tmp/$op.$arch.cubin" "$tmp/$op.cu"
  done
done
for op in __vminu2 __vminu4 __vaddus4 __vadd4 __vsub4; do
  printf "%-10s %6d %6d\n" $op $(( $(count "$tmp/$op.87.cubin") - $(count "$tmp/base.87.cubin") + 1 )) \
    $(( $(count "$tmp/$op.90.cubin") - $(count "$tmp/base.90.cubin") + 1 ))
done
# The path kernel as the build compiles it, for each architecture.
for arch in 87 90; do
  nvcc -cubin -arch=sm_$arch --std=c++17 -D_FORCE_INLINES $inc -Isrc -Isrc_cuda -o "$tmp/agg.$arch.cubin" \
    src_cuda/aggregation.cu
  nvcc -cubin -arch=sm_$arch --std=c++17 -D_FORCE_INLINES $inc -Isrc -Isrc_cuda -o "$tmp/wta.$arch.cubin" \
    src_cuda/winner_takes_all.cu
  "$CUOBJDUMP" -sass "$tmp/agg.$arch.cubin" > "$tmp/agg.$arch.sass"
  nvcc -cubin -arch=sm_$arch --std=c++17 -D_FORCE_INLINES $inc -Isrc -Isrc_cuda -o "$tmp/mc.$arch.cubin" \
    src_cuda/matching_cost.cu
  "$CUOBJDUMP" -sass "$tmp/wta.$arch.cubin" >> "$tmp/agg.$arch.sass"
  "$CUOBJDUMP" -sass "$tmp/mc.$arch.cubin" >> "$tmp/agg.$arch.sass"
  python3 - "$tmp/agg.$arch.sass" $arch <<'EOF'
import re, sys
text, arch = open(sys.argv[1]).read(), sys.argv[2]

def functions():
    # (name, [(address, instruction)]) of each function of the listing
    for f in re.split(r'\n\s*Function : ', text)[1:]:
        ins = [(int(a, 16), t.strip()) for a, t in re.findall(r'/\*([0-9a-f]{4,})\*/\s+([^;]*);', f)]
        yield f.split('\n', 1)[0], ins

def loops(ins):
    # the instructions from each backward branch's target to the branch
    for addr, t in ins:
        m = re.search(r'BRA\s+(?:\S+\s+)?0x([0-9a-f]+)', t)
        if m and 'DIV' not in t and int(m.group(1), 16) < addr:
            yield [o for a, o in ins if int(m.group(1), 16) <= a <= addr]

# the kernels' lanes a line as butterflies of the line's minimum (log2 LW), and the words a row loads
packed = {'ILb0ELb0ELb1E': ('stored costs', 2, 2), 'ILb1ELb0ELb0E': ('computed costs, DDC', 3, 2)}
for name, ins in functions():
    if 'pathKernelILi8ELi8ELi2ELb1ELb1ELb1ELb0E' in name:
        loop = max(map(len, loops(ins)), default=0)   # the longest: the step loop (unrolled twice)
        print(f"sm_{arch}: pathKernel<8, 8> (128 disparities, DDC, edge rule): {len(ins)} SASS instructions, "
              f"step loop (two steps of four lines) {loop}")
    if 'wtaKernel' in name:
        # the chunk loop: 16 keys, one shared-memory atomicMin each (the right view's)
        body = next((b for b in loops(ins) if sum(o.startswith('ATOMS.MIN') for o in b) == 16), [])
        check = 'with' if 'wtaKernelILb1E' in name else 'without'
        print(f"sm_{arch}: wtaKernel {check} the uniqueness check: chunk loop (16 disparities) "
              f"{sum(not o.startswith('NOP') for o in body)} SASS instructions")
    if 'windowCostsKernel' in name:
        # each loop stores a thread's costs and zeroes its sums with 16-byte stores, eight disparities a pair of them
        for body in loops(ins):
            stores = sum('STG.E.128' in o for o in body)
            if stores:
                n = sum(not o.startswith('NOP') for o in body)
                print(f"sm_{arch}: windowCostsKernel {'with' if 'windowCostsKernelILb1E' in name else 'without'} "
                      f"DDC: {n} SASS instructions a loop of {4 * stores} disparities, {n / (4 * stores):.2f} each")
    kind = next((v for k, v in packed.items() if 'packedWindowPathKernel' + k in name), None)
    if kind is None:
        continue
    kind, butterflies, rowWords = kind
    perK = {}
    for body in loops(ins):
        body = [o for o in body if not o.startswith('NOP')]
        steps = sum('SHFL.BFLY' in o for o in body) // butterflies   # the line's minimum: log2 LW a step
        if steps not in (1, 2):   # a step loop runs one or two steps (not the segments' loop around them)
            continue
        ops = [o.split()[1] if o.startswith('@') else o.split()[0] for o in body]
        words = sum(4 if op.endswith('.128') else 2 if op.endswith('.64') else 1 for op in ops
                    if op.startswith('LDG')) // steps
        # stored: a row's costs; computed: its right strings, then the left string and the facts
        K = words // rowWords if kind == 'stored costs' else (words - 2) // rowWords
        perK.setdefault(K, []).append(len(body) / steps)
    cells = ', '.join(f'K={K}: ' + ' / '.join(f'{v:g}' for v in sorted(perK[K])) for K in sorted(perK))
    print(f"sm_{arch}: packedWindowPathKernel, {kind}: instructions a step of {32 >> butterflies} lines (lines "
          f"owning their rows / masked): {cells}")
EOF
done
