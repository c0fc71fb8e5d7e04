// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visibility filter of the sparse input, CUDA twin of src/visibility_filter.cpp (hiddenBy, pipeline.hpp).

#include "cuda_stages.hpp"
#include "sparse_window.cuh"
#include "histogram.cuh"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

//! The 32 x 32 bit transpose of a warp's words: bit i of lane t's result is bit t of lane i's word.
__device__ __forceinline__ unsigned warpTransposeBits(unsigned w, int lane)
{
    const unsigned low[5] = { 0x0000FFFFu, 0x00FF00FFu, 0x0F0F0F0Fu, 0x33333333u, 0x55555555u };
#pragma unroll
    for (int k = 0, j = 16; k < 5; k++, j >>= 1)
    {
        // Swap the off-diagonal j x j blocks of each 2j x 2j block.
        const unsigned other = __shfl_xor_sync(0xFFFFFFFFu, w, j);
        w = (lane & j) ? (w & ~low[k]) | ((other >> j) & low[k]) : (w & low[k]) | ((other & low[k]) << j);
    }
    return w;
}

enum { SCAN_BLOCK_ROWS = 32, SCAN_ROWS = SCAN_BLOCK_ROWS + SCAN_GAP_BINS - 2 };

/* rowPointGap and columnPointGap of a block's 32 x 32 pixels, a warp a row. The block first stores, for its rows and
 the 30 below, which of the 96 columns around its own hold a point (three ballots a row); then a point's row gap is
 one shift of its row's bits, and its column gap the first of the next 30 rows whose 5 columns around it hold one:
 lane i takes row y + 1 + i's dilated bits and a bit transpose gives each lane its column's, so no warp walks the
 rows one load after the other. Most points fall in a few bins: a block counts in shared memory first, so that the
 global atomics do not all meet on the same addresses. */
__global__ void scanGapHistogramKernel(PtrStepSz<short> sparse16, int* stats)
{
    static_assert(RING_COLUMNS == 2, "the column windows below are 5 bits wide");
    static_assert(SCAN_GAP_BINS == 32, "a gap below the cap lies in the next 30 columns or rows");
    __shared__ int hist[2 * SCAN_GAP_BINS];
    __shared__ unsigned bits[SCAN_ROWS][3];   // columns x0 - 32 + 32 k + bit
    const int lane = threadIdx.x, warp = threadIdx.y, tid = warp * 32 + lane;
    const int W = sparse16.cols, H = sparse16.rows;
    const int x0 = blockIdx.x * 32, by = blockIdx.y * SCAN_BLOCK_ROWS, x = x0 + lane, y = by + warp;
    if (tid < 2 * SCAN_GAP_BINS)
        hist[tid] = 0;
    const int LOADS = (3 * SCAN_ROWS + SCAN_BLOCK_ROWS - 1) / SCAN_BLOCK_ROWS;
    bool hit[LOADS];
#pragma unroll   // the loads all in flight at once
    for (int k = 0; k < LOADS; k++)
    {
        const int i = warp + k * SCAN_BLOCK_ROWS, v = by + i / 3, c = x0 - 32 + 32 * (i % 3) + lane;
        hit[k] = i < 3 * SCAN_ROWS && v < H && c >= 0 && c < W && sparse16(v, c) != NO_DISP;
    }
#pragma unroll
    for (int k = 0; k < LOADS; k++)
    {
        const int i = warp + k * SCAN_BLOCK_ROWS;
        const unsigned b = __ballot_sync(0xFFFFFFFFu, hit[k]);
        if (lane == 0 && i < 3 * SCAN_ROWS)
            bits[i / 3][i % 3] = b;
    }
    __syncthreads();
    const unsigned own = bits[warp][1];
    if (y < H && own != 0u)   // the whole warp
    {
        const unsigned cap = SCAN_GAP_BINS - 1;
        const bool point = (own >> lane) & 1u;
        // The row: the first point among the next cap - 1 columns.
        const unsigned long long right = (unsigned long long)bits[warp][2] << 32 | own;
        const unsigned ahead = (unsigned)(right >> (lane + 1)) & ((1u << (cap - 1)) - 1);
        const int gr = ahead ? __ffs(ahead) : x + (int)cap < W ? (int)cap : -1;
        // The rows below: lane i's bit t says whether row y + 1 + i holds a point in columns x0 + t -+ 2.
        unsigned dilated = 0u;
        if (lane < (int)cap - 1)
        {
            const unsigned* const b = bits[warp + 1 + lane];
            const unsigned long long w = b[0] >> 30 | (unsigned long long)b[1] << 2 |
                                         (unsigned long long)(b[2] & 3u) << 34;   // bit j: column x0 - 2 + j
            dilated = (unsigned)(w | w >> 1 | w >> 2 | w >> 3 | w >> 4);
        }
        const unsigned below = warpTransposeBits(dilated, lane);   // bit i: row y + 1 + i, for this lane's column
        const int gc = below ? __ffs(below) : y + (int)cap < H ? (int)cap : -1;
        if (point)
        {
            if (gr >= 0)
                atomicAdd(hist + gr, 1);
            if (gc >= 0)
                atomicAdd(hist + SCAN_GAP_BINS + gc, 1);
        }
    }
    __syncthreads();
    if (tid < 2 * SCAN_GAP_BINS && hist[tid] > 0)
        atomicAdd(stats + tid, hist[tid]);
}

//! One warp: visibilityGrowthApplies.
__global__ void scanTestKernel(int* stats)
{
    const int rows = warpLowerMedian<SCAN_GAP_BINS>(stats);
    const int columns = warpLowerMedian<SCAN_GAP_BINS>(stats + SCAN_GAP_BINS);
    if (threadIdx.x == 0)
        stats[2 * SCAN_GAP_BINS] = scanGapsApply(rows, columns) ? 1 : 0;
}

/* Two blocks of 1024 threads an SM where a multiprocessor holds 2048 threads (sm_80, sm_90, sm_100); one elsewhere
 (sm_86 to sm_89, Jetson Orin's sm_87 among them, and sm_110 hold 1536, sm_75 1024), where ptxas would ignore a bound
 of two with a warning. */
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ != 800 && __CUDA_ARCH__ != 900 && __CUDA_ARCH__ != 1000
const int VISIBILITY_BLOCKS_PER_SM = 1;
#else
const int VISIBILITY_BLOCKS_PER_SM = 2;
#endif

/* stats: null, or the scan test's result at stats[2 SCAN_GAP_BINS] (0: no parallax growth). A warp is one row of 32
 pixels (blocks of 32 x 32); it takes its sparse pixels one at a time, and its 32 lanes test each against the tile's
 points in the rows that can hide it together: a pixel's own loop over the list would hold the whole warp for its
 longest search (the window grows with the parallax: hundreds of points a tile on a 64-line scan). */
// (Two blocks an SM: 32 registers. Without the bound nvcc takes 40, which leaves one block of 1024 an SM.)
__global__ void __launch_bounds__(1024, VISIBILITY_BLOCKS_PER_SM)
visibilityKernel(PtrStepSz<short> sparse16, SparseRows rows, PipelineParams p, int reach, const int* stats,
                 PtrStepSz<short> out)
{
    extern __shared__ int smem[];   // listTilePoints
    if (stats && stats[2 * SCAN_GAP_BINS] == 0)
        p.visibilityParallax256 = 0;
    const TilePoints tile = listTilePoints(rows, reach, smem);
    const int lane = threadIdx.x, x = blockIdx.x * blockDim.x + lane, y = blockIdx.y * blockDim.y + threadIdx.y;
    const bool inside = x < sparse16.cols && y < sparse16.rows;
    const int d = inside ? sparse16(y, x) : NO_DISP;
    bool hidden = false;
    for (unsigned todo = __ballot_sync(0xFFFFFFFFu, d != NO_DISP); todo != 0; todo &= todo - 1)
    {
        const int src = __ffs(todo) - 1, dq = __shfl_sync(0xFFFFFFFFu, d, src), xq = x - lane + src;
        // No point of the tile hides dq beyond the growth its largest value allows (hiddenBy): the rows within
        // visibilityRadiusY plus that growth hold every point that can.
        const int growth = visibilityGrowthAllowed(tile.maxValue - dq, p);
        const int ry = p.visibilityRadiusY + growth;
        const int k1 = tile.end(y + ry);
        bool h = false;
        for (int i = tile.begin(y - ry) + lane; i < k1 && !h; i += 32)
        {
            const int at = tile.points[2 * i];
            h = hiddenBy(tile.points[2 * i + 1], dq, (at & 0xFFFF) - xq, (at >> 16) - y, p);
        }
        h = __any_sync(0xFFFFFFFFu, h);
        hidden = lane == src ? h : hidden;
    }
    if (inside)
        out(y, x) = (short)(hidden ? NO_DISP : d);
}

} // namespace

void testScan(PtrStepSz<short> sparse16, int* stats, cudaStream_t stream)
{
    const dim3 block(32, SCAN_BLOCK_ROWS);
    const dim3 grid(cv::cudev::divUp(sparse16.cols, block.x), cv::cudev::divUp(sparse16.rows, block.y));
    CV_CUDEV_SAFE_CALL(cudaMemsetAsync(stats, 0, 2 * SCAN_GAP_BINS * sizeof(int), stream));
    scanGapHistogramKernel<<<grid, block, 0, stream>>>(sparse16, stats);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    scanTestKernel<<<1, 32, 0, stream>>>(stats);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

void filterHiddenPoints(PtrStepSz<short> sparse16, const SparseRows& rows, const PipelineParams& p,
                        PtrStepSz<short> visible16, const int* stats, cudaStream_t stream)
{
    // A warp per row (visibilityKernel). 32 rows a block: with doc/params/kitti_best.yml's margin of 27 pixels, a
    // block lists 7.2 pixels a pixel of it, against 11.8 with 16 rows, and a point's search covers the same rows
    // (KITTI size on 8 H100 SMs: 250 against 286 us, 9.2 against 12.2 M warp instructions).
    const dim3 block(32, 32);
    const dim3 grid(cv::cudev::divUp(sparse16.cols, block.x), cv::cudev::divUp(sparse16.rows, block.y));
    const bool growth = p.visibilityParallax256 > 0;
    // The tile's margin: the larger half-size of the base window grown by the largest parallax growth.
    const int reach = std::max(p.visibilityRadiusX, p.visibilityRadiusY) + visibilityGrowth(p);
    const size_t smem = tileKernelSmem(visibilityKernel, block, reach);
    visibilityKernel<<<grid, block, smem, stream>>>(sparse16, rows, p, reach, growth ? stats : nullptr,
                                                    visible16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
