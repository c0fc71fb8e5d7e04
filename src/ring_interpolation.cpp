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

namespace cv { namespace lidarsgm { namespace detail {

void interpolateRings(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                      Mat& semidense16, RingMaps& rings)
{
    rings.valid = false;
    if (p.ringGapFactor16 <= 0 || sparse16.empty())
        return;
    CV_Assert(sparse16.type() == CV_16SC1 && semidense16.type() == CV_16SC1 && sparse16.size() == censusL.size() &&
              semidense16.size() == censusL.size());
    const int W = censusL.cols, H = censusL.rows;
    Mat& above16 = rings.above16;
    Mat& below16 = rings.below16;
    above16.create(H, W, CV_16SC1);
    below16.create(H, W, CV_16SC1);
    // Row y's maps from row y - 1's (above) and row y + 1's (below): one pass each way, row by row.
    above16.row(0).setTo(Scalar::all(-1));
    for (int y = 1; y < H; y++)
    {
        const short *s = sparse16.ptr<short>(y - 1), *prev = above16.ptr<short>(y - 1);
        short* a = above16.ptr<short>(y);
        for (int x = 0; x < W; x++)
            a[x] = s[x] != NO_DISP ? (short)(y - 1) : prev[x];
    }
    below16.row(H - 1).setTo(Scalar::all(-1));
    for (int y = H - 2; y >= 0; y--)
    {
        const short *s = sparse16.ptr<short>(y + 1), *next = below16.ptr<short>(y + 1);
        short* b = below16.ptr<short>(y);
        for (int x = 0; x < W; x++)
            b[x] = s[x] != NO_DISP ? (short)(y + 1) : next[x];
    }
    int hist[RING_GAP_BINS] = {};
    for (int y = 0; y < H; y++)
    {
        const short* s = sparse16.ptr<short>(y);
        for (int x = 0; x < W; x++)
        {
            const int g = s[x] != NO_DISP ? ringPointGap(above16.ptr<short>(y), below16.ptr<short>(y), x, W, y)
                                          : -1;
            if (g >= 0)
                hist[g]++;
        }
    }
    const int gap = ringGapLimit(p.ringGapFactor16, histogramLowerMedian(hist, RING_GAP_BINS));
    rings.gap = gap;
    rings.valid = true;
    const int Ts = p.semidenseThreshold, lo = p.minDisparity, hi = p.minDisparity + p.numDisparities - 1;
    const short *above = above16.ptr<short>(), *below = below16.ptr<short>(), *sparse = sparse16.ptr<short>();
    const size_t step = above16.step1(), sparseStep = sparse16.step1();
    CV_Assert(below16.step1() == step);
    parallel_for_(Range(0, H), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            const unsigned* L = censusL.ptr<unsigned>(y);
            const unsigned* R = censusR.ptr<unsigned>(y);
            short* out = semidense16.ptr<short>(y);
            for (int x = 0; x < W; x++)
            {
                if (out[x] != NO_DISP)
                    continue;
                const int v = ringCandidate16(above, below, step, sparse, sparseStep, x, y, W, gap);
                if (v == NO_DISP || !sparseInRange(v, lo, hi))
                    continue;
                const int xr = std::min(std::max(x - roundDisp16(v), 0), W - 1);
                if (popcount32(L[x] ^ R[xr]) < Ts)
                    out[x] = (short)v;
            }
        }
    }, rowStripes(H));
}

}}} // namespace cv::lidarsgm::detail
