// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visiting the sparse disparities inside a square window around each pixel, CUDA twin of src/sparse_window.hpp.
// A block lists the sparse points of its tile (its pixels plus r on every side) in shared memory once, row by row, so
// each pixel scans the part of that short list in its window's rows instead of its whole (2r + 1)^2 window of mostly
// empty pixels. The list comes from the map's points row by row (listSparseRows), made once for every block.

#ifndef OPENCV_LIDARSGM_SPARSE_WINDOW_CUH
#define OPENCV_LIDARSGM_SPARSE_WINDOW_CUH

#include "cuda_stages.hpp"
#include "histogram.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! Bytes of shared memory listTilePoints needs for a block of bw x bh pixels and radius r: two ints a tile pixel, two
//! a tile row, the largest value.
static inline size_t tilePointsBytes(int bw, int bh, int r)
{
    return ((size_t)(bw + 2 * r) * (bh + 2 * r) * 2 + 2 * (bh + 2 * r) + 2) * sizeof(int);
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

/** A block's tile of sparse points in shared memory (listTilePoints): points[2 k] = y << 16 | x, points[2 k + 1] =
 value, row by row and left to right within a row, so that the points of a band of rows are one range. */
struct TilePoints
{
    const int* points;
    const int* rowStart;   // rows + 1: image row y0 + t holds [rowStart[t], rowStart[t + 1])
    int y0, rows;
    int maxValue;          // the largest value (INT_MIN: no point)

    //! The range of the points in image rows [ya, yb] (clipped to the tile).
    __device__ __forceinline__ int begin(int ya) const { return rowStart[::min(::max(ya - y0, 0), rows)]; }
    __device__ __forceinline__ int end(int yb) const { return rowStart[::min(::max(yb - y0 + 1, 0), rows)]; }
};

//! The points of row y of `rows` left of column x (0 <= x <= the map's width).
__device__ __forceinline__ int pointsBefore(const SparseRows& rows, int y, int x)
{
    const int2 c = rows.chunks(y, x >> 5);
    return c.x + __popc((unsigned)c.y & ((1u << (x & 31)) - 1u));
}

/** Called by every thread of the block (a whole number of warps), smem of tilePointsBytes. Lists the sparse points of
 the block's tile (its pixels plus r on every side, within the image; coordinates below 32768) from the map's rows
 (listSparseRows): a tile row's points are one run of its row's, found from two chunks' counts and bits, so a thread
 a row finds the counts, a scan of them gives each row's start in the list, and a warp a row copies its run there. No
 atomics order it: the list is the same on every run. */
__device__ __forceinline__ TilePoints listTilePoints(const SparseRows& sparse, int r, int* smem)
{
    const int W = sparse.entries.cols, H = sparse.entries.rows;
    const int tid = threadIdx.y * blockDim.x + threadIdx.x, lane = tid & 31, warp = tid >> 5;
    const int threads = (int)(blockDim.x * blockDim.y), warps = threads >> 5;
    // The tile within the image.
    const int bx = (int)(blockIdx.x * blockDim.x), by = (int)(blockIdx.y * blockDim.y);
    const int x0 = ::max(bx - r, 0), x1 = ::min(bx + (int)blockDim.x + r, W);
    const int y0 = ::max(by - r, 0), y1 = ::min(by + (int)blockDim.y + r, H);
    const int rows = y1 - y0;
    int* const maxValue = smem;
    int* const rowStart = smem + 1;          // the rows' counts first
    int* const rowFrom = rowStart + rows + 1;   // a row's first point among its row's
    int* const points = smem + ((2 * rows + 2 + 1) & ~1);
    if (tid == 0)
        *maxValue = INT_MIN;
    for (int t = tid; t < rows; t += threads)
    {
        const int from = pointsBefore(sparse, y0 + t, x0);
        rowFrom[t] = from;
        rowStart[t] = pointsBefore(sparse, y0 + t, x1) - from;
    }
    __syncthreads();
    if (warp == 0)
    {
        // The counts' exclusive scan, 32 rows at a time; rowStart[rows] is the total.
        int carry = 0;
        for (int i0 = 0; i0 <= rows; i0 += 32)
        {
            const int i = i0 + lane, c = i < rows ? rowStart[i] : 0;
            const int v = warpInclusiveSum(c, lane);
            if (i <= rows)
                rowStart[i] = carry + v - c;
            carry += __shfl_sync(0xFFFFFFFFu, v, 31);
        }
    }
    __syncthreads();
    int top = INT_MIN;
    for (int t = warp; t < rows; t += warps)
    {
        const int* const run = sparse.entries.ptr(y0 + t) + rowFrom[t];
        const int start = rowStart[t], n = rowStart[t + 1] - start;
        for (int j = lane; j < n; j += 32)
        {
            const int e = run[j], v = e >> 16;
            points[2 * (start + j)] = (y0 + t) << 16 | (e & 0xFFFF);
            points[2 * (start + j) + 1] = v;
            top = ::max(top, v);
        }
    }
    top = __reduce_max_sync(0xFFFFFFFFu, top);
    if (lane == 0 && top != INT_MIN)
        atomicMax(maxValue, top);
    __syncthreads();
    const TilePoints t = { points, rowStart, y0, rows, *maxValue };
    return t;
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
