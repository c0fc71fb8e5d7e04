// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The disparity windows, CUDA twin of src/search_window.cpp: per tile the range of the prior indices in the tile and
// the tiles around it (tileWindow, pipeline.hpp); where none of them has a prior, the range of the coarse pass's
// disparities there. The coarse pass runs on every windowed call (the CPU runs it only where a tile needs it; the
// windows do not depend on it elsewhere), so that nothing waits for the host.

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"
#include <climits>

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

//! Both images reduced by COARSE_SCALE in one launch (blockIdx.z: left, right): coarseMean of each block, the
//! border replicated.
template <typename T>
__global__ void coarseKernel(PtrStepSz<T> left, PtrStepSz<T> right, PtrStepSz<T> coarseL, PtrStepSz<T> coarseR)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const PtrStepSz<T> in = blockIdx.z ? right : left;
    PtrStepSz<T> out = blockIdx.z ? coarseR : coarseL;
    if (x >= out.cols || y >= out.rows)
        return;
    const int S = COARSE_SCALE;
    int sum = 0;
    for (int v = 0; v < S; v++)
        for (int u = 0; u < S; u++)
            sum += in(::min(y * S + v, in.rows - 1), ::min(x * S + u, in.cols - 1));
    out(y, x) = (T)coarseMean(sum);
}

//! A tile's threads in tileRangesKernel: four of its pixels each; one coarse pixel each.
const int TILE_RANGE_THREADS = 256, COARSE_TILE_RANGE_THREADS = 64;

/* Per tile (one block each), the lowest and highest prior index (COARSE false: prior16's pixels in the tile) or
 coarse index range (COARSE: coarse pixels in the tile, each standing for COARSE_SCALE^2 pixels; a coarse disparity
 c stands for the full-scale disparities c S - S .. c S + S), clamped to [0, D): ranges(ty, tx) = (kMin, kMax),
 kMin > kMax where the tile has none. */
template <bool COARSE>
__global__ void tileRangesKernel(PtrStepSz<short> map, int minD, int D, PtrStepSz<int2> ranges)
{
    __shared__ int kMin, kMax;
    if (threadIdx.x == 0)
    {
        kMin = INT_MAX;
        kMax = INT_MIN;
    }
    __syncthreads();
    const int S = COARSE ? COARSE_SCALE : 1, span = WINDOW_TILE / S;
    const int x0 = blockIdx.x * span, y0 = blockIdx.y * span;
    const int x1 = ::min(x0 + span, map.cols), y1 = ::min(y0 + span, map.rows);
    // The thread's pixels of the tile, their loads in flight together.
    const int THREADS = COARSE ? COARSE_TILE_RANGE_THREADS : TILE_RANGE_THREADS, PER = span * span / THREADS;
    int v[PER];
#pragma unroll
    for (int k = 0; k < PER; k++)
    {
        const int i = threadIdx.x + k * THREADS, x = x0 + i % span, y = y0 + i / span;
        v[k] = x < x1 && y < y1 ? map(y, x) : NO_DISP;
    }
    int lo = INT_MAX, hi = INT_MIN;
#pragma unroll
    for (int k = 0; k < PER; k++)
    {
        if (v[k] == NO_DISP)
            continue;
        const int a = COARSE ? v[k] * S - S - minD : roundDisp16(v[k]) - minD, b = COARSE ? v[k] * S + S - minD : a;
        lo = ::min(lo, ::min(::max(a, 0), D - 1));
        hi = ::max(hi, ::min(::max(b, 0), D - 1));
    }
    lo = __reduce_min_sync(0xFFFFFFFFu, lo);
    hi = __reduce_max_sync(0xFFFFFFFFu, hi);
    if ((threadIdx.x & 31) == 0)
    {
        atomicMin(&kMin, lo);
        atomicMax(&kMax, hi);
    }
    __syncthreads();
    if (threadIdx.x == 0)
        ranges(blockIdx.y, blockIdx.x) = make_int2(kMin, kMax);
}

//! The union of the ranges of tile (tx, ty) and the tiles around it.
__device__ int2 dilatedRange(const PtrStepSz<int2>& ranges, int tx, int ty)
{
    int2 r = make_int2(INT_MAX, INT_MIN);
    for (int v = ::max(ty - 1, 0); v <= ::min(ty + 1, ranges.rows - 1); v++)
        for (int u = ::max(tx - 1, 0); u <= ::min(tx + 1, ranges.cols - 1); u++)
        {
            const int2 q = ranges(v, u);
            r.x = ::min(r.x, q.x);
            r.y = ::max(r.y, q.y);
        }
    return r;
}

//! Each tile's window (lo, hi) from its dilated prior range, else its dilated coarse range, else the full range.
__global__ void windowsKernel(PtrStepSz<int2> own, PtrStepSz<int2> coarse, int margin, int D, PtrStepSz<short2> windows)
{
    const int tx = blockIdx.x * blockDim.x + threadIdx.x, ty = blockIdx.y * blockDim.y + threadIdx.y;
    if (tx >= windows.cols || ty >= windows.rows)
        return;
    int2 r = dilatedRange(own, tx, ty);
    if (r.x > r.y)
        r = dilatedRange(coarse, tx, ty);
    int lo = 0, hi = D;
    if (r.x <= r.y)
        tileWindow(r.x, r.y, margin, D, lo, hi);
    windows(ty, tx) = make_short2((short)lo, (short)hi);
}

/* The compact volume's bases (windowPairOffset): an exclusive prefix sum of the tiles' units in one block, each thread
over a run of consecutive tiles; the last thread's end is the total, at bases[tiles]. */
__global__ void windowLayoutKernel(PtrStepSz<int> windows, int* bases)
{
    __shared__ int warpSums[32];
    const int n = windows.rows * windows.cols, per = (n + (int)blockDim.x - 1) / (int)blockDim.x;
    const int t0 = ::min((int)threadIdx.x * per, n), t1 = ::min(t0 + per, n);
    const auto units = [&](int t) {
        const unsigned w = (unsigned)windows(t / windows.cols, t % windows.cols);
        return (int)((w >> 16) - (w & 0xFFFFu)) / WINDOW_ALIGN;
    };
    int own = 0;
    for (int t = t0; t < t1; t++)
        own += units(t);
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5, warps = (int)blockDim.x >> 5;
    int v = own;   // inclusive scan within the warp, then over the warps' totals
    for (int o = 1; o < 32; o <<= 1)
    {
        const int u = __shfl_up_sync(0xFFFFFFFFu, v, o);
        v += lane >= o ? u : 0;
    }
    if (lane == 31)
        warpSums[warp] = v;
    __syncthreads();
    if (warp == 0)
    {
        int s = lane < warps ? warpSums[lane] : 0;
        for (int o = 1; o < 32; o <<= 1)
        {
            const int u = __shfl_up_sync(0xFFFFFFFFu, s, o);
            s += lane >= o ? u : 0;
        }
        warpSums[lane] = s;
    }
    __syncthreads();
    int at = v - own + (warp > 0 ? warpSums[warp - 1] : 0);
    for (int t = t0; t < t1; t++)
    {
        bases[t] = at;
        at += units(t);
    }
    if (threadIdx.x == blockDim.x - 1)
        bases[n] = at;
}

} // namespace

void windowLayout(PtrStepSz<int> windows, int* bases, cudaStream_t stream)
{
    windowLayoutKernel<<<1, 1024, 0, stream>>>(windows, bases);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

void coarseImages(PtrStepSz<uchar> left, PtrStepSz<uchar> right, PtrStepSz<uchar> coarseL, PtrStepSz<uchar> coarseR,
                  cudaStream_t stream)
{
    const dim3 block(32, 8), grid(cv::cudev::divUp(coarseL.cols, 32), cv::cudev::divUp(coarseL.rows, 8), 2);
    coarseKernel<<<grid, block, 0, stream>>>(left, right, coarseL, coarseR);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

void coarseImages(PtrStepSz<ushort> left, PtrStepSz<ushort> right, PtrStepSz<ushort> coarseL,
                  PtrStepSz<ushort> coarseR, cudaStream_t stream)
{
    const dim3 block(32, 8), grid(cv::cudev::divUp(coarseL.cols, 32), cv::cudev::divUp(coarseL.rows, 8), 2);
    coarseKernel<<<grid, block, 0, stream>>>(left, right, coarseL, coarseR);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

void searchWindows(PtrStepSz<short> prior16, PtrStepSz<short> coarse, const PipelineParams& p,
                   PtrStepSz<int2> ownRanges, PtrStepSz<int2> coarseRanges, PtrStepSz<short2> windows,
                   cudaStream_t stream)
{
    const dim3 tiles(windows.cols, windows.rows);
    const int D = p.numDisparities, minD = p.minDisparity;
    // An empty prior16 (0 x 0) gives every tile no range.
    tileRangesKernel<false><<<tiles, TILE_RANGE_THREADS, 0, stream>>>(prior16, minD, D, ownRanges);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    tileRangesKernel<true><<<tiles, COARSE_TILE_RANGE_THREADS, 0, stream>>>(coarse, minD, D, coarseRanges);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    const dim3 block(32, 8), grid(cv::cudev::divUp(windows.cols, 32), cv::cudev::divUp(windows.rows, 8));
    windowsKernel<<<grid, block, 0, stream>>>(ownRanges, coarseRanges, p.searchWindow, D, windows);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
