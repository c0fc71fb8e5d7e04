// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Census transform: censusString (pipeline.hpp) of every pixel, coordinates outside the image clamped (replicated
// border); the rows run with the kernels for this CPU's instruction set (census.simd.hpp).

#include "precomp.hpp"
#include "census.simd.hpp"
#include "census.simd_declarations.hpp"

namespace cv { namespace lidarsgm { namespace detail {

static void runCensusRows(const Mat& image, Mat& census, const Range& r)
{
    CV_CPU_DISPATCH(censusRows, (image, census, r), CV_CPU_DISPATCH_MODES_ALL);
}

void censusTransform(const Mat& image, Mat& census)
{
    CV_Assert(image.type() == CV_8UC1 || image.type() == CV_16UC1);
    census.create(image.size(), CV_32SC1);
    parallel_for_(Range(0, image.rows), [&](const Range& r) { runCensusRows(image, census, r); },
                  rowStripes(image.rows));
}

}}} // namespace cv::lidarsgm::detail
