// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU aggregation's sweeps in order (aggregation.simd.hpp), each running the kernels compiled for the best
// instruction set this CPU has (OpenCV's CPU dispatch: baseline, SSE4.1, AVX2), and the tables they read: the right
// census rows as the matching cost reads them and each pixel's DDC terms. Also the volume forms of the matching cost
// and the winner-takes-all, for the per-stage tests: the same kernels.

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

/* The DDC terms (ddcTerm, pipeline.hpp) as table rows: a pixel with prior index k reads ddcTerm(d, k) at
ddcTable[addend + d] (ddcAddends in aggregation.simd.hpp), a row of zeros where it has no prior. Row r (1: w, 2: wCopy,
copiedPrior) holds the term of d - k = j - D at j, so that addend = r * ddcRowLength + D - k. */
void ddcTables(AggregationState& a)
{
    const PipelineParams& p = a.p;
    const int D = a.D;
    a.ddcRowLength = 2 * D + 64;
    a.ddcTable.assign((size_t)3 * a.ddcRowLength, 0);
    for (int r = 1; r <= 2; r++)
        for (int j = 0; j < a.ddcRowLength; j++)
            a.ddcTable[(size_t)r * a.ddcRowLength + j] = (ushort)ddcTerm(j, D, r == 1 ? p.w : p.wCopy);
}

void fillIota(AggregationState& a)
{
    a.iota.resize(MAX_DISPARITIES + 64);
    for (size_t i = 0; i < a.iota.size(); i++)
        a.iota[i] = (ushort)i;
}

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
    ddcTables(a);
    fillIota(a);
}

// CV_CPU_DISPATCH returns from the function it stands in: one small function per kernel.
void runSweepRow(AggregationState& a, int i, int x0, int x1, int strip, bool down)
{
    CV_CPU_DISPATCH(sweepRow, (a, i, x0, x1, strip, down), CV_CPU_DISPATCH_MODES_ALL);
}
void runRightViewRows(const AggregationState& a, int y0, int y1, Mat& dispRight)
{
    CV_CPU_DISPATCH(rightViewRows, (a, y0, y1, dispRight), CV_CPU_DISPATCH_MODES_ALL);
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

/* The windows (the full range without them) and where each tile row's pixels keep their sums in the volume
(AggregationState::rowBase, tileBase); returns the cells the volume needs. */
static size_t volumeLayout(AggregationState& a, const Mat& windows)
{
    const int W = a.W, H = a.H, D = a.D, T = WINDOW_TILE;
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
        for (int tx = tiles.width - 1; tx >= 0; tx--)   // right to left (AggregationState::sum)
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
    return total;
}

//! The winner-takes-all's maps (and the tests' complete sums), which the up sweep writes through the state.
static void winnerOutputs(AggregationState& a, WinnerMaps& out, Mat* finalSum)
{
    const int W = a.W, H = a.H;
    out.disp16.create(H, W, CV_16SC1);
    out.dispInt.create(H, W, CV_16SC1);
    out.dispRight.create(H, W, CV_16SC1);
    a.disp16 = out.disp16;
    a.dispInt = out.dispInt;
    if (ringCheckOn(a.p))
    {
        out.nonUnique16.create(H, W, CV_16SC1);
        a.nonUnique16 = out.nonUnique16;
    }
    else
        a.nonUnique16.release();
    if (finalSum)
    {
        finalSum->create(H, W * a.D, CV_16UC1);
        a.finalSum = *finalSum;
    }
}

/* The vertical directions of each sweep (with 4 paths only the straight one): predecessor at x - dx in the row
before. Each keeps a record per slot (sweepRow). */
static void pathRecords(AggregationState& a)
{
    a.ndirs = a.p.numPaths == 8 ? 3 : 1;
    a.dx[0] = 0; a.dx[1] = 1; a.dx[2] = -1;
    a.stride = a.D + RECORD_PAD;
    const size_t st = a.stride;
    for (int k = 0; k < a.ndirs; k++)
    {
        const int slots = a.W + 2 * a.H;
        a.records[k].assign((size_t)(slots + 1) * st + 2 * RECORD_PAD, PATH_SENTINEL);
    }
}

/* The strips: at least 32 pixels, up to four per thread and the same number for every thread where the width allows
(each thread keeps to its own strips: Wavefront); and the horizontal paths' hand-offs: with diagonal paths the strips
stay within a row of each other (two rows do), else a few rows per thread let a strip run ahead. Where the strips
start: equal widths over the full range; with windows, equal shares of the work, a pixel counting its set-up (as much
as about STRIP_PIXEL_CELLS of its disparities) and its window's width. The strips run a row at a time each
(Wavefront), so a strip with more work holds up the others. Returns the widest strip. */
static int stripLayout(AggregationState& a, int threads)
{
    const int W = a.W, H = a.H, T = WINDOW_TILE;
    const int strips = threads == 1 ? 1 : W / 32 < threads ? std::max(1, W / 32)
                                                            : threads * std::min(4, W / 32 / threads);
    a.strips = strips;
    a.ring = a.ndirs > 1 ? 2 : std::min(H, 2 * threads + 4);
    a.stripX.resize(strips + 1);
    for (int s = 0; s <= strips; s++)
        a.stripX[s] = W * s / strips;
    if (a.narrowed && strips > 1)
    {
        const int minWidth = std::min(16, W / strips);
        std::vector<double> columnWork(W + 1, 0.0);   // prefix sums over the columns
        for (int x = 0; x < W; x++)
        {
            double w = 0;
            for (int ty = 0; ty < a.windows.rows; ty++)
            {
                const Vec2s win = a.windows.at<Vec2s>(ty, x / T);
                w += std::min(T, H - ty * T) * (double)(STRIP_PIXEL_CELLS + win[1] - win[0]);
            }
            columnWork[x + 1] = columnWork[x] + w;
        }
        for (int s = 1, x = 0; s < strips; s++)
        {
            const double share = columnWork[W] * s / strips;
            while (x < W && columnWork[x] < share)
                x++;
            a.stripX[s] = std::min(std::max(x, a.stripX[s - 1] + minWidth), W - (strips - s) * minWidth);
        }
    }
    int widest = 0;
    for (int s = 0; s < strips; s++)
        widest = std::max(widest, a.stripX[s + 1] - a.stripX[s]);
    return widest;
}

/* The hand-off records and, per strip (AggregationState::scratch), first the buffers at fixed addresses, each after
the one before (4 KB of them hold the lot at 128 disparities), then the copies and jump rows. */
static void stripScratch(AggregationState& a, int widest)
{
    const int D = a.D, strips = a.strips;
    const size_t st = a.stride;
    a.edge.create(a.ring, (strips + 1) * a.stride + 2 * RECORD_PAD, CV_16UC1);
    a.edge.setTo(Scalar::all(PATH_SENTINEL));
    const size_t page = 2048;   // 4 KB in elements
    a.scratchSums = st + RECORD_PAD;
    a.scratchIota = a.scratchSums + D + 2 * RECORD_PAD;
    a.scratchDdc = a.scratchIota + D + 2 * RECORD_PAD;
    a.scratchTemp = a.scratchDdc + a.ddcTable.size() + RECORD_PAD;
    a.scratchJumps = a.scratchTemp + (size_t)(a.ndirs + 1) * st + RECORD_PAD;
    a.jumpStride = (size_t)(widest + RECORD_PAD);
    a.scratchRight = a.scratchJumps + (size_t)2 * JUMPS * a.jumpStride;
    a.scratchAddend = a.scratchRight + (size_t)2 * (widest + D + 2 * RECORD_PAD);
    a.scratchPerStrip = (a.scratchAddend + widest + 2 * RECORD_PAD + page - 1) / page * page;
    a.scratchMemory.assign(a.scratchPerStrip * strips + page, PATH_SENTINEL);
    a.scratch = alignPtr(a.scratchMemory.data(), (int)(2 * page));
    for (int s = 0; s < strips; s++)
    {
        ushort* block = a.scratch + a.scratchPerStrip * s;
        std::copy(a.iota.begin(), a.iota.begin() + D + 2 * RECORD_PAD, block + a.scratchIota);
        std::copy(a.ddcTable.begin(), a.ddcTable.end(), block + a.scratchDdc);
    }
    a.noPath.assign(st + 2 * RECORD_PAD, PATH_SENTINEL);
}

/* Strip s offers right-view candidates to right pixels [x0 - minD - D + 1, x1 - minD), i.e. u = W - 1 - xr in
[W - x1 + minD, W - x0 + minD + D - 1): room for every row (those outside the right image are dropped when the strips
are joined). Each strip marks its row empty before the row (sweepRow), so that nothing here runs alone over the
whole. */
static void rightViewLayout(AggregationState& a)
{
    const int W = a.W, strips = a.strips;
    a.rightAt.resize(strips);
    a.rightLo.resize(strips);
    a.rightWidth.resize(strips);
    size_t rightTotal = 0;
    for (int s = 0; s < strips; s++)
    {
        const int x0 = a.stripX[s], x1 = a.stripX[s + 1];
        a.rightLo[s] = W - x1 + a.p.minDisparity;
        a.rightWidth[s] = x1 - x0 + a.D - 1;
        a.rightAt[s] = (int)rightTotal;
        rightTotal += (size_t)a.rightWidth[s] * a.H;
    }
    a.rightCost.resize(rightTotal + 64);
    a.rightIndex.resize(rightTotal + 64);
}

//! aggregateCosts' two forms, finalSum null where the sums are not asked for.
static void aggregate(const AggregationInputs& in, const PipelineParams& p, WinnerMaps& out,
                      Ptr<AggregationState>* work, Mat* finalSum)
{
    CV_Assert(p.edgeThreshold == 0 || !in.left.empty());
    Ptr<AggregationState> temporary;
    Ptr<AggregationState>& held = work ? *work : temporary;
    if (!held)
        held = makePtr<AggregationState>();
    AggregationState& a = *held;
    initState(a, in.censusL, in.censusR, in.prior16, in.left, p, in.own16);
    const int W = a.W, H = a.H, D = a.D;
    const size_t total = volumeLayout(a, in.windows);
    // At least the rows that hold them (W D cells a row: the full range's layout where no window is narrower).
    createVolume(a, std::max((int)((total + (size_t)W * D - 1) / ((size_t)W * D)), 1), W * D);
    winnerOutputs(a, out, finalSum);
    pathRecords(a);
    const int threads = std::max(1, getNumThreads());
    stripScratch(a, stripLayout(a, threads));
    rightViewLayout(a);

    const auto sweep = [&](bool down) {
        // Down: the left-right path enters from the strip on the left; up: the right-left path from the right.
        Wavefront(a.strips, H, a.ndirs > 1, down ? -1 : 1, a.ring).run(threads, [&](int s, int i) {
            runSweepRow(a, i, a.stripX[s], a.stripX[s + 1], s, down);
        });
    };
    sweep(true);
    sweep(false);

    parallel_for_(Range(0, H), [&](const Range& r) { runRightViewRows(a, r.start, r.end, out.dispRight); },
                  rowStripes(H));
}

void aggregateCosts(const AggregationInputs& in, const PipelineParams& p, WinnerMaps& out,
                    Ptr<AggregationState>* work)
{
    aggregate(in, p, out, work, nullptr);
}

void aggregateCosts(const AggregationInputs& in, const PipelineParams& p, WinnerMaps& out, Mat& finalSum,
                    Ptr<AggregationState>* work)
{
    aggregate(in, p, out, work, &finalSum);
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
    fillIota(a);
    disp16.create(a.H, a.W, CV_16SC1);
    dispInt.create(a.H, a.W, CV_16SC1);
    dispRight.create(a.H, a.W, CV_16SC1);
    nonUnique16.create(a.H, a.W, CV_16SC1);
    parallel_for_(Range(0, a.H), [&](const Range& r) {
        runSelectRows(a, sum, r.start, r.end, disp16, dispInt, dispRight, nonUnique16);
    }, rowStripes(a.H));
}

}}} // namespace cv::lidarsgm::detail
