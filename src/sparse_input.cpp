// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Sparse disparity input: KITTI-encoded CV_16UC1 (x256, 0 = none) or CV_32FC1 pixels (<= 0, NaN, inf = none),
// to the internal 1/16-pixel CV_16SC1 map.

#include "precomp.hpp"
#include "cpu_stages.hpp"
#include <atomic>

namespace cv { namespace lidarsgm { namespace detail {

namespace {

template <typename T, typename Convert>
void convertRows(const Mat& sparse, int lo, int hi, Mat& sparse16, SparseCounts* counts, Convert convert)
{
    std::atomic<int> measured(0), inRange(0), beyond(0);
    const int width = sparse.cols;
    parallel_for_(Range(0, sparse.rows), [&](const Range& r) {
        int m = 0, k = 0, b = 0;
        for (int y = r.start; y < r.end; y++)
        {
            const T* src = sparse.ptr<T>(y);
            short* dst = sparse16.ptr<short>(y);
            for (int x = 0; x < width; x++)
            {
                const int d16 = convert(src[x], lo, hi);
                dst[x] = (short)d16;
                bool measuredHere, kept, beyondHere;
                countSparseValue(src[x], d16, width, measuredHere, kept, beyondHere);
                m += measuredHere;
                k += kept;
                b += beyondHere;
            }
        }
        measured += m;
        inRange += k;
        beyond += b;
    });
    if (counts)
        *counts = { measured.load(), inRange.load(), beyond.load() };
}

} // namespace

void convertSparse(const Mat& sparse, int minDisparity, int numDisparities, Mat& sparse16, SparseCounts* counts)
{
    CV_Assert(sparse.type() == CV_16UC1 || sparse.type() == CV_32FC1);
    sparse16.create(sparse.size(), CV_16SC1);
    const int lo = minDisparity, hi = minDisparity + numDisparities - 1;
    if (sparse.type() == CV_32FC1)
        convertRows<float>(sparse, lo, hi, sparse16, counts,
                           [](float v, int l, int h) { return sparseFromFloat(v, l, h); });
    else
        convertRows<ushort>(sparse, lo, hi, sparse16, counts,
                            [](ushort v, int l, int h) { return sparseFromKitti16(v, l, h); });
}

void checkSparseUnits(const SparseCounts& c, int sparseType, const PipelineParams& p, bool& warned)
{
    const int lo = p.minDisparity, hi = p.minDisparity + p.numDisparities;
    if (unitsLookWrong(c))
    {
        const double share = 100.0 * c.beyond / c.measured;
        if (sparseType == CV_32FC1)
            LIDARSGM_Error_(Error::StsOutOfRange,
                            ("lidarsgm: %.1f %% of the %d values of the sparse disparity map (CV_32F, pixels) lie outside "
                             "the search range [%d, %d) px and beyond the image's width, where no disparity can be. A "
                             "KITTI disparity PNG holds pixels x 256: pass its CV_16U map as it is (the matcher divides "
                             "by 256), or divide it by 256 for CV_32F. If the values are pixels, check the projection's "
                             "focalBaseline", share, c.measured, lo, hi));
        LIDARSGM_Error_(Error::StsOutOfRange,
                        ("lidarsgm: %.1f %% of the %d values of the sparse disparity map (CV_16U, KITTI's pixels x 256) "
                         "lie outside the search range [%d, %d) px and beyond the image's width, where no disparity "
                         "can be. A CV_16U map must hold disparity x 256: give pixels as CV_32F instead. If the "
                         "encoding is right, check the projection's focalBaseline", share, c.measured, lo, hi));
    }
    const bool needsPriors = p.ddc || p.lidarCheck;
    if (needsPriors && c.inRange == 0 && !warned)
    {
        warned = true;
        lidarsgmWarning(cv::format("lidarsgm: the sparse disparity map has no value in the search range [%d, %d) px "
                                   "(%d measurements, none in range; 0, negative, NaN and infinite values are none): "
                                   "this matcher fuses without the LiDAR. Check the projection, or for stereo "
                                   "alone use MODE_SGM with CHECK_STEREO (said once per matcher)",
                                   lo, hi, c.measured));
    }
}

}}} // namespace cv::lidarsgm::detail
