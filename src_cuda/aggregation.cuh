// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The path kernel's device helpers (src_cuda/aggregation.cu): the line geometry, the loads of the right census strings
// and of the sum volume's cost pairs, and the packed 16-bit minimum. Included by aggregation.cu only.

#ifndef OPENCV_LIDARSGM_AGGREGATION_CUH
#define OPENCV_LIDARSGM_AGGREGATION_CUH

#include "opencv2/core/cuda_types.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl { namespace aggregation {

using cv::cuda::PtrStepSz;

const unsigned BIG16 = 0x7FFF;    // stands for "no such disparity": above every path cost, never the minimum
const unsigned BIG16X2 = BIG16 * 0x10001u;

//! Both 16-bit halves' minima (min.u16x2: one instruction from sm_90 on).
__device__ __forceinline__ unsigned vmin2(unsigned a, unsigned b)
{
    return __vminu2(a, b);
}

/* censusTerm (pipeline.hpp) of two Hamming distances at once, h packed as h0 | h1 << 16: with census256 = 256 hi + lo,
 the term is hi h + (lo h + 128) / 256 (256 hi h is a multiple of 256). lo h + 128 < 2^16 (h <= 32), so one multiply
 gives both halves' lo products, whose bytes 1 and 3 are the quotients; hi h + quotient is the term itself, below 2^16
 since every cost is. No carry crosses between the halves. */
__device__ __forceinline__ unsigned censusTermPair(unsigned h, unsigned lo, unsigned hi)
{
    return h * hi + __byte_perm(h * lo + 0x00800080u, 0, 0x4341);
}

/* Line `line` of direction (dx, dy): its first pixel. Horizontal lines are rows, vertical lines columns; diagonal
 lines start on the row the direction enters from (W lines), then on the column it enters from (H - 1 lines). */
__device__ __forceinline__ bool lineStart(int line, int dx, int dy, int W, int H, int& x, int& y)
{
    if (dy == 0)
    {
        if (line >= H) return false;
        y = line; x = dx > 0 ? 0 : W - 1;
    }
    else if (dx == 0)
    {
        if (line >= W) return false;
        x = line; y = dy > 0 ? 0 : H - 1;
    }
    else
    {
        if (line >= W + H - 1) return false;
        if (line < W) { x = line; y = dy > 0 ? 0 : H - 1; }
        else { x = dx > 0 ? 0 : W - 1; y = dy > 0 ? line - W + 1 : H - 1 - (line - W + 1); }
    }
    return true;
}

/* The right census strings of disparities d0 .. d0 + DPT - 1 at a pixel: q[-j], q pointing at the right pixel of d0
 (x - minD - d0). The row has rightCensusPadBefore / After(p) readable columns before / after it holding its end
 pixels' strings (censusTransform), so no index is clamped here: the loads take constant offsets. */
template <int DPT> __device__ __forceinline__ void loadRight(const int* q, unsigned (&r)[DPT])
{
#pragma unroll
    for (int j = 0; j < DPT; j++)
        r[j] = (unsigned)q[-j];
}

//! Asks the line holding p into L2 without waiting for it.
__device__ __forceinline__ void prefetchL2(const void* p)
{
    asm volatile("prefetch.global.L2 [%0];" :: "l"(p));
}

//! The sum volume's pairs of 16-bit costs of disparities d0, d0 + 1, ... at pixel (x, y).
__device__ __forceinline__ unsigned* sumPairs(PtrStepSz<ushort> sum, int x, int y, int D, int d0)
{
    return (unsigned*)(sum.ptr(y) + (size_t)x * D + d0);
}

/* The first n of PPT consecutive pairs. PPT 2 and 4: one vector access, n = PPT (d0 = lane * 2 * PPT and the row
 offset x * D are multiples of 2 * PPT 16-bit values since D is a multiple of 16, so the address is aligned to the
 access size and the lane's run ends at or before D). PPT 1 and 3: one pair at a time (with PPT 3 the last active
 lane's run may pass D: n < PPT). */
template <int PPT> __device__ __forceinline__ void loadPairs(const unsigned* S, int n, unsigned (&v)[PPT])
{
    if (PPT == 4)
    {
        const uint4 a = *(const uint4*)S;
        v[0] = a.x; v[1 % PPT] = a.y; v[2 % PPT] = a.z; v[3 % PPT] = a.w;
    }
    else if (PPT == 2) { const uint2 a = *(const uint2*)S; v[0] = a.x; v[1 % PPT] = a.y; }
    else
    {
#pragma unroll
        for (int i = 0; i < PPT; i++)
            if (i < n)
                v[i] = S[i];
    }
}

template <int PPT> __device__ __forceinline__ void storePairs(unsigned* S, int n, const unsigned (&v)[PPT])
{
    if (PPT == 4) *(uint4*)S = make_uint4(v[0], v[1 % PPT], v[2 % PPT], v[3 % PPT]);
    else if (PPT == 2) *(uint2*)S = make_uint2(v[0], v[1 % PPT]);
    else
    {
#pragma unroll
        for (int i = 0; i < PPT; i++)
            if (i < n)
                S[i] = v[i];
    }
}

/* The path kernel's sums of a lane: NG = PPT / G groups of G adjacent pairs, group g at S[32 G g] (the lane's first
 pair at S). A whole group is one access for G 1, 2 and 4 (aligned: D is a multiple of 16), three for G 3; in the
 last group a lane holds all its pairs or none (pairsLast G or 0). */
template <int G> __device__ __forceinline__ void loadGroup(const unsigned* q, unsigned* v)
{
    if (G == 4) { const uint4 a = *(const uint4*)q; v[0] = a.x; v[1] = a.y; v[2] = a.z; v[3] = a.w; }
    else if (G == 2) { const uint2 a = *(const uint2*)q; v[0] = a.x; v[1] = a.y; }
    else
    {
#pragma unroll
        for (int j = 0; j < G; j++)
            v[j] = q[j];
    }
}

template <int G> __device__ __forceinline__ void storeGroup(unsigned* q, const unsigned* v)
{
    if (G == 4) *(uint4*)q = make_uint4(v[0], v[1], v[2], v[3]);
    else if (G == 2) *(uint2*)q = make_uint2(v[0], v[1]);
    else
    {
#pragma unroll
        for (int j = 0; j < G; j++)
            q[j] = v[j];
    }
}

template <int PPT, int G> __device__ __forceinline__ void loadSums(const unsigned* S, int pairsLast, unsigned (&v)[PPT])
{
#pragma unroll
    for (int g = 0; g < PPT / G; g++)
        if (g < PPT / G - 1 || pairsLast == G)
            loadGroup<G>(S + 32 * G * g, v + G * g);
}

template <int PPT, int G> __device__ __forceinline__ void storeSums(unsigned* S, int pairsLast, const unsigned (&v)[PPT])
{
#pragma unroll
    for (int g = 0; g < PPT / G; g++)
        if (g < PPT / G - 1 || pairsLast == G)
            storeGroup<G>(S + 32 * G * g, v + G * g);
}

}}}}} // namespace cv::lidarsgm::detail::cuda_impl::aggregation

#endif
