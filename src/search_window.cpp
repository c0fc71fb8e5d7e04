// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The disparity windows (tileWindow, pipeline.hpp): per tile, the range of the prior indices in the tile and the
// tiles around it; where none of them has a prior, the range of the coarse pass's disparities there.

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace {

//! The lowest and highest index seen (kMin > kMax: none).
struct IndexRange
{
    int kMin = INT_MAX, kMax = INT_MIN;
    bool empty() const { return kMin > kMax; }
    void add(int k) { kMin = std::min(kMin, k); kMax = std::max(kMax, k); }
    void add(const IndexRange& r) { kMin = std::min(kMin, r.kMin); kMax = std::max(kMax, r.kMax); }
};

//! Per tile, the union of the index ranges of a map's pixels (rangeAt(x, y), empty: none), each pixel standing for
//! scale x scale pixels.
template <typename RangeAt>
void tileRanges(Size size, int scale, Size tiles, const RangeAt& rangeAt, std::vector<IndexRange>& ranges)
{
    ranges.assign((size_t)tiles.area(), IndexRange());
    const int T = WINDOW_TILE;
    for (int y = 0; y < size.height; y++)
        for (int x = 0; x < size.width; x++)
            ranges[(size_t)(y * scale / T) * tiles.width + x * scale / T].add(rangeAt(x, y));
}

//! The range of one index, clamped to [0, D).
IndexRange clampedRange(int kMin, int kMax, int D)
{
    IndexRange r;
    r.add(std::min(std::max(kMin, 0), D - 1));
    r.add(std::min(std::max(kMax, 0), D - 1));
    return r;
}

//! Each tile's range joined with those of the tiles around it.
void dilateRanges(Size tiles, const std::vector<IndexRange>& in, std::vector<IndexRange>& out)
{
    out.assign(in.size(), IndexRange());
    for (int ty = 0; ty < tiles.height; ty++)
        for (int tx = 0; tx < tiles.width; tx++)
            for (int v = std::max(ty - 1, 0); v <= std::min(ty + 1, tiles.height - 1); v++)
                for (int u = std::max(tx - 1, 0); u <= std::min(tx + 1, tiles.width - 1); u++)
                    out[(size_t)ty * tiles.width + tx].add(in[(size_t)v * tiles.width + u]);
}

} // namespace

PipelineParams coarseParams(const PipelineParams& p)
{
    const int S = COARSE_SCALE;
    PipelineParams q = PipelineParams();
    // Whole coarse disparities covering [minD, minD + D) at full scale: floor(minD / S) up to the last one, their
    // count rounded up to a multiple of 16 (the aggregation's unit on the GPU; the extra ones are clamped away).
    const auto floorDiv = [](int a, int b) { return (a - (((a % b) + b) % b)) / b; };
    q.minDisparity = floorDiv(p.minDisparity, S);
    q.numDisparities = (floorDiv(p.minDisparity + p.numDisparities - 1, S) + 1 - q.minDisparity + 15) / 16 * 16;
    q.numPaths = 4;
    q.subpixel = false;
    q.uniqueness1024 = 1024;
    q.medianSize = 1;
    q.w = computeCostWeights(10, 120, 0, 0, 0.0, 4, false);
    return q;
}

void coarseDisparities(const Mat& left, const Mat& right, const PipelineParams& p, Mat& coarse,
                       Ptr<AggregationState>* work)
{
    CV_Assert(left.type() == right.type() && left.size() == right.size());
    CV_Assert(left.type() == CV_8UC1 || left.type() == CV_16UC1);
    const int S = COARSE_SCALE;
    const Size cs(std::max(left.cols / S, 1), std::max(left.rows / S, 1));
    Mat small[2];
    const Mat* full[2] = { &left, &right };
    for (int i = 0; i < 2; i++)
    {
        small[i].create(cs, left.type());
        parallel_for_(Range(0, cs.height), [&](const Range& r) {
            for (int y = r.start; y < r.end; y++)
                for (int x = 0; x < cs.width; x++)
                {
                    int sum = 0;
                    for (int v = 0; v < S; v++)
                        for (int u = 0; u < S; u++)
                        {
                            const int yy = std::min(y * S + v, left.rows - 1), xx = std::min(x * S + u, left.cols - 1);
                            sum += left.depth() == CV_8U ? full[i]->at<uchar>(yy, xx) : full[i]->at<ushort>(yy, xx);
                        }
                    const int m = coarseMean(sum);
                    if (left.depth() == CV_8U)
                        small[i].at<uchar>(y, x) = (uchar)m;
                    else
                        small[i].at<ushort>(y, x) = (ushort)m;
                }
        }, rowStripes(cs.height));
    }
    const PipelineParams q = coarseParams(p);
    AggregationInputs in;
    censusTransform(small[0], in.censusL);
    censusTransform(small[1], in.censusR);
    WinnerMaps out;
    aggregateCosts(in, q, out, work);
    coarse = out.dispInt;
}

void searchWindows(const Mat& prior16, const Mat& left, const Mat& right, const PipelineParams& p, Mat& windows,
                   Ptr<AggregationState>* work, Mat* coarseOut)
{
    const int T = WINDOW_TILE, D = p.numDisparities, minD = p.minDisparity, S = COARSE_SCALE;
    const Size size = left.size();
    const Size tiles((size.width + T - 1) / T, (size.height + T - 1) / T);
    std::vector<IndexRange> own, near;
    if (!prior16.empty())
    {
        CV_Assert(prior16.type() == CV_16SC1 && prior16.size() == size);
        tileRanges(size, 1, tiles, [&](int x, int y) {
            const short v = prior16.at<short>(y, x);
            return v == NO_DISP ? IndexRange() : clampedRange(roundDisp16(v) - minD, roundDisp16(v) - minD, D);
        }, own);
    }
    else
        own.assign((size_t)tiles.area(), IndexRange());
    dilateRanges(tiles, own, near);
    // The coarse pass only where a tile has no prior around it.
    bool needCoarse = false;
    for (const IndexRange& r : near)
        needCoarse = needCoarse || r.empty();
    std::vector<IndexRange> coarseNear;
    Mat coarse;
    if (needCoarse)
    {
        coarseDisparities(left, right, p, coarse, work);
        // A coarse disparity c stands for the full-scale disparities c S - S .. c S + S (the rounding of both).
        std::vector<IndexRange> coarseOwn;
        tileRanges(coarse.size(), S, tiles, [&](int x, int y) {
            const short v = coarse.at<short>(y, x);
            return v == NO_DISP ? IndexRange() : clampedRange(v * S - S - minD, v * S + S - minD, D);
        }, coarseOwn);
        dilateRanges(tiles, coarseOwn, coarseNear);
    }
    windows.create(tiles, CV_16SC2);
    for (int ty = 0; ty < tiles.height; ty++)
        for (int tx = 0; tx < tiles.width; tx++)
        {
            const size_t i = (size_t)ty * tiles.width + tx;
            const IndexRange r = !near[i].empty() ? near[i] : coarseNear.empty() ? IndexRange() : coarseNear[i];
            int lo = 0, hi = D;
            if (!r.empty())
                tileWindow(r.kMin, r.kMax, p.searchWindow, D, lo, hi);
            windows.at<Vec2s>(ty, tx) = Vec2s((short)lo, (short)hi);
        }
    if (coarseOut)
        *coarseOut = coarse;
}

int64 windowCells(const Mat& windows, Size size)
{
    const int T = WINDOW_TILE;
    int64 cells = 0;
    for (int ty = 0; ty < windows.rows; ty++)
        for (int tx = 0; tx < windows.cols; tx++)
        {
            const Vec2s w = windows.at<Vec2s>(ty, tx);
            const int tw = std::min(T, size.width - tx * T), th = std::min(T, size.height - ty * T);
            cells += (int64)tw * th * (w[1] - w[0]);
        }
    return cells;
}

}}} // namespace cv::lidarsgm::detail
