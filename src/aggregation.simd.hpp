// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation (paper Eq. 2; the jump penalty is jumpPenalty, pipeline.hpp) over 4 paths (left-right,
// right-left, top-down, bottom-up) or 8 (plus the four diagonals), with the matching cost computed inside the path
// loop (no cost volume) and the winner-takes-all done as each pixel's sum completes. Two sweeps over one 16-bit
// volume, row by row in column strips (wavefront.hpp), each pixel in one pass over its disparities:
//  1. down, each strip's row left to right: the top-down directions (1 or 3) and the left-right path; their sum
//     goes to the volume;
//  2. up, each strip's row right to left: the bottom-up directions and the right-left path, the volume's partial sum
//     added; the winner, its uniqueness and the right view's candidates are tracked in the same pass (selectPixel).
// The vertical directions keep one record of path costs per slot, and a pixel writes its own into the record that
// the pixel before it in the row has just read (the slots move by dx + 1 per row down, dx - 1 up, so that the
// records of a row take the place of the row before), so a step's loads and stores never overlap; the horizontal
// path keeps one record per strip, overwritten in place.
// Path costs stay below the matching cost plus P2, and the weights are scaled so that the sum of all paths fits in
// 16 bits: the saturating adds never saturate on real values, only on the 0xFFFF sentinels that stand for "no cost"
// (d - 1 / d + 1 out of range, or out of a window), so the order of the adds does not matter. Compiled once per
// instruction set (CPU dispatch, aggregation.dispatch.cpp).

#include "cpu_stages.hpp"
#include "opencv2/core/hal/intrin.hpp"
#include <memory>

#ifndef LIDARSGM_AGGREGATION_STATE
#define LIDARSGM_AGGREGATION_STATE
namespace cv { namespace lidarsgm { namespace detail {

//! Stands for "no path cost" beside and, with windows, inside a pixel's path costs (and for "no key" in the right
//! view).
const ushort PATH_SENTINEL = 0xFFFF;

/** A pixel's path costs (a record): RECORD_PAD elements, then the D costs (aligned for the widest vector), in a
stride of D + RECORD_PAD; the element before the costs and the one after them (the next record's first) hold
PATH_SENTINEL, and a vector's worth on each side may be read. The costs' minimum sits at RECORD_MIN, in the pad.
A strip row's jump penalties are kept JUMPS per pixel (sweepRow). */
enum { RECORD_PAD = 16, RECORD_MIN = -2, JUMPS = 4 };

//! A pixel's set-up in both sweeps costs about as much as this many of its disparities (callgrind: ~500
//! instructions against ~10.5 a disparity; AggregationState::stripX).
enum { STRIP_PIXEL_CELLS = 48 };

/** The right view's best candidates so far, indexed by u = W - 1 - xr (reversed, so that the candidates one pixel
offers are contiguous and increasing in d): the lowest cost and its disparity index, NONE where nothing was offered
yet. The up sweep walks a row from the right, so a right pixel's candidates arrive in decreasing d: a later one
replaces an earlier one at a lower or equal cost, so of equal costs the smallest d stays, as on the GPU (where the
(cost << 16 | d) keys are compared). */
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
    int W, H, D, stride;                        // stride: D + RECORD_PAD, a record's elements
    Mat sum;                                    // the 16-bit volume of the down sweep's partial sums, every
                                                // pixel's window in turn (at sumAt), one continuous block; a
                                                // row's pixels from right to left, the order the up sweep reads
                                                // them in (a descending stream defeats the prefetchers)
    std::shared_ptr<void> sumMemory;            // sum's memory where aggregation.dispatch.cpp allocates it itself
    // The disparity windows (searchWindows; [0, D) everywhere without them): tile (tx, ty) searches [lo, hi) =
    // windows(ty, tx). In the volume, row y starts at rowBase[y] and tile tx of it at rowBase[y] + tileBase[ty][tx]
    // (the tiles of a row from right to left).
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
    //! Pixel (x, y)'s sums in the volume (hi - lo of them); pixel x - 1's follow them.
    ushort* sumAt(int x, int y, int n) const
    {
        if (!narrowed)
            return (ushort*)sum.data + ((size_t)y * W + (W - 1 - x)) * D;
        const int tx = x / WINDOW_TILE, tileEnd = std::min(W, (tx + 1) * WINDOW_TILE);
        return (ushort*)sum.data + rowBase[y] + tileBase[(size_t)(y / WINDOW_TILE) * windows.cols + tx] +
               (size_t)(tileEnd - 1 - x) * n;
    }
    // The DDC term of a pixel at disparity index d: ddcTable[addend + d], addend by its prior (ddcAddends): rows of
    // ddcRowLength, a row of zeros where it has no prior.
    std::vector<ushort> ddcTable;
    int ddcRowLength;
    int strips, ring;
    std::vector<int> stripX;                    // strip s covers columns [stripX[s], stripX[s + 1])
    // The horizontal path's hand-off between strips: the path costs at the strip's last pixel of a row, as a
    // record at edge.ptr(row % ring) + strip * stride.
    Mat edge;
    /* Per strip a block of scratch (sweepRow), 4 KB aligned. The buffers that the path loop reads or writes at the
    same addresses for every pixel (the horizontal record, the sums, the DDC rows and the indices) lie at different
    offsets modulo 4 KB: a load whose address matches a recent store's in its low 12 bits waits for the store (4K
    aliasing), and with the record over the DDC table a strip ran at half speed. */
    std::vector<ushort> scratchMemory;
    ushort* scratch;
    size_t scratchPerStrip, scratchSums, scratchIota, scratchDdc, scratchTemp, scratchJumps, jumpStride;
    size_t scratchRight, scratchAddend;   // a strip row's right census halves and DDC offsets
    // A record of sentinels: the predecessor of a path's first pixel (with minimum 0 and P2 0 the step gives L = C).
    std::vector<ushort> noPath;
    Mat finalSum;                               // optional (tests): the complete sums
    Mat disp16, dispInt, nonUnique16;           // outputs of the winner-takes-all (nonUnique16 may be empty)
    int ndirs, dx[3];                           // vertical directions of each sweep: predecessor at x - dx
    // Per vertical direction, the records of path costs and their minima: pixel x of the sweep's row i writes slot
    // x - c i + max(c, 0) (H - 1), c = dx + 1 down and dx - 1 up (sweepRow), W + 2 H - 2 slots at most.
    std::vector<ushort> records[3];
    // The right view's candidates per strip and row (RightView): strip s, row y at rightAt[s] + y * rightWidth[s],
    // covering u in [rightLo[s], rightLo[s] + rightWidth[s]) (beyond [0, W) where the strip offers candidates that
    // fall outside the right image).
    std::vector<ushort> rightCost, rightIndex;
    std::vector<int> rightAt, rightLo, rightWidth;
    std::vector<ushort> iota;                   // iota[i] = i (WinnerLanes)
};

}}} // namespace cv::lidarsgm::detail
#endif

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void sweepRow(AggregationState& a, int i, int x0, int x1, int strip, bool down);
void rightViewRows(const AggregationState& a, int y0, int y1, Mat& dispRight);
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

/** One pixel's step: ND directions (NV vertical ones, then the sweep's horizontal path), the matching cost computed
in the loop, n disparities (the window's; a multiple of the vector width where there are vectors). */
template <int NV>
struct StepArgs
{
    enum { ND = NV + 1 };
    CostInput cost;
    // Direction k: the predecessor's costs at the window's first disparity (lp[k][-1] and lp[k][n] readable, a
    // vector's worth beyond them too), the outputs, the predecessor's minimum and the jump penalty. Only the
    // horizontal path (the last direction) may write where it reads.
    const ushort* lp[ND];
    ushort* out[ND];
    ushort minPrev[ND], p2[ND];
    ushort minOut[ND];
    const ushort* partial;   // up: the down sweep's partial sums
    ushort* sum;             // down: the partial sums out (to the volume, aligned: streaming stores); up: the
                             // complete sums
};

/** The recursion (paper Eq. 2) for each direction k of the step: Lout[k](d) = C(d) + min(Lp[k](d), Lp[k](d-1) + P1,
Lp[k](d+1) + P1, minPrev[k] + P2[k]) - minPrev[k], minOut[k] = min_d Lout[k](d); the sum of the directions (and of
the partial sums, up) to sum. UP: then the winner's lanes and the right view's candidates from the sums. The
horizontal path (the last direction) reads what the previous pixel has just stored: its neighbours d - 1 and d + 1
are shifted out of the vectors at d and d +- one vector, loaded as they were stored (a load that spans two recent
stores waits for both to reach the cache: a failed store forwarding). */
template <int NV, bool UP, bool EXACT>
inline void pathStep(StepArgs<NV>& s, int n, ushort P1, WinnerLanes* win, const RightOffer* rv)
{
    enum { ND = NV + 1, H = NV };
    int d = 0;
#if CV_SIMD
    const int N = VTraits<v_uint16>::nlanes;
    const CostVectors cv(s.cost);
    const v_uint16 vp1 = vx_setall_u16(P1);
    v_uint16 vjump[ND], vmp[ND], vmin[ND];
    for (int k = 0; k < ND; k++)
    {
        vmp[k] = vx_setall_u16(s.minPrev[k]);
        vjump[k] = vx_setall_u16((ushort)(s.minPrev[k] + s.p2[k]));
        vmin[k] = vx_setall_u16(SENTINEL);
    }
    const ushort* hp = s.lp[H];
    v_uint16 below = vx_load(hp - N), ha = vx_load(hp);   // below's last lane: hp[-1]
#if CV_AVX2 && CV_SIMD_WIDTH == 32
    // The lane permute that shifts in the vector below is the one the previous vector needed for the one above.
    __m256i swap = _mm256_permute2x128_si256(below.val, ha.val, 0x21);
#endif
    for (; d < n; d += N)
    {
        const v_uint16 c = costAt<EXACT>(cv, s.cost, d);
        v_uint16 sum = UP ? vx_load(s.partial + d) : vx_setzero_u16();
        for (int k = 0; k < NV; k++)
        {
            const ushort* q = s.lp[k] + d;
            const v_uint16 a = vx_load(q);
            // min(Lp(d-1) + P1, Lp(d+1) + P1) as min(Lp(d-1), Lp(d+1)) + P1: the saturating add is monotonic
            // (and SENTINEL + P1 stays SENTINEL), so one add does for both.
            const v_uint16 b = v_add(v_min(vx_load(q - 1), vx_load(q + 1)), vp1);
            const v_uint16 l = v_sub(v_add(c, v_min(v_min(a, b), vjump[k])), vmp[k]);
            v_store(s.out[k] + d, l);
            vmin[k] = v_min(vmin[k], l);
            sum = v_add(sum, l);
        }
        {
            const v_uint16 above = vx_load(hp + d + N);
#if CV_AVX2 && CV_SIMD_WIDTH == 32
            const __m256i next = _mm256_permute2x128_si256(ha.val, above.val, 0x21);
            const v_uint16 b = v_add(v_min(v_uint16(_mm256_alignr_epi8(ha.val, swap, 14)),
                                           v_uint16(_mm256_alignr_epi8(next, ha.val, 2))), vp1);
            swap = next;
#else
            const v_uint16 b = v_add(v_min(v_extract<N - 1>(below, ha), v_extract<1>(ha, above)), vp1);
#endif
            const v_uint16 l = v_sub(v_add(c, v_min(v_min(ha, b), vjump[H])), vmp[H]);
            v_store(s.out[H] + d, l);
            vmin[H] = v_min(vmin[H], l);
            sum = v_add(sum, l);
            below = ha;
            ha = above;
        }
        if (UP)
            v_store(s.sum + d, sum);
        else
            v_store_aligned_nocache(s.sum + d, sum);   // read again only by the up sweep, after the whole image
    }
    for (int k = 0; k < ND; k++)
        s.minOut[k] = minLane(vmin[k]);
    // The winner and the right view from the sums just stored (in L1): in the loop above their state would not
    // fit in the vector registers beside the paths'.
    if (UP)
        selectSums(s.sum, n, *win, *rv);
#else
    // Scalar: the horizontal path's input is copied first, as it overwrites it.
    ushort m[ND];
    for (int k = 0; k < ND; k++)
        m[k] = SENTINEL;
    AutoBuffer<ushort> tmpBuf(n + 2);
    for (int j = -1; j <= n; j++)
        tmpBuf[j + 1] = s.lp[H][j];
    s.lp[H] = tmpBuf.data() + 1;
    for (; d < n; d++)
    {
        int sum = UP ? s.partial[d] : 0;
        const int c = costAt(s.cost, d);
        for (int k = 0; k < ND; k++)
        {
            const ushort* lp = s.lp[k];
            const int best = std::min(std::min((int)lp[d], std::min((int)lp[d - 1], (int)lp[d + 1]) + P1),
                                      s.minPrev[k] + s.p2[k]);
            const ushort l = (ushort)(c + best - s.minPrev[k]);
            s.out[k][d] = l;
            m[k] = std::min(m[k], l);
            sum += l;
        }
        s.sum[d] = (ushort)sum;
    }
    for (int k = 0; k < ND; k++)
        s.minOut[k] = m[k];
    if (UP)
        selectSums(s.sum, n, *win, *rv);
#endif
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

//! The jump penalty from intensity iq to ip (I null: no edge rule, always P2).
inline ushort jump(const PipelineParams& p, const ushort* I, const ushort* Iq, int x, int xq)
{
    return I ? (ushort)jumpPenalty(I[x], Iq[xq], p.edgeThreshold, p.w) : (ushort)p.w.p2;
}

} // namespace

/** The DDC offsets (AggregationState::ddcTable) of the pixels x0 .. x1 - 1 of row y to out[x - x0]: 0 (the row of
zeros) without a prior, else r * ddcRowLength + D - k for prior index k (round(prior) - minD, in range by
construction, clamped so that a read never leaves its row), r 2 for a copied prior (copiedPrior: wCopy), else 1. */
static void ddcAddends(const AggregationState& a, int y, int x0, int x1, ushort* out)
{
    const int D = a.D, minD = a.p.minDisparity, L = a.ddcRowLength;
    if (a.prior16.empty())
    {
        std::fill(out, out + (x1 - x0), (ushort)0);
        return;
    }
    const short* prior = a.prior16.ptr<short>(y);
    const short* own = a.own16.empty() ? nullptr : a.own16.ptr<short>(y);
    int x = x0;
#if CV_SIMD
    const int N = VTraits<v_int16>::nlanes;
    const v_int16 none = vx_setall_s16(NO_DISP), zero = vx_setzero_s16();
    const v_int16 base = vx_setall_s16((short)(L + D + minD)), eight = vx_setall_s16(8);
    const v_int16 kLo = vx_setall_s16((short)minD), kHi = vx_setall_s16((short)(minD + D - 1));
    const v_int16 row = vx_setall_s16((short)L);
    // The last vector overlaps the one before where the width is no multiple of N (the same values written again).
    for (; x < x1 && x1 - x0 >= N; x += N)
    {
        x = std::min(x, x1 - N);
        const v_int16 v = vx_load(prior + x);
        // The scalar rule below in lanes: roundDisp16(prior) as minD + k, clamped to [minD, minD + D - 1]; base
        // minus it is L + D - k.
        const v_int16 k = v_min(v_max(v_shr<4>(v_add_wrap(v, eight)), kLo), kHi);
        v_int16 o = v_sub_wrap(base, k);
        if (own)
        {
            // copiedPrior: v != own (the lanes without a prior are zeroed below)
            const v_int16 copied = v_not(v_eq(v, vx_load(own + x)));
            o = v_add_wrap(o, v_and(copied, row));
        }
        v_store((short*)out + (x - x0), v_select(v_eq(v, none), zero, o));
    }
#endif
    for (; x < x1; x++)
    {
        if (prior[x] == NO_DISP)
        {
            out[x - x0] = 0;
            continue;
        }
        const int k = std::min(std::max(roundDisp16(prior[x]) - minD, 0), D - 1);
        const int r = own && copiedPrior(true, prior[x], own[x]) ? 2 : 1;
        out[x - x0] = (ushort)(r * L + D - k);
    }
}

/** The jump penalties (jumpPenalty; I null: no edge rule, P2) of the pixels x0 .. x1 - 1 of row I from their
predecessors x - dq in row Iq, to out[x - x0]; 0 where the predecessor lies outside the image (a path's first pixel:
with minimum 0 and a row of sentinels the step gives L = C). */
static void jumpRow(const PipelineParams& p, const ushort* I, const ushort* Iq, int dq, int W, int x0, int x1,
                    ushort* out)
{
    const int xs = std::min(std::max(x0, dq), x1), xe = std::max(std::min(x1, W + dq), xs);
    int x = x0;
    for (; x < xs; x++)
        out[x - x0] = 0;
    if (!I)
        for (; x < xe; x++)
            out[x - x0] = (ushort)p.w.p2;
    else
    {
#if CV_SIMD
        const int N = VTraits<v_uint16>::nlanes;
        const v_uint16 thr = vx_setall_u16((ushort)p.edgeThreshold), p2 = vx_setall_u16((ushort)p.w.p2),
                       p2e = vx_setall_u16((ushort)p.w.p2Edge);
        // The last vector overlaps the one before where the span is no multiple of N.
        for (; x < xe && xe - xs >= N; x += N)
        {
            x = std::min(x, xe - N);
            v_store(out + (x - x0), v_select(v_gt(v_absdiff(vx_load(I + x), vx_load(Iq + x - dq)), thr), p2e, p2));
        }
#endif
        for (; x < xe; x++)
            out[x - x0] = (ushort)jumpPenalty(I[x], Iq[x - dq], p.edgeThreshold, p.w);
    }
    for (; x < x1; x++)
        out[x - x0] = 0;
}

/** The jump penalties of the pixels x0 .. x1 - 1 of the sweep's row for its vertical directions (predecessors x - dx
in row Iq; zeros in the sweep's first row, Iq null) and its horizontal path (predecessor x - step), JUMPS per pixel
(out[JUMPS (x - x0) + k], k the direction), so that a pixel reads them through one pointer. rows: scratch for
JUMPS rows of stride x1 - x0 + lanes. */
template <int NV>
static void jumpRows(const AggregationState& a, const ushort* I, const ushort* Iq, bool first, int step, int x0,
                     int x1, ushort* out, ushort* rows, size_t stride)
{
    const int W = a.W, w = x1 - x0;
    for (int k = 0; k < JUMPS; k++)
    {
        ushort* r = rows + (size_t)k * stride;
        if (k < NV && !first)
            jumpRow(a.p, I, Iq, a.dx[k], W, x0, x1, r);
        else if (k == NV)
            jumpRow(a.p, I, I, step, W, x0, x1, r);
        else
            std::fill(r, r + w, (ushort)0);
    }
    int x = 0;
#if CV_SIMD
    const int N = VTraits<v_uint16>::nlanes;
    for (; x + N <= w; x += N)
        v_store_interleave(out + JUMPS * x, vx_load(rows + x), vx_load(rows + stride + x),
                           vx_load(rows + 2 * stride + x), vx_load(rows + 3 * stride + x));
#endif
    for (; x < w; x++)
        for (int k = 0; k < JUMPS; k++)
            out[JUMPS * x + k] = rows[k * stride + x];
}

#if defined(__clang__)
#define LIDARSGM_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define LIDARSGM_UNROLL _Pragma("GCC unroll 4")
#else
#define LIDARSGM_UNROLL
#endif

//! A hint to fetch the cache line at p (for reading).
static inline void prefetchRead(const char* p)
{
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(p, 0, 3);
#else
    (void)p;
#endif
}
/* In the up sweep each pixel fetches the partial sums of the pixel PREFETCH_AHEAD after it (distances 2 to 8 measured
alike; about 1 % of the call at 2 threads). The records stream in ascending addresses and need no hint. */
enum { PREFETCH_AHEAD = 4 };

//! The horizontal path's predecessor as the walk goes: its record (window [lo, hi)) and the record's minimum.
struct HorizontalPrev
{
    const ushort* rec;
    ushort min;
    int lo, hi;
};

/** One strip's row of one sweep: pixels x0 .. x1 - 1 of the sweep's row i (down: image row i, walked left to right;
up: row H - 1 - i, right to left). NARROW: some window is narrower than the range (searchWindows): the row is walked
tile by tile, a tile's window, predecessor windows and volume layout set once per tile segment. The pixels at the
ends of a segment (the horizontal path's hand-offs, the image's edges, a predecessor in another tile), those of the
sweep's first row and those whose predecessors' windows do not hold theirs take the general set-up (generalInputs);
the others only advance pointers (plainInputs). The constructor sets the row up; segment() walks one segment. The
flags are template parameters, so the walk has no branch on them. The step's arguments and the winner's lanes stay
outside the object: where a path step is not inlined it takes their addresses, and the row's state would then be
reloaded around every call. */
template <int NV, bool UP, bool EXACT, bool NARROW>
struct RowSweep
{
    enum { ND = NV + 1, H = NV, STEP = UP ? -1 : 1 };
    AggregationState& a;
    int i, x0, x1, strip, y, yq;
    bool first;
    const unsigned* L;        // the row's left census strings
    const ushort* noPath;     // a record of sentinels (AggregationState::noPath)
    ushort* hrec;             // the strip's horizontal record, overwritten in place along the strip
    ushort* sums;             // up: the complete sums
    const ushort* ddc;        // the strip's copy of the DDC rows
    ushort* temp[ND];         // per direction, a copy of a predecessor (pathInput)
    const ushort* rl0;        // the right census halves at j in [W - x1, W - x0 + D - 1): rl0[j], rh0[j]
    const ushort* rh0;
    const ushort* addRow;     // pixel x's DDC offset at addRow[x]
    const ushort* jumps;      // pixel x's jump penalties at jumps[JUMPS x + k]
    int xEnd;                 // the horizontal path walks to xEnd - step, and leaves through hEdge
    ushort* hEdge;
    HorizontalPrev h;
    RightView rv;             // up: this strip's right-view candidates of row y
    short* d16;               // up: the winner-takes-all's rows (nu, finalSum: null where not asked for)
    short* dInt;
    short* nu;
    ushort* finalSum;
    const Vec2s* winRowQ;     // NARROW: the windows of the predecessors' tile row
    // Vertical direction k, in the walk's coordinate u (x down, W - 1 - x up; its predecessor at u - du, du = dx
    // down and -dx up): pixel u writes record slot u - c i + offset (c = du + 1) and reads its predecessor's, slot u -
    // du - c (i - 1) + offset: the one the pixel before it has just read. Slots ascend along the walk, so that the
    // records stream in ascending addresses. A record keeps its minimum at RECORD_MIN.
    ushort* recBase[NV];
    int du[NV], c[NV], offset[NV];

    //! One segment's window and what its pixels share.
    struct Segment
    {
        int lo, hi, n, xFirst, xLast;
        int qlo, qhi;         // NARROW: the window of the predecessors above in this tile column
        bool allGeneral;      // every pixel takes the general set-up
    };
    //! What advances from pixel to pixel: the right strings, the records written and read (their disparity 0), the
    //! volume.
    struct Cursor
    {
        const ushort* rl;
        const ushort* rh;
        const ushort* rd[NV];
        ushort* wr[NV];
        ushort* vol;
    };

    RowSweep(AggregationState& state, int i_, int x0_, int x1_, int strip_)
        : a(state), i(i_), x0(x0_), x1(x1_), strip(strip_), y(UP ? state.H - 1 - i_ : i_), yq(y - STEP),
          first(i_ == 0)
    {
        L = a.censusL.ptr<unsigned>(y);
        noPath = a.noPath.data() + RECORD_PAD;
        rowTables();
        handOff();
        outputRows();
        recordSlots();
    }

    /** The strip's scratch (AggregationState::scratch): its horizontal record, the complete sums, its copies of the
    indices and DDC rows, one copy of a predecessor per direction (pathInput), the jump penalties; and the row's tables
    in it: the right census halves reversed, the DDC offsets of its pixels, their jump penalties. */
    void rowTables()
    {
        const int W = a.W, D = a.D;
        const ushort* I = a.intensity.empty() ? nullptr : a.intensity.ptr<ushort>(y);
        const ushort* Iq = I && !first ? a.intensity.ptr<ushort>(yq) : nullptr;
        ushort* scratch = a.scratch + a.scratchPerStrip * strip;
        hrec = scratch + RECORD_PAD;
        sums = scratch + a.scratchSums;
        ddc = scratch + a.scratchDdc;
        for (int k = 0; k < ND; k++)
            temp[k] = scratch + a.scratchTemp + (size_t)k * a.stride + RECORD_PAD;
        ushort* rlBuf = scratch + a.scratchRight;
        ushort* rhBuf = rlBuf + (a.scratchAddend - a.scratchRight) / 2;
        reversedRightRow(a.censusR.ptr<unsigned>(y), W, a.p.minDisparity, W - x1, W - x0 + D - 1, rlBuf, rhBuf);
        rl0 = rlBuf - (W - x1);
        rh0 = rhBuf - (W - x1);
        ushort* addBuf = scratch + a.scratchAddend;
        ddcAddends(a, y, x0, x1, addBuf);
        addRow = addBuf - x0;
        ushort* jumpBuf = scratch + a.scratchJumps;
        jumpRows<NV>(a, I, Iq, first, STEP, x0, x1, jumpBuf, jumpBuf + JUMPS * a.jumpStride, a.jumpStride);
        jumps = jumpBuf - JUMPS * x0;
    }

    /** The horizontal path walks xBegin .. xEnd - step: it enters from the strip it comes from (that strip's hand-off
    of this row) or starts at the image's edge, and leaves through this strip's hand-off. */
    void handOff()
    {
        const ptrdiff_t st = a.stride;
        const int slot = i % a.ring;
        const int xBegin = UP ? x1 - 1 : x0;
        xEnd = UP ? x0 - 1 : x1;
        const bool enters = UP ? x1 < a.W : x0 > 0;
        ushort* edgeRow = a.edge.ptr<ushort>(slot) + RECORD_PAD;
        const int from = strip - STEP;
        h.rec = enters ? edgeRow + (size_t)from * st : noPath;
        h.min = enters ? h.rec[RECORD_MIN] : 0;
        h.lo = 0;
        h.hi = a.D;
        if (NARROW && enters)
            a.window(xBegin - STEP, y, h.lo, h.hi);
        hEdge = edgeRow + (size_t)strip * st;
    }

    //! The right view (up): this strip's candidates of row y, marked empty first; the outputs' rows.
    void outputRows()
    {
        rv = { nullptr, nullptr, 0 };
        if (UP)
        {
            const size_t at = (size_t)a.rightAt[strip] + (size_t)y * a.rightWidth[strip];
            rv = { a.rightCost.data() + at, a.rightIndex.data() + at, a.rightLo[strip] };
            std::fill(rv.cost, rv.cost + a.rightWidth[strip], (ushort)SENTINEL);
            std::fill(rv.index, rv.index + a.rightWidth[strip], (ushort)RightView::NONE);
        }
        d16 = UP ? a.disp16.ptr<short>(y) : nullptr;
        dInt = UP ? a.dispInt.ptr<short>(y) : nullptr;
        nu = UP && !a.nonUnique16.empty() ? a.nonUnique16.ptr<short>(y) : nullptr;
        finalSum = UP && !a.finalSum.empty() ? a.finalSum.ptr<ushort>(y) : nullptr;
        winRowQ = NARROW ? a.windows.ptr<Vec2s>(first ? y / WINDOW_TILE : yq / WINDOW_TILE) : nullptr;
    }

    void recordSlots()
    {
        LIDARSGM_UNROLL
        for (int k = 0; k < NV; k++)
        {
            recBase[k] = a.records[k].data() + RECORD_PAD;
            du[k] = UP ? -a.dx[k] : a.dx[k];
            c[k] = du[k] + 1;
            offset[k] = std::max(c[k], 0) * (a.H - 1);
        }
    }

    //! The segment [xa, xb) with window [lo, hi): its walk order and whether the predecessors above hold its window.
    Segment segmentOf(int xa, int xb, int lo, int hi) const
    {
        Segment g;
        g.lo = lo;
        g.hi = hi;
        g.n = hi - lo;
        g.xFirst = UP ? xb - 1 : xa;
        g.xLast = UP ? xa : xb - 1;
        // NARROW: whether the predecessors above in this tile column hold the window (else pathInput copies).
        bool copyAbove = false;
        g.qlo = 0;
        g.qhi = a.D;
        if (NARROW && !first)
        {
            const Vec2s w = winRowQ[xa / WINDOW_TILE];
            g.qlo = w[0];
            g.qhi = w[1];
            copyAbove = lo < g.qlo || hi > g.qhi;
        }
        g.allGeneral = first || copyAbove;
        return g;
    }

    //! The cursor at the segment's first pixel.
    void startCursor(const Segment& g, Cursor& cur) const
    {
        const ptrdiff_t st = a.stride;
        cur.rl = rl0 + (a.W - 1 - g.xFirst) + g.lo;
        cur.rh = rh0 + (a.W - 1 - g.xFirst) + g.lo;
        const int uFirst = UP ? a.W - 1 - g.xFirst : g.xFirst;
        LIDARSGM_UNROLL
        for (int k = 0; k < NV; k++)
        {
            cur.wr[k] = recBase[k] + (uFirst - c[k] * i + offset[k]) * st;
            cur.rd[k] = recBase[k] + (uFirst - du[k] - c[k] * (i - 1) + offset[k]) * st;
        }
        cur.vol = a.sumAt(g.xFirst, y, g.n);
    }

    /** The general set-up of pixel x's step: each vertical predecessor where it lies in the image (else a path
    starts), copied where its window does not hold the pixel's (NARROW). Returns the horizontal path's output
    record: the strip's hand-off at its last pixel. */
    ushort* generalInputs(StepArgs<NV>& s, const Segment& g, const Cursor& cur, const ushort* jx, int x) const
    {
        const int W = a.W, T = WINDOW_TILE, lo = g.lo, hi = g.hi;
        LIDARSGM_UNROLL
        for (int k = 0; k < NV; k++)
        {
            s.out[k] = cur.wr[k] + lo;
            s.p2[k] = jx[k];
            const int xp = x - a.dx[k];
            if (first || xp < 0 || xp >= W)
            {
                s.lp[k] = noPath + lo;
                s.minPrev[k] = 0;
                continue;
            }
            s.minPrev[k] = cur.rd[k][RECORD_MIN];
            s.lp[k] = cur.rd[k] + lo;
            if (NARROW)
            {
                // A predecessor in another tile column (the segment's ends), or above a wider window.
                int plo = g.qlo, phi = g.qhi;
                if (xp / T != x / T)
                {
                    const Vec2s w = winRowQ[xp / T];
                    plo = w[0];
                    phi = w[1];
                }
                s.lp[k] = pathInput(cur.rd[k], plo, phi, lo, hi, temp[k]) + lo;
            }
        }
        // The horizontal path: its input is the previous pixel's record (h.rec, window [h.lo, h.hi)), overwritten in
        // place along the strip; the strip's last pixel writes the hand-off.
        s.lp[H] = (NARROW ? pathInput(h.rec, h.lo, h.hi, lo, hi, temp[H]) : h.rec) + lo;
        return x + STEP == xEnd ? hEdge : hrec;
    }

    //! A pixel inside the segment, its predecessors in the image and holding its window: pointers only.
    void plainInputs(StepArgs<NV>& s, const Cursor& cur, const ushort* jx, int lo) const
    {
        LIDARSGM_UNROLL
        for (int k = 0; k < NV; k++)
        {
            s.out[k] = cur.wr[k] + lo;
            s.p2[k] = jx[k];
            s.minPrev[k] = cur.rd[k][RECORD_MIN];
            s.lp[k] = cur.rd[k] + lo;
        }
        s.lp[H] = hrec + lo;
    }

    /** After pixel x's step: the records' minima (and, NARROW, the sentinels around a new window), the horizontal
    path's predecessor for the next pixel, and (up) the pixel's winner. */
    void finishPixel(const StepArgs<NV>& s, const WinnerLanes& win, const Segment& g, const Cursor& cur, ushort* hOut,
                     int x)
    {
        const int lo = g.lo, hi = g.hi;
        LIDARSGM_UNROLL
        for (int k = 0; k < NV; k++)
        {
            cur.wr[k][RECORD_MIN] = s.minOut[k];
            if (NARROW)
            {
                cur.wr[k][lo - 1] = SENTINEL;   // the record's -1 and D hold SENTINEL already
                cur.wr[k][hi] = SENTINEL;
            }
        }
        if (NARROW && (x == g.xFirst || hOut == hEdge))   // a new window in the record, or the hand-off
        {
            hOut[lo - 1] = SENTINEL;
            hOut[hi] = SENTINEL;
        }
        h.rec = hOut;
        h.min = s.minOut[H];
        h.lo = lo;
        h.hi = hi;
        if (UP)
        {
            if (finalSum)
            {
                ushort* fs = finalSum + (size_t)x * a.D;
                std::fill(fs, fs + a.D, SENTINEL);
                memcpy(fs + lo, sums + lo, g.n * sizeof(ushort));
            }
            selectPixel(win, sums + lo, lo, g.n, a.p, d16[x], dInt[x], nu ? nu + x : nullptr);
        }
    }

    //! The pixels of the segment [xa, xb) (walk order xFirst .. xLast) with window [lo, hi).
    void segment(StepArgs<NV>& s, WinnerLanes& win, int xa, int xb, int lo, int hi)
    {
        const ptrdiff_t st = a.stride;
        const ushort P1 = (ushort)a.p.w.p1;
        const Segment g = segmentOf(xa, xb, lo, hi);
        const int n = g.n;
        Cursor cur;
        startCursor(g, cur);
        const ptrdiff_t volStep = -(ptrdiff_t)STEP * n;
        RightOffer offer = { nullptr, nullptr };
        if (UP)
        {
            const int u0 = a.W - 1 - g.xFirst + a.p.minDisparity;
            offer.cost = rv.cost + (u0 + lo - rv.lo);
            offer.index = rv.index + (u0 + lo - rv.lo);
        }
        for (int x = g.xFirst;; x += STEP)
        {
            s.cost.rl = cur.rl;
            s.cost.rh = cur.rh;
            s.cost.l = L[x];
            s.cost.add = ddc + addRow[x] + lo;
            const ushort* jx = jumps + JUMPS * x;
            ushort* hOut = hrec;
            if (g.allGeneral || x == g.xFirst || x == g.xLast)
                hOut = generalInputs(s, g, cur, jx, x);
            else
                plainInputs(s, cur, jx, lo);
            s.minPrev[H] = h.min;
            s.p2[H] = jx[H];
            s.out[H] = hOut + lo;
            s.partial = cur.vol;
            s.sum = UP ? sums + lo : cur.vol;
            for (int b = 0; UP && b < n * (int)sizeof(ushort); b += 64)
                prefetchRead((const char*)(cur.vol + PREFETCH_AHEAD * volStep) + b);
            if (UP)
            {
                win.reset(lo);
                pathStep<NV, true, EXACT>(s, n, P1, &win, &offer);
            }
            else
                pathStep<NV, false, EXACT>(s, n, P1, nullptr, nullptr);
            finishPixel(s, win, g, cur, hOut, x);
            if (x == g.xLast)
                break;
            cur.rl -= STEP;
            cur.rh -= STEP;
            LIDARSGM_UNROLL
            for (int k = 0; k < NV; k++)
            {
                cur.wr[k] += st;
                cur.rd[k] += st;
            }
            cur.vol += volStep;
            if (UP)
            {
                offer.cost -= STEP;
                offer.index -= STEP;
            }
        }
    }
};

//! One strip's row of one sweep (RowSweep): its segments, a tile's each with windows, then the hand-off's minimum.
template <int NV, bool UP, bool EXACT, bool NARROW>
static void sweepRowT(AggregationState& a, int i, int x0, int x1, int strip)
{
    RowSweep<NV, UP, EXACT, NARROW> row(a, i, x0, x1, strip);
    StepArgs<NV> s;
    s.cost.census256 = a.p.w.census256;
    WinnerLanes win;
    win.iota = a.scratch + a.scratchPerStrip * strip + a.scratchIota;
    if (NARROW)
    {
        const int T = WINDOW_TILE, step = UP ? -1 : 1;
        const Vec2s* winRow = a.windows.ptr<Vec2s>(row.y / T);
        const int t0 = x0 / T, t1 = (x1 - 1) / T;
        for (int t = UP ? t1 : t0; UP ? t >= t0 : t <= t1; t += step)
            row.segment(s, win, std::max(x0, t * T), std::min(x1, t * T + T), winRow[t][0], winRow[t][1]);
    }
    else
        row.segment(s, win, x0, x1, 0, a.D);
    row.hEdge[RECORD_MIN] = row.h.min;
#if CV_SSE2
    if (!UP)
        _mm_sfence();   // the streamed stores are weakly ordered: the row is complete before the item says so
#endif
}

template <int NV, bool UP, bool EXACT>
static void sweepRowW(AggregationState& a, int i, int x0, int x1, int strip)
{
    if (a.narrowed)
        sweepRowT<NV, UP, EXACT, true>(a, i, x0, x1, strip);
    else
        sweepRowT<NV, UP, EXACT, false>(a, i, x0, x1, strip);
}

void sweepRow(AggregationState& a, int i, int x0, int x1, int strip, bool down)
{
    const bool exact = censusMulExact(a.p.w);
    if (a.ndirs == 3)
    {
        if (down)
            exact ? sweepRowW<3, false, true>(a, i, x0, x1, strip) : sweepRowW<3, false, false>(a, i, x0, x1, strip);
        else
            exact ? sweepRowW<3, true, true>(a, i, x0, x1, strip) : sweepRowW<3, true, false>(a, i, x0, x1, strip);
    }
    else
    {
        if (down)
            exact ? sweepRowW<1, false, true>(a, i, x0, x1, strip) : sweepRowW<1, false, false>(a, i, x0, x1, strip);
        else
            exact ? sweepRowW<1, true, true>(a, i, x0, x1, strip) : sweepRowW<1, true, false>(a, i, x0, x1, strip);
    }
}

/** The right view (dispRight's rows y0 .. y1 - 1) from the strips' candidates: strip by strip from the left, a strip's
candidate replaces the one so far only at a lower cost (its disparities are larger: RightView); the candidates outside
the right image are dropped. */
void rightViewRows(const AggregationState& a, int y0, int y1, Mat& dispRight)
{
    const int W = a.W, minD = a.p.minDisparity;
    const ushort NONE = RightView::NONE;
    AutoBuffer<ushort> costBuf(W), indexBuf(W);
    ushort *mc = costBuf.data(), *mi = indexBuf.data();
#if CV_SIMD
    const int N = VTraits<v_uint16>::nlanes;
    const v_uint16 vnone = vx_setall_u16(NONE);
#endif
    for (int y = y0; y < y1; y++)
    {
        std::fill(mi, mi + W, NONE);
        std::fill(mc, mc + W, NONE);
        for (int s = 0; s < a.strips; s++)
        {
            const size_t at = (size_t)a.rightAt[s] + (size_t)y * a.rightWidth[s];
            const ushort* c = a.rightCost.data() + at;
            const ushort* k = a.rightIndex.data() + at;
            const int i0 = std::max(-a.rightLo[s], 0), i1 = std::min(W - a.rightLo[s], a.rightWidth[s]);
            const int lo = a.rightLo[s];
            int i = i0;
#if CV_SIMD
            for (; i + N <= i1; i += N)
            {
                const v_uint16 vc = vx_load(c + i), vk = vx_load(k + i);
                const v_uint16 oc = vx_load(mc + lo + i), ok = vx_load(mi + lo + i);
                // the scalar rule below: a candidate (vk not NONE) where there is none yet, or at a lower cost
                // (min(vc, oc) != oc)
                const v_uint16 lower = v_not(v_eq(v_min(vc, oc), oc));
                const v_uint16 take = v_and(v_not(v_eq(vk, vnone)), v_or(v_eq(ok, vnone), lower));
                v_store(mc + lo + i, v_select(take, vc, oc));
                v_store(mi + lo + i, v_select(take, vk, ok));
            }
#endif
            for (; i < i1; i++)
                if (k[i] != NONE && (mi[lo + i] == NONE || c[i] < mc[lo + i]))
                {
                    mc[lo + i] = c[i];
                    mi[lo + i] = k[i];
                }
        }
        short* dr = dispRight.ptr<short>(y);
        for (int xr = 0; xr < W; xr++)
        {
            const ushort k = mi[W - 1 - xr];
            dr[xr] = (short)(k == NONE ? NO_DISP : k + minD);
        }
    }
}

void costRows(const AggregationState& a, int y0, int y1, Mat& cost)
{
    const int W = a.W, D = a.D;
    AutoBuffer<ushort> rvBuf(2 * (W + D) + W);
    ushort *rvLo = rvBuf.data(), *rvHi = rvLo + (W + D - 1), *addRow = rvHi + (W + D - 1);
    for (int y = y0; y < y1; y++)
    {
        reversedRightRow(a.censusR.ptr<unsigned>(y), W, a.p.minDisparity, 0, W + D - 1, rvLo, rvHi);
        ddcAddends(a, y, 0, W, addRow);
        for (int x = 0; x < W; x++)
        {
            const CostInput in = { rvLo + (W - 1 - x), rvHi + (W - 1 - x), a.censusL.ptr<unsigned>(y)[x],
                                   a.ddcTable.data() + addRow[x], a.p.w.census256 };
            costVector(in, a.p.w, D, cost.ptr<ushort>(y) + (size_t)x * D);
        }
    }
}

void selectRows(const AggregationState& a, const Mat& sum, int y0, int y1, Mat& disp16, Mat& dispInt, Mat& dispRight,
                Mat& nonUnique16)
{
    const int W = a.W, D = a.D;
    AutoBuffer<ushort> costBuf(W + 2 * D), indexBuf(W + 2 * D);
    // Candidates of u in [-D, W + D) (those outside the right image are dropped at the end).
    RightView rv = { costBuf.data(), indexBuf.data(), -D };
    WinnerLanes win;
    win.iota = a.iota.data();
    for (int y = y0; y < y1; y++)
    {
        std::fill(rv.cost, rv.cost + W + 2 * D, (ushort)PATH_SENTINEL);
        std::fill(rv.index, rv.index + W + 2 * D, (ushort)RightView::NONE);
        for (int x = W - 1; x >= 0; x--)
        {
            const ushort* s = sum.ptr<ushort>(y) + (size_t)x * D;
            const int u0 = W - 1 - x + a.p.minDisparity;
            const RightOffer pix = { rv.cost + (u0 - rv.lo), rv.index + (u0 - rv.lo) };
            win.reset(0);
            selectSums(s, D, win, pix);
            selectPixel(win, s, 0, D, a.p, disp16.ptr<short>(y)[x], dispInt.ptr<short>(y)[x],
                        nonUnique16.ptr<short>(y) + x);
        }
        short* dr = dispRight.ptr<short>(y);
        for (int xr = 0; xr < W; xr++)
        {
            const ushort k = rv.index[W - 1 - xr - rv.lo];
            dr[xr] = (short)(k == RightView::NONE ? NO_DISP : k + a.p.minDisparity);
        }
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
