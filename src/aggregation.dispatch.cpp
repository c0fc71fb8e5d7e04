// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU aggregation's sweeps in order (aggregation.simd.hpp), each running the kernels compiled for the best
// instruction set this CPU has (OpenCV's CPU dispatch: baseline, SSE4.1, AVX2). Also the volume forms of the
// matching cost and the winner-takes-all, for the per-stage tests: the same kernels.

#include "precomp.hpp"
#include "aggregation.simd.hpp"
#include "aggregation.simd_declarations.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace {

void initState(AggregationState& a, const Mat& censusL, const Mat& censusR, const Mat& prior16, const Mat& left,
               const PipelineParams& p)
{
    CV_Assert(censusL.type() == CV_32SC1 && censusR.type() == CV_32SC1 && censusR.size() == censusL.size());
    CV_Assert(prior16.empty() || (prior16.type() == CV_16SC1 && prior16.size() == censusL.size()));
    a.censusL = censusL;
    a.censusR = censusR;
    a.prior16 = prior16;
    a.p = p;
    a.W = censusL.cols;
    a.H = censusL.rows;
    a.D = p.numDisparities;
    a.stride = a.D + 2;
    if (p.edgeThreshold > 0 && !left.empty())
    {
        CV_Assert(left.size() == censusL.size());
        left.convertTo(a.intensity, CV_16U);   // the edge rule reads 16-bit intensities (8-bit values unchanged)
    }
}

// CV_CPU_DISPATCH returns from the function it stands in: one small function per kernel.
void runHorizontalRow(AggregationState& a, int y)
{
    CV_CPU_DISPATCH(horizontalRow, (a, y), CV_CPU_DISPATCH_MODES_ALL);
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
                   Mat& dispRight)
{
    CV_CPU_DISPATCH(selectRows, (a, sum, y0, y1, disp16, dispInt, dispRight), CV_CPU_DISPATCH_MODES_ALL);
}

} // namespace

void aggregateCosts(const Mat& censusL, const Mat& censusR, const Mat& prior16, const Mat& left,
                    const PipelineParams& p, Mat& disp16, Mat& dispInt, Mat& dispRight, OutputArray finalSum,
                    Mat* workVolume)
{
    CV_Assert(p.edgeThreshold == 0 || !left.empty());
    AggregationState a;
    initState(a, censusL, censusR, prior16, left, p);
    const int W = a.W, H = a.H, D = a.D;
    if (workVolume)
    {
        workVolume->create(H, W * D, CV_16UC1);
        a.sum = *workVolume;
    }
    else
        a.sum.create(H, W * D, CV_16UC1);
    disp16.create(H, W, CV_16SC1);
    dispInt.create(H, W, CV_16SC1);
    dispRight.create(H, W, CV_16SC1);
    a.disp16 = disp16;
    a.dispInt = dispInt;
    if (finalSum.needed())
    {
        finalSum.create(H, W * D, CV_16UC1);
        a.finalSum = finalSum.getMat();
    }

    // The strips of a row: several per thread, so that the threads that do not take the horizontal paths of the row
    // before (the longest task of a down step, started first) share the strips evenly.
    a.ndirs = p.numPaths == 8 ? 3 : 1;
    a.dx[0] = 0; a.dx[1] = 1; a.dx[2] = -1;
    for (int k = 0; k < a.ndirs; k++)
        for (int i = 0; i < 2; i++)
        {
            a.L[k][i].assign((size_t)W * a.stride, PATH_SENTINEL);
            a.minL[k][i].assign(W, 0);
        }
    // With 4 paths a column depends only on itself: a strip runs a block of rows on its own, and the horizontal paths
    // of the block before run beside it (fewer barriers). The diagonals of 8 paths need the neighbours' last row, so
    // there a down step is one row; its horizontal paths (a quarter of a row's work, one task) wait for a batch of
    // hBatch rows, one task each, so that no step waits on one long task while the other threads idle. The ring of
    // cost rows holds the rows waiting for their horizontal paths and the block being written.
    const int threads = std::max(1, getNumThreads());
    const int block = a.ndirs == 1 ? 8 : 1;
    const int hBatch = a.ndirs == 1 ? block : std::min(threads, 8);
    a.costRows.create(hBatch + block, W * D, CV_16UC1);
    const int strips = threads == 1 ? 1 : std::max(1, std::min(4 * threads, W / 32));
    // Strip s offers right-view candidates to right pixels [x0 - minD - D + 1, x1 - minD), i.e. u = W - 1 - xr in
    // [W - x1 + minD, W - x0 + minD + D - 1): room for every row.
    a.rightAt.resize(strips);
    a.rightLo.resize(strips);
    a.rightWidth.resize(strips);
    size_t total = 0;
    for (int s = 0; s < strips; s++)
    {
        const int x0 = W * s / strips, x1 = W * (s + 1) / strips;
        a.rightLo[s] = std::max(W - x1 + p.minDisparity, 0);
        a.rightWidth[s] = std::max(std::min(W - x0 + p.minDisparity + D - 1, W) - a.rightLo[s], 0);
        a.rightAt[s] = (int)total;
        total += (size_t)a.rightWidth[s] * H;
    }
    a.rightCost.resize(total);
    a.rightIndex.assign(total, (ushort)RightView::NONE);

    // 1. Down, block by block: the horizontal paths of the rows finished before (first, a task per row: they are the
    // longest tasks), once hBatch of them wait or at the end, and the strips of this block's rows together.
    const int blocks = (H + block - 1) / block;
    int hDone = 0;
    for (int b = 0; b <= blocks; b++)
    {
        const int y0 = std::min(H, b * block), y1 = std::min(H, y0 + block);
        const int h0 = hDone, hRows = y0 - hDone >= hBatch || b == blocks ? y0 - hDone : 0;
        hDone += hRows;
        const int tasks = hRows + (b < blocks ? strips : 0);
        parallel_for_(Range(0, tasks), [&](const Range& r) {
            for (int t = r.start; t < r.end; t++)
                if (t < hRows)
                    runHorizontalRow(a, h0 + t);
                else
                    for (int y = y0; y < y1; y++)
                        runVerticalStrip(a, y, W * (t - hRows) / strips, W * (t - hRows + 1) / strips, t - hRows, true);
        }, tasks);
    }

    // 2. Up: the bottom-up paths complete the sums; the winner is taken at once. With 4 paths a column depends only
    // on itself, so each strip runs all rows on its own; the diagonals of 8 paths need the neighbours' last row.
    const auto up = [&](int s, int y) { runVerticalStrip(a, y, W * s / strips, W * (s + 1) / strips, s, false); };
    if (a.ndirs == 1)
        parallel_for_(Range(0, strips), [&](const Range& r) {
            for (int s = r.start; s < r.end; s++)
                for (int y = H - 1; y >= 0; y--)
                    up(s, y);
        }, strips);
    else
        for (int y = H - 1; y >= 0; y--)
            parallel_for_(Range(0, strips), [&](const Range& r) {
                for (int s = r.start; s < r.end; s++)
                    up(s, y);
            }, strips);

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
    }, std::max(1, H / 16));
}

void computeMatchingCost(const Mat& censusL, const Mat& censusR, const Mat& prior16, const PipelineParams& p,
                         Mat& cost)
{
    AggregationState a;
    initState(a, censusL, censusR, prior16, Mat(), p);
    cost.create(a.H, a.W * a.D, CV_16UC1);
    parallel_for_(Range(0, a.H), [&](const Range& r) {
        runCostRows(a, r.start, r.end, cost);
    }, std::max(1, a.H / 16));
}

void winnerTakesAll(const Mat& sum, int width, const PipelineParams& p, Mat& disp16, Mat& dispInt, Mat& dispRight)
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
    parallel_for_(Range(0, a.H), [&](const Range& r) {
        runSelectRows(a, sum, r.start, r.end, disp16, dispInt, dispRight);
    }, std::max(1, a.H / 16));
}

}}} // namespace cv::lidarsgm::detail
