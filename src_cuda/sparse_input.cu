// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Sparse input to the internal 1/16-pixel map, CUDA twin of src/sparse_input.cpp (same rounding, in double).

#include "pipeline_cuda.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

__global__ void convertSparseKernel(PtrStepSz<ushort> s16u, PtrStepSz<float> s32f, int lo, int hi, PtrStepSz<short> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= out.cols || y >= out.rows)
        return;
    int d16 = NO_DISP;
    if (s16u.data)
    {
        const int v = s16u(y, x);
        if (v != 0)
            d16 = (v + 8) >> 4;
    }
    else
    {
        const float v = s32f(y, x);
        if (v > 0.f && v < 1536.f)
            d16 = (int)floor((double)v * 16.0 + 0.5);
    }
    if (d16 != NO_DISP && !sparseInRange(d16, lo, hi))
        d16 = NO_DISP;
    out(y, x) = (short)d16;
}

void convertSparse(PtrStepSz<ushort> sparse16u, PtrStepSz<float> sparse32f, int minDisparity, int numDisparities,
                   PtrStepSz<short> sparse16, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(sparse16.cols, block.x), cv::cuda::device::divUp(sparse16.rows, block.y));
    convertSparseKernel<<<grid, block, 0, stream>>>(sparse16u, sparse32f, minDisparity,
                                                    minDisparity + numDisparities - 1, sparse16);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
