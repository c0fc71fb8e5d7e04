// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all, CUDA twin of src/winner_takes_all.simd.hpp. Ties go to the smallest disparity, as on the CPU:
// candidates are compared as (cost << 16 | d). The right-view disparity is an atomicMin of the same keys per right
// pixel, so its result does not depend on the order the threads run in.

#include "cuda_stages.hpp"
#include "aggregation.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

using aggregation::loadPairs;

const int WARPS = 8, PIXELS_PER_WARP = 4, SEG = WARPS * PIXELS_PER_WARP;  // a block: 32 pixels of one row
const int MAX_D = MAX_DISPARITIES;

//! Index of right-pixel offset i in the block's key array: one pad word per 32 keeps the lanes' atomics (which
//! step DPT words apart) on distinct banks.
__device__ __forceinline__ int keySlot(int i) { return i + (i >> 5); }

//! 16-bit half h (0 low, 1 high) of pair j of v, j and h lane-varying: picked by masks, not by an indexed array
//! (which the compiler puts in local memory).
template <int PPT> __device__ __forceinline__ unsigned costOf(const unsigned (&v)[PPT], int j, int h)
{
    unsigned t = v[0];
#pragma unroll
    for (int i = 1; i < PPT; i++)
    {
        const unsigned m = 0u - (unsigned)(j == i);
        t = (t & ~m) | (v[i] & m);
    }
    return (t >> (16 * h)) & 0xFFFFu;
}

//! The minimum over the LANES lanes of a pixel (32: the warp's reduction; else a butterfly within the segment).
template <int LANES> __device__ __forceinline__ unsigned pixelMin(unsigned v)
{
    if constexpr (LANES == 32)
        return __reduce_min_sync(0xFFFFFFFFu, v);
    else
    {
#pragma unroll
        for (int o = LANES / 2; o > 0; o >>= 1)
            v = ::min(v, __shfl_xor_sync(0xFFFFFFFFu, v, o));
        return v;
    }
}

/* The winners of a block's pixels over their window [lo, hi) (the whole range without windows), PPT pairs a lane.
 LANES 32: a warp takes its PIXELS_PER_WARP pixels one after the other; LANES 32 / PIXELS_PER_WARP: together, one a
 segment of LANES lanes (more disparities a lane: fewer steps of each reduction, and one pass). Lane t of a pixel holds
 disparities [lo + t DPT, lo + t DPT + DPT), DPT = 2 PPT. Pixel x's sums start at first + (x - x0) stride (at
 disparity lo). Their right-view candidates go to rkey. */
template <int PPT, int LANES>
__device__ __forceinline__ void selectPixels(const ushort* first, int stride, int W, const PipelineParams& p, int lo,
                                             int hi, int x0, int y, int lane, int warp, unsigned* rkey,
                                             PtrStepSz<short>& disp16, PtrStepSz<short>& dispInt,
                                             PtrStepSz<short>& nonUnique16)
{
    static_assert(LANES == 32 || LANES * PIXELS_PER_WARP == 32, "a pixel takes the warp or a segment");
    const int NPIX = LANES == 32 ? PIXELS_PER_WARP : 1;   // pixels a lane takes in turn
    const int seg = LANES == 32 ? 0 : lane / LANES, sub = lane % LANES;
    const int D = p.numDisparities, minD = p.minDisparity;
    const int DPT = 2 * PPT, d0 = lo + sub * DPT;
    // The window's ends are even: pairs never straddle them.
    const int pairs = d0 < hi ? ::min(PPT, (hi - d0) / 2) : 0;
    // Load the costs of all of this lane's pixels first: independent loads in flight instead of one.
    unsigned v[NPIX][PPT];
#pragma unroll
    for (int i = 0; i < NPIX; i++)
    {
        const int x = ::min(x0 + warp + WARPS * (i + seg), W - 1);
#pragma unroll
        for (int j = 0; j < PPT; j++)
            v[i][j] = 0xFFFFFFFFu;
        if (pairs > 0)
            loadPairs<PPT>((const unsigned*)(first + (size_t)(x - x0) * stride + (d0 - lo)), pairs, v[i]);
    }
    struct { int x; bool valid, parabola; int bd, c0, cm, cp; } mine = { -1, false, false, 0, 0, 0, 0 };
#pragma unroll
    for (int i = 0; i < NPIX; i++)
    {
        const int x = x0 + warp + WARPS * (i + seg);
        // A whole warp's pixel past the row's end ends its loop; a segment's pixel there still joins the shuffles.
        if (LANES == 32 && x >= W)
            break;
        const bool inRow = x < W;
        unsigned best = 0xFFFFFFFFu;
        const int k0 = (x - x0) + (D - 1) - d0;   // key offset of disparity d0's right pixel; d0 + k is k before
#pragma unroll
        for (int j = 0; j < PPT; j++)
            if (j < pairs)
            {
                const unsigned lo = (v[i][j] << 16) | (unsigned)(d0 + 2 * j);
                const unsigned hi = (v[i][j] & 0xFFFF0000u) | (unsigned)(d0 + 2 * j + 1);
                best = ::min(best, ::min(lo, hi));
                if (inRow)
                {
                    atomicMin(&rkey[keySlot(k0 - 2 * j)], lo);
                    atomicMin(&rkey[keySlot(k0 - 2 * j - 1)], hi);
                }
            }
        best = pixelMin<LANES>(best);
        const int bd = (int)(best & 0xFFFFu), minv = (int)(best >> 16);
        bool valid = true;
        if (p.uniqueness1024 < 1024)
        {
            // The lowest cost more than one disparity away from bd.
            unsigned second = 0xFFFFFFFFu;
#pragma unroll
            for (int j = 0; j < PPT; j++)
                if (j < pairs)
                {
                    const int d = d0 + 2 * j;
                    if ((unsigned)(d - bd + 1) > 2u)
                        second = ::min(second, v[i][j] & 0xFFFFu);
                    if ((unsigned)(d - bd + 2) > 2u)   // d + 1 outside [bd - 1, bd + 1]
                        second = ::min(second, v[i][j] >> 16);
                }
            second = pixelMin<LANES>(second);
            valid = uniqueWinner(minv, (int)second, p.uniqueness1024);   // windows >= 16 wide: second is a cost
        }
        // The parabola's neighbour costs from the lanes that hold them (uniform across the pixel's lanes: bd and valid
        // are; the shuffles run in every segment, whether its pixel takes them or not); a non-unique winner needs them
        // only for nonUnique16.
        const bool parabola = (valid || nonUnique16.data) && p.subpixel && bd > lo && bd < hi - 1;
        int cm = 0, cp = 0;
        if (LANES < 32 || parabola)
        {
            const int dm = ::max(bd - 1 - lo, 0), dp = ::min(bd + 1 - lo, hi - lo - 1);   // from the window's start
            cm = (int)__shfl_sync(0xFFFFFFFFu, costOf<PPT>(v[i], (dm % DPT) >> 1, dm & 1), dm / DPT, LANES);
            cp = (int)__shfl_sync(0xFFFFFFFFu, costOf<PPT>(v[i], (dp % DPT) >> 1, dp & 1), dp / DPT, LANES);
        }
        // Lane i of the warp (LANES 32), or the segment's first lane, finishes the pixel: one division per lane
        // instead of one per pixel for the whole warp.
        if ((LANES == 32 ? lane == i : sub == 0) && inRow)
            mine = { x, valid, parabola, bd, minv, cm, cp };
    }
    if (mine.x >= 0)
    {
        const int d16 = (mine.bd + minD) * 16 + (mine.parabola ? subpixelOffset16(mine.cm, mine.c0, mine.cp) : 0);
        disp16(y, mine.x) = mine.valid ? (short)d16 : NO_DISP;
        dispInt(y, mine.x) = mine.valid ? (short)(mine.bd + minD) : NO_DISP;
        if (nonUnique16.data)
            nonUnique16(y, mine.x) = mine.valid ? NO_DISP : (short)d16;
    }
}

/* A warp's four pixels one after the other (LANES 32) or together (8 lanes each), a block per 32 consecutive pixels
 of a row. Lane t of a pixel holds disparities [t * DPT, t * DPT + DPT), DPT = 2 * PPT, two 16-bit costs per register
 (one or two vector loads per pixel; with PPT 3, 5, 6 or 7 per pair, and the last active lane's run may pass D). The right-view candidates of those pixels fall on right pixels [x0 - minD - (D - 1),
 x0 + 31 - minD]: they are reduced in shared memory first, then merged into the global right-view keys with one
 atomicMin per right pixel and block. Keys are cost << 16 | d: the lowest is the lowest cost, and the lowest
 disparity among equal costs (winnerTakesAll on the CPU). With disparity windows (windows: per tile lo | hi << 16; a
 block's 32 pixels lie in one tile) only the window's sums are read, compared and offered to the right view, and the
 parabola needs both neighbours in the window (selectPixel). */
template <int PPT, int LANES>
__global__ void wtaKernel(PtrStepSz<ushort> sum, int W, PipelineParams p, WindowMap windows,
                          PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<int> rightKey,
                          PtrStepSz<short> nonUnique16)
{
    __shared__ unsigned rkey[SEG + MAX_D + (SEG + MAX_D) / 32];
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    const int y = blockIdx.y, x0 = blockIdx.x * SEG;
    const int D = p.numDisparities, minD = p.minDisparity;
    const int base = x0 - minD - (D - 1);   // right pixel of key offset 0
    const int keys = SEG + D - 1;
    for (int i = threadIdx.x; i < keys; i += blockDim.x)
        rkey[keySlot(i)] = 0xFFFFFFFFu;
    __syncthreads();

    if (!windows.tiles.data)
    {
        selectPixels<PPT, LANES>(sum.ptr(y) + (size_t)x0 * D, D, W, p, 0, D, x0, y, lane, warp, rkey, disp16,
                                 dispInt, nonUnique16);
    }
    else
    {
        // The block's window (its 32 pixels lie in one tile, in one row: their sums follow each other in the compact
        // volume), with as few pairs a lane as it needs.
        const int ty = y / WINDOW_TILE, tx = x0 / WINDOW_TILE;
        const unsigned w = (unsigned)windows.tiles(ty, tx);
        const int lo = (int)(w & 0xFFFFu), hi = (int)(w >> 16), need = (hi - lo + 2 * LANES - 1) / (2 * LANES);
        const ushort* const first =
            (const ushort*)((const unsigned*)sum.data + windowPairOffset(windows.base(tx, ty), x0, y, lo, hi));
        if (need <= 1)
            selectPixels<1, LANES>(first, hi - lo, W, p, lo, hi, x0, y, lane, warp, rkey, disp16, dispInt,
                                   nonUnique16);
        else if (need <= 2 || PPT <= 2)
            selectPixels<(PPT < 2 ? PPT : 2), LANES>(first, hi - lo, W, p, lo, hi, x0, y, lane, warp, rkey, disp16,
                                                     dispInt, nonUnique16);
        else if (need <= 4 || PPT <= 4)
            selectPixels<(PPT < 4 ? PPT : 4), LANES>(first, hi - lo, W, p, lo, hi, x0, y, lane, warp, rkey, disp16,
                                                     dispInt, nonUnique16);
        else
            selectPixels<PPT, LANES>(first, hi - lo, W, p, lo, hi, x0, y, lane, warp, rkey, disp16, dispInt,
                                     nonUnique16);
    }
    __syncthreads();
    unsigned* rk = (unsigned*)rightKey.ptr(y);
    for (int i = threadIdx.x; i < keys; i += blockDim.x)
    {
        const int xr = base + i;
        const unsigned key = rkey[keySlot(i)];
        if (key != 0xFFFFFFFFu && xr >= 0 && xr < W)
            atomicMin(rk + xr, key);
    }
}

__global__ void rightKeyToDisparity(PtrStepSz<int> rightKey, int minD, PtrStepSz<short> dispRight)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= dispRight.cols || y >= dispRight.rows)
        return;
    const unsigned key = (unsigned)rightKey(y, x);
    dispRight(y, x) = (short)(key == 0xFFFFFFFFu ? NO_DISP : (int)(key & 0xFFFFu) + minD);
}

} // namespace

void winnerTakesAll(const WinnerInputs& in, const PipelineParams& p, const WinnerMaps& out, PtrStepSz<int> rightKey,
                    cudaStream_t stream)
{
    const PtrStepSz<ushort> sum = in.sum;
    const int width = in.width, height = in.height;
    const WindowMap windows = in.windows;
    const PtrStepSz<short> disp16 = out.disp16, dispInt = out.dispInt, dispRight = out.dispRight,
                           nonUnique16 = out.nonUnique16;
    CV_CUDEV_SAFE_CALL(cudaMemset2DAsync(rightKey.data, rightKey.step, 0xFF, rightKey.cols * sizeof(int), rightKey.rows,
                                   stream));
    const dim3 grid((width + SEG - 1) / SEG, height);
    const auto launch = [&](void (*kernel)(PtrStepSz<ushort>, int, PipelineParams, WindowMap, PtrStepSz<short>,
                                           PtrStepSz<short>, PtrStepSz<int>, PtrStepSz<short>)) {
        kernel<<<grid, 32 * WARPS, 0, stream>>>(sum, width, p, windows, disp16, dispInt, rightKey, nonUnique16);
    };
    // Up to 128 disparities a pixel takes 8 lanes (D / 16 pairs each) and a warp its four pixels at once; above, the
    // warp takes them in turn.
    if (p.numDisparities <= 128)
        switch (p.numDisparities / 16)
        {
        case 1: launch(wtaKernel<1, 8>); break;
        case 2: launch(wtaKernel<2, 8>); break;
        case 3: launch(wtaKernel<3, 8>); break;
        case 4: launch(wtaKernel<4, 8>); break;
        case 5: launch(wtaKernel<5, 8>); break;
        case 6: launch(wtaKernel<6, 8>); break;
        case 7: launch(wtaKernel<7, 8>); break;
        default: launch(wtaKernel<8, 8>); break;
        }
    else
        switch ((p.numDisparities + 63) / 64)
        {
        case 3: launch(wtaKernel<3, 32>); break;
        case 4: launch(wtaKernel<4, 32>); break;
        case 5: launch(wtaKernel<5, 32>); break;
        case 6: launch(wtaKernel<6, 32>); break;
        case 7: launch(wtaKernel<7, 32>); break;
        default: launch(wtaKernel<8, 32>); break;
        }
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    const dim3 block(32, 8);
    const dim3 grid2(cv::cudev::divUp(width, block.x), cv::cudev::divUp(height, block.y));
    rightKeyToDisparity<<<grid2, block, 0, stream>>>(rightKey, p.minDisparity, dispRight);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
