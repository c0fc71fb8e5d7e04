// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all, CUDA twin of src/winner_takes_all.cpp. One warp per pixel. Ties go to the smallest disparity,
// as on the CPU: candidates are compared as (cost << 16 | d). The right-view disparity is an atomicMin of the same
// keys per right pixel, so its result does not depend on the order the threads run in.

#include "pipeline_cuda.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int PIXELS_PER_BLOCK = 8;

__device__ __forceinline__ unsigned warpMinU(unsigned v)
{
    for (int o = 16; o > 0; o >>= 1)
        v = ::min(v, __shfl_xor_sync(0xFFFFFFFFu, v, o));
    return v;
}

__device__ __forceinline__ int subpixelOffset16(int sm, int s0, int sp)
{
    const int num = 8 * (sm - sp);
    const int den = ::max(sm + sp - 2 * s0, 1);
    return num >= 0 ? (num + den / 2) / den : -((-num + den / 2) / den);
}

__global__ void wtaKernel(PtrStepSz<ushort> sum, int W, PipelineParams p, PtrStepSz<short> disp16,
                          PtrStepSz<short> dispInt, PtrStepSz<int> rightKey)
{
    const int lane = threadIdx.x & 31;
    const int pix = blockIdx.x * PIXELS_PER_BLOCK + (threadIdx.x >> 5);
    const int H = sum.rows, D = p.numDisparities, minD = p.minDisparity;
    if (pix >= W * H)
        return;
    const int y = pix / W, x = pix - y * W;
    const ushort* s = sum.ptr(y) + (size_t)x * D;
    unsigned* rk = (unsigned*)rightKey.ptr(y);

    unsigned best = 0xFFFFFFFFu;
    for (int d = lane; d < D; d += 32)
    {
        const unsigned key = ((unsigned)s[d] << 16) | (unsigned)d;
        best = ::min(best, key);
        const int xr = x - minD - d;
        if (xr >= 0 && xr < W)
            atomicMin(rk + xr, key);
    }
    best = warpMinU(best);
    const int bd = (int)(best & 0xFFFFu), minv = (int)(best >> 16);

    bool valid = true;
    if (p.uniqueness1024 < 1024)
    {
        unsigned second = 0xFFFFFFFFu;
        for (int d = lane; d < D; d += 32)
            if (d < bd - 1 || d > bd + 1)
                second = ::min(second, (unsigned)s[d]);
        second = warpMinU(second);
        valid = second == 0xFFFFFFFFu || minv * 1024 <= p.uniqueness1024 * (int)second;
    }
    if (lane != 0)
        return;
    if (!valid)
    {
        disp16(y, x) = NO_DISP;
        dispInt(y, x) = NO_DISP;
        return;
    }
    int d16 = (bd + minD) * 16;
    if (p.subpixel && bd > 0 && bd < D - 1)
        d16 += subpixelOffset16(s[bd - 1], s[bd], s[bd + 1]);
    disp16(y, x) = (short)d16;
    dispInt(y, x) = (short)(bd + minD);
}

} // namespace

void winnerTakesAll(PtrStepSz<ushort> sum, int width, const PipelineParams& p, PtrStepSz<short> disp16,
                    PtrStepSz<short> dispInt, PtrStepSz<int> rightKey, cudaStream_t stream)
{
    const int pixels = width * sum.rows;
    wtaKernel<<<(pixels + PIXELS_PER_BLOCK - 1) / PIXELS_PER_BLOCK, 32 * PIXELS_PER_BLOCK, 0, stream>>>(
        sum, width, p, disp16, dispInt, rightKey);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
