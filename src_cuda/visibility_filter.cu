// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visibility filter of the sparse input, CUDA twin of src/visibility_filter.cpp (hiddenBy, pipeline.hpp).

#include "cuda_stages.hpp"
#include "sparse_window.cuh"
#include "histogram.cuh"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

/* rowPointGap and columnPointGap of a warp's 32 pixels of a row together: the row's points to their right and the
 rows below come as ballots (32 columns a load), so that each row below is one load for the warp rather than a
 search of RING_COLUMNS-wide rows by each point's thread; the warp stops at the row where every point has its gap.
 Most points fall in a few bins: a block counts in shared memory first, so that the global atomics do not all meet on
 the same addresses. */
__global__ void scanGapHistogramKernel(PtrStepSz<short> sparse16, int* stats)
{
    static_assert(RING_COLUMNS == 2, "the column windows below are 5 bits wide");
    static_assert(SCAN_GAP_BINS == 32, "a gap below the cap lies in the next 30 columns or rows");
    __shared__ int hist[2 * SCAN_GAP_BINS];
    const int tid = threadIdx.y * blockDim.x + threadIdx.x, nthreads = blockDim.x * blockDim.y;
    for (int i = tid; i < 2 * SCAN_GAP_BINS; i += nthreads)
        hist[i] = 0;
    __syncthreads();
    const int W = sparse16.cols, H = sparse16.rows, lane = threadIdx.x;
    const int x0 = blockIdx.x * blockDim.x, x = x0 + lane, y = blockIdx.y * blockDim.y + threadIdx.y;
    const auto has = [&](int v, int c) { return c >= 0 && c < W && sparse16(v, c) != NO_DISP; };
    if (y < H)   // the whole warp
    {
        const bool point = has(y, x);
        if (__any_sync(0xFFFFFFFFu, point))
        {
            const unsigned cap = SCAN_GAP_BINS - 1;
            // The row: the first point among the next cap - 1 columns.
            const unsigned next = __ballot_sync(0xFFFFFFFFu, has(y, x + 32));
            const unsigned long long right = (unsigned long long)next << 32 | __ballot_sync(0xFFFFFFFFu, point);
            const unsigned ahead = (unsigned)(right >> (lane + 1)) & ((1u << (cap - 1)) - 1);
            const int gr = ahead ? __ffs(ahead) : x + (int)cap < W ? (int)cap : -1;
            // The rows below: bit i of a row's window mask is column x0 - RING_COLUMNS + i.
            int gc = -1;
            bool open = point;
            for (int v = y + 1; v < H && v - y < (int)cap && __any_sync(0xFFFFFFFFu, open); v++)
            {
                const int c = lane < 2 ? x0 - 2 + lane : x0 + 30 + lane;   // the columns beside the warp's
                const unsigned edge = __ballot_sync(0xFFFFFFFFu, lane < 4 && has(v, c));
                const unsigned long long row = (unsigned long long)(edge & 3u) |
                                               (unsigned long long)__ballot_sync(0xFFFFFFFFu, has(v, x)) << 2 |
                                               (unsigned long long)(edge >> 2) << 34;
                if (open && ((row >> lane) & 0x1Fu))
                {
                    gc = v - y;
                    open = false;
                }
            }
            if (open && y + (int)cap < H)
                gc = (int)cap;
            if (point)
            {
                if (gr >= 0)
                    atomicAdd(hist + gr, 1);
                if (gc >= 0)
                    atomicAdd(hist + SCAN_GAP_BINS + gc, 1);
            }
        }
    }
    __syncthreads();
    for (int i = tid; i < 2 * SCAN_GAP_BINS; i += nthreads)
        if (hist[i] > 0)
            atomicAdd(stats + i, hist[i]);
}

//! One warp: visibilityGrowthApplies.
__global__ void scanTestKernel(int* stats)
{
    const int rows = warpLowerMedian<SCAN_GAP_BINS>(stats);
    const int columns = warpLowerMedian<SCAN_GAP_BINS>(stats + SCAN_GAP_BINS);
    if (threadIdx.x == 0)
        stats[2 * SCAN_GAP_BINS] = scanGapsApply(rows, columns) ? 1 : 0;
}

/* stats: null, or the scan test's result at stats[2 SCAN_GAP_BINS] (0: no parallax growth). A warp is one row of 32
 pixels (blocks of 32 x 32); it takes its sparse pixels one at a time, and its 32 lanes test each against the tile's
 points in the rows that can hide it together: a pixel's own loop over the list would hold the whole warp for its
 longest search (the window grows with the parallax: hundreds of points a tile on a 64-line scan). */
__global__ void visibilityKernel(PtrStepSz<short> sparse16, PipelineParams p, int reach, const int* stats,
                                 PtrStepSz<short> out)
{
    extern __shared__ int smem[];   // listTilePoints
    if (stats && stats[2 * SCAN_GAP_BINS] == 0)
        p.visibilityParallax256 = 0;
    const TilePoints tile = listTilePoints(sparse16, reach, smem);
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
    const dim3 block(32, 8);
    const dim3 grid(cv::cudev::divUp(sparse16.cols, block.x), cv::cudev::divUp(sparse16.rows, block.y));
    CV_CUDEV_SAFE_CALL(cudaMemsetAsync(stats, 0, 2 * SCAN_GAP_BINS * sizeof(int), stream));
    scanGapHistogramKernel<<<grid, block, 0, stream>>>(sparse16, stats);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    scanTestKernel<<<1, 32, 0, stream>>>(stats);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

void filterHiddenPoints(PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> visible16,
                        const int* stats, cudaStream_t stream)
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
    visibilityKernel<<<grid, block, smem, stream>>>(sparse16, p, reach, growth ? stats : nullptr, visible16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
