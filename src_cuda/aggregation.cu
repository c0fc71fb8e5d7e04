// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.simd.hpp, with the matching cost (src/matching_cost.simd.hpp on
// the CPU) computed as the paths walk. All directions in one launch; one warp walks one path line, its lanes hold the
// path costs of the line's disparities, and neighbours d - 1 / d + 1 across lanes come by shuffles. Every direction
// adds into the one 16-bit sum volume (the only large buffer) with atomics; integer sums: the order does not matter.
// Measured against one launch per direction, and pairs of opposite directions walking each line from both ends, without
// atomics: this is the fastest at every size since the census strings' loads span few cache lines (doc/perf.md, "Tried
// and dropped").

#include "cuda_stages.hpp"
#include "aggregation.cuh"
#include "opencv2/cudev/common.hpp"
#include <algorithm>

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int WARPS_PER_BLOCK = 4;
using namespace aggregation;

/* One warp walks one line of direction blockIdx.y (lineStart), adding its path costs into the zeroed sum volume with
 64-bit (or 32-bit) reductions on packed 16-bit costs: exact, since each 16-bit half stays below 65536 (the weights
 are scaled for that), so no carry crosses into the other half. The left census and prior are warp-uniform loads; the
 right census strings are read through L1 (a horizontal line's row stays there). The loads for the next pixel are
 issued before the current step's recurrence, to hide their latency. The left image is read (warp-uniform) only for
 the edge rule of the jump penalty (jumpPenalty). */
template <int PPT, int G, typename T>
__global__ void pathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                           PtrStepSz<T> image, PipelineParams p, PtrStepSz<short> own16, const int* scan,
                           PtrStepSz<ushort> sum)
{
    // Directions 0..7: (1,0) (-1,0) (0,1) (0,-1) (1,1) (-1,1) (1,-1) (-1,-1); computed, not a table (a table
    // indexed by blockIdx would live in local memory).
    const int dir = (int)blockIdx.y;
    const int dx = dir < 2 ? 1 - 2 * dir : dir < 4 ? 0 : 1 - 2 * (dir & 1);
    const int dy = dir < 2 ? 0 : dir < 4 ? 5 - 2 * dir : dir < 6 ? 1 : -1;
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    const int line = blockIdx.x * WARPS_PER_BLOCK + warp;
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    int x, y;
    if (!lineStart(line, dx, dy, W, H, x, y))
        return;
    // The line's length: steps until it leaves the image.
    const int n = ::min(dx > 0 ? W - x : dx < 0 ? x + 1 : INT_MAX, dy > 0 ? H - y : dy < 0 ? y + 1 : INT_MAX);
    const CostWeights w = p.w, wCopy = p.wCopy;
    // Lane t holds PPT pairs in NG = PPT / G groups of G adjacent pairs: pair i = gG + j covers disparities
    // e_i = 2 (32 G g + G t + j) and e_i + 1. Across the warp the census strings of one pair index then lie 8 G bytes
    // apart: a load spans 2 G cache lines (with one run of 2 PPT disparities per lane it spanned 2 PPT).
    const int NG = PPT / G;
    int e[PPT];
#pragma unroll
    for (int i = 0; i < PPT; i++)
        e[i] = 2 * (32 * G * (i / G) + G * lane + i % G);
    // Pairs with e_i < D hold disparities (D is even: a pair never straddles it); all groups but the last are whole.
    // lastActive: the lanes whose last group holds disparities.
    const int lastActive = ::min(32, (D - 64 * G * (NG - 1) + 2 * G - 1) / (2 * G));
    const bool lastIn = lane < lastActive;
    const bool active = lastIn || NG > 1;   // the lane holds at least one pair

    // Pointers to the current pixel, moved by one step's byte offsets: no row address is computed per step. pR points
    // at the right pixel of disparity 2 G t (x - minD - 2 G t); the strings of pair i lie e_i - 2 G t and one more
    // columns before it. Lanes past D in the last group read group 0's strings, and lanes without any pair lane 0's
    // (within the padding).
    const ptrdiff_t stepL = dy * (ptrdiff_t)censusL.step + dx * (ptrdiff_t)sizeof(int);
    const ptrdiff_t stepR = dy * (ptrdiff_t)censusR.step + dx * (ptrdiff_t)sizeof(int);
    const ptrdiff_t stepP = dy * (ptrdiff_t)prior16.step + dx * (ptrdiff_t)sizeof(short);
    const ptrdiff_t stepO = dy * (ptrdiff_t)own16.step + dx * (ptrdiff_t)sizeof(short);
    const ptrdiff_t stepI = dy * (ptrdiff_t)image.step + dx * (ptrdiff_t)sizeof(T);
    const ptrdiff_t stepS = dy * (ptrdiff_t)sum.step + dx * (ptrdiff_t)D * (ptrdiff_t)sizeof(ushort);
    int roff[PPT];   // the strings of pair i: pR[-roff[i]] and pR[-roff[i] - 1]
#pragma unroll
    for (int i = 0; i < PPT; i++)
        roff[i] = (i / G < NG - 1 || lastIn ? 64 * G * (i / G) : 0) + 2 * (i % G);
    const int* pL = censusL.ptr(y) + x;
    const int* pR = censusR.ptr(y) + x - minD - 2 * G * (active ? lane : 0);
    const bool hasPrior = prior16.data != nullptr, edges = p.edgeThreshold > 0;
    const short* pP = hasPrior ? prior16.ptr(y) + x : nullptr;
    // Copied priors take wCopy where the scan test (run on the device before this kernel) passed.
    const bool copies = own16.data != nullptr && *scan != 0;
    const short* pO = copies ? own16.ptr(y) + x : nullptr;
    const T* pI = edges ? image.ptr(y) + x : nullptr;
    // jumpPenalty's threshold made "never" (not 0) when the edge rule is off: the same penalty, one select a step.
    const int edgeThreshold = edges ? p.edgeThreshold : INT_MAX;
    // The sums of pair i: S[32 G (i / G) + i % G], S at this lane's first pair.
    unsigned* S = (unsigned*)(sum.ptr(y) + (size_t)x * D) + G * lane;
    int left = n;

    // Values of the current pixel, loaded one step ahead.
    unsigned l = (unsigned)*pL;
    int pr = hasPrior ? *pP : NO_DISP;
    int own = copies ? *pO : NO_DISP;
    int intensity = edges ? (int)*pI : 0, prevIntensity = intensity;
    unsigned r[2 * PPT];
#pragma unroll
    for (int i = 0; i < PPT; i++)
    {
        r[2 * i] = (unsigned)pR[-roff[i]];
        r[2 * i + 1] = (unsigned)pR[-roff[i] - 1];
    }

    // The path costs of the lane's disparities, two per register (e_i low, e_i + 1 high): every value stays below
    // BIG16 and BIG16 + P1 below 2^16, so plain 32-bit adds and subtractions never carry between the halves
    // (C + best - minPrev >= 0 since best >= minPrev), and min.u16x2 takes both minima at once. Pairs past D compute
    // values that no other pair reads and that are neither stored nor in the minimum.
    unsigned P[PPT];
    int minPrev = 0;
    const unsigned c256lo = (unsigned)w.census256 & 255u, c256hi = (unsigned)w.census256 >> 8;
    for (int step = 0; ; step++)
    {
        const bool start = step == 0;
        // k: the prior's disparity index; without a prior far below every lane's run, so that no lane is near it.
        const bool hasK = pr != NO_DISP;
        const int k = hasK ? roundDisp16(pr) - minD : -1024;
        // matchingCost (pipeline.hpp) in pairs: the census term, plus the DDC term, which is one value (0 without a
        // prior, Q2 with one) except within one disparity of the prior, in at most two pairs that add it exactly.
        const bool copied = copiedPrior(copies, pr, own);
        const CostWeights wk = copied ? wCopy : w;
        const unsigned ddcFar = hasK ? (unsigned)wk.q2 * 0x10001u : 0u;
        unsigned h[2 * PPT], Cp[PPT];
        bool near = false;
#pragma unroll
        for (int j = 0; j < 2 * PPT; j++)
            h[j] = (unsigned)popcount32(l ^ r[j]);
#pragma unroll
        for (int i = 0; i < PPT; i++)
            Cp[i] = censusTermPair(__byte_perm(h[2 * i], h[2 * i + 1], 0x5410), c256lo, c256hi) + ddcFar;
#pragma unroll
        for (int g = 0; g < NG; g++)
            near |= (unsigned)(k - e[G * g] + 1) <= (unsigned)(2 * G + 1);   // k in [e - 1, e + 2 G], e the group's first
        if (near)
        {
#pragma unroll
            for (int i = 0; i < PPT; i++)
                Cp[i] = (unsigned)matchingCost((int)h[2 * i], e[i], k, wk) |
                        ((unsigned)matchingCost((int)h[2 * i + 1], e[i] + 1, k, wk) << 16);
        }
        const int curIntensity = intensity;
        const bool more = --left > 0;
        if (more)
        {
            pL = (const int*)((const char*)pL + stepL);
            pR = (const int*)((const char*)pR + stepR);
            l = (unsigned)*pL;

            if (hasPrior)
            {
                pP = (const short*)((const char*)pP + stepP);
                pr = *pP;
            }
            if (copies)
            {
                pO = (const short*)((const char*)pO + stepO);
                own = *pO;
            }
            if (edges)
            {
                pI = (const T*)((const char*)pI + stepI);
                intensity = *pI;
            }
#pragma unroll
            for (int i = 0; i < PPT; i++)
            {
                r[2 * i] = (unsigned)pR[-roff[i]];
                r[2 * i + 1] = (unsigned)pR[-roff[i] - 1];
            }
        }
        if (start)
        {
#pragma unroll
            for (int i = 0; i < PPT; i++)
                P[i] = Cp[i];
        }
        else
        {
            // Neighbour pairs (L(d - 1), L(d)) and (L(d + 1), L(d + 2)) by byte permutes; across lanes by shuffles
            // that rotate the warp, so that lane 0 receives lane 31's pair (the previous group's top) and lane 31
            // lane 0's (the next group's bottom).
            unsigned up[NG], down[NG];
#pragma unroll
            for (int g = 0; g < NG; g++)
            {
                up[g] = __shfl_sync(0xFFFFFFFFu, P[g * G + G - 1], (lane + 31) & 31);
                down[g] = __shfl_sync(0xFFFFFFFFu, P[g * G], (lane + 1) & 31);
            }
            const unsigned jump =
                (unsigned)(minPrev + jumpPenalty(curIntensity, prevIntensity, edgeThreshold, w)) * 0x10001u;
            const unsigned p1 = (unsigned)w.p1 * 0x10001u, mp = (unsigned)minPrev * 0x10001u;
            unsigned Pn[PPT];
#pragma unroll
            for (int i = 0; i < PPT; i++)
            {
                const int g = i / G, j = i % G;
                const unsigned below = lane > 0 ? up[g] : g > 0 ? up[(g + NG - 1) % NG] : BIG16X2;
                const unsigned above = g < NG - 1 ? (lane < 31 ? down[g] : down[(g + 1) % NG])
                                                  : (lane + 1 < lastActive ? down[g] : BIG16X2);
                const unsigned lm = __byte_perm(j > 0 ? P[i - 1] : below, P[i], 0x5432);
                const unsigned lp = __byte_perm(P[i], j < G - 1 ? P[i + 1] : above, 0x5432);
                const unsigned best = vmin2(vmin2(P[i], jump), vmin2(lm, lp) + p1);
                Pn[i] = Cp[i] + best - mp;
            }
#pragma unroll
            for (int i = 0; i < PPT; i++)
                P[i] = Pn[i];
        }
        // The minimum over the pairs that hold disparities: a lane's last group holds all its pairs or none (D is a
        // multiple of 16; with G = 2 pairs of 4 disparities).
        unsigned mLast = P[G * (NG - 1)];
#pragma unroll
        for (int j = 1; j < G; j++)
            mLast = vmin2(mLast, P[G * (NG - 1) + j]);
        unsigned mPair = lastIn ? mLast : BIG16X2;
#pragma unroll
        for (int i = 0; i < G * (NG - 1); i++)
            mPair = vmin2(mPair, P[i]);
        minPrev = (int)__reduce_min_sync(0xFFFFFFFFu, ::min(mPair & 0xFFFFu, mPair >> 16));
        if (active)
        {
            // Even G: four 16-bit costs per 64-bit reduction (8-byte aligned), half the atomic operations of 32-bit
            // ones, the same exactness (no carry leaves a 16-bit field).
#pragma unroll
            for (int g = 0; g < NG; g++)
                if (g < NG - 1 || lastIn)
                {
#pragma unroll
                    for (int j = 0; j < G; j += G % 2 == 0 ? 2 : 1)
                    {
                        unsigned* q = S + 32 * G * g + j;
                        if (G % 2 == 0)
                            atomicAdd((unsigned long long*)q, (unsigned long long)P[G * g + j] |
                                                                  ((unsigned long long)P[(G * g + j + 1) % PPT] << 32));
                        else
                            atomicAdd(q, P[G * g + j]);
                    }
                }
        }
        prevIntensity = curIntensity;
        if (!more)
            break;
        S = (unsigned*)((char*)S + stepS);
    }
}

/* PPT = D / 64 rounded up pairs per lane, in groups of G = 2 adjacent pairs where PPT is even (four costs per 64-bit
 reduction; a load of census strings spans four cache lines), else G = 1 (measured: G = 4 at 256 disparities, one
 run of eight per lane, made each load span eight lines and kept L1 busy; doc/perf.md). */
template <int PPT, typename T>
void run(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
         const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    const int W = censusL.cols, H = censusL.rows;
    CV_CUDEV_SAFE_CALL(cudaMemset2DAsync(sum.data, sum.step, 0, sum.cols * sizeof(ushort), sum.rows, stream));
    const int maxLines = p.numPaths == 8 ? W + H - 1 : std::max(W, H);   // diagonals, or rows and columns
    const dim3 grid(cv::cudev::divUp(maxLines, WARPS_PER_BLOCK), p.numPaths);
    pathKernel<PPT, PPT % 2 == 0 ? 2 : 1, T><<<grid, dim3(32 * WARPS_PER_BLOCK), 0, stream>>>(censusL, censusR, prior16,
                                                                                             image, p, own16, scan, sum);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

template <typename T>
void aggregate(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
               const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum,
               cudaStream_t stream)
{
    switch ((p.numDisparities + 63) / 64)
    {
    case 1: run<1>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    case 2: run<2>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    case 3: run<3>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    case 4: run<4>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    case 5: run<5>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    case 6: run<6>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    case 7: run<7>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    default: run<8>(censusL, censusR, prior16, image, p, own16, scan, sum, stream); break;
    }
}

} // namespace

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<uchar> left,
                    const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum,
                    cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, own16, scan, sum, stream);
}

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<ushort> left,
                    const PipelineParams& p, PtrStepSz<short> own16, const int* scan, PtrStepSz<ushort> sum,
                    cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, own16, scan, sum, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
