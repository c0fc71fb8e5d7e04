// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// matchingResidual (calibration.hpp): each sparse value against the disparity at which its pixel's census block
// matches the right image best nearby; the per-frame calibration check, cheap beside a fusion call.

#include "precomp.hpp"
#include "projection.hpp"
#include "matching_residual.simd.hpp"
#include "matching_residual.simd_declarations.hpp"
#include "opencv2/lidarsgm/calibration.hpp"
#include <algorithm>

namespace cv { namespace lidarsgm {

namespace detail {

static void runMatchingOffsetRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, int radius,
                                  int uniqueness1024, const Range& r, std::vector<int>* offsets16)
{
    CV_CPU_DISPATCH(matchingOffsetRows, (censusL, censusR, sparse16, radius, uniqueness1024, r, offsets16),
                    CV_CPU_DISPATCH_MODES_ALL);
}

} // namespace detail

namespace {

//! The first and last rows of sparse16 with values that have a 3x3 block (not the image's first and last rows);
//! first > last where there are none.
void valueRows(const Mat& sparse16, int& first, int& last)
{
    const auto hasValue = [&](int y) {
        const short* s = sparse16.ptr<short>(y);
        return std::any_of(s, s + sparse16.cols, [](short v) { return v != detail::NO_DISP; });
    };
    first = 1;
    last = sparse16.rows - 2;
    while (first <= last && !hasValue(first))
        first++;
    while (last >= first && !hasValue(last))
        last--;
}

/** The census strings of rows [y0, y0 + rows) of a pair, for the blocks of sparse values in rows [first, last] and
of the same values moved by up to `reach` rows. Those rows alone (a scan covers part of the image: on KITTI the lower
two thirds): a string within the band's inner rows is the full image's, its 9x7 window lying inside the band or
clamped at the image's own border. */
struct CensusBand
{
    Mat left, right;
    int y0;
    CensusBand(const Mat& l, const Mat& r, int first, int last, int reach)
    {
        const int ry = detail::CENSUS_HEIGHT / 2;
        y0 = std::max(first - reach - 1 - ry, 0);
        const int y1 = std::min(last + reach + 2 + ry, l.rows);
        detail::censusTransform(l.rowRange(y0, y1), left);
        detail::censusTransform(r.rowRange(y0, y1), right);
    }
};

/** The median |sparse - matched| (1/16 pixel) over the values of sparse16 (rows [first, last], which the band covers)
with a unique match, or -1 where fewer than kMinCalibrationPoints have one (count receives how many do). */
int medianOffset16(const CensusBand& band, const Mat& sparse16, int first, int last, int radius, int& count)
{
    count = 0;
    if (first > last)
        return -1;
    // The matcher's default uniqueness ratio, as the pipeline takes it (x 1024, rounded).
    static const int uniqueness1024 = cvRound(StereoLidarSGM::create()->getUniquenessRatio() * 1024);
    const Mat rows16 = sparse16.rowRange(band.y0, band.y0 + band.left.rows);
    // |sparse - matched| in 1/16 pixel, per row, so that the rows run in parallel.
    std::vector<std::vector<int> > rows(rows16.rows);
    parallel_for_(Range(first - band.y0, last - band.y0 + 1), [&](const Range& range) {
        detail::runMatchingOffsetRows(band.left, band.right, rows16, radius, uniqueness1024, range, rows.data());
    }, detail::rowStripes(last - first + 1));
    std::vector<int> all;
    for (const std::vector<int>& v : rows)
        all.insert(all.end(), v.begin(), v.end());
    count = (int)all.size();
    if (count < detail::kMinCalibrationPoints)
        return -1;
    std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
    return all[all.size() / 2];
}

//! The inputs of matchingResidual and checkLidar checked, and the sparse map in 1/16 pixel.
void residualInputs(InputArray left, InputArray right, InputArray sparseDisparity, const char* fn, Mat& l, Mat& r,
                    Mat& sparse16)
{
    if (left.kind() == _InputArray::CUDA_GPU_MAT || right.kind() == _InputArray::CUDA_GPU_MAT ||
        sparseDisparity.kind() == _InputArray::CUDA_GPU_MAT)
        CV_Error_(Error::StsBadArg, ("lidarsgm: %s runs on the CPU: pass cv::Mat inputs", fn));
    detail::checkInputs(left, right, sparseDisparity, noArray(), true, fn);
    l = left.getMat();
    r = right.getMat();
    detail::convertSparse(sparseDisparity.getMat(), 0, l.cols, sparse16);
}

//! sparse16's values moved by (dx, dy) pixels into moved16 (NO_DISP where nothing lands).
void moveValues(const Mat& sparse16, int dx, int dy, Mat& moved16)
{
    moved16.create(sparse16.size(), sparse16.type());
    moved16.setTo(Scalar::all(detail::NO_DISP));
    const int w = sparse16.cols - std::abs(dx), h = sparse16.rows - std::abs(dy);
    if (w > 0 && h > 0)
        sparse16(Rect(std::max(-dx, 0), std::max(-dy, 0), w, h))
            .copyTo(moved16(Rect(std::max(dx, 0), std::max(dy, 0), w, h)));
}

} // namespace

double matchingResidual(InputArray left, InputArray right, InputArray sparseDisparity, int searchRadius)
{
    CV_INSTRUMENT_REGION();
    Mat l, r, sparse16;
    residualInputs(left, right, sparseDisparity, "matchingResidual", l, r, sparse16);
    CV_CheckTrue(searchRadius >= 1 && searchRadius <= 64,
                 "lidarsgm: matchingResidual: searchRadius must be in [1, 64]");
    int first, last, count = 0, median16 = -1;
    valueRows(sparse16, first, last);
    if (first <= last)
        median16 = medianOffset16(CensusBand(l, r, first, last, 0), sparse16, first, last, searchRadius, count);
    if (median16 < 0)
        CV_Error_(Error::StsError, ("lidarsgm: matchingResidual: only %d sparse pixels can be compared with the images "
                                    "(at least %d needed): textureless images, an empty sparse map, or one outside "
                                    "the images' overlap", count, detail::kMinCalibrationPoints));
    return median16 / 16.0;
}

LidarCheck checkLidar(InputArray left, InputArray right, InputArray sparseDisparity, double maxResidual, int maxShift)
{
    CV_INSTRUMENT_REGION();
    Mat l, r, sparse16;
    residualInputs(left, right, sparseDisparity, "checkLidar", l, r, sparse16);
    CV_CheckTrue(maxResidual > 0 && maxResidual < 64, "lidarsgm: checkLidar: maxResidual must be in (0, 64) pixels");
    CV_CheckTrue(maxShift >= 0 && maxShift <= 1024, "lidarsgm: checkLidar: maxShift must be in [0, 1024] pixels");
    if (maxShift == 0)
        maxShift = std::max(l.cols / detail::kLidarShiftFraction, 1);
    const int radius = 6;   // matchingResidual's default
    LidarCheck c;
    int first, last, count = 0;
    valueRows(sparse16, first, last);
    if (first > last)
        return c;   // nothing to compare: residual NaN, trusted
    const CensusBand band(l, r, first, last, maxShift);
    const int at0 = medianOffset16(band, sparse16, first, last, radius, count);
    if (at0 < 0)
        return c;
    c.residual = c.shiftedResidual = at0 / 16.0;
    if (c.residual <= maxResidual)
        return c;
    // Above the band: is the map right but misplaced (a calibration error moves the points on the image) or do the
    // images match poorly? Search the moves of the map, coarse to fine, for the one with the lowest residual.
    Mat moved16;
    int best = at0;
    const auto tryMove = [&](int dx, int dy) {
        dx = std::max(-maxShift, std::min(maxShift, dx));
        dy = std::max(-maxShift, std::min(maxShift, dy));
        moveValues(sparse16, dx, dy, moved16);
        int f, t, n;
        valueRows(moved16, f, t);
        const int m = f <= t ? medianOffset16(band, moved16, f, t, radius, n) : -1;
        if (m >= 0 && m < best)
        {
            best = m;
            c.shift = Point(dx, dy);
        }
    };
    int step = (maxShift + 3) / 4;
    for (int j = -4; j <= 4; j++)
        for (int i = -4; i <= 4; i++)
            if (i != 0 || j != 0)
                tryMove(i * step, j * step);
    while (step > 1)
    {
        step = (step + 1) / 2;
        const Point centre = c.shift;
        for (int j = -1; j <= 1; j++)
            for (int i = -1; i <= 1; i++)
                if (i != 0 || j != 0)
                    tryMove(centre.x + i * step, centre.y + j * step);
    }
    c.shiftedResidual = best / 16.0;
    c.trusted = !(c.shiftedResidual < detail::kLidarShiftGain * c.residual);
    return c;
}

}} // namespace cv::lidarsgm
