// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform, CUDA twin of src/census.cpp (same bits, same clamped border).

#include "cuda_stages.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! Pixel at offset (dx, dy) of (x, y), coordinates clamped to the image.
template <typename T>
struct ClampedWindow
{
    const PtrStepSz<T>& img;
    int x, y;
    __host__ __device__ __forceinline__ T operator()(int dx, int dy) const
    {
        return img(::min(::max(y + dy, 0), img.rows - 1), ::min(::max(x + dx, 0), img.cols - 1));
    }
};

/* Both images in one launch: blockIdx.z picks the image. Column c of the grid is pixel c - padBefore; the right
 image's padding columns get the string of the nearest pixel of the row. */
template <typename T>
__global__ void censusKernel(PtrStepSz<T> left, PtrStepSz<T> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR,
                             int padBefore, int padAfter)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x - padBefore, y = blockIdx.y * blockDim.y + threadIdx.y;
    const bool isLeft = blockIdx.z == 0;
    if (y >= left.rows || x >= left.cols + (isLeft ? 0 : padAfter) || (isLeft && x < 0))
        return;
    const PtrStepSz<T>& img = isLeft ? left : right;
    const ClampedWindow<T> at = { img, ::min(::max(x, 0), img.cols - 1), y };
    (isLeft ? censusL : censusR).ptr(y)[x] = (int)censusString(at);
}

template <typename T>
void runCensus(PtrStepSz<T> left, PtrStepSz<T> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR, int padBefore,
               int padAfter, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(censusL.cols + padBefore + padAfter, block.x),
                    cv::cuda::device::divUp(censusL.rows, block.y), 2);
    censusKernel<T><<<grid, block, 0, stream>>>(left, right, censusL, censusR, padBefore, padAfter);
    cudaSafeCall(cudaGetLastError());
}

void censusTransform(PtrStepSz<uchar> left, PtrStepSz<uchar> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR,
                     int padBefore, int padAfter, cudaStream_t stream)
{
    runCensus(left, right, censusL, censusR, padBefore, padAfter, stream);
}

void censusTransform(PtrStepSz<ushort> left, PtrStepSz<ushort> right, PtrStepSz<int> censusL,
                     PtrStepSz<int> censusR, int padBefore, int padAfter, cudaStream_t stream)
{
    runCensus(left, right, censusL, censusR, padBefore, padAfter, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
