// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Ring interpolation, CUDA twin of src/ring_interpolation.cpp (the rule and its arithmetic: pipeline.hpp). The ring
// spacing stays on the GPU: a histogram, its median and the gap limit are computed in stream order, no copy to the
// host.

#include "cuda_stages.hpp"
#include "histogram.cuh"
#include "pixel_rows.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

/* A block of 32 columns x 32 row segments: each thread finds its segment's first and last point, the segments before
and after it give the points beyond its segment (the nearest above is the last one of the segments before, the
nearest below the first one of those after), then it writes its segment's rows. */
__global__ void ringNeighboursKernel(PtrStepSz<short> sparse16, PtrStepSz<short> above, PtrStepSz<short> below)
{
    __shared__ short first[32][33], last[32][33];   // [segment][column], padded against bank conflicts
    const int tx = threadIdx.x, ts = threadIdx.y;
    const int x = blockIdx.x * 32 + tx, H = sparse16.rows, len = (H + 31) / 32;
    const int y0 = ts * len, y1 = ::min(y0 + len, H);
    const bool inside = x < sparse16.cols;
    short f = -1, l = -1;
    for (int y = y0; inside && y < y1; y++)
        if (sparse16(y, x) != NO_DISP)
        {
            if (f < 0)
                f = (short)y;
            l = (short)y;
        }
    first[ts][tx] = f;
    last[ts][tx] = l;
    __syncthreads();
    if (!inside)
        return;
    short a = -1, b = -1;
    for (int t = 0; t < ts; t++)
        a = ::max(a, last[t][tx]);
    for (int t = 31; t > ts; t--)
        if (first[t][tx] >= 0)
            b = first[t][tx];
    for (int y = y0; y < y1; y++)
    {
        above(y, x) = a;
        if (sparse16(y, x) != NO_DISP)
            a = (short)y;
    }
    for (int y = y1 - 1; y >= y0; y--)
    {
        below(y, x) = b;
        if (sparse16(y, x) != NO_DISP)
            b = (short)y;
    }
}

/* A block counts in shared memory first: most points fall in a few bins, and their global atomics would queue on them.
 PixelRows: four pixels a thread, their loads in flight together. */
__global__ void ringGapHistogramKernel(PtrStepSz<short> sparse16, PtrStepSz<short> above, PtrStepSz<short> below,
                                       int* hist)
{
    __shared__ int local[RING_GAP_BINS];
    const int tid = threadIdx.y * blockDim.x + threadIdx.x, nthreads = blockDim.x * blockDim.y;
    for (int i = tid; i < RING_GAP_BINS; i += nthreads)
        local[i] = 0;
    const int x = PixelRows::x();
    short v[PixelRows::N];
#pragma unroll
    for (int k = 0; k < PixelRows::N; k++)
    {
        const int y = PixelRows::y(k);
        v[k] = x < sparse16.cols && y < sparse16.rows ? sparse16(y, x) : (short)NO_DISP;
    }
    __syncthreads();
#pragma unroll
    for (int k = 0; k < PixelRows::N; k++)
    {
        const int y = PixelRows::y(k);
        if (v[k] != NO_DISP)
        {
            const int g = ringPointGap(above.ptr(y), below.ptr(y), x, sparse16.cols, y);
            if (g >= 0)
                atomicAdd(local + g, 1);
        }
    }
    __syncthreads();
    for (int i = tid; i < RING_GAP_BINS; i += nthreads)
        if (local[i] > 0)
            atomicAdd(hist + i, local[i]);
}

//! One warp.
__global__ void ringGapLimitKernel(int* stats, int factor16)
{
    const int spacing = warpLowerMedian<RING_GAP_BINS>(stats);
    if (threadIdx.x == 0)
        stats[RING_GAP_BINS] = ringGapLimit(factor16, spacing);
}

__global__ void ringFillKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                               PtrStepSz<short> above, PtrStepSz<short> below, const int* stats, int Ts, int lo,
                               int hi, PtrStepSz<short> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const int W = out.cols;
    if (x >= W || y >= out.rows || out(y, x) != NO_DISP)
        return;
    const int v = ringCandidate16(above.data, below.data, above.step / sizeof(short), sparse16.data,
                                  sparse16.step / sizeof(short), x, y, W, stats[RING_GAP_BINS]);
    if (v == NO_DISP || !sparseInRange(v, lo, hi))
        return;
    const int xr = ::min(::max(x - roundDisp16(v), 0), W - 1);
    if (popcount32((unsigned)censusL(y, x) ^ (unsigned)censusR(y, xr)) < Ts)
        out(y, x) = (short)v;
}

} // namespace

void interpolateRings(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                      const PipelineParams& p, PtrStepSz<short> semidense16, PtrStepSz<short> above,
                      PtrStepSz<short> below, int* stats, cudaStream_t stream)
{
    using cv::cudev::divUp;
    const int W = semidense16.cols, H = semidense16.rows;
    ringNeighboursKernel<<<divUp(W, 32), dim3(32, 32), 0, stream>>>(sparse16, above, below);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    CV_CUDEV_SAFE_CALL(cudaMemsetAsync(stats, 0, (RING_GAP_BINS + 1) * sizeof(int), stream));
    const dim3 block(32, 8), grid(divUp(W, block.x), divUp(H, block.y));
    ringGapHistogramKernel<<<PixelRows::grid(W, H), PixelRows::block(), 0, stream>>>(sparse16, above, below, stats);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    ringGapLimitKernel<<<1, 32, 0, stream>>>(stats, p.ringGapFactor16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    ringFillKernel<<<grid, block, 0, stream>>>(censusL, censusR, sparse16, above, below, stats,
                                               p.semidenseThreshold, p.minDisparity,
                                               p.minDisparity + p.numDisparities - 1, semidense16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
