# Extracts from one version of a kernel's source what tools/emulate/<kernel>.cpp runs under emulation:
#   python3 extract.py packed_walk aggregation.cu out.inc: WARPS_PER_BLOCK, tileSegmentEnd, and from the predicated
#     reduction helpers to packedWindowPathKernel's end, without its inline-asm helpers (packed_walk.cpp defines them);
#   python3 extract.py winner_takes_all winner_takes_all.cu out.inc (or matching_cost matching_cost.cu): the file's
#     anonymous namespace (the kernels);
#   python3 extract.py scan_gaps visibility_filter.cu out.inc: scanGapHistogramKernel and its helpers, and its launch's
#     block rows (SCAN_LAUNCH_ROWS);
#   python3 extract.py tile_points both.cu out.inc (sparse_window.cuh and sparse_input.cu one after the other):
#     tilePointsBytes, TilePoints, listTilePoints and listSparseRowsKernel;
#   python3 extract.py ring_fill ring_interpolation.cu out.inc: ringFillKernel and its launch's shape
#     (RING_FILL_PIXEL_ROWS);
#   python3 extract.py visibility visibility_filter.cu out.inc: visibilityKernel, its dynamic shared memory taken
#     from the case's buffer (dynamicSmem);
#   python3 extract.py consistency_check consistency_check.cu out.inc: checkKernel and its helpers, the same.
import re, sys
kind, src, out = sys.argv[1:4]
s = open(src).read()
if kind == "packed_walk":
    a = s.index("/* *a += v where p: a predicated reduction")
    b = s.index("/* LW lanes a line and PPT pairs a lane")
    t = s[a:b]
    # drop every reduceAddIf definition (comment + body)
    t = re.sub(r"/\* \*a \+= v where p[^/]*?\*/\s*__device__ __forceinline__ void reduceAddIf\([^)]*\)\s*\{.*?\n\}\n",
               "", t, flags=re.S)
    # the walk's tile helper and the kernels' block size, from the same file
    m = re.search(r"__device__ __forceinline__ int tileSegmentEnd\(.*?\n\}\n", s, flags=re.S)
    w = re.search(r"\bWARPS_PER_BLOCK = (\d+)", s)
    t = "const int WARPS_PER_BLOCK = %s;\n" % w.group(1) + m.group(0) + "\n" + t
elif kind in ("winner_takes_all", "matching_cost"):
    a = s.index("\nnamespace {\n")
    b = s.index("\n} // namespace\n", a)
    t = s[a:b] + "\n} // namespace\n"
elif kind == "scan_gaps":
    # the histogram kernel and what it calls, and the block rows its launch takes
    a = s.index("\nnamespace {\n") + len("\nnamespace {\n")
    b = s.index("//! One warp: visibilityGrowthApplies.")
    rows = re.search(r"scanGapHistogramKernel<<<.*", s) and re.search(r"const dim3 block\(32, (\w+)\);\s*\n[^\n]*\n"
                                                                       r"[^\n]*cudaMemsetAsync\(stats", s)
    t = s[a:b] + "const int SCAN_LAUNCH_ROWS = %s;\n" % rows.group(1)
elif kind == "tile_points":
    # sparse_window.cuh then sparse_input.cu, one after the other: the list's size, the tile listing, the rows' listing
    a = s.index("//! Bytes of shared memory listTilePoints needs")
    b = s.index("/** Dynamic shared memory for a kernel")
    c = s.index("/** A block's tile of sparse points")
    d = s.index("}}}} // namespace", c)
    e = s.index("/* A warp a row: 32 columns a chunk")
    f = s.index("void listSparseRows(", e)
    t = s[a:b] + s[c:d] + s[e:f]
elif kind == "ring_fill":
    # ringFillKernel (after ringGapLimitKernel's end), and whether its launch takes PixelRows' shape (else 32 x 8
    # threads a pixel each)
    a = s.index("__global__ void ringGapLimitKernel")
    a = s.index("\n}\n", a) + 3
    b = s.index("} // namespace", a)
    t = s[a:b] + "const bool RING_FILL_PIXEL_ROWS = %s;\n" % (
        "true" if "ringFillKernel<<<PixelRows::grid" in s else "false")
elif kind == "visibility":
    # visibilityKernel and its blocks-per-SM constant; its dynamic shared memory becomes the case's buffer
    a = s.index("/* Two blocks of 1024 threads an SM")
    b = s.index("} // namespace\n\nvoid testScan(")
    t = s[a:b].replace("extern __shared__ int smem[];", "int* const smem = dynamicSmem;")
    assert "dynamicSmem" in t, "no dynamic shared memory found"
elif kind == "consistency_check":
    # the file's anonymous namespace up to encodeKernel (the check's helpers and checkKernel); its dynamic shared
    # memory becomes the case's buffer
    a = s.index("\nnamespace {\n") + len("\nnamespace {\n")
    b = s.index("template <typename T>\n__global__ void encodeKernel")
    t = s[a:b].replace("extern __shared__ int smem[];", "int* const smem = dynamicSmem;")
    assert "dynamicSmem" in t, "no dynamic shared memory found"
else:
    sys.exit("extract.py: unknown kernel %s (packed_walk, winner_takes_all, matching_cost, scan_gaps, tile_points,"
             " ring_fill, visibility, consistency_check)" % kind)
assert "asm" not in t, "asm left"
open(out, "w").write(t)
