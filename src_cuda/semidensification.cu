// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification, CUDA twin of src/semidensification.*: the same candidate order (semidenseKey), so ties resolve
// identically.

#include "sparse_window.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

/* One block = 32 x 8 pixels; each pixel visits the sparse points of its block's tile (sparse_window.cuh). The choice
 uses the full key (semidenseKey), so it does not depend on the order of the list. */
__global__ void semidenseKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                                int rs, int Ts, PtrStepSz<short> out)
{
    extern __shared__ int points[];   // (y << 16 | x), value
    __shared__ int count;
    const int W = out.cols, H = out.rows;
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const int n = listTilePoints(sparse16, rs, points, &count);
    if (x >= W || y >= H)
        return;
    const unsigned l = (unsigned)censusL(y, x);
    const int* R = censusR.ptr(y);
    unsigned best = 0xFFFFFFFFu;
    short bestVal = NO_DISP;
    for (int k = 0; k < n; k++)
    {
        const int pos = points[2 * k];
        const int c = pos & 0xFFFF, q = pos >> 16;
        if (abs(c - x) > rs || abs(q - y) > rs)
            continue;
        const short v = (short)points[2 * k + 1];
        const int xr = ::min(::max(x - roundDisp16(v), 0), W - 1);
        const unsigned key = semidenseKey(popcount32(l ^ (unsigned)R[xr]), c - x, q - y, rs);
        if (key < best)
        {
            best = key;
            bestVal = v;
        }
    }
    out(y, x) = semidenseKeyCost(best) < Ts ? bestVal : sparse16(y, x);
}

void semidensify(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                 const PipelineParams& p, PtrStepSz<short> semidense16, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cudev::divUp(semidense16.cols, block.x), cv::cudev::divUp(semidense16.rows, block.y));
    const int rs = p.semidenseRadius;
    const size_t smem = tileKernelSmem(semidenseKernel, block, rs);
    semidenseKernel<<<grid, block, smem, stream>>>(censusL, censusR, sparse16, rs, p.semidenseThreshold, semidense16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
