// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation (paper Eq. 2; the jump penalty is jumpPenalty, pipeline.hpp) over 4 paths (left-right,
// right-left, top-down, bottom-up) or 8 (plus the four diagonals), with the matching cost computed as the paths go
// (no cost volume) and the winner-takes-all done as each pixel's sum completes. Two sweeps over one 16-bit volume:
//  1. down, row by row in column strips: verticalStrip computes the row's costs into a ring row of costs, the
//     top-down paths (1 or 3 directions, previous row at x - dx) and the left-right path (entering from the strip
//     on the left) and their sum into a ring row; rightLeftStrip then adds the right-left path (entering from the
//     strip on the right, from the same cost row) and stores the sum in the volume;
//  2. up, row by row in the same strips: verticalStrip computes the costs again and the bottom-up paths, completes
//     each pixel's sum, and selectPixel takes the winner.
// A strip's row depends on its own row before and on a pixel's path costs at each edge, so the strips run in
// parallel, each a few rows behind the one before it (wavefront.hpp), and a row's data stays with the thread that
// has the strip: the horizontal paths pass from strip to strip as one pixel's path costs (the edge slots) instead
// of the whole row going to one thread. Path costs stay below the matching cost plus P2, and the
// weights are scaled so that the sum of all paths fits in 16 bits: the saturating adds never saturate on real values,
// only on the 0xFFFF sentinels that stand for "d - 1 / d + 1 out of range" (so the order of the adds does not
// matter). Compiled once per instruction set (CPU dispatch, aggregation.dispatch.cpp).

#include "cpu_stages.hpp"
#include "opencv2/core/hal/intrin.hpp"
#include <memory>

#ifndef LIDARSGM_AGGREGATION_STATE
#define LIDARSGM_AGGREGATION_STATE
namespace cv { namespace lidarsgm { namespace detail {

//! Stands for "d - 1 / d + 1 out of range" beside a pixel's path costs (and for "no key" in the right view).
const ushort PATH_SENTINEL = 0xFFFF;

/** The right view's best candidates so far, indexed by u = W - 1 - xr (reversed, so that the candidates one pixel
offers are contiguous and increasing in d): the lowest cost and its disparity index, NONE where nothing was offered
yet. A later candidate replaces an earlier one only at a lower cost, so of equal costs the first one offered stays:
the pixels of a row offer in increasing x, i.e. in increasing d for a given right pixel, so that is the smallest d,
as on the GPU (where the (cost << 16 | d) keys are compared). */
struct RightView
{
    enum { NONE = 0xFFFF };
    ushort* cost;    // cost[i], index[i]: u = lo + i
    ushort* index;
    int lo;
};

//! Everything the sweeps of one call share (made by aggregation.dispatch.cpp).
struct AggregationState
{
    Mat censusL, censusR, prior16, intensity;   // intensity: CV_16U left image, empty without the edge rule
    Mat own16;   // the filtered sparse map where copied priors take wCopy (copiedPrior), else empty
    PipelineParams p;
    int W, H, D, stride;                        // stride: D + 2, a sentinel on each side of a pixel's path costs
    Mat sum;                                    // the 16-bit volume of the top-down + horizontal paths, every
                                                // pixel's window in turn (at sumAt), one continuous block
    std::shared_ptr<void> sumMemory;            // sum's memory where aggregation.dispatch.cpp allocates it itself
    // The disparity windows (searchWindows; [0, D) everywhere without them): tile (tx, ty) searches [lo, hi) =
    // windows(ty, tx). In the volume, row y starts at rowBase[y] and tile tx of it at rowBase[y] + tileBase[ty][tx].
    // narrowed: some window is narrower than [0, D); else the lookups below give the full range and its layout.
    Mat windows;
    std::vector<size_t> rowBase, tileBase;
    bool narrowed;
    //! Pixel (x, y)'s window.
    void window(int x, int y, int& lo, int& hi) const
    {
        if (!narrowed)
        {
            lo = 0;
            hi = D;
            return;
        }
        const Vec2s w = windows.at<Vec2s>(y / WINDOW_TILE, x / WINDOW_TILE);
        lo = w[0];
        hi = w[1];
    }
    //! Pixel (x, y)'s sums in the volume (hi - lo of them).
    ushort* sumAt(int x, int y, int n) const
    {
        if (!narrowed)
            return (ushort*)sum.data + ((size_t)y * W + x) * D;
        const int tx = x / WINDOW_TILE;
        return (ushort*)sum.data + rowBase[y] + tileBase[(size_t)(y / WINDOW_TILE) * windows.cols + tx] +
               (size_t)(x - tx * WINDOW_TILE) * n;
    }
    int strips, ring;                           // column strips; rows in each ring below
    Mat costRows, downRows;                     // rings (down sweep) of rows of costs and of the sums of the
                                                // top-down and left-right paths: row y in row y % ring
    // The horizontal paths' hand-offs (down sweep): in row y % ring, at strip * stride + 1, the left-right path
    // costs at strip's last pixel of row y (lrEdge) and the right-left ones at its first (rlEdge), between
    // sentinels; their minima at [(y % ring) * strips + strip].
    Mat lrEdge, rlEdge;
    std::vector<ushort> lrEdgeMin, rlEdgeMin;
    // D + 2 sentinels: the predecessor of a path's first pixel (with minPrev 0 and P2 0, pathStepsAndSum gives L = C).
    std::vector<ushort> noPath;
    Mat finalSum;                               // optional (tests): the complete sums
    Mat disp16, dispInt, nonUnique16;           // outputs of the winner-takes-all (nonUnique16 may be empty)
    int ndirs, dx[3];                           // vertical directions of each sweep: predecessor at x - dx
    std::vector<ushort> L[3][2], minL[3][2];    // per direction, rows of path costs: row y in [y & 1]
    // The right view's candidates per strip and row (RightView): strip s, row y at rightAt[s] + y * rightWidth[s],
    // covering u in [rightLo[s], rightLo[s] + rightWidth[s]).
    std::vector<ushort> rightCost, rightIndex;
    std::vector<int> rightAt, rightLo, rightWidth;
};

}}} // namespace cv::lidarsgm::detail
#endif

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void rightLeftStrip(AggregationState& a, int y, int x0, int x1, int strip);
void verticalStrip(AggregationState& a, int y, int x0, int x1, int strip, bool down);
void costRows(const AggregationState& a, int y0, int y1, Mat& cost);
void selectRows(const AggregationState& a, const Mat& sum, int y0, int y1, Mat& disp16, Mat& dispInt, Mat& dispRight,
                Mat& nonUnique16);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

//! The lowest lane: SSE4.1's minimum-position instruction on a 128-bit half, instead of a ladder of shifts and minima.
static inline ushort minLane(const v_uint16& v)
{
#if CV_AVX2 && CV_SIMD_WIDTH == 32
    const __m128i m = _mm_min_epu16(_mm256_castsi256_si128(v.val), _mm256_extracti128_si256(v.val, 1));
    return (ushort)_mm_cvtsi128_si32(_mm_minpos_epu16(m));
#elif CV_SSE4_1 && CV_SIMD_WIDTH == 16
    return (ushort)_mm_cvtsi128_si32(_mm_minpos_epu16(v.val));
#else
    return (ushort)v_reduce_min(v);
#endif
}

#include "matching_cost.simd.hpp"
#include "winner_takes_all.simd.hpp"

namespace {

const ushort SENTINEL = PATH_SENTINEL;

/* The path loops' scratch rows live on the heap, never on the stack: the main thread's stack starts at a random offset
in every process (address-space layout randomisation), and with the rows there one single-thread process in four or
five ran about a third slower for its whole life while MODE_SGBM_3WAY beside it did not; with the randomisation off
(`setarch -R`) no process did (tools/analysis/cpu_pinned.sh, doc/perf.md). A likely mechanism is the CPU's false
store-to-load dependence between addresses equal in their low 12 bits. The heap's placement is the same in every
process. */
template <typename T>
using ScratchRow = AutoBuffer<T, 1>;

/** One step of the recursion (paper Eq. 2) for each of ND paths through one pixel, in one pass over the
disparities: for direction k, Lout[k](d) = C(d) + min(Lp[k](d), Lp[k](d-1) + P1, Lp[k](d+1) + P1, minPrev[k] + P2[k])
- minPrev[k], minOut[k] = min_d Lout[k](d); and S = A + Lout[0] + ... + Lout[ND - 1] + B (A, B may be null). Lp[k][-1]
and Lp[k][D] must hold SENTINEL; a path's first pixel passes a row of sentinels, minPrev 0 and P2 0, which gives
Lout = C. C and the outputs are loaded once instead of once per direction. stream: S is written with streaming stores
(aligned). FRESH: the direction whose Lp the previous pixel has just stored (a horizontal path; -1: none). Its
neighbours d - 1 and d + 1 are shifted out of the vectors at d and d +- one vector, loaded as they were stored: a
load that spans two recent stores waits for both to reach the cache (a failed store forwarding, 4.9 % of
verticalStrip's samples with windows on, perf). */
template <int ND, int FRESH = -1>
inline void pathStepsAndSum(const ushort* C, const ushort* const* Lp, const ushort* minPrev, ushort* const* Lout,
                            ushort* minOut, const ushort* P2, const ushort* A, const ushort* B, ushort* S, int D,
                            ushort P1, bool stream = false)
{
    int d = 0;
    ushort m[ND];
    for (int k = 0; k < ND; k++)
        m[k] = SENTINEL;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n = VTraits<v_uint16>::vlanes();
    const v_uint16 vp1 = vx_setall_u16(P1);
    v_uint16 vjump[ND], vmp[ND], vmin[ND];
    for (int k = 0; k < ND; k++)
    {
        vjump[k] = vx_setall_u16((ushort)(minPrev[k] + P2[k]));
        vmp[k] = vx_setall_u16(minPrev[k]);
        vmin[k] = vx_setall_u16(SENTINEL);
    }
#if CV_SIMD
    const int N = VTraits<v_uint16>::nlanes;   // n, as a constant for the shifts
    v_uint16 freshBelow = vx_setall_u16(FRESH >= 0 ? Lp[FRESH < 0 ? 0 : FRESH][-1] : SENTINEL);
#endif
    for (; d <= D - n; d += n)
    {
        const v_uint16 c = vx_load(C + d);
        v_uint16 sum = A ? vx_load(A + d) : vx_setzero_u16();
        for (int k = 0; k < ND; k++)
        {
            const ushort* lp = Lp[k];
            const v_uint16 a = vx_load(lp + d);
            // min(Lp(d-1) + P1, Lp(d+1) + P1) as min(Lp(d-1), Lp(d+1)) + P1: the saturating add is monotonic
            // (and SENTINEL + P1 stays SENTINEL), so one add does for both.
            v_uint16 b;
#if CV_SIMD
            if (k == FRESH && (d + 2 * N <= D || d + N == D))
            {
                const v_uint16 above = d + N == D ? vx_setall_u16(lp[D]) : vx_load(lp + d + N);
                b = v_min(v_extract<N - 1>(freshBelow, a), v_extract<1>(a, above));
            }
            else
#endif
                b = v_min(vx_load(lp + d - 1), vx_load(lp + d + 1));
#if CV_SIMD
            if (k == FRESH)
                freshBelow = a;
#endif
            b = v_add(b, vp1);
            const v_uint16 best = v_min(v_min(a, b), vjump[k]);
            const v_uint16 l = v_sub(v_add(c, best), vmp[k]);
            v_store(Lout[k] + d, l);
            vmin[k] = v_min(vmin[k], l);
            sum = v_add(sum, l);
        }
        if (B)
            sum = v_add(sum, vx_load(B + d));
        if (stream)
            v_store_aligned_nocache(S + d, sum);
        else
            v_store(S + d, sum);
    }
    for (int k = 0; k < ND; k++)
        m[k] = minLane(vmin[k]);
#endif
    for (; d < D; d++)
    {
        int sum = A ? A[d] : 0;
        for (int k = 0; k < ND; k++)
        {
            const ushort* lp = Lp[k];
            const int best = std::min(std::min((int)lp[d], (int)lp[d - 1] + P1),
                                      std::min((int)lp[d + 1] + P1, minPrev[k] + P2[k]));
            const ushort l = (ushort)(C[d] + best - minPrev[k]);
            Lout[k][d] = l;
            m[k] = std::min(m[k], l);
            sum += l;
        }
        S[d] = (ushort)(sum + (B ? B[d] : 0));
    }
    for (int k = 0; k < ND; k++)
        minOut[k] = m[k];
}

/** The previous pixel's path costs lp (window [plo, phi), with SENTINEL at plo - 1 and phi) as the step at window
[lo, hi) reads them, at lo - 1 .. hi: lp itself where they lie within what it holds, else a copy in temp with SENTINEL
for the disparities it has no cost for (searchWindows: they are reached through the minimum + P2 only). */
inline const ushort* pathInput(const ushort* lp, int plo, int phi, int lo, int hi, ushort* temp)
{
    if (lo >= plo && hi <= phi)
        return lp;
    for (int d = lo - 1; d <= hi; d++)
        temp[d] = d >= plo && d < phi ? lp[d] : SENTINEL;
    return temp;
}

/** SENTINEL beside a pixel's path costs L[lo, hi) that pathInput reads as "no cost". At -1 and D they are there from
the start and never overwritten; inside the range they are written only for a narrower window (a scalar store that the
next pixel's vector loads overlap stalls their forwarding: about 10 % of the full-range aggregation). */
inline void fenceWindow(ushort* L, int lo, int hi, int D)
{
    if (lo > 0)
        L[lo - 1] = SENTINEL;
    if (hi < D)
        L[hi] = SENTINEL;
}

//! The jump penalty from xq to x on an intensity row I (nullptr: no edge rule, always P2).
inline ushort jump(const AggregationState& a, const ushort* I, int x, int xq)
{
    return I ? (ushort)jumpPenalty(I[x], I[xq], a.p.edgeThreshold, a.p.w) : (ushort)a.p.w.p2;
}

} // namespace

/* The right-left sweep in two forms: Narrowed (some window is narrower than the range: lookups per pixel, pathInput,
fences, the compact volume) and the full range's (none of it: callgrind, two create() calls at KITTI size, 184.6 M
instructions in this sweep against 248.8 M when the full range ran the windowed form). */
template <bool Narrowed>
void rightLeftStripT(AggregationState& a, int y, int x0, int x1, int strip)
{
    const int W = a.W, D = a.D, st = a.stride, slot = y % a.ring;
    const ushort P1 = (ushort)a.p.w.p1;
    ScratchRow<ushort> pathBuf(3 * (size_t)st);
    ushort* u = pathBuf.data() + 1;
    ushort* v = u + st;
    ushort* temp = v + st;
    u[-1] = u[D] = v[-1] = v[D] = SENTINEL;
    const ushort* C = a.costRows.ptr<ushort>(slot);
    const ushort* I = a.intensity.empty() ? nullptr : a.intensity.ptr<ushort>(y);
    const ushort* V = a.downRows.ptr<ushort>(slot);
    ushort* edge = a.rlEdge.ptr<ushort>(slot) + 1;
    ushort* edgeMin = &a.rlEdgeMin[(size_t)slot * a.strips];
    // The volume row is read again only by the up sweep, after the whole image: streaming stores write it without
    // first reading each cache line in (aligned vectors only).
    ushort* const rowSum = Narrowed ? nullptr : (ushort*)a.sum.data + (size_t)y * W * D;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const bool streamRow = !Narrowed && ((size_t)rowSum % (size_t)CV_SIMD_WIDTH) == 0 &&
                           (D * sizeof(ushort)) % CV_SIMD_WIDTH == 0;
#else
    const bool streamRow = false;
#endif
    bool streamed = streamRow;
    // The path enters from strip + 1's first pixel; at the image's right edge it starts.
    const bool enters = x1 < W;
    const ushort* lp = enters ? edge + (size_t)(strip + 1) * st : a.noPath.data() + 1;
    ushort m = enters ? edgeMin[strip + 1] : 0;
    int plo = 0, phi = D;
    if (Narrowed && enters)
        a.window(x1, y, plo, phi);
    for (int x = x1 - 1; x >= x0; x--)
    {
        int lo = 0, hi = D;
        if (Narrowed)
            a.window(x, y, lo, hi);
        const int n = hi - lo;
        const ushort p2 = x + 1 < W ? jump(a, I, x, x + 1) : 0;
        ushort* out = x == x0 ? edge + (size_t)strip * st : u;
        const ushort* in = Narrowed ? pathInput(lp, plo, phi, lo, hi, temp) + lo : lp;
        ushort* outLo = out + lo;
        ushort* S = Narrowed ? a.sumAt(x, y, n) : rowSum + (size_t)x * D;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        const bool stream = Narrowed ? ((size_t)S % (size_t)CV_SIMD_WIDTH) == 0 &&
                                       (n * sizeof(ushort)) % CV_SIMD_WIDTH == 0 : streamRow;
#else
        const bool stream = false;
#endif
        streamed = streamed || stream;
        // S = (top-down + left-right) + right-left, each volume row written once.
        pathStepsAndSum<1, 0>(C + (size_t)x * D + lo, &in, &m, &outLo, &m, &p2, V + (size_t)x * D + lo, nullptr, S, n,
                              P1, stream);
        if (Narrowed)
            fenceWindow(out, lo, hi, D);
        lp = out;
        plo = lo;
        phi = hi;
        std::swap(u, v);
    }
    edgeMin[strip] = m;
#if CV_SSE2
    if (streamed)
        _mm_sfence();   // the streamed stores are weakly ordered: the row is complete before the item says so
#else
    (void)streamed;
#endif
}

void rightLeftStrip(AggregationState& a, int y, int x0, int x1, int strip)
{
    if (a.narrowed)
        rightLeftStripT<true>(a, y, x0, x1, strip);
    else
        rightLeftStripT<false>(a, y, x0, x1, strip);
}

void verticalStrip(AggregationState& a, int y, int x0, int x1, int strip, bool down)
{
    const int W = a.W, D = a.D, st = a.stride, minD = a.p.minDisparity;
    const ushort P1 = (ushort)a.p.w.p1;
    const bool first = down ? y == 0 : y == a.H - 1;
    const int yq = down ? y - 1 : y + 1;
    // The right strings of the strip's pixels: rv[W - 1 - x + d] (only the strip's span is written); up: a pixel's
    // costs and sums (the down sweep writes both to ring rows).
    ScratchRow<ushort> rvBuf(2 * (W + D)), cBuf(down ? 0 : D), fBuf(down ? 0 : D);
    ushort *rvLo = rvBuf.data(), *rvHi = rvLo + W + D;
    reversedRightRow(a.censusR.ptr<unsigned>(y), W, minD, D, x0, x1, rvLo, rvHi);
    const unsigned* L = a.censusL.ptr<unsigned>(y);
    const short* prior = a.prior16.empty() ? nullptr : a.prior16.ptr<short>(y);
    const short* own = a.own16.empty() ? nullptr : a.own16.ptr<short>(y);
    // Down: the costs and the sums of the top-down and left-right paths go to the row's ring rows, for
    // rightLeftStrip. Up: the costs to a scratch vector.
    const int slot = down ? y % a.ring : 0;
    ushort* costRow = down ? a.costRows.ptr<ushort>(slot) : nullptr;
    ushort* downRow = down ? a.downRows.ptr<ushort>(slot) : nullptr;
    const int cur = y & 1, prev = 1 - cur;
    ushort *curL[3] = {}, *prevL[3] = {}, *curMin[3] = {}, *prevMin[3] = {};
    for (int k = 0; k < a.ndirs; k++)
    {
        curL[k] = a.L[k][cur].data() + 1;
        prevL[k] = a.L[k][prev].data() + 1;
        curMin[k] = a.minL[k][cur].data();
        prevMin[k] = a.minL[k][prev].data();
    }
    const ushort* I = a.intensity.empty() ? nullptr : a.intensity.ptr<ushort>(y);
    const ushort* Iq = I && !first ? a.intensity.ptr<ushort>(yq) : nullptr;
    RightView rv = { nullptr, nullptr, 0 };
    if (!down && a.rightWidth[strip] > 0)
    {
        const size_t at = (size_t)a.rightAt[strip] + (size_t)y * a.rightWidth[strip];
        rv = { a.rightCost.data() + at, a.rightIndex.data() + at, a.rightLo[strip] };
        std::fill(rv.index, rv.index + a.rightWidth[strip], (ushort)RightView::NONE);
    }
    ushort* finalSum = a.finalSum.empty() ? nullptr : a.finalSum.ptr<ushort>(y);
    short* d16 = down ? nullptr : a.disp16.ptr<short>(y);
    short* dInt = down ? nullptr : a.dispInt.ptr<short>(y);
    short* nu = down || a.nonUnique16.empty() ? nullptr : a.nonUnique16.ptr<short>(y);
    const ushort* noPath = a.noPath.data() + 1;
    // Down: the left-right path, as one more direction (index ndirs) of each pixel: it enters from strip - 1's last
    // pixel (or starts at the image's left edge), steps through lrBuf, and leaves from the strip's last pixel.
    ScratchRow<ushort> lrBuf(down ? 2 * (size_t)st : 0);
    ushort *lrU = nullptr, *lrV = nullptr;
    if (down)
    {
        lrU = lrBuf.data() + 1;
        lrV = lrU + st;
        lrU[-1] = lrU[D] = lrV[-1] = lrV[D] = SENTINEL;
    }
    ushort* lrEdge = down ? a.lrEdge.ptr<ushort>(slot) + 1 : nullptr;
    ushort* lrEdgeMin = down ? &a.lrEdgeMin[(size_t)slot * a.strips] : nullptr;
    const ushort* lrPrev = down && x0 > 0 ? lrEdge + (size_t)(strip - 1) * st : noPath;
    ushort lrMin = down && x0 > 0 ? lrEdgeMin[strip - 1] : 0;
    const int nd = down ? a.ndirs + 1 : a.ndirs;
    // The predecessors' path costs where their windows do not hold the pixel's (pathInput), one row per direction.
    const bool narrowed = a.narrowed;
    ScratchRow<ushort> tempBuf(narrowed ? 4 * (size_t)st : 0);
    int lrLo = 0, lrHi = D;
    if (down && x0 > 0)
        a.window(x0 - 1, y, lrLo, lrHi);
    auto pixel = [&](int x) {
        int lo, hi;
        a.window(x, y, lo, hi);
        const int n = hi - lo;
        ushort* c = (down ? costRow + (size_t)x * D : cBuf.data()) + lo;
        costVector(rvLo + (W - 1 - x), rvHi + (W - 1 - x), L[x], prior ? priorIndex(prior[x], minD) : -1,
                   own && copiedPrior(true, prior[x], own[x]) ? a.p.wCopy : a.p.w, lo, n, c);
        // out: each direction's path costs at this pixel; outLo: from lo, set beside out (copied from out afterwards,
        // the pointers just stored were reloaded with vector loads: a failed store forwarding that took 6 % of this
        // function's samples with windows on, perf).
        const ushort* lp[4] = {};
        ushort *out[4] = {}, *outLo[4] = {};
        ushort minPrev[4] = {}, p2[4] = {}, mins[4];
        for (int k = 0; k < a.ndirs; k++)
        {
            const int xp = x - a.dx[k];
            out[k] = curL[k] + (size_t)x * st;
            outLo[k] = out[k] + lo;
            if (first || xp < 0 || xp >= W)
                lp[k] = noPath;
            else
            {
                lp[k] = prevL[k] + (size_t)xp * st;
                minPrev[k] = prevMin[k][xp];
                p2[k] = Iq ? (ushort)jumpPenalty(I[x], Iq[xp], a.p.edgeThreshold, a.p.w) : (ushort)a.p.w.p2;
            }
        }
        if (down)
        {
            const int k = a.ndirs;
            lp[k] = lrPrev;
            minPrev[k] = lrMin;
            p2[k] = x > 0 ? jump(a, I, x, x - 1) : 0;
            out[k] = x == x1 - 1 ? lrEdge + (size_t)strip * st : lrU;
            outLo[k] = out[k] + lo;
        }
        // Windows: each predecessor's costs as this window reads them, all pointers from lo. Apart from the full
        // range's loop above (kept as it was: a window test inside it stopped the compiler from unrolling it, 180
        // instructions a pixel measured by callgrind).
        if (narrowed)
        {
            for (int k = 0; k < nd; k++)
            {
                int plo = 0, phi = D;
                if (k == a.ndirs)
                {
                    plo = lrLo;
                    phi = lrHi;
                }
                else if (lp[k] != noPath)
                    a.window(x - a.dx[k], yq, plo, phi);
                lp[k] = pathInput(lp[k], plo, phi, lo, hi, tempBuf.data() + k * st + 1) + lo;
            }
        }
        // Down: the sum of the top-down and left-right paths to the ring row; up: the pixel's complete sum.
        ushort* f = down ? downRow + (size_t)x * D + lo : fBuf.data();
        const ushort* base = down ? nullptr : a.sumAt(x, y, n);
        // Down, the left-right path (the last direction) reads what the previous pixel has just stored.
        switch (down ? nd : -nd)
        {
        case 4: pathStepsAndSum<4, 3>(c, lp, minPrev, outLo, mins, p2, base, nullptr, f, n, P1); break;
        case 2: pathStepsAndSum<2, 1>(c, lp, minPrev, outLo, mins, p2, base, nullptr, f, n, P1); break;
        case -3: pathStepsAndSum<3>(c, lp, minPrev, outLo, mins, p2, base, nullptr, f, n, P1); break;
        case -1: pathStepsAndSum<1>(c, lp, minPrev, outLo, mins, p2, base, nullptr, f, n, P1); break;
        default: CV_Error(Error::StsInternal, "lidarsgm: unexpected number of directions");
        }
        for (int k = 0; narrowed && k < nd; k++)
            fenceWindow(out[k], lo, hi, D);
        for (int k = 0; k < a.ndirs; k++)
            curMin[k][x] = mins[k];
        if (down)
        {
            lrPrev = out[a.ndirs];
            lrMin = mins[a.ndirs];
            lrLo = lo;
            lrHi = hi;
            std::swap(lrU, lrV);
            return;
        }
        if (finalSum)
        {
            ushort* fs = finalSum + (size_t)x * D;
            std::fill(fs, fs + D, SENTINEL);
            memcpy(fs + lo, f, n * sizeof(ushort));
        }
        selectPixel(f, x, W, a.p, lo, n, d16[x], dInt[x], nu ? nu + x : nullptr, rv);
    };
    for (int x = x0; x < x1; x++)
        pixel(x);
    if (down && x1 > x0)
        lrEdgeMin[strip] = lrMin;
}

void costRows(const AggregationState& a, int y0, int y1, Mat& cost)
{
    const int W = a.W, D = a.D;
    ScratchRow<ushort> rvBuf(2 * (W + D));
    ushort *rvLo = rvBuf.data(), *rvHi = rvLo + W + D;
    for (int y = y0; y < y1; y++)
    {
        reversedRightRow(a.censusR.ptr<unsigned>(y), W, a.p.minDisparity, D, 0, W, rvLo, rvHi);
        const short* prior = a.prior16.empty() ? nullptr : a.prior16.ptr<short>(y);
        for (int x = 0; x < W; x++)
            costVector(rvLo + (W - 1 - x), rvHi + (W - 1 - x), a.censusL.ptr<unsigned>(y)[x],
                       prior ? priorIndex(prior[x], a.p.minDisparity) : -1, a.p.w, 0, D,
                       cost.ptr<ushort>(y) + (size_t)x * D);
    }
}

void selectRows(const AggregationState& a, const Mat& sum, int y0, int y1, Mat& disp16, Mat& dispInt, Mat& dispRight,
                Mat& nonUnique16)
{
    const int W = a.W, D = a.D;
    ScratchRow<ushort> fBuf(D), costBuf(W), indexBuf(W);
    RightView rv = { costBuf.data(), indexBuf.data(), 0 };
    for (int y = y0; y < y1; y++)
    {
        std::fill(rv.index, rv.index + W, (ushort)RightView::NONE);
        for (int x = 0; x < W; x++)
        {
            memcpy(fBuf.data(), sum.ptr<ushort>(y) + (size_t)x * D, D * sizeof(ushort));
            selectPixel(fBuf.data(), x, W, a.p, 0, D, disp16.ptr<short>(y)[x], dispInt.ptr<short>(y)[x],
                        nonUnique16.ptr<short>(y) + x, rv);
        }
        short* dr = dispRight.ptr<short>(y);
        for (int xr = 0; xr < W; xr++)
        {
            const ushort k = rv.index[W - 1 - xr];
            dr[xr] = (short)(k == RightView::NONE ? NO_DISP : k + a.p.minDisparity);
        }
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
