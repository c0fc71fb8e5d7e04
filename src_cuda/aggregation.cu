// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.cpp, with the matching cost (src/matching_cost.cpp on the
// CPU) computed as the paths walk. All directions in one launch; one warp walks one path line, its lanes hold the path
// costs of the line's disparities, and neighbours d - 1 / d + 1 across lanes come by shuffles. Every direction adds
// into the one 16-bit sum volume (the only large buffer) with atomics; integer sums: the order does not matter.
// Measured against one launch per direction, and pairs of opposite directions walking each line from both ends,
// without atomics: this is the fastest at every size since the census strings' loads span few cache lines
// (doc/perf.md, "Tried and dropped").

#include "cuda_stages.hpp"
#include "aggregation.cuh"
#include "opencv2/core/cuda/common.hpp"
#include <algorithm>

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int WARPS_PER_BLOCK = 4;
using namespace aggregation;

//! The prior of every pixel when there is none: every fetch reads this cell (a step of 0), so no load is conditional.
__device__ const short noPriorCell = NO_DISP;

/* Direction groups: the lines one warp walks side by side, all on one row at every step. ROWS_BOTH: a row left to
 right and right to left. DOWN / UP: a column top-down (bottom-up) and two diagonals through the same column's pixel
 at the first row, walking right and left; a diagonal that leaves the image at the side re-enters at the other side on
 the next row and starts a new path there (its line of the original layout), so every line of a group is the height
 long. DOWN_COLUMN / UP_COLUMN: the column alone (4 paths). */
enum Group { ROWS_BOTH = 0, DOWN = 1, UP = 2, DOWN_COLUMN = 3, UP_COLUMN = 4 };

/* One warp walks the lines of group blockIdx.y + group0 through slot blockIdx.x * WARPS_PER_BLOCK + warp (the row, or
 the first row's column), adding their path costs into the zeroed sum volume with 64-bit (or 32-bit) reductions on
 packed 16-bit costs: exact, since each 16-bit half stays below 65536 (the weights are scaled for that), so no carry
 crosses into the other half. The lines of a group share nothing but the row: independent recurrences the scheduler
 interleaves, and the same row's sums, touched by the group's lines within a few steps of each other, so the
 reductions of a group meet in L2 instead of each reading the volume from memory. The loads of the next pixels are
 issued before the current step's recurrence, to hide their latency. */
template <int PPT, int G, int NL, typename T>
__global__ void pathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                           PtrStepSz<T> image, PipelineParams p, PtrStepSz<ushort> sum, int group0)
{
    const int group = group0 + (int)blockIdx.y;
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    const int slot = blockIdx.x * WARPS_PER_BLOCK + warp;
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    const bool rows = group == ROWS_BOTH;
    if (slot >= (rows ? H : W))
        return;
    const int nl = rows ? 2 : group == DOWN || group == UP ? 3 : 1;   // lines this warp walks (<= NL)
    const int n = rows ? W : H;                                       // steps
    const int dy = rows ? 0 : group == DOWN || group == DOWN_COLUMN ? 1 : -1;
    const int y0 = rows ? slot : dy > 0 ? 0 : H - 1;
    int dx[NL], x[NL];
#pragma unroll
    for (int k = 0; k < NL; k++)
    {
        dx[k] = rows ? 1 - 2 * k : k == 0 ? 0 : k == 1 ? 1 : -1;
        x[k] = rows ? (k == 0 ? 0 : W - 1) : slot;
    }
    const CostWeights w = p.w;
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
    // The strings of pair i at a pixel x: the right row's column x - minD - 2 G t - roff[i] and one more before it.
    // Lanes past D in the last group read group 0's strings, and lanes without any pair lane 0's (within the padding).
    int roff[PPT];
#pragma unroll
    for (int i = 0; i < PPT; i++)
        roff[i] = (i / G < NG - 1 || lastIn ? 64 * G * (i / G) : 0) + 2 * (i % G) + minD + 2 * G * (active ? lane : 0);

    // Row pointers, moved by one row's bytes per step (the group's lines are always on one row).
    const bool hasPrior = prior16.data != nullptr;
    const char* rowL = (const char*)censusL.ptr(y0);
    const char* rowR = (const char*)censusR.ptr(y0);
    const char* rowP = hasPrior ? (const char*)prior16.ptr(y0) : (const char*)&noPriorCell;
    const char* rowI = (const char*)image.ptr(y0);
    char* rowS = (char*)sum.ptr(y0);
    const ptrdiff_t stepL = dy * (ptrdiff_t)censusL.step, stepR = dy * (ptrdiff_t)censusR.step;
    const ptrdiff_t stepP = hasPrior ? dy * (ptrdiff_t)prior16.step : 0, stepI = dy * (ptrdiff_t)image.step;
    const ptrdiff_t stepS = dy * (ptrdiff_t)sum.step;
    const int priorCols = hasPrior ? 1 : 0;   // the prior's column factor (0: the one NO_DISP cell)
    const bool edges = p.edgeThreshold > 0;
    // jumpPenalty's threshold made "never" (not 0) when the edge rule is off: the same penalty, one select a step.
    const int edgeThreshold = edges ? p.edgeThreshold : INT_MAX;

    // Values of each line's current pixel, loaded one step ahead; every load is unconditional (the last step reloads
    // its own pixel): a load under a condition became a register move at the loop's end that waited for it.
    unsigned l[NL], r[NL][2 * PPT];
    int pr[NL], intensity[NL], prevIntensity[NL];
    bool restart[NL];   // this pixel starts a path (a diagonal re-entering at the other side)
    auto load = [&](int k) {
        const int xk = x[k];
        l[k] = (unsigned)((const int*)rowL)[xk];
        pr[k] = ((const short*)rowP)[xk * priorCols];
        intensity[k] = (int)((const T*)rowI)[xk];
        const int* pR = (const int*)rowR + xk;
#pragma unroll
        for (int i = 0; i < PPT; i++)
        {
            r[k][2 * i] = (unsigned)pR[-roff[i]];
            r[k][2 * i + 1] = (unsigned)pR[-roff[i] - 1];
        }
    };
#pragma unroll
    for (int k = 0; k < NL; k++)
        if (k < nl)
        {
            load(k);
            prevIntensity[k] = intensity[k];
            restart[k] = true;
        }

    // The path costs of the lane's disparities, two per register (e_i low, e_i + 1 high): every value stays below
    // BIG16 and BIG16 + P1 below 2^16, so plain 32-bit adds and subtractions never carry between the halves
    // (C + best - minPrev >= 0 since best >= minPrev), and min.u16x2 takes both minima at once. Pairs past D compute
    // values that no other pair reads and that are neither stored nor in the minimum.
    unsigned P[NL][PPT];
    int minPrev[NL];
    const unsigned q2Pair = (unsigned)w.q2 * 0x10001u;
    const unsigned c256lo = (unsigned)w.census256 & 255u, c256hi = (unsigned)w.census256 >> 8;
    const unsigned p1 = (unsigned)w.p1 * 0x10001u;
    for (int left = n; left > 0; left--)
    {
        // matchingCost (pipeline.hpp) in pairs: the census term, plus the DDC term, which is one value (0 without a
        // prior, Q2 with one) except within one disparity of the prior, in at most two pairs that add it exactly.
        unsigned Cp[NL][PPT];
        int k_[NL], cur[NL], xs[NL];
        bool start[NL];
#pragma unroll
        for (int k = 0; k < NL; k++)
            if (k < nl)
            {
                // k_: the prior's disparity index; without a prior far below every lane's run, so that no lane is near.
                const bool hasK = pr[k] != NO_DISP;
                k_[k] = hasK ? roundDisp16(pr[k]) - minD : -1024;
                unsigned h[2 * PPT];
#pragma unroll
                for (int j = 0; j < 2 * PPT; j++)
                    h[j] = (unsigned)popcount32(l[k] ^ r[k][j]);
                const unsigned ddcFar = hasK ? q2Pair : 0u;
                bool near = false;
#pragma unroll
                for (int i = 0; i < PPT; i++)
                    Cp[k][i] = censusTermPair(__byte_perm(h[2 * i], h[2 * i + 1], 0x5410), c256lo, c256hi) + ddcFar;
#pragma unroll
                for (int g = 0; g < NG; g++)
                    near |= (unsigned)(k_[k] - e[G * g] + 1) <= (unsigned)(2 * G + 1);   // k in [e - 1, e + 2 G]
                if (near)
                {
#pragma unroll
                    for (int i = 0; i < PPT; i++)
                        Cp[k][i] = (unsigned)matchingCost((int)h[2 * i], e[i], k_[k], w) |
                                   ((unsigned)matchingCost((int)h[2 * i + 1], e[i] + 1, k_[k], w) << 16);
                }
                cur[k] = intensity[k];
                start[k] = restart[k];
                xs[k] = x[k];
            }
        // The next pixels: the row moves for columns and diagonals; a diagonal leaving at a side re-enters at the
        // other and restarts. On the last step nothing moves (the loads read the same pixels again).
        const char* rowSnow = rowS;
        if (left > 1)
        {
            rowL += stepL; rowR += stepR; rowP += stepP; rowI += stepI; rowS += stepS;
#pragma unroll
            for (int k = 0; k < NL; k++)
                if (k < nl)
                {
                    int xn = x[k] + dx[k];
                    restart[k] = xn < 0 || xn >= W;
                    x[k] = xn < 0 ? W - 1 : xn >= W ? 0 : xn;
                }
        }
#pragma unroll
        for (int k = 0; k < NL; k++)
            if (k < nl)
                load(k);
#pragma unroll
        for (int k = 0; k < NL; k++)
            if (k < nl)
            {
                if (start[k])
                {
#pragma unroll
                    for (int i = 0; i < PPT; i++)
                        P[k][i] = Cp[k][i];
                }
                else
                {
                    // Neighbour pairs (L(d - 1), L(d)) and (L(d + 1), L(d + 2)) by byte permutes; across lanes by
                    // shuffles that rotate the warp, so that lane 0 receives lane 31's pair (the previous group's
                    // top) and lane 31 lane 0's (the next group's bottom).
                    unsigned up[NG], down[NG];
#pragma unroll
                    for (int g = 0; g < NG; g++)
                    {
                        up[g] = __shfl_sync(0xFFFFFFFFu, P[k][g * G + G - 1], (lane + 31) & 31);
                        down[g] = __shfl_sync(0xFFFFFFFFu, P[k][g * G], (lane + 1) & 31);
                    }
                    const unsigned jump = (unsigned)(minPrev[k] + jumpPenalty(cur[k], prevIntensity[k],
                                                                             edgeThreshold, w)) * 0x10001u;
                    const unsigned mp = (unsigned)minPrev[k] * 0x10001u;
                    unsigned Pn[PPT];
#pragma unroll
                    for (int i = 0; i < PPT; i++)
                    {
                        const int g = i / G, j = i % G;
                        const unsigned below = lane > 0 ? up[g] : g > 0 ? up[(g + NG - 1) % NG] : BIG16X2;
                        const unsigned above = g < NG - 1 ? (lane < 31 ? down[g] : down[(g + 1) % NG])
                                                          : (lane + 1 < lastActive ? down[g] : BIG16X2);
                        const unsigned lm = __byte_perm(j > 0 ? P[k][i - 1] : below, P[k][i], 0x5432);
                        const unsigned lp = __byte_perm(P[k][i], j < G - 1 ? P[k][i + 1] : above, 0x5432);
                        const unsigned best = vmin2(vmin2(P[k][i], jump), vmin2(lm, lp) + p1);
                        Pn[i] = Cp[k][i] + best - mp;
                    }
#pragma unroll
                    for (int i = 0; i < PPT; i++)
                        P[k][i] = Pn[i];
                }
                prevIntensity[k] = cur[k];
                // The minimum over the pairs that hold disparities: a lane's last group holds all its pairs or none
                // (D is a multiple of 16; with G = 2 pairs of 4 disparities).
                unsigned mLast = P[k][G * (NG - 1)];
#pragma unroll
                for (int j = 1; j < G; j++)
                    mLast = vmin2(mLast, P[k][G * (NG - 1) + j]);
                unsigned mPair = lastIn ? mLast : BIG16X2;
#pragma unroll
                for (int i = 0; i < G * (NG - 1); i++)
                    mPair = vmin2(mPair, P[k][i]);
                minPrev[k] = (int)__reduce_min_sync(0xFFFFFFFFu, ::min(mPair & 0xFFFFu, mPair >> 16));
                if (active)
                {
                    // The sums of pair i: S[32 G (i / G) + i % G], S at this lane's first pair. Even G: four 16-bit
                    // costs per 64-bit reduction (8-byte aligned), half the atomic operations of 32-bit ones, the
                    // same exactness (no carry leaves a 16-bit field).
                    unsigned* S = (unsigned*)((ushort*)rowSnow + (size_t)xs[k] * D) + G * lane;
#pragma unroll
                    for (int g = 0; g < NG; g++)
                        if (g < NG - 1 || lastIn)
                        {
#pragma unroll
                            for (int j = 0; j < G; j += G % 2 == 0 ? 2 : 1)
                            {
                                unsigned* q = S + 32 * G * g + j;
                                if (G % 2 == 0)
                                    atomicAdd((unsigned long long*)q,
                                              (unsigned long long)P[k][G * g + j] |
                                                  ((unsigned long long)P[k][(G * g + j + 1) % PPT] << 32));
                                else
                                    atomicAdd(q, P[k][G * g + j]);
                            }
                        }
                }
            }
    }
}

/* PPT = D / 64 rounded up pairs per lane, in groups of G = 2 adjacent pairs where PPT is even (four costs per 64-bit
 reduction; a load of census strings spans four cache lines), else G = 1 (measured: G = 4 at 256 disparities, one
 run of eight per lane, made each load span eight lines and kept L1 busy; doc/perf.md). 8 paths: one launch of the
 row pairs and the DOWN and UP triples (rows first: their lines are the longest); 4 paths: the row pairs and the
 columns alone. */
template <int PPT, typename T>
void run(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
         const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    const int W = censusL.cols, H = censusL.rows;
    cudaSafeCall(cudaMemset2DAsync(sum.data, sum.step, 0, sum.cols * sizeof(ushort), sum.rows, stream));
    const dim3 block(32 * WARPS_PER_BLOCK), grid(cv::cuda::device::divUp(std::max(W, H), WARPS_PER_BLOCK), 3);
    const int G = PPT % 2 == 0 ? 2 : 1;
    if (p.numPaths == 8)
        pathKernel<PPT, G, 3, T><<<grid, block, 0, stream>>>(censusL, censusR, prior16, image, p, sum, ROWS_BOTH);
    else
    {
        pathKernel<PPT, G, 2, T><<<dim3(grid.x, 1), block, 0, stream>>>(censusL, censusR, prior16, image, p, sum,
                                                                       ROWS_BOTH);
        pathKernel<PPT, G, 1, T><<<dim3(grid.x, 2), block, 0, stream>>>(censusL, censusR, prior16, image, p, sum,
                                                                       DOWN_COLUMN);
    }
    cudaSafeCall(cudaGetLastError());
}

template <typename T>
void aggregate(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
               const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    switch ((p.numDisparities + 63) / 64)
    {
    case 1: run<1>(censusL, censusR, prior16, image, p, sum, stream); break;
    case 2: run<2>(censusL, censusR, prior16, image, p, sum, stream); break;
    case 3: run<3>(censusL, censusR, prior16, image, p, sum, stream); break;
    default: run<4>(censusL, censusR, prior16, image, p, sum, stream); break;
    }
}

} // namespace

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<uchar> left,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, sum, stream);
}

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<ushort> left,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, sum, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
