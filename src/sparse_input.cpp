// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Sparse disparity input: KITTI-encoded CV_16UC1 (x256, 0 = none) or CV_32FC1 pixels (<= 0, NaN, inf = none),
// to the internal 1/16-pixel CV_16SC1 map.

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void convertSparse(const Mat& sparse, int minDisparity, int numDisparities, Mat& sparse16)
{
    CV_Assert(sparse.type() == CV_16UC1 || sparse.type() == CV_32FC1);
    sparse16.create(sparse.size(), CV_16SC1);
    const int lo = minDisparity, hi = minDisparity + numDisparities - 1;
    const bool isFloat = sparse.type() == CV_32FC1;

    parallel_for_(Range(0, sparse.rows), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            short* dst = sparse16.ptr<short>(y);
            if (isFloat)
            {
                const float* src = sparse.ptr<float>(y);
                for (int x = 0; x < sparse.cols; x++)
                    dst[x] = (short)sparseFromFloat(src[x], lo, hi);
            }
            else
            {
                const ushort* src = sparse.ptr<ushort>(y);
                for (int x = 0; x < sparse.cols; x++)
                    dst[x] = (short)sparseFromKitti16(src[x], lo, hi);
            }
        }
    });
}

}}} // namespace cv::lidarsgm::detail
