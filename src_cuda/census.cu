// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform, CUDA twin of src/census.cpp (same bits, same clamped border).

#include "pipeline_cuda.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

template <typename T>
__global__ void censusKernel(PtrStepSz<T> img, PtrStepSz<int> census)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= img.cols || y >= img.rows)
        return;
    const int rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    unsigned c = 0;
    for (int dy = -ry; dy <= 0; dy++)
    {
        const T* a = img.ptr(::min(::max(y + dy, 0), img.rows - 1));
        const T* b = img.ptr(::min(::max(y - dy, 0), img.rows - 1));
        const int dxEnd = dy < 0 ? rx : -1;
        for (int dx = -rx; dx <= dxEnd; dx++)
        {
            const T va = a[::min(::max(x + dx, 0), img.cols - 1)];
            const T vb = b[::min(::max(x - dx, 0), img.cols - 1)];
            c = (c << 1) | (va > vb ? 1u : 0u);
        }
    }
    census(y, x) = (int)c;
}

void censusTransform(PtrStepSz<uchar> img8, PtrStepSz<ushort> img16, PtrStepSz<int> census, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(census.cols, block.x), cv::cuda::device::divUp(census.rows, block.y));
    if (img8.data)
        censusKernel<uchar><<<grid, block, 0, stream>>>(img8, census);
    else
        censusKernel<ushort><<<grid, block, 0, stream>>>(img16, census);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
