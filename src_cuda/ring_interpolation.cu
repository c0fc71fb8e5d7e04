// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Ring interpolation, CUDA twin of src/ring_interpolation.cpp (the rule and its arithmetic: pipeline.hpp). The ring
// spacing stays on the GPU: a histogram, its median and the gap limit are computed in stream order, no copy to the host.

#include "cuda_stages.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

// One thread per column, rows in order: the row of the column's nearest point above and below each pixel.
__global__ void ringNeighboursKernel(PtrStepSz<short> sparse16, PtrStepSz<short> above, PtrStepSz<short> below)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x;
    if (x >= sparse16.cols)
        return;
    const int H = sparse16.rows;
    short last = -1;
    for (int y = 0; y < H; y++)
    {
        above(y, x) = last;
        if (sparse16(y, x) != NO_DISP)
            last = (short)y;
    }
    last = -1;
    for (int y = H - 1; y >= 0; y--)
    {
        below(y, x) = last;
        if (sparse16(y, x) != NO_DISP)
            last = (short)y;
    }
}

__global__ void ringGapHistogramKernel(PtrStepSz<short> sparse16, PtrStepSz<short> below, int* hist)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= sparse16.cols || y >= sparse16.rows || sparse16(y, x) == NO_DISP)
        return;
    const int g = ringPointGap(below.ptr(y), x, sparse16.cols, y);
    if (g >= 0)
        atomicAdd(hist + g, 1);
}

__global__ void ringGapLimitKernel(int* stats, int factor16)
{
    stats[RING_GAP_BINS] = ringGapLimit(factor16, histogramLowerMedian(stats, RING_GAP_BINS));
}

__global__ void ringFillKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                               PtrStepSz<short> above, PtrStepSz<short> below, const int* stats, int Ts,
                               PtrStepSz<short> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const int W = out.cols;
    if (x >= W || y >= out.rows || out(y, x) != NO_DISP)
        return;
    int xa, ya, xb, yb;
    nearestRingPoints(above.ptr(y), below.ptr(y), x, W, xa, ya, xb, yb);
    if (ya < 0 || yb < 0 || yb - ya > stats[RING_GAP_BINS])
        return;
    const int v = ringInterpolate16(sparse16(ya, xa), ya, sparse16(yb, xb), yb, y);
    const int xr = ::min(::max(x - roundDisp16(v), 0), W - 1);
    if (popcount32((unsigned)censusL(y, x) ^ (unsigned)censusR(y, xr)) < Ts)
        out(y, x) = (short)v;
}

} // namespace

void interpolateRings(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                      const PipelineParams& p, PtrStepSz<short> semidense16, PtrStepSz<short> above,
                      PtrStepSz<short> below, int* stats, cudaStream_t stream)
{
    using cv::cuda::device::divUp;
    const int W = semidense16.cols, H = semidense16.rows;
    ringNeighboursKernel<<<divUp(W, 64), 64, 0, stream>>>(sparse16, above, below);
    cudaSafeCall(cudaGetLastError());
    cudaSafeCall(cudaMemsetAsync(stats, 0, (RING_GAP_BINS + 1) * sizeof(int), stream));
    const dim3 block(32, 8), grid(divUp(W, block.x), divUp(H, block.y));
    ringGapHistogramKernel<<<grid, block, 0, stream>>>(sparse16, below, stats);
    cudaSafeCall(cudaGetLastError());
    ringGapLimitKernel<<<1, 1, 0, stream>>>(stats, p.ringGapFactor16);
    cudaSafeCall(cudaGetLastError());
    ringFillKernel<<<grid, block, 0, stream>>>(censusL, censusR, sparse16, above, below, stats,
                                               p.semidenseThreshold, semidense16);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
