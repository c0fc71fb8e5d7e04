// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Sparse input to the internal 1/16-pixel map, CUDA twin of src/sparse_input.cpp (sparseFromKitti16, sparseFromFloat,
// and the units check's counts); the map's points row by row (SparseRows) for the kernels that list a tile's points.

#include "cuda_stages.hpp"
#include "pixel_rows.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

__device__ __forceinline__ int sparseValue(ushort v, int lo, int hi) { return sparseFromKitti16(v, lo, hi); }
__device__ __forceinline__ int sparseValue(float v, int lo, int hi) { return sparseFromFloat(v, lo, hi); }

//! PixelRows: four pixels a thread, their loads in flight together.
template <typename T>
__global__ void convertSparseKernel(PtrStepSz<T> sparse, int lo, int hi, PtrStepSz<short> out, int* counts)
{
    __shared__ int blockCounts[3];
    const int x = PixelRows::x(), tid = threadIdx.y * PixelRows::BX + threadIdx.x;
    if (tid < 3)
        blockCounts[tid] = 0;
    T v[PixelRows::N];
#pragma unroll
    for (int k = 0; k < PixelRows::N; k++)
    {
        const int y = PixelRows::y(k);
        v[k] = x < out.cols && y < out.rows ? sparse(y, x) : T();
    }
    int c[3] = { 0, 0, 0 };   // measured, kept, beyond
#pragma unroll
    for (int k = 0; k < PixelRows::N; k++)
    {
        const int y = PixelRows::y(k);
        if (x < out.cols && y < out.rows)
        {
            const int d16 = sparseValue(v[k], lo, hi);
            out(y, x) = (short)d16;
            bool measured, kept, beyond;
            countSparseValue(v[k], d16, out.cols, measured, kept, beyond);
            c[0] += measured;
            c[1] += kept;
            c[2] += beyond;
        }
    }
    // The units check's counts (SparseCounts): summed by the warps, then one atomic per block and count.
    if (!counts)
        return;
    __syncthreads();
#pragma unroll
    for (int i = 0; i < 3; i++)
    {
        const int s = __reduce_add_sync(0xFFFFFFFFu, c[i]);
        if (threadIdx.x == 0 && s)
            atomicAdd(blockCounts + i, s);
    }
    __syncthreads();
    if (tid < 3 && blockCounts[tid])
        atomicAdd(counts + tid, blockCounts[tid]);
}

template <typename T>
void runConvert(PtrStepSz<T> sparse, int minDisparity, int numDisparities, PtrStepSz<short> sparse16, int* counts,
                cudaStream_t stream)
{
    convertSparseKernel<T><<<PixelRows::grid(sparse16.cols, sparse16.rows), PixelRows::block(), 0, stream>>>(
        sparse, minDisparity, minDisparity + numDisparities - 1, sparse16, counts);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

void convertSparse(PtrStepSz<ushort> sparse, int minDisparity, int numDisparities, PtrStepSz<short> sparse16,
                   int* counts, cudaStream_t stream)
{
    runConvert(sparse, minDisparity, numDisparities, sparse16, counts, stream);
}

void convertSparse(PtrStepSz<float> sparse, int minDisparity, int numDisparities, PtrStepSz<short> sparse16,
                   int* counts, cudaStream_t stream)
{
    runConvert(sparse, minDisparity, numDisparities, sparse16, counts, stream);
}

/* A warp a row: 32 columns a chunk, four chunks' loads in flight before their ballots; a chunk's count is the points
 before it, each point stored at its rank in the row. */
__global__ void listSparseRowsKernel(PtrStepSz<short> sparse16, SparseRows rows)
{
    const int lane = threadIdx.x, y = blockIdx.x * blockDim.y + threadIdx.y;
    if (y >= sparse16.rows)
        return;   // the whole warp
    const int W = sparse16.cols, chunks = W / 32 + 1;
    const short* const row = sparse16.ptr(y);
    int* const entries = rows.entries.ptr(y);
    int2* const chunk = rows.chunks.ptr(y);
    int n = 0;
    for (int c0 = 0; c0 < chunks; c0 += 4)
    {
        short v[4];
#pragma unroll
        for (int k = 0; k < 4; k++)
        {
            const int x = 32 * (c0 + k) + lane;
            v[k] = x < W ? row[x] : NO_DISP;
        }
#pragma unroll
        for (int k = 0; k < 4 && c0 + k < chunks; k++)
        {
            const unsigned hits = __ballot_sync(0xFFFFFFFFu, v[k] != NO_DISP);
            if (lane == 0)
                chunk[c0 + k] = make_int2(n, (int)hits);
            if (v[k] != NO_DISP)
                entries[n + __popc(hits & ((1u << lane) - 1u))] = (int)((unsigned)v[k] << 16) | (32 * (c0 + k) + lane);
            n += __popc(hits);
        }
    }
}

void listSparseRows(PtrStepSz<short> sparse16, const SparseRows& rows, cudaStream_t stream)
{
    CV_DbgAssert(rows.entries.cols == sparse16.cols && rows.entries.rows == sparse16.rows &&
                 rows.chunks.cols == sparse16.cols / 32 + 1 && sparse16.cols < 32768);
    const dim3 block(32, 8);
    listSparseRowsKernel<<<cv::cudev::divUp(sparse16.rows, block.y), block, 0, stream>>>(sparse16, rows);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
