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

double matchingResidual(InputArray left, InputArray right, InputArray sparseDisparity, int searchRadius)
{
    CV_INSTRUMENT_REGION();
    if (left.kind() == _InputArray::CUDA_GPU_MAT || right.kind() == _InputArray::CUDA_GPU_MAT ||
        sparseDisparity.kind() == _InputArray::CUDA_GPU_MAT)
        CV_Error(Error::StsBadArg, "lidarsgm: matchingResidual runs on the CPU: pass cv::Mat inputs");
    detail::checkInputs(left, right, sparseDisparity, noArray(), true, "matchingResidual");
    CV_CheckTrue(searchRadius >= 1 && searchRadius <= 64,
                 "lidarsgm: matchingResidual: searchRadius must be in [1, 64]");
    const Mat l = left.getMat(), r = right.getMat();
    Mat sparse16;
    detail::convertSparse(sparseDisparity.getMat(), 0, l.cols, sparse16);
    // The rows with sparse values that have a 3x3 block (not the image's first and last).
    const int H = l.rows;
    int first = 1, last = H - 2;
    const auto hasValue = [&](int y) {
        const short* s = sparse16.ptr<short>(y);
        return std::any_of(s, s + sparse16.cols, [](short v) { return v != detail::NO_DISP; });
    };
    while (first <= last && !hasValue(first))
        first++;
    while (last >= first && !hasValue(last))
        last--;
    // |sparse - matched| in 1/16 pixel, per row, so that the rows run in parallel.
    std::vector<std::vector<int> > rows(H);
    if (first <= last)
    {
        // The census strings of the rows that the blocks read, and of those alone (a scan covers part of the image:
        // on KITTI the lower two thirds): a string within the band's inner rows is the full image's, its 9x7 window
        // lying inside the band or clamped at the image's own border.
        const int ry = detail::CENSUS_HEIGHT / 2;
        const int y0 = std::max(first - 1 - ry, 0), y1 = std::min(last + 2 + ry, H);
        Mat censusL, censusR;
        detail::censusTransform(l.rowRange(y0, y1), censusL);
        detail::censusTransform(r.rowRange(y0, y1), censusR);
        const Mat band = sparse16.rowRange(y0, y1);
        // The matcher's default uniqueness ratio, as the pipeline takes it (x 1024, rounded).
        static const int uniqueness1024 = cvRound(StereoLidarSGM::create()->getUniquenessRatio() * 1024);
        parallel_for_(Range(first - y0, last - y0 + 1), [&](const Range& range) {
            detail::runMatchingOffsetRows(censusL, censusR, band, searchRadius, uniqueness1024, range, &rows[y0]);
        }, detail::rowStripes(last - first + 1));
    }
    std::vector<int> all;
    for (const std::vector<int>& v : rows)
        all.insert(all.end(), v.begin(), v.end());
    if (all.size() < (size_t)detail::kMinCalibrationPoints)
        CV_Error_(Error::StsError, ("lidarsgm: matchingResidual: only %d sparse pixels can be compared with the images "
                                    "(at least %d needed): textureless images, an empty sparse map, or one outside "
                                    "the images' overlap", (int)all.size(), detail::kMinCalibrationPoints));
    std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
    return all[all.size() / 2] / 16.0;
}

}} // namespace cv::lidarsgm
