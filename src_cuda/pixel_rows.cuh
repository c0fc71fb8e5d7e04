// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The launch shape of the per-pixel kernels that wait on one load a pixel: a thread takes PixelRows::N pixels of its
// column, a block's height apart, and issues their loads together. On a few multiprocessors such a kernel, a pixel a
// thread, runs in waves of blocks each about a load's latency long (KITTI size on 8 SMs: 28 waves of 2048 threads an
// SM); with four pixels a thread, a quarter of the waves. KITTI 000002 on 8 SMs of an H100: the sparse conversion
// 32.7 -> 19.1 us, the ring gap histogram 47.3 -> 24.4 us; the facts kernel, seven loads a pixel, 46.9 -> 52.5 us, so
// it keeps a pixel a thread (doc/design.md).

#ifndef OPENCV_LIDARSGM_PIXEL_ROWS_CUH
#define OPENCV_LIDARSGM_PIXEL_ROWS_CUH

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

/** Blocks of BX x BY threads, each over BX x (BY N) pixels: thread (tx, ty) takes column x() and rows y(0) ..
 y(N - 1), BY apart, so that a warp still reads 32 consecutive pixels of a row. */
struct PixelRows
{
    enum { BX = 32, BY = 8, N = 4 };
    static dim3 block() { return dim3(BX, BY); }
    static dim3 grid(int cols, int rows) { return dim3(cv::cudev::divUp(cols, BX), cv::cudev::divUp(rows, BY * N)); }
    __device__ __forceinline__ static int x() { return (int)(blockIdx.x * BX + threadIdx.x); }
    __device__ __forceinline__ static int y(int k) { return (int)(blockIdx.y * (BY * N) + threadIdx.y + BY * k); }
};

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
