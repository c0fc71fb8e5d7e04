// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform, CUDA twin of src/census.simd.hpp (same bits, same clamped border).

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! Pixel at offset (dx, dy) of (x, y), coordinates clamped to the image.
template <typename T>
struct ClampedWindow
{
    PtrStepSz<T> img;
    int x, y;
    __device__ __forceinline__ T operator()(int dx, int dy) const
    {
        return img(::min(::max(y + dy, 0), img.rows - 1), ::min(::max(x + dx, 0), img.cols - 1));
    }
};

const int BX = 32, BY = 8;                                   // a block's pixels
const int RX = CENSUS_WIDTH / 2, RY = CENSUS_HEIGHT / 2;
const int TW = BX + 2 * RX, TH = BY + 2 * RY;                // its tile of the image, window margins included

//! The window of tile pixel (x, y): the tile holds the image's clamped border, so no index is clamped here.
template <typename T>
struct TileWindow
{
    const T* tile;
    int x, y;
    __device__ __forceinline__ T operator()(int dx, int dy) const { return tile[(y + dy) * TW + x + dx]; }
};

/* Both images in one launch: blockIdx.z picks the image. Column c of the grid is pixel c - padBefore; the right
 image's padding columns get the string of the nearest pixel of the row (their window is its window). The block's tile
 (with the clamped border, as ClampedWindow reads it) goes to shared memory once, from the block's first pixel
 clamped to the row: the windows of its pixels, their columns clamped to the row, all lie in it, so padding pixels
 read it too, not the image. */
template <typename T>
__global__ void censusKernel(PtrStepSz<T> left, PtrStepSz<T> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR,
                             int padBefore, int padAfter)
{
    __shared__ T tile[TH * TW];
    const bool isLeft = blockIdx.z == 0;
    const PtrStepSz<T> img = isLeft ? left : right;
    const int x0 = ::min(::max((int)blockIdx.x * BX - padBefore, 0), img.cols - 1);   // the block's first pixel
    const ClampedWindow<T> origin = { img, x0 - RX, (int)blockIdx.y * BY - RY };
    for (int i = threadIdx.y * BX + threadIdx.x; i < TH * TW; i += BX * BY)
    {
        const int ty = i / TW, tx = i - ty * TW;
        tile[i] = origin(tx, ty);
    }
    __syncthreads();
    const int x = blockIdx.x * BX + threadIdx.x - padBefore, y = blockIdx.y * BY + threadIdx.y;
    if (y >= img.rows || x >= img.cols + (isLeft ? 0 : padAfter) || (isLeft && x < 0))
        return;
    const TileWindow<T> at = { tile, ::min(::max(x, 0), img.cols - 1) - x0 + RX, (int)threadIdx.y + RY };
    (isLeft ? censusL : censusR).ptr(y)[x] = (int)censusString(at);
}

template <typename T>
void runCensus(PtrStepSz<T> left, PtrStepSz<T> right, PtrStepSz<int> censusL, PtrStepSz<int> censusR, int padBefore,
               int padAfter, cudaStream_t stream)
{
    const dim3 block(BX, BY);
    const dim3 grid(cv::cudev::divUp(censusL.cols + padBefore + padAfter, block.x),
                    cv::cudev::divUp(censusL.rows, block.y), 2);
    censusKernel<T><<<grid, block, 0, stream>>>(left, right, censusL, censusR, padBefore, padAfter);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
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
