// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visiting the sparse disparities inside a square window around each pixel, CUDA twin of src/sparse_window.hpp.
// A block lists the sparse points of its tile (its pixels plus r on every side) in shared memory once, so each pixel
// scans that short list instead of its whole (2r + 1)^2 window of mostly empty pixels.

#ifndef OPENCV_LIDARSGM_SPARSE_WINDOW_CUH
#define OPENCV_LIDARSGM_SPARSE_WINDOW_CUH

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! Bytes of shared memory listTilePoints needs for a block of bw x bh pixels and radius r.
static inline size_t tilePointsBytes(int bw, int bh, int r)
{
    return (size_t)(bw + 2 * r) * (bh + 2 * r) * 2 * sizeof(int);
}

/** Dynamic shared memory for a kernel whose blocks call listTilePoints with radius r; raises the kernel's limit where
it needs more than the default 48 KB (rs up to 32: 54 KB; rc up to 64: 174 KB for 32 x 8 blocks). */
template <typename Kernel>
static size_t tileKernelSmem(Kernel kernel, dim3 block, int r)
{
    const size_t smem = tilePointsBytes(block.x, block.y, r);
    if (smem > 48 * 1024)
        CV_CUDEV_SAFE_CALL(cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, (int)smem));
    return smem;
}

/** Called by every thread of the block. Writes (y << 16 | x, value) pairs to points (coordinates below 32768) and
 returns their count. The order depends on thread timing: callers must not depend on it. */
__device__ __forceinline__ int listTilePoints(PtrStepSz<short> sparse16, int r, int* points, int* count)
{
    const int W = sparse16.cols, H = sparse16.rows;
    const int tid = threadIdx.y * blockDim.x + threadIdx.x, nthreads = blockDim.x * blockDim.y;
    if (tid == 0)
        *count = 0;
    __syncthreads();
    const int tx0 = blockIdx.x * blockDim.x - r, ty0 = blockIdx.y * blockDim.y - r;
    const int tw = blockDim.x + 2 * r, th = blockDim.y + 2 * r;
    for (int i = tid; i < tw * th; i += nthreads)
    {
        const int tx = tx0 + i % tw, ty = ty0 + i / tw;
        if (tx < 0 || ty < 0 || tx >= W || ty >= H)
            continue;
        const int v = sparse16(ty, tx);
        if (v != NO_DISP)
        {
            const int k = atomicAdd(count, 1);
            points[2 * k] = (ty << 16) | tx;
            points[2 * k + 1] = v;
        }
    }
    __syncthreads();
    return *count;
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
