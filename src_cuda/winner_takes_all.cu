// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all, CUDA twin of src/winner_takes_all.simd.hpp. Ties go to the smallest disparity, as on the CPU:
// candidates are compared as keys (cost << 16 | d), the lowest key wins. The right-view disparity is an atomicMin of
// the same keys per right pixel, so its result does not depend on the order the threads run in.

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int WARPS = 8, SEG = 32, BLOCK_PIXELS = WARPS * SEG;   // a warp: 32 pixels of a row; a block: 8 warps in a row
const int CHUNK = 16;   // disparities a lane takes from shared memory at a time
// A pixel's chunk in shared memory: 8 words and 4 of pad, so that eight lanes' 16-byte reads fall on distinct banks.
const int ROW_QUADS = 3;

//! The sentinel key: no candidate.
const unsigned NO_KEY = 0xFFFFFFFFu;

/* One pixel's winner as the minima of its chunks of CHUNK keys arrive in disparity order (one lane, one pixel): the
 lowest key (best) and, for the uniqueness check (UNIQUE), what the runner-up, the lowest key more than one disparity
 away from it, needs (secondKey): the lowest chunk minimum more than one chunk away (second); the minima of the chunks
 just before and after the winner's (before, after), each without its key next to the winner where that is the
 chunk's minimum; and the winner's chunk's minima of its pairs of disparities (pairs). A chunk's minimum comes from its
 pairs' minima, and its minima without its first or last key from the same tree, so the whole rule costs the tree, a
 few selects a chunk and nothing that reads the sums again but two values. */
template <bool UNIQUE> struct ChunkWinner
{
    unsigned best = NO_KEY, second = NO_KEY, below2 = NO_KEY, last = NO_KEY, lastNoEnd = NO_KEY, before = NO_KEY,
             after = NO_KEY, pairs[CHUNK / 2];
    bool lastWon = false;

    /* The next chunk: its pairs' minima pm, its minimum m and its minima without its first key (noFirst) and without
     its last (noEnd). */
    __device__ __forceinline__ void take(const unsigned (&pm)[CHUNK / 2], unsigned m, unsigned noFirst, unsigned noEnd)
    {
        const bool won = m < best;
        if (UNIQUE)
        {
            // A new winning chunk replaces second with the lowest minimum up to two chunks before it (below2). The
            // previous chunk's minimum is next to the winner only at its last disparity, the next chunk's at its first.
            const unsigned d = m & 0xFFFFu;
            before = won ? ((last & 0xFFFFu) + 1 == d ? lastNoEnd : last) : before;
            after = won ? NO_KEY : (lastWon ? ((best & 0xFFFFu) + 1 == d ? noFirst : m) : after);
            const unsigned kept = lastWon ? second : ::min(second, m);
            second = won ? below2 : kept;
            below2 = ::min(below2, last);
#pragma unroll
            for (int j = 0; j < CHUNK / 2; j++)
                pairs[j] = won ? pm[j] : pairs[j];
            lastWon = won;
            last = m;
            lastNoEnd = noEnd;
        }
        best = ::min(best, m);
    }
};

/* The uniqueness check's runner-up of a pixel whose sums over [lo, hi) start at s: the lowest key more than one
 disparity away from the winner bd, from w's minima of the other chunks and, in the winner's chunk, from the pairs that
 hold neither bd - 1, bd nor bd + 1, and the keys of bd - 2 and bd + 2 (whose pairs may hold bd - 1 or bd + 1). */
template <bool UNIQUE>
__device__ __forceinline__ unsigned secondKey(const ChunkWinner<UNIQUE>& w, const ushort* s, int lo)
{
    const int bd = (int)(w.best & 0xFFFFu), o = (bd - lo) % CHUNK;   // the winner's place in its chunk
    unsigned second = ::min(w.second, ::min(w.before, w.after));
#pragma unroll
    for (int j = 0; j < CHUNK / 2; j++)
        second = 2 * j + 2 < o || 2 * j > o + 1 ? ::min(second, w.pairs[j]) : second;
    const ushort* const sb = s + (bd - lo);
    if (o >= 2)
        second = ::min(second, (unsigned)sb[-2] << 16 | (unsigned)(bd - 2));
    if (o + 2 < CHUNK)
        second = ::min(second, (unsigned)sb[2] << 16 | (unsigned)(bd + 2));
    return second;
}

/* Walk the keys of a warp's 32 pixels (lane i: pixel x0 + i) over the window [lo, hi) (a multiple of CHUNK wide),
 their sums at first + i * stride + (d - lo). Each key is also the right view's candidate of the right pixel
 x0 + i - d - minD, whose slot in rkey is slot0 + i - (d - lo): consecutive across the lanes, so that the warp's
 atomicMin of a disparity falls on distinct banks. */
template <bool UNIQUE>
__device__ __forceinline__ ChunkWinner<UNIQUE> walkWindow(const ushort* first, int stride, int lo, int hi, int pixels,
                                                          int lane, uint4* stage, unsigned* rkey, int slot0)
{
    ChunkWinner<UNIQUE> w;
    unsigned* const rk = rkey + slot0 + lane;
    const unsigned invalid = lane < pixels ? 0u : NO_KEY;
    // Chunk c of the window: pixel p's 32 bytes at first + p * stride + c * CHUNK, two 16-byte loads; lane t loads
    // pixel t / 2's half t % 2, and pixel t / 2 + 16's.
    const int p0 = lane >> 1, h = lane & 1;
    // (pixels past the row's end load nothing: the full layout ends with the row)
    const uint4* const g0 = (const uint4*)(first + (size_t)p0 * stride) + h;
    const uint4* const g1 = (const uint4*)(first + (size_t)(p0 + 16) * stride) + h;
    const bool in0 = p0 < pixels, in1 = p0 + 16 < pixels;
    const int chunkQuads = CHUNK / 8, chunks = (hi - lo) / CHUNK;
    const uint4 none = make_uint4(NO_KEY, NO_KEY, NO_KEY, NO_KEY);
    uint4 n0 = in0 ? g0[0] : none, n1 = in1 ? g1[0] : none;
    for (int c = 0; c < chunks; c++)
    {
        stage[p0 * ROW_QUADS + h] = n0;
        stage[(p0 + 16) * ROW_QUADS + h] = n1;
        __syncwarp();
        if (c + 1 < chunks)
        {
            if (in0)
                n0 = g0[(c + 1) * chunkQuads];
            if (in1)
                n1 = g1[(c + 1) * chunkQuads];
        }
        const uint4 a = stage[lane * ROW_QUADS], b = stage[lane * ROW_QUADS + 1];
        __syncwarp();
        const unsigned pair[8] = { a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w };
        const unsigned dc = (unsigned)(lo + c * CHUNK) | invalid;   // disparities dc | 0 .. dc | 15
        const int s0 = c * CHUNK;
        unsigned key[CHUNK], pm[CHUNK / 2];
#pragma unroll
        for (int k = 0; k < CHUNK; k++)
        {
            // (pixels past the row's end have pairs of NO_KEY: their keys are NO_KEY)
            key[k] = __byte_perm(pair[k >> 1], dc | (unsigned)k, k & 1 ? 0x3254 : 0x1054);
            atomicMin(rk - (s0 + k), key[k]);
        }
#pragma unroll
        for (int j = 0; j < CHUNK / 2; j++)
            pm[j] = ::min(key[2 * j], key[2 * j + 1]);
        // The pairs' minima as a tree whose inner part serves the minima without the first or the last key.
        unsigned inner = pm[1];
#pragma unroll
        for (int j = 2; j < CHUNK / 2 - 1; j++)
            inner = ::min(inner, pm[j]);
        const unsigned m = ::min(inner, ::min(pm[0], pm[CHUNK / 2 - 1]));
        const unsigned noFirst = UNIQUE ? ::min(inner, ::min(key[1], pm[CHUNK / 2 - 1])) : NO_KEY;
        const unsigned noEnd = UNIQUE ? ::min(inner, ::min(pm[0], key[CHUNK - 2])) : NO_KEY;
        w.take(pm, m, noFirst, noEnd);
    }
    return w;
}

/* The winners of row y's pixels [X0, X0 + 256), a warp per 32 (x0), over their tile's window (the whole range
 without windows). The right-view candidates of the block's pixels fall on right pixels [X0 - minD - (D - 1),
 X0 + 255 - minD]: they meet in shared memory (rkey, slot 0 the first), then go to the global right-view keys with one
 atomicMin per right pixel and block. With windows the parabola needs both neighbours in the window. */
template <bool UNIQUE>
__global__ void __launch_bounds__(32 * WARPS)
wtaKernel(PtrStepSz<ushort> sum, int W, PipelineParams p, WindowMap windows, PtrStepSz<short> disp16,
          PtrStepSz<short> dispInt, PtrStepSz<int> rightKey, PtrStepSz<short> nonUnique16)
{
    __shared__ uint4 stage[WARPS][SEG * ROW_QUADS];
    __shared__ unsigned rkey[BLOCK_PIXELS + MAX_DISPARITIES];
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    const int y = blockIdx.y, X0 = blockIdx.x * BLOCK_PIXELS, x0 = X0 + warp * SEG;
    const int D = p.numDisparities, minD = p.minDisparity;
    const int keys = BLOCK_PIXELS + D - 1;
    for (int i = threadIdx.x; i < keys; i += blockDim.x)
        rkey[i] = NO_KEY;
    __syncthreads();

    if (x0 < W)
    {
        int lo = 0, hi = D;
        const ushort* first = sum.ptr(y) + (size_t)x0 * D;
        if (windows.tiles.data)
        {
            // The warp's 32 pixels lie in one tile, in one row: their sums follow each other in the compact volume.
            const int ty = y / WINDOW_TILE, tx = x0 / WINDOW_TILE;
            const unsigned wd = (unsigned)windows.tiles(ty, tx);
            lo = (int)(wd & 0xFFFFu);
            hi = (int)(wd >> 16);
            first = (const ushort*)((const unsigned*)sum.data + windowPairOffset(windows.base(tx, ty), x0, y, lo, hi));
        }
        // Slot of the right pixel x0 - lo - minD (lane 0 at disparity lo); slot 0 is X0 - minD - (D - 1).
        const int slot0 = x0 - X0 - lo + D - 1;
        const ChunkWinner<UNIQUE> w =
            walkWindow<UNIQUE>(first, hi - lo, lo, hi, W - x0, lane, stage[warp], rkey, slot0);
        const int x = x0 + lane;
        if (x < W)
        {
            const int bd = (int)(w.best & 0xFFFFu), minv = (int)(w.best >> 16);
            // The pixel's sums, read again once (cached: just read) rather than tracked at every step.
            const ushort* const sums = first + (size_t)lane * (hi - lo);
            const bool valid = !UNIQUE || uniqueWinner(minv, (int)(secondKey(w, sums, lo) >> 16), p.uniqueness1024);
            const bool parabola = (valid || nonUnique16.data) && p.subpixel && bd > lo && bd < hi - 1;
            const ushort* const s = sums + (bd - lo);
            const int d16 = (bd + minD) * 16 + (parabola ? subpixelOffset16(s[-1], minv, s[1]) : 0);
            disp16(y, x) = valid ? (short)d16 : NO_DISP;
            dispInt(y, x) = valid ? (short)(bd + minD) : NO_DISP;
            if (nonUnique16.data)
                nonUnique16(y, x) = valid ? NO_DISP : (short)d16;
        }
    }
    __syncthreads();
    unsigned* rk = (unsigned*)rightKey.ptr(y);
    const int base = X0 - minD - (D - 1);   // right pixel of slot 0
    for (int i = threadIdx.x; i < keys; i += blockDim.x)
    {
        const int xr = base + i;
        const unsigned key = rkey[i];
        if (key != NO_KEY && xr >= 0 && xr < W)
            atomicMin(rk + xr, key);
    }
}

__global__ void rightKeyToDisparity(PtrStepSz<int> rightKey, int minD, PtrStepSz<short> dispRight)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= dispRight.cols || y >= dispRight.rows)
        return;
    dispRight(y, x) = rightKeyDisparity((unsigned)rightKey(y, x), minD);
}

} // namespace

void winnerTakesAll(const WinnerInputs& in, const PipelineParams& p, const WinnerMaps& out, PtrStepSz<int> rightKey,
                    cudaStream_t stream)
{
    CV_CUDEV_SAFE_CALL(cudaMemset2DAsync(rightKey.data, rightKey.step, 0xFF, rightKey.cols * sizeof(int), rightKey.rows,
                                         stream));
    const dim3 grid((in.width + BLOCK_PIXELS - 1) / BLOCK_PIXELS, in.height);
    if (p.uniqueness1024 < 1024)
        wtaKernel<true><<<grid, 32 * WARPS, 0, stream>>>(in.sum, in.width, p, in.windows, out.disp16, out.dispInt,
                                                         rightKey, out.nonUnique16);
    else
        wtaKernel<false><<<grid, 32 * WARPS, 0, stream>>>(in.sum, in.width, p, in.windows, out.disp16, out.dispInt,
                                                          rightKey, out.nonUnique16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    if (!out.dispRight.data)
        return;
    const dim3 block(32, 8);
    const dim3 grid2(cv::cudev::divUp(in.width, block.x), cv::cudev::divUp(in.height, block.y));
    rightKeyToDisparity<<<grid2, block, 0, stream>>>(rightKey, p.minDisparity, out.dispRight);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
