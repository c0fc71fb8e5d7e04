// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Ring interpolation (beyond the paper; the rule is in pipeline.hpp): a spinning LiDAR samples the scene in rings, and
// with 16 or 32 of them the rows between rings hold no sparse point, so semidensification (a window of rs around
// each point) leaves bands without a prior. Surfaces seen from both neighbouring rings (road, walls, vehicle sides)
// are locally planar, and a plane's disparity is linear in the image, so the column interpolation between the rings
// is that surface's disparity; the census cost test, as for semidensification's own candidates, rejects it where the
// pixel shows something else. The gap limit follows the ring spacing measured on each map, so one setting serves
// every LiDAR density. Beyond the outermost rings (the near road below the lowest one) the line through the two
// nearest rings is extended: a plane again.

#include "precomp.hpp"
#include "cpu_stages.hpp"
#include "sparse_window.hpp"
#include "ring_interpolation.simd.hpp"
#include "ring_interpolation.simd_declarations.hpp"

namespace cv { namespace lidarsgm { namespace detail {

static void runRingAboveBelow(const Mat& sparse16, Mat& above16, Mat& below16)
{
    CV_CPU_DISPATCH(ringAboveBelow, (sparse16, above16, below16), CV_CPU_DISPATCH_MODES_ALL);
}
static void runRingNearestRows(const Mat& above16, const Mat& below16, Mat& nearest, const Range& r)
{
    CV_CPU_DISPATCH(ringNearestRows, (above16, below16, nearest, r), CV_CPU_DISPATCH_MODES_ALL);
}
static void runRingFillRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const Mat& nearest,
                            const PipelineParams& p, int gap, Mat& semidense16, const Range& r)
{
    CV_CPU_DISPATCH(ringFillRows, (censusL, censusR, sparse16, nearest, p, gap, semidense16, r),
                    CV_CPU_DISPATCH_MODES_ALL);
}

void ringNearestMaps(const Mat& sparse16, RingMaps& rings)
{
    CV_Assert(sparse16.type() == CV_16SC1);
    const int W = sparse16.cols, H = sparse16.rows;
    rings.above16.create(H, W, CV_16SC1);
    rings.below16.create(H, W, CV_16SC1);
    rings.nearest.create(H, W, CV_16SC4);
    runRingAboveBelow(sparse16, rings.above16, rings.below16);
    parallel_for_(Range(0, H), [&](const Range& r) {
        runRingNearestRows(rings.above16, rings.below16, rings.nearest, r);
    }, rowStripes(H));
}

void interpolateRings(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                      Mat& semidense16, RingMaps& rings, const SparseColumns* points)
{
    rings.valid = false;
    if (p.ringGapFactor16 <= 0 || sparse16.empty())
        return;
    CV_Assert(sparse16.type() == CV_16SC1 && semidense16.type() == CV_16SC1 && sparse16.size() == censusL.size() &&
              semidense16.size() == censusL.size());
    const int W = censusL.cols, H = censusL.rows;
    ringNearestMaps(sparse16, rings);
    // The ring spacing: each sparse point's distance to the nearest point below it (ringPointGap), their median.
    SparseColumns own;
    if (!points)
        own.build(sparse16);
    const SparseColumns& pts = points ? *points : own;
    CV_Assert((int)pts.rowStart.size() == H + 1);
    int hist[RING_GAP_BINS] = {};
    for (int y = 0; y < H; y++)
    {
        const Vec4s* near = rings.nearest.ptr<Vec4s>(y);
        for (int i = pts.rowStart[y]; i < pts.rowStart[y + 1]; i++)
        {
            const int yb = near[pts.column[i]][3];
            if (yb >= 0)
                hist[std::min(yb - y, (int)RING_GAP_BINS - 1)]++;
        }
    }
    const int gap = ringGapLimit(p.ringGapFactor16, histogramLowerMedian(hist, RING_GAP_BINS));
    rings.gap = gap;
    rings.valid = true;
    CV_Assert(W > 0);
    parallel_for_(Range(0, H), [&](const Range& r) {
        runRingFillRows(censusL, censusR, sparse16, rings.nearest, p, gap, semidense16, r);
    }, rowStripes(H));
}

}}} // namespace cv::lidarsgm::detail
