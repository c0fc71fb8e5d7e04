// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all, CUDA twin of src/winner_takes_all.cpp. Ties go to the smallest disparity, as on the CPU:
// candidates are compared as (cost << 16 | d). The right-view disparity is an atomicMin of the same keys per right
// pixel, so its result does not depend on the order the threads run in.

#include "cuda_stages.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int WARPS = 8, PIXELS_PER_WARP = 4, SEG = WARPS * PIXELS_PER_WARP;  // a block: 32 pixels of one row
const int MAX_D = 256;

/* The cost of disparity d (warp-uniform) from the lane that holds it. The register is picked by masks: as a chain of
 conditional assignments the compiler turned the pick into an indexed load from local memory. */
template <int ND> __device__ __forceinline__ int costAt(const unsigned (&v)[ND], int d)
{
    unsigned t = v[0];
#pragma unroll
    for (int j = 1; j < ND; j++)
    {
        const unsigned m = 0u - (unsigned)(d >> 5 == j);   // a mask, not a branch: no indexed (local) array
        t = (t & ~m) | (v[j] & m);
    }
    return (int)__shfl_sync(0xFFFFFFFFu, t, d & 31);
}

/* One warp per pixel, a block per 32 consecutive pixels of a row; lane t holds disparities t, t + 32, ... below D,
 ND = D / 32 rounded up of them (a template argument: no loop over disparities that do not exist). The right-view
 candidates of those pixels fall on right pixels [x0 - minD - (D - 1), x0 + 31 - minD]: they are reduced in shared
 memory first, then merged into the global right-view keys with one atomicMin per right pixel and block. */
template <int ND>
__global__ void wtaKernel(PtrStepSz<ushort> sum, int W, PipelineParams p, PtrStepSz<short> disp16,
                          PtrStepSz<short> dispInt, PtrStepSz<int> rightKey)
{
    __shared__ unsigned rkey[SEG + MAX_D];
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    const int y = blockIdx.y, x0 = blockIdx.x * SEG;
    const int D = p.numDisparities, minD = p.minDisparity;
    const int base = x0 - minD - (D - 1);   // right pixel of rkey[0]
    for (int i = threadIdx.x; i < SEG + D; i += blockDim.x)
        rkey[i] = 0xFFFFFFFFu;
    __syncthreads();

    // Load the costs of all of this warp's pixels first: four independent loads in flight instead of one.
    unsigned v[PIXELS_PER_WARP][ND];
#pragma unroll
    for (int i = 0; i < PIXELS_PER_WARP; i++)
    {
        const int x = x0 + warp + WARPS * i;
        const ushort* s = sum.ptr(y) + (size_t)::min(x, W - 1) * D;
#pragma unroll
        for (int j = 0; j < ND; j++)
        {
            const int d = lane + 32 * j;
            v[i][j] = d < D && x < W ? (unsigned)s[d] : 0xFFFFu;
        }
    }
#pragma unroll
    for (int i = 0; i < PIXELS_PER_WARP; i++)
    {
        const int x = x0 + warp + WARPS * i;
        if (x >= W)
            break;
        unsigned best = 0xFFFFFFFFu;
#pragma unroll
        for (int j = 0; j < ND; j++)
        {
            const int d = lane + 32 * j;
            if (d < D)
            {
                const unsigned key = (v[i][j] << 16) | (unsigned)d;
                best = ::min(best, key);
                const int xr = x - minD - d;
                if (xr >= 0 && xr < W)
                    atomicMin(&rkey[xr - base], key);
            }
        }
        best = __reduce_min_sync(0xFFFFFFFFu, best);
        const int bd = (int)(best & 0xFFFFu), minv = (int)(best >> 16);
        bool valid = true;
        if (p.uniqueness1024 < 1024)
        {
            unsigned second = 0xFFFFFFFFu;
#pragma unroll
            for (int j = 0; j < ND; j++)
            {
                const int d = lane + 32 * j;
                if (d < D && (d < bd - 1 || d > bd + 1))
                    second = ::min(second, v[i][j]);
            }
            second = __reduce_min_sync(0xFFFFFFFFu, second);
            valid = second == 0xFFFFFFFFu || minv * 1024 <= p.uniqueness1024 * (int)second;
        }
        // The parabola's three costs from the lanes that hold them (warp-uniform: bd and valid are).
        int d16 = (bd + minD) * 16;
        if (valid && p.subpixel && bd > 0 && bd < D - 1)
            d16 += subpixelOffset16(costAt<ND>(v[i], bd - 1), costAt<ND>(v[i], bd), costAt<ND>(v[i], bd + 1));
        if (lane == 0)
        {
            disp16(y, x) = valid ? (short)d16 : NO_DISP;
            dispInt(y, x) = valid ? (short)(bd + minD) : NO_DISP;
        }
    }
    __syncthreads();
    unsigned* rk = (unsigned*)rightKey.ptr(y);
    for (int i = threadIdx.x; i < SEG + D; i += blockDim.x)
        if (rkey[i] != 0xFFFFFFFFu)
            atomicMin(rk + base + i, rkey[i]);
}

//! The right view's keys to disparities (the key's low half is the disparity index).
__global__ void rightKeyToDisparity(PtrStepSz<int> rightKey, int minD, PtrStepSz<short> dispRight)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= dispRight.cols || y >= dispRight.rows)
        return;
    const unsigned key = (unsigned)rightKey(y, x);
    dispRight(y, x) = (short)(key == 0xFFFFFFFFu ? NO_DISP : (int)(key & 0xFFFFu) + minD);
}

} // namespace

void winnerTakesAll(PtrStepSz<ushort> sum, int width, const PipelineParams& p, PtrStepSz<short> disp16,
                    PtrStepSz<short> dispInt, PtrStepSz<int> rightKey, PtrStepSz<short> dispRight,
                    cudaStream_t stream)
{
    cudaSafeCall(cudaMemset2DAsync(rightKey.data, rightKey.step, 0xFF, rightKey.cols * sizeof(int), rightKey.rows,
                                   stream));
    const dim3 grid((width + SEG - 1) / SEG, sum.rows);
    switch ((p.numDisparities + 31) / 32)
    {
    case 1: wtaKernel<1><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    case 2: wtaKernel<2><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    case 3: wtaKernel<3><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    case 4: wtaKernel<4><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    case 5: wtaKernel<5><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    case 6: wtaKernel<6><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    case 7: wtaKernel<7><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    default: wtaKernel<8><<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, disp16, dispInt, rightKey); break;
    }
    cudaSafeCall(cudaGetLastError());
    const dim3 block(32, 8);
    const dim3 grid2(cv::cuda::device::divUp(width, block.x), cv::cuda::device::divUp(sum.rows, block.y));
    rightKeyToDisparity<<<grid2, block, 0, stream>>>(rightKey, p.minDisparity, dispRight);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
