// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visiting the sparse disparities inside a square window around each pixel, CUDA twin of src/sparse_window.hpp.
// A block lists the sparse points of its tile (its pixels plus r on every side) in shared memory once, row by row, so
// each pixel scans the part of that short list in its window's rows instead of its whole (2r + 1)^2 window of mostly
// empty pixels.

#ifndef OPENCV_LIDARSGM_SPARSE_WINDOW_CUH
#define OPENCV_LIDARSGM_SPARSE_WINDOW_CUH

#include "cuda_stages.hpp"
#include "histogram.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! Bytes of shared memory listTilePoints needs for a block of bw x bh pixels and radius r: two ints a tile pixel, the
//! rows' starts and the largest value.
static inline size_t tilePointsBytes(int bw, int bh, int r)
{
    return ((size_t)(bw + 2 * r) * (bh + 2 * r) * 2 + (bh + 2 * r) + 2) * sizeof(int);
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

/** Called by every thread of the block (a whole number of warps), smem of tilePointsBytes. Lists the sparse points of
 the block's tile (its pixels plus r on every side, within the image; coordinates below 32768). A warp takes the
 tile's rows in turn, 32 pixels a load, and writes each row's points to the row's own part of the list (row t from
 2 t width ints on); a scan of the rows' counts gives their starts in the packed list, and the block packs the list in
 place in rounds of one entry a thread (an entry never moves up, so a round's stores never reach a later round's
 loads). No atomics order it: the list is the same on every run. */
__device__ __forceinline__ TilePoints listTilePoints(PtrStepSz<short> sparse16, int r, int* smem)
{
    const int W = sparse16.cols, H = sparse16.rows;
    const int tid = threadIdx.y * blockDim.x + threadIdx.x, lane = tid & 31, warp = tid >> 5;
    const int threads = (int)(blockDim.x * blockDim.y), warps = threads >> 5;
    // The tile within the image.
    const int bx = (int)(blockIdx.x * blockDim.x), by = (int)(blockIdx.y * blockDim.y);
    const int x0 = ::max(bx - r, 0), x1 = ::min(bx + (int)blockDim.x + r, W);
    const int y0 = ::max(by - r, 0), y1 = ::min(by + (int)blockDim.y + r, H);
    const int rows = y1 - y0, width = x1 - x0;
    int* const maxValue = smem;
    int* const rowStart = smem + 1;   // the rows' counts first
    int* const points = smem + ((rows + 2 + 1) & ~1);
    if (tid == 0)
        *maxValue = INT_MIN;
    __syncthreads();
    for (int ty = y0 + warp; ty < y1; ty += warps)
    {
        const short* row = sparse16.ptr(ty);
        int* const out = points + 2 * (ty - y0) * width;
        int n = 0, top = INT_MIN;
        for (int c = x0; c < x1; c += 32)
        {
            const int tx = c + lane;
            const int v = tx < x1 ? row[tx] : NO_DISP;
            const unsigned hits = __ballot_sync(0xFFFFFFFFu, v != NO_DISP);
            if (v != NO_DISP)
            {
                const int at = n + __popc(hits & ((1u << lane) - 1));
                out[2 * at] = (ty << 16) | tx;
                out[2 * at + 1] = v;
                top = ::max(top, v);
            }
            n += __popc(hits);
        }
        if (n > 0)
        {
            top = __reduce_max_sync(0xFFFFFFFFu, top);
            if (lane == 0)
                atomicMax(maxValue, top);
        }
        if (lane == 0)
            rowStart[ty - y0] = n;
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
    const int n = rowStart[rows];
    for (int j0 = 0; j0 < n; j0 += threads)
    {
        const int j = j0 + tid;
        int at = 0, value = 0;
        if (j < n)
        {
            // Entry j's row: the last whose start is at most j.
            int lo = 0, hi = rows - 1;
            while (lo < hi)
            {
                const int mid = (lo + hi + 1) >> 1;
                if (rowStart[mid] <= j)
                    lo = mid;
                else
                    hi = mid - 1;
            }
            const int from = lo * width + j - rowStart[lo];
            at = points[2 * from];
            value = points[2 * from + 1];
        }
        __syncthreads();
        if (j < n)
        {
            points[2 * j] = at;
            points[2 * j + 1] = value;
        }
        __syncthreads();
    }
    const TilePoints t = { points, rowStart, y0, rows, *maxValue };
    return t;
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
