// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform, CUDA twin of src/census.cpp (same bits, same clamped border).

#include "pipeline_cuda.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

template <typename T>
__device__ __forceinline__ void censusAt(const PtrStepSz<T>& img, PtrStepSz<int>& census, int x, int y)
{
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

//! Both images in one launch: blockIdx.z picks the image.
template <typename T>
__global__ void censusKernel(PtrStepSz<T> left, PtrStepSz<T> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= left.cols || y >= left.rows)
        return;
    if (blockIdx.z == 0)
        censusAt(left, censusL, x, y);
    else
        censusAt(right, censusR, x, y);
}

void censusTransform(PtrStepSz<uchar> left8, PtrStepSz<uchar> right8, PtrStepSz<ushort> left16,
                     PtrStepSz<ushort> right16, PtrStepSz<int> censusL, PtrStepSz<int> censusR, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(censusL.cols, block.x), cv::cuda::device::divUp(censusL.rows, block.y), 2);
    if (left8.data)
        censusKernel<uchar><<<grid, block, 0, stream>>>(left8, right8, censusL, censusR);
    else
        censusKernel<ushort><<<grid, block, 0, stream>>>(left16, right16, censusL, censusR);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
