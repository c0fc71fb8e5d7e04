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

/** Called by every thread of the block (a whole number of warps). Writes (y << 16 | x, value) pairs to points
 (coordinates below 32768) and returns their count. A warp takes the tile's rows in turn, 32 pixels a load, and
 reserves its points of each load with one atomic (most loads find none: sparse maps are sparse). The order depends
 on thread timing: callers must not depend on it. */
__device__ __forceinline__ int listTilePoints(PtrStepSz<short> sparse16, int r, int* points, int* count)
{
    const int W = sparse16.cols, H = sparse16.rows;
    const int tid = threadIdx.y * blockDim.x + threadIdx.x, lane = tid & 31, warp = tid >> 5;
    const int warps = (int)(blockDim.x * blockDim.y) >> 5;
    if (tid == 0)
        *count = 0;
    __syncthreads();
    // The tile (the block's pixels plus r on every side) within the image.
    const int bx = (int)(blockIdx.x * blockDim.x), by = (int)(blockIdx.y * blockDim.y);
    const int x0 = ::max(bx - r, 0), x1 = ::min(bx + (int)blockDim.x + r, W);
    const int y0 = ::max(by - r, 0), y1 = ::min(by + (int)blockDim.y + r, H);
    for (int ty = y0 + warp; ty < y1; ty += warps)
    {
        const short* row = sparse16.ptr(ty);
        for (int c = x0; c < x1; c += 32)
        {
            const int tx = c + lane;
            const int v = tx < x1 ? row[tx] : NO_DISP;
            const unsigned hits = __ballot_sync(0xFFFFFFFFu, v != NO_DISP);
            if (hits == 0)
                continue;
            int k = 0;
            if (lane == 0)
                k = atomicAdd(count, __popc(hits));
            k = __shfl_sync(0xFFFFFFFFu, k, 0) + __popc(hits & ((1u << lane) - 1));
            if (v != NO_DISP)
            {
                points[2 * k] = (ty << 16) | tx;
                points[2 * k + 1] = v;
            }
        }
    }
    __syncthreads();
    return *count;
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
