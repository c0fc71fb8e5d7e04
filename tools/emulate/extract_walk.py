# Extracts the packed windows' walk and kernel of one version of src_cuda/aggregation.cu (WARPS_PER_BLOCK,
# tileSegmentEnd, and from the predicated reduction helpers to packedWindowPathKernel's end), without its inline-asm
# helpers (tools/emulate/packed_walk.cpp defines them): python3 extract_walk.py aggregation.cu out.inc
import re, sys
s = open(sys.argv[1]).read()
a = s.index("/* *a += v where p: a predicated reduction")
b = s.index("/* LW lanes a line and PPT pairs a lane")
t = s[a:b]
# drop every reduceAddIf definition (comment + body)
t = re.sub(r"/\* \*a \+= v where p[^/]*?\*/\s*__device__ __forceinline__ void reduceAddIf\([^)]*\)\s*\{.*?\n\}\n", "", t, flags=re.S)
# the walk's tile helper and the kernels' block size, from the same file
m = re.search(r"__device__ __forceinline__ int tileSegmentEnd\(.*?\n\}\n", s, flags=re.S)
w = re.search(r"\bWARPS_PER_BLOCK = (\d+)", s)
t = "const int WARPS_PER_BLOCK = %s;\n" % w.group(1) + m.group(0) + "\n" + t
assert "asm" not in t, "asm left"
open(sys.argv[2], "w").write(t)
