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
    a.costRow[0].create(1, W * D, CV_16UC1);
    a.costRow[1].create(1, W * D, CV_16UC1);
    const int threads = std::max(1, getNumThreads());
    const int strips = threads == 1 ? 1 : std::max(1, std::min(4 * threads, W / 32));
    a.rightCost.assign((size_t)strips * W, 0);
    a.rightIndex.assign((size_t)strips * W, (ushort)RightView::NONE);

    // 1. Down: the horizontal paths of row y - 1 (task 0) and row y's strips (tasks 1 .. strips) together.
    a.cur = 0;
    for (int y = 0; y <= H; y++)
    {
        const int first = y > 0 ? 0 : 1, last = y < H ? strips + 1 : 1;
        parallel_for_(Range(first, last), [&](const Range& r) {
            for (int t = r.start; t < r.end; t++)
                if (t == 0)
                    runHorizontalRow(a, y - 1);
                else
                    runVerticalStrip(a, y, W * (t - 1) / strips, W * t / strips, t - 1, true);
        }, last - first);
        a.cur = 1 - a.cur;
    }

    // 2. Up: the bottom-up paths complete the sums; the winner is taken at once.
    a.cur = 0;
    AutoBuffer<ushort> mergedCost(W), mergedIndex(W);
    for (int y = H - 1; y >= 0; y--)
    {
        parallel_for_(Range(0, strips), [&](const Range& r) {
            for (int s = r.start; s < r.end; s++)
                runVerticalStrip(a, y, W * s / strips, W * (s + 1) / strips, s, false);
        }, strips);
        a.cur = 1 - a.cur;
        // The right view of row y: strip by strip from the left, a strip's candidate replaces the one so far only at
        // a lower cost (its disparities are larger: RightView). Strip s offers to right pixels
        // [x0 - minD - D + 1, x1 - minD) only, u = W - 1 - xr.
        std::fill(mergedIndex.data(), mergedIndex.data() + W, (ushort)RightView::NONE);
        for (int s = 0; s < strips; s++)
        {
            ushort* c = a.rightCost.data() + (size_t)s * W;
            ushort* k = a.rightIndex.data() + (size_t)s * W;
            const int lo = std::max(W - W * (s + 1) / strips + p.minDisparity, 0);
            const int hi = std::min(W - W * s / strips + p.minDisparity + D - 1, W);
            for (int u = lo; u < hi; u++)
                if (k[u] != RightView::NONE && (mergedIndex[u] == RightView::NONE || c[u] < mergedCost[u]))
                {
                    mergedCost[u] = c[u];
                    mergedIndex[u] = k[u];
                }
            std::fill(k + lo, k + std::max(lo, hi), (ushort)RightView::NONE);
        }
        short* dr = dispRight.ptr<short>(y);
        for (int xr = 0; xr < W; xr++)
        {
            const ushort k = mergedIndex[W - 1 - xr];
            dr[xr] = (short)(k == RightView::NONE ? NO_DISP : k + p.minDisparity);
        }
    }
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
