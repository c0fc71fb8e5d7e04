// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visibility filter of the sparse input, CUDA twin of src/visibility_filter.cpp (hiddenBy, pipeline.hpp).

#include "cuda_stages.hpp"
#include "sparse_window.cuh"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

__global__ void visibilityKernel(PtrStepSz<short> sparse16, PipelineParams p, int reach, PtrStepSz<short> out)
{
    extern __shared__ int points[];   // (y << 16 | x), value: 2 ints per sparse point of the tile
    __shared__ int count;
    const int n = listTilePoints(sparse16, reach, points, &count);
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= sparse16.cols || y >= sparse16.rows)
        return;
    const int d = sparse16(y, x);
    bool hidden = false;
    if (d != NO_DISP)
        for (int i = 0; i < n && !hidden; i++)
        {
            const int at = points[2 * i];
            hidden = hiddenBy(points[2 * i + 1], d, (at & 0xFFFF) - x, (at >> 16) - y, p);
        }
    out(y, x) = (short)(hidden ? NO_DISP : d);
}

} // namespace

void filterHiddenPoints(PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> visible16,
                        cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(sparse16.cols, block.x), cv::cuda::device::divUp(sparse16.rows, block.y));
    // The tile's margin: the larger half-size of the base window grown by the largest parallax growth.
    const int reach = std::max(p.visibilityRadiusX, p.visibilityRadiusY) + visibilityGrowth(p);
    const size_t smem = tileKernelSmem(visibilityKernel, block, reach);
    visibilityKernel<<<grid, block, smem, stream>>>(sparse16, p, reach, visible16);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
