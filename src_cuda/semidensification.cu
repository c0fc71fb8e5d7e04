// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification, CUDA twin of src/semidensification.cpp: the same candidate order (census cost, squared
// distance, row, column), so ties resolve identically. One thread per pixel scans its window.

#include "pipeline_cuda.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

__global__ void semidenseKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                                int rs, int Ts, PtrStepSz<short> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const int W = out.cols, H = out.rows;
    if (x >= W || y >= H)
        return;
    const unsigned l = (unsigned)censusL(y, x);
    const int* R = censusR.ptr(y);
    int bestCost = INT_MAX, bestDist = INT_MAX, bestRow = INT_MAX, bestCol = INT_MAX;
    short bestVal = NO_DISP;
    const int r0 = ::max(0, y - rs), r1 = ::min(H - 1, y + rs), c0 = ::max(0, x - rs), c1 = ::min(W - 1, x + rs);
    for (int q = r0; q <= r1; q++)
    {
        const short* s = sparse16.ptr(q);
        for (int c = c0; c <= c1; c++)
        {
            const short v = s[c];
            if (v == NO_DISP)
                continue;
            const int xr = ::min(::max(x - roundDisp16(v), 0), W - 1);
            const int cost = popcount32(l ^ (unsigned)R[xr]);
            const int dist = (c - x) * (c - x) + (q - y) * (q - y);
            if (cost < bestCost || (cost == bestCost && (dist < bestDist ||
                (dist == bestDist && (q < bestRow || (q == bestRow && c < bestCol))))))
            {
                bestCost = cost; bestDist = dist; bestRow = q; bestCol = c; bestVal = v;
            }
        }
    }
    out(y, x) = bestCost < Ts ? bestVal : sparse16(y, x);
}

void semidensify(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                 const PipelineParams& p, PtrStepSz<short> semidense16, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(semidense16.cols, block.x), cv::cuda::device::divUp(semidense16.rows, block.y));
    semidenseKernel<<<grid, block, 0, stream>>>(censusL, censusR, sparse16, p.semidenseRadius, p.semidenseThreshold,
                                                semidense16);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
