// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.simd.hpp, with the matching cost (src/matching_cost.simd.hpp on
// the CPU) computed as the paths walk, or for the packed windows on a few SMs read from where src_cuda/matching_cost.cu
// stored it. All directions in one launch; one warp walks one path line, its lanes hold the
// path costs of the line's disparities, and neighbours d - 1 / d + 1 across lanes come by shuffles. Every direction
// adds into the one 16-bit sum volume (the only large buffer) with atomics; integer sums: the order does not matter.
// Measured against one launch per direction, and pairs of opposite directions walking each line from both ends, without
// atomics: this is the fastest at every size since the census strings' loads span few cache lines (doc/perf.md, "Tried
// and dropped").
//
// A step's work that does not depend on the disparities is kept small: what a pixel contributes besides its census
// string (the prior, its class, the edges of the jump penalty) is packed into 16 bits by factsKernel before the walk;
// the kernel is instantiated for what a call uses (prior, edge rule, last group full), so that no flag is tested per
// step; the DDC term of a lane's pairs is one shared-memory load from a table of the pair terms; addresses are one
// multiply-add from the step number.

#include "cuda_stages.hpp"
#include "aggregation.cuh"
#include "opencv2/cudev/common.hpp"
#include <cuda.h>
#include <algorithm>
#include <utility>
#include <type_traits>

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int WARPS_PER_BLOCK = 4, MAX_BLOCKS_PER_SM = 6;
/* The path lines per multiprocessor from which the packed layout (several lines a warp) is faster than one line a warp:
with four lines a warp a call has a quarter of the warps, too few to hide the step's latency where each multiprocessor
has few lines. Measured on the H200 (doc/perf.md, "a few SMs"), full range: at KITTI size (9,698 lines) packed is
0.86 x on 8 to 32 SMs, 0.95 x on 64 (152 lines a multiprocessor) and 1.28 x on 132 (73); at 1080p with 256
disparities (18,000 lines, two a warp) 0.88 x on 16 and 32, 0.92 x on 64 and 1.04 x on 132 (136). */
const int PACKED_LINES_PER_SM = 150;
/* The same for the packed windows' stored costs (windowCostsStored) against computing them as the walk goes: a load
from the volume on each step's critical path, which needs many warps to hide. H200, KITTI size (9,698 lines),
kitti_best.yml: stored 0.89 x on 16 SMs (606 lines a multiprocessor), 0.91 x on 32 (303), 1.12 x on 64 (152), 1.28 x
on 132 (doc/perf.md). */
const int STORED_COSTS_LINES_PER_SM = 220;

//! Whether a call with disparity windows takes the packed windows' path kernel (PackedWindowWalk).
bool packedWindowsTake(int numDisparities)
{
    return numDisparities > 96 && numDisparities <= 128;
}

//! The path lines of a call, every direction's.
int pathLines(const PipelineParams& p, int W, int H)
{
    int lines = 0;
    for (int dir = 0; dir < p.numPaths; dir++)
    {
        int dx, dy;
        aggregation::pathDirection(dir, dx, dy);
        lines += aggregation::lineCount(dx, dy, W, H);
    }
    return lines;
}

/* Blocks a multiprocessor holds of the packed windows' path kernel: at most 102 registers a thread (96 as nvcc 13.0
 compiles it, with no stack), so that 20 warps hide a step's latency; with the stored costs at most 85 (80), 24
 warps. */
const int PACKED_WINDOW_BLOCKS_PER_SM = 5, STORED_COSTS_BLOCKS_PER_SM = 6;
using namespace aggregation;

/* The facts of each pixel (packFacts). May write over prior16 (same size and memory): each thread reads its pixel's
 prior before it writes. */
template <typename T>
__global__ void factsKernel(PtrStepSz<short> prior16, PtrStepSz<short> own16, const int* scan, PtrStepSz<T> image,
                           int minD, int edgeThreshold, PtrStepSz<ushort> facts)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= facts.cols || y >= facts.rows)
        return;
    int k = 0, cls = 0;
    if (prior16.data)
    {
        const int pr = prior16(y, x);
        if (pr != NO_DISP)
        {
            const bool copied = own16.data && copiedPrior(*scan != 0, pr, own16(y, x));
            k = roundDisp16(pr) - minD;
            cls = copied ? 2 : 1;
        }
    }
    unsigned edges = 0;
    if (edgeThreshold > 0)
    {
        const int ip = image(y, x);
        const int fx[4] = { 1, 0, 1, -1 };
#pragma unroll
        for (int b = 0; b < 4; b++)
        {
            const int qx = x - fx[b], qy = y - (b == 0 ? 0 : 1);
            if (qx >= 0 && qx < image.cols && qy >= 0 && intensityEdge(ip, image(qy, qx), edgeThreshold))
                edges |= 1u << b;
        }
    }
    facts(y, x) = (ushort)packFacts(k, cls, edges);
}

//! a b as a 64-bit product (mul.wide.u32: the compiler otherwise widens one operand early and multiplies in 64 bits).
__device__ __forceinline__ size_t wideMul(unsigned a, unsigned b)
{
    unsigned long long r;
    asm("mul.wide.u32 %0, %1, %2;" : "=l"(r) : "r"(a), "r"(b));
    return (size_t)r;
}

/* LW lanes walk one line (warpLine), 32 / LW lines a warp, adding their path costs into the zeroed sum volume with
 64-bit (or 32-bit) reductions on packed 16-bit costs: exact, since each 16-bit half stays below 65536 (the weights are
 scaled for that), so no carry crosses into the other half. Fewer lanes a line give each lane more disparities, so
 that a step's fixed part (the census and facts loads, the jump penalty, the minimum's exchange) is shared by more of
 them. The left census and the facts are uniform across a line's lanes; the right census strings are read through L1
 (a horizontal line's row stays there). The loads for the next pixel are issued before the current step's recurrence,
 to hide their latency. Instantiated for G pairs per group (see below), FULL: every lane's last group holds
 disparities, DDC: a prior, EDGES: the edge rule of jumpPenalty, WIN: the disparity windows (windows; sum then holds
 the compact volume), where every pixel's costs outside its window are the sentinel BIG16 (the CPU's: windowPathKernel
 computes the window alone) and are not added. */
template <int LW, int PPT, int G, bool FULL, bool DDC, bool EDGES, bool WIN>
__global__ void __launch_bounds__(32 * WARPS_PER_BLOCK)
pathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, PipelineParams p,
           PtrStepSz<ushort> sum, WindowMap windows)
{
    static_assert(LW >= 4 && LW <= 32 && (LW & (LW - 1)) == 0, "a line takes 4, 8, 16 or 32 lanes");
    __shared__ __align__(8) unsigned ddcTable[DDC ? DDC_TABLE_WORDS : 1];
    if (DDC)
        fillDdcTable<G>(ddcTable, p);
    const int lane = threadIdx.x & (LW - 1);   // within the line
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    int dir, dx, dy, x, y, n;
    // Lanes past the direction's last line walk that line again without adding their sums (nLive 0).
    const bool hasLine = warpLine(WARPS_PER_BLOCK * 32 / LW, (int)threadIdx.x / LW, p.numPaths == 8, W, H, dir, dx,
                                  dy, x, y, n, LW < 32);
    if (LW == 32 ? !hasLine : !__any_sync(0xFFFFFFFFu, hasLine))
        return;
    const int nLive = hasLine ? n : 0;
    // Lane t holds PPT pairs in NG = PPT / G groups of G adjacent pairs: pair i = gG + j covers disparities
    // e_i = 2 (LW G g + G t + j) and e_i + 1. Across a line's lanes the census strings of one pair index then lie 8 G
    // bytes apart: a load spans 2 G cache lines a line (with one run of 2 PPT disparities per lane it spanned 2 PPT).
    const int NG = PPT / G;
    // Pairs with e_i < D hold disparities (D is even: a pair never straddles it); all groups but the last are whole.
    // lastActive: the lanes whose last group holds disparities.
    const int lastActive = FULL ? LW : ::min(LW, (D - 2 * LW * G * (NG - 1) + 2 * G - 1) / (2 * G));
    const bool lastIn = FULL || lane < lastActive;
    const bool active = lastIn || NG > 1;   // the lane holds at least one pair

    // Addresses of pixel s of the line (lineAddressing): idx |step| bytes after an origin. The right census origin
    // oR is the right pixel of disparity 2 G t (x - minD - 2 G t, t the lane); the strings of pair i lie e_i - 2 G t
    // and one more columns before it. Lanes past D in the last group read group 0's strings, and lanes without any
    // pair lane 0's (within the padding). The sums of pair i: S[LW G (i / G) + i % G], S at this lane's first pair.
    const LineAddressing ad = lineAddressing(x, y, dx, dy, n, censusL.step, censusR.step, facts.step, sum.step, D);
    int roff[PPT];   // the strings of pair i: pR[-roff[i]] and pR[-roff[i] - 1]
#pragma unroll
    for (int i = 0; i < PPT; i++)
        roff[i] = (i / G < NG - 1 || lastIn ? 2 * LW * G * (i / G) : 0) + 2 * (i % G);
    const char* const oL = (const char*)(censusL.ptr(ad.yo) + ad.xo);
    const char* const oR = (const char*)(censusR.ptr(ad.yo) + ad.xo - minD - 2 * G * (active ? lane : 0));
    const char* const oF = DDC || EDGES ? (const char*)(facts.ptr(ad.yo) + ad.xo) : nullptr;
    char* const oS = (char*)((unsigned*)(sum.ptr(ad.yo) + (size_t)ad.xo * D) + G * lane);
    int idx = ad.idx;   // of the pixel whose values are loaded
    int px = x, py = y;   // its position (WIN)

    const unsigned edgeMask = edgeMaskOf(dir);
    const PairWeights wk = pairWeights(p.w);

    // Values of the current pixel, loaded one step ahead; with windows its tile's window and base.
    unsigned l, f = 0, fPrev = 0, r[2 * PPT], win = 0;
    int winBase = 0;
    auto load = [&]() {
        if (WIN)
        {
            const int tx = (int)((unsigned)px / WINDOW_TILE), ty = (int)((unsigned)py / WINDOW_TILE);
            win = (unsigned)windows.tiles(ty, tx);
            winBase = windows.base(tx, ty);
        }
        l = *(const unsigned*)(oL + wideMul(idx, ad.stepL));
        if (DDC || EDGES)
            f = *(const ushort*)(oF + wideMul(idx, ad.stepF));
        const int* pR = (const int*)(oR + wideMul(idx, ad.stepR));
#pragma unroll
        for (int i = 0; i < PPT; i++)
        {
            r[2 * i] = (unsigned)pR[-roff[i]];
            r[2 * i + 1] = (unsigned)pR[-roff[i] - 1];
        }
    };
    load();

    // The path costs of the lane's disparities, two per register (e_i low, e_i + 1 high): every value stays below
    // BIG16 and BIG16 + P1 below 2^16, so plain 32-bit adds and subtractions never carry between the halves
    // (C + best - minPrev >= 0 since best >= minPrev), and min.u16x2 takes both minima at once. Pairs past D compute
    // values that no other pair reads and that are neither stored nor in the minimum. Zero path costs and minimum
    // before the first pixel make its recurrence give its matching costs (best = 0), as the path's start.
    unsigned P[PPT];
#pragma unroll
    for (int i = 0; i < PPT; i++)
        P[i] = 0;
    unsigned mp2 = 0;   // the previous pixel's minimum, in both halves
    // Pixel s of the line; loadNext: the next pixel's values are loaded (all but the warp's last step). A line shorter
    // than the warp's longest (LW < 32) reloads its last pixel and adds no sums past it.
    auto step = [&](int s, auto loadNext) {
        // matchingCost (pipeline.hpp) in pairs: the census term, and the DDC term of the pair from the table (0
        // without a prior), added with the minimum's subtraction: add[i] = ddc - minPrev.
        unsigned T[PPT], add[PPT];
#pragma unroll
        for (int i = 0; i < PPT; i++)
        {
            T[i] = censusPairTerm(l, r[2 * i], r[2 * i + 1], wk);
            add[i] = 0u - mp2;
        }
        if (DDC)
        {
            const unsigned a = f & ((1u << FACT_PAIR_BITS) - 1);
            const unsigned* row = ddcRow(ddcTable, f);
#pragma unroll
            for (int g = 0; g < NG; g++)
            {
                const unsigned u = ::min(a - (unsigned)(LW * G * g + G * lane), (unsigned)(G + 1));
                if (G == 2)
                {
                    const uint2 v = *(const uint2*)(row + 2 * u);
                    add[2 * g] = v.x - mp2;
                    add[(2 * g + 1) % PPT] = v.y - mp2;
                }
                else
                    add[g] = row[u] - mp2;
            }
        }
        unsigned jump = mp2 + wk.p2x2;
        if (EDGES)
            jump = mp2 + ((f | fPrev << 16) & edgeMask ? wk.p2Edgex2 : wk.p2x2);
        fPrev = f;
        // The sums of this pixel's pairs: with windows pair e / 2 of the compact volume's (windowPairOffset) at
        // S[e / 2 - lo / 2 - G t].
        const int lo = (int)(win & 0xFFFFu), hi = (int)(win >> 16);
        unsigned* const S = WIN ? (unsigned*)sum.data + windowPairOffset(winBase, px, py, lo, hi) + G * lane - (lo >> 1)
                                : (unsigned*)(oS + wideMul(idx, ad.stepS));
        if (decltype(loadNext)::value)
        {
            const bool more = LW == 32 || s + 1 < n;
            idx += more ? ad.dIdx : 0;
            if (WIN && more)
            {
                px += dx;
                py += dy;
            }
            load();
        }

        // Neighbour pairs (L(d - 1), L(d)) and (L(d + 1), L(d + 2)) by byte permutes; across lanes by shuffles that
        // rotate the line's lanes, so that lane 0 receives lane LW - 1's pair (the previous group's top) and lane
        // LW - 1 lane 0's (the next group's bottom).
        unsigned up[NG], down[NG];
#pragma unroll
        for (int g = 0; g < NG; g++)
        {
            up[g] = __shfl_sync(0xFFFFFFFFu, P[g * G + G - 1], (lane + LW - 1) & (LW - 1), LW);
            down[g] = __shfl_sync(0xFFFFFFFFu, P[g * G], (lane + 1) & (LW - 1), LW);
        }
        unsigned Pn[PPT];
#pragma unroll
        for (int i = 0; i < PPT; i++)
        {
            const int g = i / G, j = i % G;
            const unsigned below = lane > 0 ? up[g] : g > 0 ? up[(g + NG - 1) % NG] : BIG16X2;
            const unsigned above = g < NG - 1 ? (lane < LW - 1 ? down[g] : down[(g + 1) % NG])
                                              : (lane + 1 < lastActive ? down[g] : BIG16X2);
            const unsigned lm = __byte_perm(j > 0 ? P[i - 1] : below, P[i], 0x5432);
            const unsigned lp = __byte_perm(P[i], j < G - 1 ? P[i + 1] : above, 0x5432);
            const unsigned best = vmin2(vmin2(P[i], jump), vmin2(lm, lp) + wk.p1x2);
            Pn[i] = T[i] + best + add[i];
        }
        // With windows, the groups in the pixel's window (its ends are multiples of 16, a group's 2 G disparities lie
        // in it or out of it).
        bool inWin[NG];
#pragma unroll
        for (int g = 0; g < NG; g++)
            inWin[g] = !WIN || (unsigned)(2 * (LW * G * g + G * lane) - lo) < (unsigned)(hi - lo);
#pragma unroll
        for (int i = 0; i < PPT; i++)
            P[i] = inWin[i / G] ? Pn[i] : BIG16X2;
        // The minimum over the pairs that hold disparities: a lane's last group holds all its pairs or none (D is a
        // multiple of 16; with G = 2 pairs of 4 disparities). Both halves take it, so that the reduction of the
        // packed words gives it in both halves.
        unsigned mLast = P[G * (NG - 1)];
#pragma unroll
        for (int j = 1; j < G; j++)
            mLast = vmin2(mLast, P[G * (NG - 1) + j]);
        unsigned m = lastIn ? mLast : BIG16X2;
#pragma unroll
        for (int i = 0; i < G * (NG - 1); i++)
            m = vmin2(m, P[i]);
        m = vmin2(m, __byte_perm(m, 0, 0x1032));
        if (LW == 32)
            mp2 = __reduce_min_sync(0xFFFFFFFFu, m);
        else
        {
#pragma unroll
            for (int o = LW / 2; o > 0; o >>= 1)
                m = ::min(m, __shfl_xor_sync(0xFFFFFFFFu, m, o));
            mp2 = m;
        }
        if (active && (LW == 32 || s < nLive))
        {
            // Even G: four 16-bit costs per 64-bit reduction (8-byte aligned), half the atomic operations of 32-bit
            // ones, the same exactness (no carry leaves a 16-bit field).
#pragma unroll
            for (int g = 0; g < NG; g++)
                if ((g < NG - 1 || lastIn) && inWin[g])
                {
#pragma unroll
                    for (int j = 0; j < G; j += G % 2 == 0 ? 2 : 1)
                    {
                        unsigned* q = S + LW * G * g + j;
                        if (G % 2 == 0)
                            atomicAdd((unsigned long long*)q, (unsigned long long)P[G * g + j] |
                                                                  ((unsigned long long)P[(G * g + j + 1) % PPT] << 32));
                        else
                            atomicAdd(q, P[G * g + j]);
                    }
                }
        }
    };
    const int steps = LW == 32 ? n : __reduce_max_sync(0xFFFFFFFFu, n);
#pragma unroll 2
    for (int s = 0; s + 1 < steps; s++)
        step(s, std::true_type());
    step(steps - 1, std::false_type());
}

/* The step after the last pixel in the window tile of pixel s (< n) of the line from (x, y) in direction (dx, dy), n
 pixels long: where the line leaves that tile, or n. */
__device__ __forceinline__ int tileSegmentEnd(int x, int y, int dx, int dy, int n, int s)
{
    const unsigned cx = x + s * dx, cy = y + s * dy;
    int len = n - s;
    if (dx != 0)
        len = ::min(len, (int)(dx > 0 ? WINDOW_TILE - cx % WINDOW_TILE : cx % WINDOW_TILE + 1));
    if (dy != 0)
        len = ::min(len, (int)(dy > 0 ? WINDOW_TILE - cy % WINDOW_TILE : cy % WINDOW_TILE + 1));
    return s + len;
}

/* One warp's walk of one line over the disparity windows (windows: per tile lo | hi << 16), windowPathKernel's body in
 named steps: the lanes cover the pixel's window only. Lane t holds in group c the pair of disparities
 e = lo + 64 c + 2 t and e + 1, so a window of up to 64 disparities takes one group whatever the range. Where the
 window moves along the line, the previous pixel's costs are shuffled to the new layout (moveWindow: a warp-uniform
 branch, at tile boundaries only); a disparity outside the previous window has no path cost there (BIG16: the CPU's
 sentinel), reached through the jump only. The census strings of the next pixel are loaded for its window. Sums:
 64-bit reductions by the even lanes into the compact volume (windowPairOffset), each with its odd neighbour's pair (a
 window's ends are multiples of 16, so both are in it or out of it). NC: the range's groups (D / 64 rounded up). A
 line is walked in segments, one per tile it crosses (run): the window, the next segment's window and the sums' step
 are known when a segment starts, so its steps read no window and compute no address but one add. Each segment has
 code for the groups its window needs (K: 1, 2, 4 or NC), chosen once per segment, so that its steps have no branch
 and compute no group past the window. (Chosen per step instead: 137 warp instructions a step at 1080p / 256 / 4
 paths against 125, ncu.) */
template <int NC, bool DDC, bool EDGES>
struct WindowWalk
{
    const unsigned* ddcTable;
    WindowMap windows;
    unsigned* volume;
    int lane, dir, dx, dy, x, y, n;
    LineAddressing ad;
    const char *oL, *oR, *oF;
    int idx;   // of the pixel whose values are loaded
    unsigned edgeMask;
    PairWeights wk;
    // The loaded pixel's census strings and facts; the previous pixel's facts.
    unsigned l, f, fPrev, r[2 * NC];
    // Path costs as pathKernel's, in the window's layout; positions past the window hold BIG16. mp2: the previous
    // pixel's minimum, in both halves.
    unsigned P[NC], mp2;
    // The current segment [.., end) and its window; winNext: the next segment's (the last segment's own); prevWin:
    // the window of the costs in P.
    int end;
    unsigned win, winNext, prevWin;
    // The pixel's first sum in the compact volume: set where a segment starts, then moved by the segment's step.
    unsigned* sums;
    int sumStep;
    // The edge pairs that the registers do not hold (set where the window moves, for the first step in it).
    unsigned belowEdge, aboveEdge;

    //! The warp's line and its first pixel's values; false past the last line.
    __device__ __forceinline__ bool begin(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts,
                                          int D, int minD, CostWeights w)
    {
        lane = threadIdx.x & 31;
        const int W = censusL.cols, H = censusL.rows;
        // The directions one after the other (in waves, warpLine: 4K 3.5 % slower, KITTI size and 1080p the same).
        if (!warpLine(WARPS_PER_BLOCK, (int)(threadIdx.x >> 5), false, W, H, dir, dx, dy, x, y, n))
            return false;
        // Addresses as pathKernel's (pixel s at idx |step| bytes from an origin); the right census origin is the
        // right pixel of disparity 2 t, moved by the window's lo at each pixel. The sums' addresses follow the compact
        // volume's layout (windowPairOffset).
        ad = lineAddressing(x, y, dx, dy, n, censusL.step, censusR.step, facts.step, 0, D);
        oL = (const char*)(censusL.ptr(ad.yo) + ad.xo);
        oR = (const char*)(censusR.ptr(ad.yo) + ad.xo - minD - 2 * lane);
        oF = DDC || EDGES ? (const char*)(facts.ptr(ad.yo) + ad.xo) : nullptr;
        idx = ad.idx;
        edgeMask = edgeMaskOf(dir);
        wk = pairWeights(w);
        f = fPrev = 0;
        end = segmentEnd(0);
        win = windowAt(0);
        winNext = end < n ? windowAt(end) : win;
        prevWin = win;
        load<NC, true>(win);
        // Zero costs and minimum before the first pixel give its matching costs.
#pragma unroll
        for (int c = 0; c < NC; c++)
            P[c] = 0;
        mp2 = 0;
        sums = volume;
        sumStep = 0;
        belowEdge = aboveEdge = BIG16X2;
        return true;
    }

    // A line crosses the tiles in segments: pixel s lies at (x + s dx, y + s dy), its window is its tile's, and the
    // segment that starts at s ends where the line leaves the tile (segmentEnd). Within a segment the window and the
    // sums' step in the compact volume stay the same.
    __device__ __forceinline__ int tileX(int s) const { return (int)((unsigned)(x + s * dx) / WINDOW_TILE); }
    __device__ __forceinline__ int tileY(int s) const { return (int)((unsigned)(y + s * dy) / WINDOW_TILE); }
    __device__ __forceinline__ unsigned windowAt(int s) const { return (unsigned)windows.tiles(tileY(s), tileX(s)); }
    __device__ __forceinline__ int segmentEnd(int s) const { return tileSegmentEnd(x, y, dx, dy, n, s); }

    /* The values of pixel idx for window w: its first G groups, those the window reaches; REACH: w may reach fewer
     (a group past it is skipped at once, a warp-uniform branch with no shuffle inside). */
    template <int G, bool REACH> __device__ __forceinline__ void load(unsigned w)
    {
        l = *(const unsigned*)(oL + wideMul(idx, ad.stepL));
        if (DDC || EDGES)
            f = *(const ushort*)(oF + wideMul(idx, ad.stepF));
        const int* pR = (const int*)(oR + wideMul(idx, ad.stepR)) - (int)(w & 0xFFFFu);
        const int pairs = (int)((w >> 16) - (w & 0xFFFFu)) >> 1;
#pragma unroll
        for (int c = 0; c < G; c++)
        {
            if (REACH && 32 * c >= pairs)
                break;
            if (32 * c + lane < pairs)
            {
                r[2 * c] = (unsigned)pR[-64 * c];
                r[2 * c + 1] = (unsigned)pR[-64 * c - 1];
            }
        }
    }

    //! Where the window changes: the previous costs to the new layout.
    __device__ __forceinline__ void moveWindow()
    {
        const int lo = (int)(win & 0xFFFFu), pairs = (int)((win >> 16) - (win & 0xFFFFu)) >> 1;
        const int plo = (int)(prevWin & 0xFFFFu);
        const int pPairs = (int)((prevWin >> 16) - (prevWin & 0xFFFFu)) >> 1;
        const int delta = (lo - plo) >> 1;   // pairs, a multiple of 8
        belowEdge = aboveEdge = BIG16X2;
        prevWin = win;
        if (delta == 0)
            return;
        // The old layout's pair at position i (warp-uniform), BIG16 outside the previous window. (The group selected
        // by a mask, not by i >> 5 == k: the compiler folds that into an index of P, which keeps P in local memory.)
        const auto oldPair = [&](int i) {
            unsigned v = 0;
#pragma unroll
            for (int k = 0; k < NC; k++)
                v |= P[k] & (0u - (unsigned)((i >> 5) == k));
            v = __shfl_sync(0xFFFFFFFFu, v, i & 31);
            return i >= 0 && i < pPairs ? v : BIG16X2;
        };
        belowEdge = oldPair(delta - 1);
        aboveEdge = oldPair(pairs + delta);
        // Position i of the new layout is position i + delta of the old one.
        unsigned R[NC];
#pragma unroll
        for (int k = 0; k < NC; k++)
            R[k] = __shfl_sync(0xFFFFFFFFu, P[k], (lane + delta) & 31);
#pragma unroll
        for (int c = 0; c < NC; c++)
        {
            const int s = 32 * c + lane + delta;
            unsigned v = BIG16X2;
#pragma unroll
            for (int k = 0; k < NC; k++)
                if (s >= 32 * k && s < 32 * k + 32)
                    v = R[k];
            P[c] = s < pPairs ? v : BIG16X2;   // s < 0 matched no k: BIG16
        }
    }

    /* One pixel of the line in a segment of K groups: K groups computed, one more shuffled (its lowest pair is the
     neighbour above the window's top); then the next pixel's values are loaded: LAST false, for the segment's window;
     LAST true (the segment's last step, s the next pixel), for the next segment's window, if there is a next pixel. */
    template <int K, bool LAST> __device__ __forceinline__ void step(int s)
    {
        const int KS = K < NC ? K + 1 : NC;
        const int lo = (int)(win & 0xFFFFu), pairs = (int)((win >> 16) - (win & 0xFFFFu)) >> 1;
        // matchingCost in pairs: the census term, and the DDC term from the table (u: the pair's index from the one
        // that holds k - 1, plus one, clamped to 2), added with the minimum's subtraction.
        unsigned T[K], add[K];
        const unsigned a = f & ((1u << FACT_PAIR_BITS) - 1);
        const unsigned* row = ddcRow(ddcTable, f);
#pragma unroll
        for (int c = 0; c < K; c++)
        {
            T[c] = censusPairTerm(l, r[2 * c], r[2 * c + 1], wk);
            add[c] = DDC ? row[::min(a - (unsigned)((lo >> 1) + 32 * c + lane), 2u)] - mp2 : 0u - mp2;
        }
        unsigned jump = mp2 + wk.p2x2;
        if (EDGES)
            jump = mp2 + ((f | fPrev << 16) & edgeMask ? wk.p2Edgex2 : wk.p2x2);
        fPrev = f;
        unsigned* const S = sums;
        sums += sumStep;
        if (!LAST)
        {
            idx += ad.dIdx;
            load<K, false>(win);
        }
        else if (s < n)
        {
            idx += ad.dIdx;
            load<NC, true>(winNext);
        }
        // Neighbours across lanes by rotating shuffles, as pathKernel's; the positions just above the window hold the
        // previous pixel's costs there (or BIG16), which the window's top pair reads.
        unsigned up[KS], down[KS];
#pragma unroll
        for (int c = 0; c < KS; c++)
        {
            up[c] = __shfl_sync(0xFFFFFFFFu, P[c], (lane + 31) & 31);
            down[c] = __shfl_sync(0xFFFFFFFFu, P[c], (lane + 1) & 31);
        }
        unsigned m = BIG16X2;
#pragma unroll
        for (int c = 0; c < K; c++)
        {
            const unsigned below = lane > 0 ? up[c] : c > 0 ? up[c - 1] : belowEdge;
            const unsigned above = lane < 31 ? down[c] : c + 1 < KS ? down[c + 1] : aboveEdge;
            const unsigned lm = __byte_perm(below, P[c], 0x5432);
            const unsigned lp = __byte_perm(P[c], above, 0x5432);
            const unsigned best = vmin2(vmin2(P[c], jump), vmin2(lm, lp) + wk.p1x2);
            const unsigned v = T[c] + best + add[c];
            P[c] = 32 * c + lane < pairs ? v : BIG16X2;
            m = vmin2(m, P[c]);
        }
        // The groups past K lie past the window: no cost there for the next pixel.
#pragma unroll
        for (int c = K; c < NC; c++)
            P[c] = BIG16X2;
        mp2 = __reduce_min_sync(0xFFFFFFFFu, vmin2(m, __byte_perm(m, 0, 0x1032)));
#pragma unroll
        for (int c = 0; c < K; c++)
        {
            const unsigned next = __shfl_down_sync(0xFFFFFFFFu, P[c], 1);
            const int i = 32 * c + lane;
            if ((lane & 1) == 0 && i < pairs)
                atomicAdd((unsigned long long*)(S + i), (unsigned long long)P[c] | (unsigned long long)next << 32);
        }
        belowEdge = aboveEdge = BIG16X2;
    }

    /* The steps of the segment that starts after pixel s, in K groups. All but the last load the next pixel for the
     segment's own window: a loop that tests no flag and reads no other window (steps that chose the window and
     whether to load took 108 SASS instructions a one-group step, with a branch around the loads that put divergence
     checks before every shuffle). The last loads for the next segment's window, or nothing at the line's end. */
    template <int K> __device__ __forceinline__ void run(int& s)
    {
        while (s + 1 < end)
            step<K, false>(++s);
        step<K, true>(++s);
    }

    //! The line, segment by segment: the layout moved, the sums' address set, the segment's steps in K groups.
    __device__ __forceinline__ void walk()
    {
        for (int s = 0; s < n;)
        {
            if (win != prevWin)
                moveWindow();
            const int lo = (int)(win & 0xFFFFu), hi = (int)(win >> 16);
            sums = volume + windowPairOffset(windows.base(tileX(s), tileY(s)), x + s * dx, y + s * dy, lo, hi);
            sumStep = (dy * WINDOW_TILE + dx) * ((hi - lo) >> 1);
            const int groups = (hi - lo + 63) >> 6;
            if (groups <= 1)
                run<1>(s);
            else if (groups <= 2 || NC <= 2)
                run<(NC < 2 ? NC : 2)>(s);
            else if (groups <= 4 || NC <= 4)
                run<(NC < 4 ? NC : 4)>(s);
            else
                run<NC>(s);
            if (s < n)
            {
                win = winNext;
                end = segmentEnd(s);
                winNext = end < n ? windowAt(end) : win;
            }
        }
    }
};

//! The path kernel over the disparity windows: one warp walks one line (WindowWalk).
template <int NC, bool DDC, bool EDGES>
__global__ void __launch_bounds__(32 * WARPS_PER_BLOCK)
windowPathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                 PipelineParams p, unsigned* volume)
{
    __shared__ __align__(8) unsigned ddcTable[DDC ? DDC_TABLE_WORDS : 1];
    if (DDC)
        fillDdcTable<1>(ddcTable, p);   // groups of one pair
    WindowWalk<NC, DDC, EDGES> walk;
    walk.ddcTable = ddcTable;
    walk.windows = windows;
    walk.volume = volume;
    if (walk.begin(censusL, censusR, facts, p.numDisparities, p.minDisparity, p.w))
        walk.walk();
}

/* *a += v where p: a predicated reduction (the compiler puts a branch and a convergence barrier around each atomic in
 an if, and keeps them around this one). */
__device__ __forceinline__ void reduceAddIf(bool p, unsigned* a, unsigned v)
{
    asm volatile("{\n\t.reg .pred q;\n\tsetp.ne.u32 q, %0, 0;\n\t@q red.global.add.u32 [%1], %2;\n\t}"
                 :: "r"((unsigned)p), "l"(a), "r"(v) : "memory");
}

/* *a += v where p for two words at once, v = lo | hi << 32, in one 64-bit reduction (a 8-byte aligned; the 16-bit
 sums never carry). */
__device__ __forceinline__ void reduceAddIf(bool p, unsigned* a, unsigned lo, unsigned hi)
{
    asm volatile("{\n\t.reg .pred q;\n\tsetp.ne.u32 q, %0, 0;\n\t@q red.global.add.u64 [%1], %2;\n\t}"
                 :: "r"((unsigned)p), "l"(a), "l"((unsigned long long)lo | (unsigned long long)hi << 32) : "memory");
}

/* The packed layout over the disparity windows, up to 128 disparities, on any number of SMs (pathKernel's packed
 layout computes every cell of the range and masks it to the windows): LW lanes walk a line, 32 / LW lines a warp,
 whose pixels lie side by side (warpLine), so that they cross the same tiles at the same steps or nearly. The
 warp's layout covers the union of its live lines' windows, [base, base + 16 K): lane t holds in row k the PL = 8 / LW
 pairs of disparities from base + 16 k + 2 PL t on, so that a window's ends (multiples of 16) fall between rows and a
 new base moves whole registers (moveLayout), with no shuffle but the two edge pairs'. Each line keeps the rows of its
 own window (ownRows) and the sentinel BIG16 in the others, as the CPU's window-only recursion leaves them. A segment
 is a run of steps in which no live line changes tile (startSegment): the union, the rows, each line's sums' (and
 costs') address and step are set when it starts, and its steps run code for its K rows (run<K>), which computes no
 row past the union and tests no flag.
 STORED: the matching costs come stored (windowMatchingCosts), in the sums' layout: one load a row instead of two
 census loads, two population counts and the DDC table's load, and every row's reduction runs (zeros outside the
 line's window, within the volume's guards) instead of a branch around each; else they are computed from the census
 strings and the DDC table as the walk goes (DDC: with the prior's term), which needs no load from the volume on a
 step's critical path: the faster where each multiprocessor holds few lines (STORED_COSTS_LINES_PER_SM). */
template <bool DDC, bool EDGES, bool STORED>
struct PackedWindowWalk
{
    /* Lanes a line and pairs a lane in a row (PL = 8 / LW), the range's rows of 16 disparities at most. Stored costs
     (a few SMs): 4 lanes, eight lines a warp, so that a step's fixed part serves twice the lines, a shuffle reaches a
     neighbour for two pairs and one 64-bit load and reduction serve both. */
    enum { LW = STORED ? 4 : 8, PL = 8 / LW, NR = 8 };
    static constexpr bool FACTS = (DDC && !STORED) || EDGES;   // whether a step reads the pixel's facts
    const unsigned* ddcTable;
    WindowMap windows;
    unsigned* volume;
    const unsigned* costVolume;
    int lane, dx, dy, x, y, n, nLive;   // nLive: n, 0 for the lanes past the direction's last line
    LineAddressing ad;
    const char *oL, *oR, *oF;
    int idx;   // of the pixel whose values are loaded
    unsigned edgeMask;
    PairWeights wk;
    // The loaded pixel's census strings (or costs, STORED) and facts; the previous pixel's facts.
    unsigned l, f, fPrev, r[2 * NR * PL];   // STORED: the costs in r[PL k + j]
    // Path costs, two per register as pathKernel's: pair j of row k in P[PL k + j]; mp2: the previous pixel's minimum.
    unsigned P[NR * PL], mp2;
    int base, rows;       // the layout: [base, base + 16 rows)
    unsigned ownRows;     // bit k: row k lies in this line's window (none past its end)
    unsigned* sums;       // lane t's first pair of row 0 for the current pixel, in its window's compact layout
    const unsigned* costs;   // STORED: the same pair of the pixel whose costs are loaded
    int sumStep;
    // The pairs just below and above the layout that the registers do not hold (set where it moves, for one step).
    unsigned belowEdge, aboveEdge;

    //! The warp's lines; false where the warp has none.
    __device__ __forceinline__ bool begin(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts,
                                          const PipelineParams& p)
    {
        lane = threadIdx.x & (LW - 1);
        const int W = censusL.cols, H = censusL.rows;
        int dir;
        const bool hasLine = warpLine(WARPS_PER_BLOCK * 32 / LW, (int)threadIdx.x / LW, p.numPaths == 8, W, H, dir, dx,
                                      dy, x, y, n, true);
        if (!__any_sync(0xFFFFFFFFu, hasLine))
            return false;
        nLive = hasLine ? n : 0;
        ad = lineAddressing(x, y, dx, dy, n, censusL.step, censusR.step, facts.step, 0, p.numDisparities);
        oL = (const char*)(censusL.ptr(ad.yo) + ad.xo);
        oR = (const char*)(censusR.ptr(ad.yo) + ad.xo - p.minDisparity - 2 * PL * lane);
        oF = FACTS ? (const char*)(facts.ptr(ad.yo) + ad.xo) : nullptr;
        idx = ad.idx;
        edgeMask = edgeMaskOf(dir);
        wk = pairWeights(p.w);
        f = fPrev = 0;
        // Zero costs and minimum before the first pixel give its matching costs, whatever the layout.
#pragma unroll
        for (int k = 0; k < NR * PL; k++)
            P[k] = 0;
        mp2 = 0;
        base = 0;
        rows = NR;
        belowEdge = aboveEdge = BIG16X2;
        return true;
    }

    //! Where the line leaves the tile of pixel s (< n).
    __device__ __forceinline__ int segmentEnd(int s) const { return tileSegmentEnd(x, y, dx, dy, n, s); }

    /* The values of pixel idx in the layout's first K rows: its census strings and facts, or its stored costs (those
     past the line's window unused) and the facts where EDGES needs them. */
    template <int K> __device__ __forceinline__ void load()
    {
        if (FACTS)
            f = *(const ushort*)(oF + wideMul(idx, ad.stepF));
        if constexpr (STORED)
        {
#pragma unroll
            for (int k = 0; k < K; k++)
            {
                if constexpr (PL == 2)
                {
                    const uint2 c = *(const uint2*)(costs + 8 * k);
                    r[2 * k] = c.x;
                    r[2 * k + 1] = c.y;
                }
                else
                    r[k] = costs[8 * k];
            }
            return;
        }
        l = *(const unsigned*)(oL + wideMul(idx, ad.stepL));
        const int* pR = (const int*)(oR + wideMul(idx, ad.stepR)) - base;
#pragma unroll
        for (int k = 0; k < K * PL; k++)
        {
            r[2 * k] = (unsigned)pR[-16 * (k / PL) - 2 * (k % PL)];
            r[2 * k + 1] = (unsigned)pR[-16 * (k / PL) - 2 * (k % PL) - 1];
        }
    }

    /* The previous pixel's costs to the layout [newBase, newBase + 16 newRows): row k takes the old row k + delta
     (BIG16 past the old layout, whose rows hold every cost the previous pixel has), and the old pairs just below and
     above the new layout become its edges (lane LW - 1 of the row below, lane 0 of the row above). */
    __device__ __forceinline__ void moveLayout(int newBase, int newRows)
    {
        const int delta = (newBase - base) / 16;
        // Pair i of old row j, selected by compares (an index into P would put it in local memory).
        const auto oldPair = [&](int j, int i) {
            unsigned v = BIG16X2;
#pragma unroll
            for (int k = 0; k < NR; k++)
                v = j == k && k < rows ? P[PL * k + i] : v;
            return v;
        };
        belowEdge = __shfl_sync(0xFFFFFFFFu, oldPair(delta - 1, PL - 1), LW - 1, LW);
        aboveEdge = __shfl_sync(0xFFFFFFFFu, oldPair(delta + newRows, 0), 0, LW);
        unsigned R[NR * PL];
#pragma unroll
        for (int k = 0; k < NR * PL; k++)
            R[k] = oldPair(k / PL + delta, k % PL);
#pragma unroll
        for (int k = 0; k < NR * PL; k++)
            P[k] = R[k];
        base = newBase;
        rows = newRows;
    }

    /* The segment that starts at step s (warp-uniform): it ends where the first live line leaves its tile; its layout
     is the union of the live lines' windows there. Returns the segment's end and sets the layout, the line's rows and
     its sums' (and costs') address and step. */
    __device__ __forceinline__ int startSegment(int s)
    {
        const bool live = s < nLive;
        const int sc = ::min(s, n - 1), px = x + sc * dx, py = y + sc * dy;
        const int tx = (int)((unsigned)px / WINDOW_TILE), ty = (int)((unsigned)py / WINDOW_TILE);
        const unsigned w = (unsigned)windows.tiles(ty, tx);
        const int lo = (int)(w & 0xFFFFu), hi = (int)(w >> 16);
        const int end = __reduce_min_sync(0xFFFFFFFFu, live ? segmentEnd(s) : INT_MAX);
        const int ulo = __reduce_min_sync(0xFFFFFFFFu, live ? lo : INT_MAX);
        const int uhi = __reduce_max_sync(0xFFFFFFFFu, live ? hi : 0);
        if (ulo != base || uhi - ulo != 16 * rows)
            moveLayout(ulo, (uhi - ulo) / 16);
        ownRows = live ? (1u << (hi - base) / 16) - (1u << (lo - base) / 16) : 0u;
        // The rows lie within WINDOW_GUARD_PAIRS of the pixel's window; a line past its end stays at the volume's
        // start (STORED: its rows add zeros there).
        const size_t at = live ? windowPairOffset(windows.base(tx, ty), px, py, lo, hi) + (base - lo) / 2 + PL * lane
                               : WINDOW_GUARD_PAIRS + PL * lane;
        sums = volume + at;
        if (STORED)
            costs = costVolume + at;
        sumStep = live ? (dy * WINDOW_TILE + dx) * ((hi - lo) >> 1) : 0;
        return end;
    }

    //! matchingCost of the loaded pixel in pairs, less the previous minimum: add[PL k + j] for pair j of row k.
    template <int K> __device__ __forceinline__ void matchingCosts(unsigned (&add)[K * PL]) const
    {
        if constexpr (STORED)
        {
#pragma unroll
            for (int k = 0; k < K * PL; k++)
                add[k] = r[k] - mp2;
            return;
        }
        // The census term, and the DDC term from the table (u: the pair's index from the one that holds k - 1, plus
        // one, clamped to 2).
        const unsigned a = (f & ((1u << FACT_PAIR_BITS) - 1)) - (unsigned)((base >> 1) + PL * lane);   // pair 0's u
        const unsigned* row = ddcRow(ddcTable, f);
#pragma unroll
        for (int k = 0; k < K * PL; k++)
        {
            add[k] = censusPairTerm(l, r[2 * k], r[2 * k + 1], wk) +
                     (DDC ? row[::min(a - (unsigned)(8 * (k / PL) + k % PL), 2u)] : 0u) - mp2;
        }
    }

    /* Step s in a segment of K rows, then the next pixel's values are loaded for the same layout where NEXT (all but
     the segment's last step). OWN: every line of the warp is live and owns all K rows (the lines lie in one tile or in
     tiles of one window, as they mostly do), so no row is masked. */
    template <int K, bool NEXT, bool OWN> __device__ __forceinline__ void step(int s)
    {
        unsigned add[K * PL];
        matchingCosts<K>(add);
        unsigned jump = mp2 + wk.p2x2;
        if (EDGES)
            jump = mp2 + ((f | fPrev << 16) & edgeMask ? wk.p2Edgex2 : wk.p2x2);
        fPrev = f;
        unsigned* const S = sums;
        sums += sumStep;
        if (STORED)
            costs += sumStep;
        idx += s + 1 < n ? ad.dIdx : 0;   // a line shorter than the warp's longest stays on its last pixel
        if (NEXT)
            load<K>();
        // Neighbour pairs across lanes by shuffles that rotate the line's lanes (a row's last pair up a lane, its
        // first down one): lane 0 takes lane LW - 1's pair of the row below, lane LW - 1 lane 0's of the row above.
        unsigned up[K], down[K];
#pragma unroll
        for (int k = 0; k < K; k++)
        {
            up[k] = __shfl_sync(0xFFFFFFFFu, P[PL * k + PL - 1], (lane + LW - 1) & (LW - 1), LW);
            down[k] = __shfl_sync(0xFFFFFFFFu, P[PL * k], (lane + 1) & (LW - 1), LW);
        }
        unsigned m = BIG16X2, out[K * PL], V[K * PL];   // out: the sums' terms, 0 past the line's window
#pragma unroll
        for (int i = 0; i < K * PL; i++)
        {
            const int k = i / PL, j = i % PL;
            const unsigned below = j > 0 ? P[i - 1] : lane > 0 ? up[k] : k > 0 ? up[k - 1] : belowEdge;
            const unsigned above = j < PL - 1 ? P[i + 1]
                                   : lane < LW - 1 ? down[k] : k + 1 < K ? down[k + 1] : aboveEdge;
            const unsigned lm = __byte_perm(below, P[i], 0x5432);
            const unsigned lp = __byte_perm(P[i], above, 0x5432);
            const unsigned v = vmin2(vmin2(P[i], jump), vmin2(lm, lp) + wk.p1x2) + add[i];
            V[i] = OWN || ownRows >> k & 1u ? v : BIG16X2;
            out[i] = OWN || ownRows >> k & 1u ? v : 0u;
            m = vmin2(m, V[i]);
        }
#pragma unroll
        for (int i = 0; i < K * PL; i++)
            P[i] = V[i];
        // The line's minimum in both halves: over the pairs, then its lanes.
        m = vmin2(m, __byte_perm(m, 0, 0x1032));
#pragma unroll
        for (int o = LW / 2; o > 0; o >>= 1)
            m = ::min(m, __shfl_xor_sync(0xFFFFFFFFu, m, o));
        mp2 = m;
        // Within a segment a live line stays live (it ends at or before every live line's end).
#pragma unroll
        for (int k = 0; k < K; k++)
        {
            if constexpr (PL == 2)
            {
                if (STORED || OWN)
                    atomicAdd((unsigned long long*)(S + 8 * k),
                              (unsigned long long)out[2 * k] | (unsigned long long)out[2 * k + 1] << 32);
                else
                    reduceAddIf(ownRows >> k & 1u, S + 8 * k, P[2 * k], P[2 * k + 1]);
            }
            else if (STORED || OWN)
                atomicAdd(S + 8 * k, out[k]);
            else
                reduceAddIf(ownRows >> k & 1u, S + 8 * k, P[k]);
        }
        belowEdge = aboveEdge = BIG16X2;
    }

    //! The steps of a segment [s, end) in K rows; the first pixel's values loaded for the segment's layout.
    template <int K, bool OWN> __device__ __forceinline__ void run(int& s, int end)
    {
        load<K>();
#pragma unroll 2
        for (; s + 1 < end; s++)
            step<K, true, OWN>(s);
        step<K, false, OWN>(s++);
    }
    //! The same, without the row mask where every line owns every row (dead lines own none).
    template <int K> __device__ __forceinline__ void run(int& s, int end)
    {
        if (__all_sync(0xFFFFFFFFu, ownRows == (1u << K) - 1))
            run<K, true>(s, end);
        else
            run<K, false>(s, end);
    }

    //! The warp's lines, segment by segment, to the longest's end.
    __device__ __forceinline__ void walk()
    {
        const int steps = __reduce_max_sync(0xFFFFFFFFu, nLive);
        for (int s = 0; s < steps;)
        {
            const int end = startSegment(s);
            switch (rows)
            {
            case 1: run<1>(s, end); break;
            case 2: run<2>(s, end); break;
            case 3: run<3>(s, end); break;
            case 4: run<4>(s, end); break;
            case 5: run<5>(s, end); break;
            case 6: run<6>(s, end); break;
            case 7: run<7>(s, end); break;
            default: run<8>(s, end); break;
            }
        }
    }
};

//! The packed path kernel over the disparity windows (PackedWindowWalk), up to 128 disparities.
template <bool DDC, bool EDGES, bool STORED>
__global__ void
__launch_bounds__(32 * WARPS_PER_BLOCK, STORED ? STORED_COSTS_BLOCKS_PER_SM : PACKED_WINDOW_BLOCKS_PER_SM)
packedWindowPathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                       PipelineParams p, unsigned* volume, const unsigned* costs)
{
    __shared__ __align__(8) unsigned ddcTable[DDC && !STORED ? DDC_TABLE_WORDS : 1];
    if (DDC && !STORED)
        fillDdcTable<1>(ddcTable, p);
    PackedWindowWalk<DDC, EDGES, STORED> walk;
    walk.ddcTable = ddcTable;
    walk.windows = windows;
    walk.volume = volume;
    walk.costVolume = costs;
    if (walk.begin(censusL, censusR, facts, p))
        walk.walk();
}

/* LW lanes a line and PPT pairs a lane (LW = 32: PPT = D / 64 rounded up), in groups of G = 2 adjacent pairs where
 PPT is even (four costs per 64-bit reduction; a load of census strings spans four cache lines), else G = 1
 (measured: G = 4 at 256 disparities, one run of eight per lane, made each load span eight lines and kept L1 busy;
 doc/perf.md). */
template <int LW, int PPT, bool DDC, bool EDGES, bool WIN>
void runPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, const PipelineParams& p,
              PtrStepSz<ushort> sum, WindowMap windows, cudaStream_t stream)
{
    const int W = censusL.cols, H = censusL.rows;
    const int maxLines = p.numPaths == 8 ? W + H - 1 : std::max(W, H);   // diagonals, or rows and columns
    const int lineBlocks = cv::cudev::divUp(maxLines, WARPS_PER_BLOCK * 32 / LW);
    // 8 paths in waves (warpLine): a 1-D grid.
    const dim3 grid = p.numPaths == 8 ? dim3(lineBlocks * 8) : dim3(lineBlocks, p.numPaths);
    const dim3 block(32 * WARPS_PER_BLOCK);
    const int G = PPT % 2 == 0 ? 2 : 1;
    // From 129 disparities on, at most MAX_BLOCKS_PER_SM blocks run on a multiprocessor (unused dynamic shared memory
    // keeps the others out): fewer lines in flight thrash L2 less with their sums (H100, 256 disparities, 6 blocks
    // against the 8 that the registers allow: 1080p 3 % faster, 4K 2 %; doc/perf.md).
    size_t smem = 0;
    if (p.numDisparities > 128)
    {
        int device = 0, perSM = 0;
        CV_CUDEV_SAFE_CALL(cudaGetDevice(&device));
        CV_CUDEV_SAFE_CALL(cudaDeviceGetAttribute(&perSM, cudaDevAttrMaxSharedMemoryPerMultiprocessor, device));
        smem = (size_t)perSM / (MAX_BLOCKS_PER_SM + 1) + 1;
    }
    if (p.numDisparities == 2 * LW * PPT)
        pathKernel<LW, PPT, G, true, DDC, EDGES, WIN><<<grid, block, smem, stream>>>(censusL, censusR, facts, p, sum,
                                                                                     windows);
    else
        pathKernel<LW, PPT, G, false, DDC, EDGES, WIN><<<grid, block, smem, stream>>>(censusL, censusR, facts, p, sum,
                                                                                      windows);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

template <int LW, int PPT, bool WIN = false>
void runPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, const PipelineParams& p,
              bool ddc, PtrStepSz<ushort> sum, cudaStream_t stream, WindowMap windows = WindowMap())
{
    const bool edges = p.edgeThreshold > 0;
    if (ddc)
        edges ? runPaths<LW, PPT, true, true, WIN>(censusL, censusR, facts, p, sum, windows, stream)
              : runPaths<LW, PPT, true, false, WIN>(censusL, censusR, facts, p, sum, windows, stream);
    else
        edges ? runPaths<LW, PPT, false, true, WIN>(censusL, censusR, facts, p, sum, windows, stream)
              : runPaths<LW, PPT, false, false, WIN>(censusL, censusR, facts, p, sum, windows, stream);
}

/* Zeroes the windows' sums of the image's pixels in the compact volume (the padding of the edge tiles is never read):
a block per row and tile, whose pixels' sums are contiguous, 16 bytes a store (multiples of 16 sums). */
__global__ void zeroWindowsKernel(WindowMap windows, int W, unsigned* volume)
{
    const int y = blockIdx.y, tx = blockIdx.x, x0 = tx * WINDOW_TILE;
    const unsigned w = (unsigned)windows.tiles(y / WINDOW_TILE, tx);
    const int lo = (int)(w & 0xFFFFu), hi = (int)(w >> 16);
    uint4* const row = (uint4*)(volume + windowPairOffset(windows.base(tx, y / WINDOW_TILE), x0, y, lo, hi));
    const int chunks = ::min(WINDOW_TILE, W - x0) * (hi - lo) / 8;
    for (int i = threadIdx.x; i < chunks; i += blockDim.x)
        row[i] = make_uint4(0, 0, 0, 0);
}

/* The packed layout's path kernel over the windows (up to 128 disparities): with costs, the windows' matching costs
first (windowMatchingCosts, which zeroes the sums too), then the paths that read them; grid and block as runPaths'
for the walk's LW (4 with the costs, else 8). */
void runPackedWindowPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                          const PipelineParams& p, bool ddc, PtrStepSz<ushort> sum, unsigned* costs,
                          cudaStream_t stream)
{
    CV_Assert(p.numDisparities <= 128);
    if (costs)
        windowMatchingCosts(censusL, censusR, facts, windows, p, ddc, (unsigned*)sum.data, costs, stream);
    const int W = censusL.cols, H = censusL.rows;
    const int maxLines = p.numPaths == 8 ? W + H - 1 : std::max(W, H);
    const int linesPerBlock = WARPS_PER_BLOCK * 32 / (costs ? (int)PackedWindowWalk<false, false, true>::LW
                                                            : (int)PackedWindowWalk<false, false, false>::LW);
    const int lineBlocks = cv::cudev::divUp(maxLines, linesPerBlock);
    const dim3 grid = p.numPaths == 8 ? dim3(lineBlocks * 8) : dim3(lineBlocks, p.numPaths);
    const bool e = p.edgeThreshold > 0;   // the edge rule
    auto kernel = e ? packedWindowPathKernel<false, true, true> : packedWindowPathKernel<false, false, true>;
    if (!costs)
        kernel = ddc ? (e ? packedWindowPathKernel<true, true, false> : packedWindowPathKernel<true, false, false>)
                     : (e ? packedWindowPathKernel<false, true, false> : packedWindowPathKernel<false, false, false>);
    kernel<<<grid, 32 * WARPS_PER_BLOCK, 0, stream>>>(censusL, censusR, facts, windows, p, (unsigned*)sum.data, costs);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

//! The windows' path kernel for NC groups of 64 disparities (the whole range's count).
template <int NC>
void runWindowPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<ushort> facts, WindowMap windows,
                    const PipelineParams& p, bool ddc, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    const int W = censusL.cols, H = censusL.rows;
    const int maxLines = p.numPaths == 8 ? W + H - 1 : std::max(W, H);
    const dim3 grid(cv::cudev::divUp(maxLines, WARPS_PER_BLOCK), p.numPaths), block(32 * WARPS_PER_BLOCK);
    const bool edges = p.edgeThreshold > 0;
    auto kernel = ddc ? (edges ? windowPathKernel<NC, true, true> : windowPathKernel<NC, true, false>)
                      : (edges ? windowPathKernel<NC, false, true> : windowPathKernel<NC, false, false>);
    kernel<<<grid, block, 0, stream>>>(censusL, censusR, facts, windows, p, (unsigned*)sum.data);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

template <typename T>
void aggregate(const AggregationInputs<T>& in, const PipelineParams& p, const AggregationOutputs& out,
               cudaStream_t stream)
{
    const PtrStepSz<int> censusL = in.censusL, censusR = in.censusR;
    const PtrStepSz<short> prior16 = in.prior16;
    const PtrStepSz<ushort> facts = out.facts, sum = out.sum;
    const WindowMap windows = in.windows;
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities;
    const bool packedWindows = windows.tiles.data && packedWindowsTake(D);
    CV_Assert(!out.costs || packedWindows);   // the costs' kernel zeroes the sums
    if (windows.tiles.data && !out.costs)
    {
        zeroWindowsKernel<<<dim3(windows.tiles.cols, censusL.rows), 128, 0, stream>>>(windows, censusL.cols,
                                                                                    (unsigned*)sum.data);
        CV_CUDEV_SAFE_CALL(cudaGetLastError());
    }
    else if (!windows.tiles.data)
        CV_CUDEV_SAFE_CALL(cudaMemset2DAsync(sum.data, sum.step, 0, sum.cols * sizeof(ushort), sum.rows, stream));
    const bool ddc = prior16.data != nullptr;
    if (ddc || p.edgeThreshold > 0)
    {
        const dim3 block(32, 8), grid(cv::cudev::divUp(censusL.cols, 32), cv::cudev::divUp(censusL.rows, 8));
        factsKernel<T><<<grid, block, 0, stream>>>(prior16, in.own16, in.scan, in.left, p.minDisparity,
                                                  p.edgeThreshold, facts);
        CV_CUDEV_SAFE_CALL(cudaGetLastError());
    }
    // With windows from 112 to 128 disparities, 4 or 8 lanes a line over the union of a warp's windows
    // (PackedWindowWalk) on any number of multiprocessors: on the whole H200 it beats one line a warp too
    // (doc/perf.md).
    if (packedWindows)
        return runPackedWindowPaths(censusL, censusR, facts, windows, p, ddc, sum, out.costs, stream);
    const int lines = pathLines(p, W, H);
    // Else, where each multiprocessor has many lines to walk, 8 or 16 lanes a line with eight pairs each (the range
    // then reaches the last of their four groups: 112 or 128 disparities, 208 to 256), with the windows as a mask
    // of the full range; else one line a warp, and the windows' own kernel.
    if ((D > 96 && D <= 128) || (D > 192 && D <= 256))
    {
        const int sms = in.smCount > 0 ? in.smCount : streamSmCount(stream);
        if (lines >= PACKED_LINES_PER_SM * sms)
        {
            if (windows.tiles.data)
                return runPaths<16, 8, true>(censusL, censusR, facts, p, ddc, sum, stream, windows);
            return D <= 128 ? runPaths<8, 8>(censusL, censusR, facts, p, ddc, sum, stream)
                            : runPaths<16, 8>(censusL, censusR, facts, p, ddc, sum, stream);
        }
    }
    if (windows.tiles.data)
    {
        switch ((p.numDisparities + 63) / 64)
        {
        case 1: runWindowPaths<1>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        case 2: runWindowPaths<2>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        case 3: runWindowPaths<3>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        case 4: runWindowPaths<4>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        case 5: runWindowPaths<5>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        case 6: runWindowPaths<6>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        case 7: runWindowPaths<7>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        default: runWindowPaths<8>(censusL, censusR, facts, windows, p, ddc, sum, stream); break;
        }
        return;
    }
    // Up to 32 disparities (the coarse pass of the windows at 128), 8 lanes a line and four lines a warp: with one
    // a warp, half of its lanes would hold no disparity.
    if (D <= 32)
        return runPaths<8, 2>(censusL, censusR, facts, p, ddc, sum, stream);
    switch ((p.numDisparities + 63) / 64)
    {
    case 1: runPaths<32, 1>(censusL, censusR, facts, p, ddc, sum, stream); break;
    case 2: runPaths<32, 2>(censusL, censusR, facts, p, ddc, sum, stream); break;
    case 3: runPaths<32, 3>(censusL, censusR, facts, p, ddc, sum, stream); break;
    case 4: runPaths<32, 4>(censusL, censusR, facts, p, ddc, sum, stream); break;
    case 5: runPaths<32, 5>(censusL, censusR, facts, p, ddc, sum, stream); break;
    case 6: runPaths<32, 6>(censusL, censusR, facts, p, ddc, sum, stream); break;
    case 7: runPaths<32, 7>(censusL, censusR, facts, p, ddc, sum, stream); break;
    default: runPaths<32, 8>(censusL, censusR, facts, p, ddc, sum, stream); break;
    }
}

} // namespace

bool windowCostsStored(const PipelineParams& p, cv::Size size, int sms)
{
    return packedWindowsTake(p.numDisparities) &&
           pathLines(p, size.width, size.height) >= STORED_COSTS_LINES_PER_SM * sms;
}

int streamSmCount(cudaStream_t stream)
{
    int device = 0, sms = 0;
    CV_CUDEV_SAFE_CALL(cudaGetDevice(&device));
    CV_CUDEV_SAFE_CALL(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device));
    // The driver's green context calls through the runtime's entry points: no link to the driver library, and a
    // driver without them leaves the device's count.
    using StreamGetGreenCtx = CUresult (*)(CUstream, CUgreenCtx*);
    using GreenCtxGetDevResource = CUresult (*)(CUgreenCtx, CUdevResource*, CUdevResourceType);
    static const std::pair<StreamGetGreenCtx, GreenCtxGetDevResource> fns = []() {
        void *a = nullptr, *b = nullptr;
        cudaDriverEntryPointQueryResult qa, qb;
        if (cudaGetDriverEntryPointByVersion("cuStreamGetGreenCtx", &a, 12040, cudaEnableDefault, &qa) != cudaSuccess ||
            cudaGetDriverEntryPointByVersion("cuGreenCtxGetDevResource", &b, 12040, cudaEnableDefault, &qb) !=
                cudaSuccess ||
            qa != cudaDriverEntryPointSuccess || qb != cudaDriverEntryPointSuccess)
        {
            (void)cudaGetLastError();
            return std::make_pair(StreamGetGreenCtx(), GreenCtxGetDevResource());
        }
        return std::make_pair((StreamGetGreenCtx)a, (GreenCtxGetDevResource)b);
    }();
    CUgreenCtx green = nullptr;
    CUdevResource sm;
    if (fns.first && stream && fns.first((CUstream)stream, &green) == CUDA_SUCCESS && green &&
        fns.second(green, &sm, CU_DEV_RESOURCE_TYPE_SM) == CUDA_SUCCESS && sm.sm.smCount > 0)
        sms = std::min(sms, (int)sm.sm.smCount);
    return sms;
}

void aggregateCosts(const AggregationInputs<uchar>& in, const PipelineParams& p, const AggregationOutputs& out,
                    cudaStream_t stream)
{
    aggregate(in, p, out, stream);
}

void aggregateCosts(const AggregationInputs<ushort>& in, const PipelineParams& p, const AggregationOutputs& out,
                    cudaStream_t stream)
{
    aggregate(in, p, out, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
