// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU aggregation's sweeps in order (aggregation.simd.hpp), each running the kernels compiled for the best
// instruction set this CPU has (OpenCV's CPU dispatch: baseline, SSE4.1, AVX2). Also the volume forms of the
// matching cost and the winner-takes-all, for the per-stage tests: the same kernels.

#include "precomp.hpp"
#if defined(__linux__)
#include <sys/mman.h>
#endif
#include <cstdlib>
#include <memory>
#include "aggregation.simd.hpp"
#include "aggregation.simd_declarations.hpp"
#include "wavefront.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace {

void initState(AggregationState& a, const Mat& censusL, const Mat& censusR, const Mat& prior16, const Mat& left,
               const PipelineParams& p, const Mat& own16 = Mat())
{
    CV_Assert(censusL.type() == CV_32SC1 && censusR.type() == CV_32SC1 && censusR.size() == censusL.size());
    CV_Assert(prior16.empty() || (prior16.type() == CV_16SC1 && prior16.size() == censusL.size()));
    CV_Assert(own16.empty() || (!prior16.empty() && own16.type() == CV_16SC1 && own16.size() == censusL.size()));
    a.censusL = censusL;
    a.censusR = censusR;
    a.prior16 = prior16;
    a.own16 = own16;
    a.p = p;
    a.W = censusL.cols;
    a.H = censusL.rows;
    a.D = p.numDisparities;
    a.stride = a.D + 2;
    a.finalSum.release();
    if (p.edgeThreshold > 0 && !left.empty())
    {
        CV_Assert(left.size() == censusL.size());
        left.convertTo(a.intensity, CV_16U);   // the edge rule reads 16-bit intensities (8-bit values unchanged)
    }
    else
        a.intensity.release();
}

// CV_CPU_DISPATCH returns from the function it stands in: one small function per kernel.
void runRightLeftStrip(AggregationState& a, int y, int x0, int x1, int strip)
{
    CV_CPU_DISPATCH(rightLeftStrip, (a, y, x0, x1, strip), CV_CPU_DISPATCH_MODES_ALL);
}
void runVerticalStrip(AggregationState& a, int y, int x0, int x1, int strip, bool down)
{
    CV_CPU_DISPATCH(verticalStrip, (a, y, x0, x1, strip, down), CV_CPU_DISPATCH_MODES_ALL);
}
void runCostRows(const AggregationState& a, int y0, int y1, Mat& cost)
{
    CV_CPU_DISPATCH(costRows, (a, y0, y1, cost), CV_CPU_DISPATCH_MODES_ALL);
}
void runSelectRows(const AggregationState& a, const Mat& sum, int y0, int y1, Mat& disp16, Mat& dispInt,
                   Mat& dispRight, Mat& nonUnique16)
{
    CV_CPU_DISPATCH(selectRows, (a, sum, y0, y1, disp16, dispInt, dispRight, nonUnique16), CV_CPU_DISPATCH_MODES_ALL);
}

} // namespace

/* The sum volume (119 MB at KITTI size) in 2 MB pages where Linux gives them on request (transparent huge pages in
"madvise" mode, a common default): each sweep streams through all of it, and with 4 KB pages every 4 KB of it is a
TLB miss (and, in a virtual machine, a two-level page walk). Elsewhere an ordinary allocation. */
static void createVolume(AggregationState& a, int rows, int cols)
{
    // With windows the rows needed change from frame to frame: a volume large enough stays (refaulting it in every
    // call would cost more than the windows save).
    if (a.sum.rows >= rows && a.sum.cols == cols && a.sum.type() == CV_16UC1)
        return;
    a.sum.release();
    a.sumMemory.reset();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const size_t page = (size_t)2 << 20;
    const size_t bytes = ((size_t)rows * cols * sizeof(ushort) + page - 1) / page * page;
    void* m = nullptr;
    if (bytes > 0 && posix_memalign(&m, page, bytes) == 0)
    {
        madvise(m, bytes, MADV_HUGEPAGE);   // a hint: without huge pages the memory works as any other
        a.sumMemory.reset(m, free);
        a.sum = Mat(rows, cols, CV_16UC1, m);
        return;
    }
#endif
    a.sum.create(rows, cols, CV_16UC1);
}

void aggregateCosts(const Mat& censusL, const Mat& censusR, const Mat& prior16, const Mat& left,
                    const PipelineParams& p, Mat& disp16, Mat& dispInt, Mat& dispRight, Mat& nonUnique16,
                    OutputArray finalSum,
                    Ptr<AggregationState>* work, const Mat& own16, const Mat& windows)
{
    CV_Assert(p.edgeThreshold == 0 || !left.empty());
    Ptr<AggregationState> temporary;
    Ptr<AggregationState>& held = work ? *work : temporary;
    if (!held)
        held = makePtr<AggregationState>();
    AggregationState& a = *held;
    initState(a, censusL, censusR, prior16, left, p, own16);
    const int W = a.W, H = a.H, D = a.D, T = WINDOW_TILE;
    // The windows (the full range without them) and where each tile row's pixels keep their sums in the volume.
    const Size tiles((W + T - 1) / T, (H + T - 1) / T);
    if (!windows.empty())
    {
        CV_Assert(windows.type() == CV_16SC2 && windows.size() == tiles);
        a.windows = windows;
    }
    else
    {
        a.windows.create(tiles, CV_16SC2);
        a.windows.setTo(Scalar(0, D));
    }
    a.tileBase.resize((size_t)tiles.area());
    a.rowBase.resize(H);
    size_t total = 0;
    a.narrowed = false;
    for (int ty = 0; ty < tiles.height; ty++)
    {
        size_t rowCells = 0;
        for (int tx = 0; tx < tiles.width; tx++)
        {
            const Vec2s w = a.windows.at<Vec2s>(ty, tx);
            CV_Assert(0 <= w[0] && w[0] < w[1] && w[1] <= D);
            a.narrowed = a.narrowed || w[0] > 0 || w[1] < D;
            a.tileBase[(size_t)ty * tiles.width + tx] = rowCells;
            rowCells += (size_t)std::min(T, W - tx * T) * (w[1] - w[0]);
        }
        for (int y = ty * T; y < std::min(H, ty * T + T); y++, total += rowCells)
            a.rowBase[y] = total;
    }
    // At least the rows that hold them (W D cells a row: the full range's layout where no window is narrower).
    createVolume(a, std::max((int)((total + (size_t)W * D - 1) / ((size_t)W * D)), 1), W * D);
    disp16.create(H, W, CV_16SC1);
    dispInt.create(H, W, CV_16SC1);
    dispRight.create(H, W, CV_16SC1);
    a.disp16 = disp16;
    a.dispInt = dispInt;
    if (ringCheckOn(p))
    {
        nonUnique16.create(H, W, CV_16SC1);
        a.nonUnique16 = nonUnique16;
    }
    else
        a.nonUnique16.release();
    if (finalSum.needed())
    {
        finalSum.create(H, W * D, CV_16UC1);
        a.finalSum = finalSum.getMat();
    }

    // With 4 paths a column depends only on itself; the diagonals of 8 paths need the neighbouring strips' last row
    // (Wavefront).
    a.ndirs = p.numPaths == 8 ? 3 : 1;
    a.dx[0] = 0; a.dx[1] = 1; a.dx[2] = -1;
    for (int k = 0; k < a.ndirs; k++)
        for (int i = 0; i < 2; i++)
        {
            a.L[k][i].assign((size_t)W * a.stride, PATH_SENTINEL);
            a.minL[k][i].assign(W, 0);
        }
    // Strips of at least 32 pixels, up to four per thread and the same number for every thread where the width
    // allows (each thread keeps to its own strips: Wavefront).
    const int threads = std::max(1, getNumThreads());
    const int strips = threads == 1 ? 1 : W / 32 < threads ? std::max(1, W / 32)
                                                            : threads * std::min(4, W / 32 / threads);
    // The rings of cost rows and of partial sums: the rows whose right-left paths wait or run, and the rows the
    // strips write meanwhile (two per thread: a strip that waits for a slot holds up the rows after it).
    const int ring = std::min(H, 2 * threads + 4);
    a.strips = strips;
    a.ring = ring;
    a.costRows.create(ring, W * D, CV_16UC1);
    a.downRows.create(ring, W * D, CV_16UC1);
    // The hand-offs of the horizontal paths between strips, each pixel's costs between sentinels (written only
    // inside them).
    a.lrEdge.create(ring, strips * a.stride, CV_16UC1);
    a.rlEdge.create(ring, strips * a.stride, CV_16UC1);
    a.lrEdge.setTo(Scalar::all(PATH_SENTINEL));
    a.rlEdge.setTo(Scalar::all(PATH_SENTINEL));
    a.lrEdgeMin.assign((size_t)ring * strips, 0);
    a.rlEdgeMin.assign((size_t)ring * strips, 0);
    a.noPath.assign(D + 2, PATH_SENTINEL);
    // Strip s offers right-view candidates to right pixels [x0 - minD - D + 1, x1 - minD), i.e. u = W - 1 - xr in
    // [W - x1 + minD, W - x0 + minD + D - 1): room for every row. Each strip marks its row empty before the row
    // (verticalStrip), so that nothing here runs alone over the whole.
    a.rightAt.resize(strips);
    a.rightLo.resize(strips);
    a.rightWidth.resize(strips);
    size_t rightTotal = 0;
    for (int s = 0; s < strips; s++)
    {
        const int x0 = W * s / strips, x1 = W * (s + 1) / strips;
        a.rightLo[s] = std::max(W - x1 + p.minDisparity, 0);
        a.rightWidth[s] = std::max(std::min(W - x0 + p.minDisparity + D - 1, W) - a.rightLo[s], 0);
        a.rightAt[s] = (int)rightTotal;
        rightTotal += (size_t)a.rightWidth[s] * H;
    }
    a.rightCost.resize(rightTotal);
    a.rightIndex.resize(rightTotal);

    const auto strip = [&](int s, int y, bool down) {
        runVerticalStrip(a, y, W * s / strips, W * (s + 1) / strips, s, down);
    };
    // 1. Down: the strips compute the costs, the top-down and left-right paths (forward items), then the right-left
    // paths, which complete the partial sums (back items).
    Wavefront(strips, H, a.ndirs > 1, ring).run(threads,
        [&](int s, int i) { strip(s, i, true); },
        [&](int s, int i) { runRightLeftStrip(a, i, W * s / strips, W * (s + 1) / strips, s); });
    // 2. Up: the bottom-up paths complete the sums; the winner is taken at once.
    Wavefront(strips, H, a.ndirs > 1, 0).run(threads,
        [&](int s, int i) { strip(s, H - 1 - i, false); }, [](int, int) {});

    // The right view: strip by strip from the left, a strip's candidate replaces the one so far only at a lower cost
    // (its disparities are larger: RightView).
    parallel_for_(Range(0, H), [&](const Range& r) {
        AutoBuffer<ushort> costBuf(W), indexBuf(W);
        ushort *mc = costBuf.data(), *mi = indexBuf.data();
        for (int y = r.start; y < r.end; y++)
        {
            std::fill(mi, mi + W, (ushort)RightView::NONE);
            for (int s = 0; s < strips; s++)
            {
                const size_t at = (size_t)a.rightAt[s] + (size_t)y * a.rightWidth[s];
                const ushort* c = a.rightCost.data() + at;
                const ushort* k = a.rightIndex.data() + at;
                for (int i = 0, u = a.rightLo[s]; i < a.rightWidth[s]; i++, u++)
                    if (k[i] != RightView::NONE && (mi[u] == RightView::NONE || c[i] < mc[u]))
                    {
                        mc[u] = c[i];
                        mi[u] = k[i];
                    }
            }
            short* dr = dispRight.ptr<short>(y);
            for (int xr = 0; xr < W; xr++)
            {
                const ushort k = mi[W - 1 - xr];
                dr[xr] = (short)(k == RightView::NONE ? NO_DISP : k + p.minDisparity);
            }
        }
    }, rowStripes(H));
}

void computeMatchingCost(const Mat& censusL, const Mat& censusR, const Mat& prior16, const PipelineParams& p,
                         Mat& cost)
{
    AggregationState a;
    initState(a, censusL, censusR, prior16, Mat(), p);
    cost.create(a.H, a.W * a.D, CV_16UC1);
    parallel_for_(Range(0, a.H), [&](const Range& r) {
        runCostRows(a, r.start, r.end, cost);
    }, rowStripes(a.H));
}

void winnerTakesAll(const Mat& sum, int width, const PipelineParams& p, Mat& disp16, Mat& dispInt, Mat& dispRight,
                    Mat& nonUnique16)
{
    CV_Assert(sum.type() == CV_16UC1 && sum.cols == width * p.numDisparities);
    AggregationState a;
    a.p = p;
    a.W = width;
    a.H = sum.rows;
    a.D = p.numDisparities;
    disp16.create(a.H, a.W, CV_16SC1);
    dispInt.create(a.H, a.W, CV_16SC1);
    dispRight.create(a.H, a.W, CV_16SC1);
    nonUnique16.create(a.H, a.W, CV_16SC1);
    parallel_for_(Range(0, a.H), [&](const Range& r) {
        runSelectRows(a, sum, r.start, r.end, disp16, dispInt, dispRight, nonUnique16);
    }, rowStripes(a.H));
}

}}} // namespace cv::lidarsgm::detail
