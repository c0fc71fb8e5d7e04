// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Visibility filter of the sparse input. The LiDAR sits apart from the camera and sees past the edges of near objects,
// so background points land on the near object in the image: wrong priors for semidensification, DDC and the LiDAR
// check. The near object's own points lie around them, within one sample spacing plus the parallax band that widens
// with the depth step; a point with a nearer point (by more than Tc) within that window is dropped (hiddenBy). The base
// window is the sensor's sample footprint: about half the spacing of neighbouring samples, plus the half pixel of
// rounding (doc/decisions.md derives it for KITTI's HDL-64E).

#include "precomp.hpp"

#include <algorithm>
#include "cpu_stages.hpp"
#include "sparse_window.hpp"
#include "opencv2/imgproc.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void scanGapHistograms(const Mat& sparse16, int* rowGaps, int* columnGaps)
{
    const int W = sparse16.cols, H = sparse16.rows;
    std::fill(rowGaps, rowGaps + SCAN_GAP_BINS, 0);
    std::fill(columnGaps, columnGaps + SCAN_GAP_BINS, 0);
    for (int y = 0; y < H; y++)
    {
        const short* s = sparse16.ptr<short>(y);
        for (int x = 0; x < W; x++)
            if (s[x] != NO_DISP)
            {
                const int gr = rowPointGap(s, x, W);
                const int gc = columnPointGap(sparse16.ptr<short>(), sparse16.step1(), x, y, W, H);
                if (gr >= 0)
                    rowGaps[gr]++;
                if (gc >= 0)
                    columnGaps[gc]++;
            }
    }
}

bool isLidarScan(const Mat& sparse16)
{
    int rowGaps[SCAN_GAP_BINS], columnGaps[SCAN_GAP_BINS];
    scanGapHistograms(sparse16, rowGaps, columnGaps);
    return visibilityGrowthApplies(rowGaps, columnGaps);
}

void filterHiddenPoints(const Mat& sparse16, const PipelineParams& params, Mat& visible16, bool scan)
{
    CV_Assert(sparse16.type() == CV_16SC1 && sparse16.data != visible16.data);
    PipelineParams p = params;
    if (p.visibilityParallax256 > 0 && !scan)
        p.visibilityParallax256 = 0;
    const int W = sparse16.cols, H = sparse16.rows, g = visibilityGrowth(p);
    const int rx = p.visibilityRadiusX + g, ry = p.visibilityRadiusY + g;   // the largest window
    const SparseColumns cols(sparse16);
    // A point can be hidden only by a value more than Tc above it in the base window, or at k pixels beyond it (k up
    // to g) by one at least k 4096 / visibilityParallax256 above it (hiddenBy). So the highest value of each pixel's
    // window grown by k = 0, 1, 2, 4, ... g (dilations; NO_DISP is the lowest short) rules out most points at once,
    // even on surfaces whose disparity changes across the window (the ground), before the exact search.
    std::vector<int> growths(1, 0);
    for (int k = 1; k <= g; k *= 2)
        growths.push_back(std::min(k, g));
    if (growths.back() < g)
        growths.push_back(g);
    std::vector<Mat> windowMax(growths.size());
    for (size_t i = 0; i < growths.size(); i++)
        dilate(sparse16, windowMax[i], getStructuringElement(MORPH_RECT, Size(2 * (p.visibilityRadiusX + growths[i]) + 1,
                                                                               2 * (p.visibilityRadiusY + growths[i]) + 1)));
    const auto mayBeHidden = [&](int x, int y, int d16) {
        for (size_t i = 0; i < growths.size(); i++)
        {
            const int above = windowMax[i].at<short>(y, x) - d16;
            if (above > p.checkThreshold16 &&
                (i == 0 || growths[i - 1] + 1 <= visibilityGrowthAllowed(above, p)))
                return true;
        }
        return false;
    };
    visible16.create(sparse16.size(), CV_16SC1);
    parallel_for_(Range(0, H), [&](const Range& r) {
        WindowCursor win(cols, ry, r.start);
        for (int y = r.start; y < r.end; y++)
        {
            win.moveTo(y);
            const short* s = sparse16.ptr<short>(y);
            short* out = visible16.ptr<short>(y);
            for (int x = 0; x < W; x++)
            {
                out[x] = s[x];
                if (s[x] == NO_DISP || !mayBeHidden(x, y, s[x]))
                    continue;
                bool hidden = false;
                for (int u = std::max(x - rx, 0); u <= std::min(x + rx, W - 1) && !hidden; u++)
                    for (int i = win.lo[u]; i < win.hi[u]; i++)
                        if (hiddenBy(cols.value[i], s[x], u - x, cols.row[i] - y, p))
                        {
                            hidden = true;
                            break;
                        }
                if (hidden)
                    out[x] = NO_DISP;
            }
        }
    }, rowStripes(H));
}

}}} // namespace cv::lidarsgm::detail
