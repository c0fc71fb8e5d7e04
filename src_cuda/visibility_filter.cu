// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visibility filter of the sparse input, CUDA twin of src/visibility_filter.cpp (hiddenBy, pipeline.hpp).

#include "cuda_stages.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

__global__ void visibilityKernel(PtrStepSz<short> sparse16, int rx, int ry, int tc, PtrStepSz<short> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= sparse16.cols || y >= sparse16.rows)
        return;
    const int d = sparse16(y, x);
    bool hidden = false;
    if (d != NO_DISP)
        for (int v = ::max(y - ry, 0); v <= ::min(y + ry, sparse16.rows - 1) && !hidden; v++)
            for (int u = ::max(x - rx, 0); u <= ::min(x + rx, sparse16.cols - 1); u++)
                if (hiddenBy(sparse16(v, u), d, tc))
                {
                    hidden = true;
                    break;
                }
    out(y, x) = (short)(hidden ? NO_DISP : d);
}

} // namespace

void filterHiddenPoints(PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> visible16,
                        cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(sparse16.cols, block.x), cv::cuda::device::divUp(sparse16.rows, block.y));
    visibilityKernel<<<grid, block, 0, stream>>>(sparse16, p.visibilityRadiusX, p.visibilityRadiusY,
                                                 p.checkThreshold16, visible16);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
