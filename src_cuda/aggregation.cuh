// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Device helpers of the path kernels (src_cuda/aggregation.cu): the lanes' share of the disparities, the loads of a
// pixel's inputs, the matching cost and the path step on packed 16-bit pairs; and the load of a pixel's cost pairs
// from the sum volume (the winner-takes-all's, src_cuda/winner_takes_all.cu).

#ifndef OPENCV_LIDARSGM_AGGREGATION_CUH
#define OPENCV_LIDARSGM_AGGREGATION_CUH

#include "cuda_stages.hpp"

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

/* The lanes' share of a pixel's disparities. Lane t holds PPT pairs in NG = PPT / G groups of G adjacent pairs: pair
 i = gG + j covers disparities e_i = 2 (32 G g + G t + j) and e_i + 1, and its sum lies at word 32 G g + G t + j of the
 pixel's row of the sum volume. Across the warp the census strings of one pair index then lie 8 G bytes apart: a load
 spans 2 G cache lines (with one run of 2 PPT disparities per lane it spanned 2 PPT). Pairs with e_i < D hold
 disparities (D is even: a pair never straddles it); all groups but the last are whole. */
template <int PPT, int G> struct Lanes
{
    static const int NG = PPT / G;
    int e[PPT];
    int roff[PPT];    //!< the strings of pair i: pR[-roff[i]] and pR[-roff[i] - 1] (pR: rightStrings)
    int lastActive;   //!< the lanes whose last group holds disparities
    bool lastIn, active;
    int lane;

    __device__ __forceinline__ explicit Lanes(int D)
    {
        lane = threadIdx.x & 31;
#pragma unroll
        for (int i = 0; i < PPT; i++)
            e[i] = 2 * (32 * G * (i / G) + G * lane + i % G);
        lastActive = ::min(32, (D - 64 * G * (NG - 1) + 2 * G - 1) / (2 * G));
        lastIn = lane < lastActive;
        active = lastIn || NG > 1;
        // Lanes past D in the last group read group 0's strings, and lanes without any pair lane 0's (within the
        // census padding).
#pragma unroll
        for (int i = 0; i < PPT; i++)
            roff[i] = (i / G < NG - 1 || lastIn ? 64 * G * (i / G) : 0) + 2 * (i % G);
    }

    //! Whether pair i holds disparities (a lane's last group holds all its pairs or none).
    __device__ __forceinline__ bool holds(int i) const { return i / G < NG - 1 || lastIn; }
};

//! What one path step reads at a pixel: the census strings, the prior and the pixel's own sparse value, and the
//! intensities of the pixel and of its predecessors (the edge rule of the jump penalty).
template <int PPT> struct PixelIn
{
    unsigned l, r[2 * PPT];
    int prior, own, intensity;
};

//! The stage inputs of the path kernels, and the loads of one pixel's.
template <typename T> struct PathInputs
{
    PtrStepSz<int> censusL, censusR;
    PtrStepSz<short> prior16, own16;   //!< empty: no prior; no copied-prior weights
    PtrStepSz<T> image;                //!< read only when edges
    CostWeights w, wCopy;
    int minD, D, edgeThreshold;        //!< edgeThreshold INT_MAX where the edge rule is off
    const int* scan;
    bool edges;

    template <int PPT, int G>
    __device__ __forceinline__ void load(const Lanes<PPT, G>& ln, bool copies, int x, int y, PixelIn<PPT>& px) const
    {
        px.l = (unsigned)censusL(y, x);
        // pR: the right pixel of disparity 2 G t (x - minD - 2 G t); lanes without a pair read lane 0's.
        const int* pR = censusR.ptr(y) + x - minD - 2 * G * (ln.active ? ln.lane : 0);
#pragma unroll
        for (int i = 0; i < PPT; i++)
        {
            px.r[2 * i] = (unsigned)pR[-ln.roff[i]];
            px.r[2 * i + 1] = (unsigned)pR[-ln.roff[i] - 1];
        }
        px.prior = prior16.data ? prior16(y, x) : NO_DISP;
        px.own = copies ? own16(y, x) : NO_DISP;
        px.intensity = edges ? (int)image(y, x) : 0;
    }

    //! The intensity at (x, y) where the edge rule is on (x clamped: outside the image nothing reads it).
    __device__ __forceinline__ int intensity(int x, int y) const
    {
        return edges ? (int)image(y, ::max(0, ::min(x, image.cols - 1))) : 0;
    }
};

/* matchingCost (pipeline.hpp) of the lane's pairs: the census term, plus the DDC term, which is one value (0 without
 a prior, Q2 with one) except within one disparity of the prior, in at most two pairs that add it exactly. copies:
 copied priors take wCopy (copiedPrior). */
template <int PPT, int G, typename T>
__device__ __forceinline__ void pairCosts(const PathInputs<T>& in, const Lanes<PPT, G>& ln, bool copies,
                                          const PixelIn<PPT>& px, unsigned (&Cp)[PPT])
{
    const bool hasK = px.prior != NO_DISP;
    // k: the prior's disparity index; without a prior far below every lane's run, so that no lane is near it.
    const int k = hasK ? roundDisp16(px.prior) - in.minD : -1024;
    const CostWeights& wk = copiedPrior(copies, px.prior, px.own) ? in.wCopy : in.w;
    const unsigned ddcFar = hasK ? (unsigned)wk.q2 * 0x10001u : 0u;
    const unsigned c256lo = (unsigned)wk.census256 & 255u, c256hi = (unsigned)wk.census256 >> 8;
    unsigned h[2 * PPT];
#pragma unroll
    for (int j = 0; j < 2 * PPT; j++)
        h[j] = (unsigned)popcount32(px.l ^ px.r[j]);
#pragma unroll
    for (int i = 0; i < PPT; i++)
        Cp[i] = censusTermPair(__byte_perm(h[2 * i], h[2 * i + 1], 0x5410), c256lo, c256hi) + ddcFar;
    bool near = false;
#pragma unroll
    for (int g = 0; g < Lanes<PPT, G>::NG; g++)   // k in [e - 1, e + 2 G], e the group's first
        near |= (unsigned)(k - ln.e[G * g] + 1) <= (unsigned)(2 * G + 1);
    if (near)
    {
#pragma unroll
        for (int i = 0; i < PPT; i++)
            Cp[i] = (unsigned)matchingCost((int)h[2 * i], ln.e[i], k, wk) |
                    ((unsigned)matchingCost((int)h[2 * i + 1], ln.e[i] + 1, k, wk) << 16);
    }
}

/* One step of a path (paper Eq. 2): Pn = C + min(P(d), P(d -+ 1) + P1, minPrev + jump) - minPrev, on pairs: every value
 stays below BIG16 and BIG16 + P1 below 2^16, so plain 32-bit adds and subtractions never carry between the halves (C
 + best - minPrev >= 0 since best >= minPrev), and min.u16x2 takes both minima at once. Neighbours within a lane by
 byte permutes; across lanes by shuffles that rotate the warp, so that lane 0 receives lane 31's pair (the previous
 group's top) and lane 31 lane 0's (the next group's bottom). Pairs past D compute values that no other pair reads. */
template <int PPT, int G>
__device__ __forceinline__ void pathStep(const Lanes<PPT, G>& ln, const unsigned (&P)[PPT], const unsigned (&Cp)[PPT],
                                         int minPrev, int jump, int p1, unsigned (&Pn)[PPT])
{
    const int NG = Lanes<PPT, G>::NG, lane = ln.lane;
    unsigned up[NG], down[NG];
#pragma unroll
    for (int g = 0; g < NG; g++)
    {
        up[g] = __shfl_sync(0xFFFFFFFFu, P[g * G + G - 1], (lane + 31) & 31);
        down[g] = __shfl_sync(0xFFFFFFFFu, P[g * G], (lane + 1) & 31);
    }
    const unsigned jp = (unsigned)(minPrev + jump) * 0x10001u;
    const unsigned p1x2 = (unsigned)p1 * 0x10001u, mp = (unsigned)minPrev * 0x10001u;
#pragma unroll
    for (int i = 0; i < PPT; i++)
    {
        const int g = i / G, j = i % G;
        const unsigned below = lane > 0 ? up[g] : g > 0 ? up[(g + NG - 1) % NG] : BIG16X2;
        const unsigned above = g < NG - 1 ? (lane < 31 ? down[g] : down[(g + 1) % NG])
                                          : (lane + 1 < ln.lastActive ? down[g] : BIG16X2);
        const unsigned lm = __byte_perm(j > 0 ? P[i - 1] : below, P[i], 0x5432);
        const unsigned lp = __byte_perm(P[i], j < G - 1 ? P[i + 1] : above, 0x5432);
        const unsigned best = vmin2(vmin2(P[i], jp), vmin2(lm, lp) + p1x2);
        Pn[i] = Cp[i] + best - mp;
    }
}

//! The lowest path cost over the pairs that hold disparities, across the warp.
template <int PPT, int G>
__device__ __forceinline__ int pathMin(const Lanes<PPT, G>& ln, const unsigned (&P)[PPT])
{
    const int NG = Lanes<PPT, G>::NG;
    unsigned mLast = P[G * (NG - 1)];
#pragma unroll
    for (int j = 1; j < G; j++)
        mLast = vmin2(mLast, P[G * (NG - 1) + j]);
    unsigned m = ln.lastIn ? mLast : BIG16X2;
#pragma unroll
    for (int i = 0; i < G * (NG - 1); i++)
        m = vmin2(m, P[i]);
    return (int)__reduce_min_sync(0xFFFFFFFFu, ::min(m & 0xFFFFu, m >> 16));
}

}}}}} // namespace cv::lidarsgm::detail::cuda_impl::aggregation

#endif
