// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification (paper Sec. IV-B, Eq. 5): spread the LiDAR disparities to pixels whose census matches them.
// No smoothness here on purpose (the paper: keeps thin structures; SGM smooths later).

#include "precomp.hpp"
#include "semidensification.simd.hpp"
#include "semidensification.simd_declarations.hpp"

namespace cv { namespace lidarsgm { namespace detail {

static void runSemidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                               const PipelineParams& p, Mat& semidense16, const Range& r)
{
    CV_CPU_DISPATCH(semidensifyRows, (censusL, censusR, sparse16, cols, p, semidense16, r), CV_CPU_DISPATCH_MODES_ALL);
}

void semidensify(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                 Mat& semidense16, const SparseColumns* points)
{
    const int H = censusL.rows;
    CV_Assert(sparse16.type() == CV_16SC1 && sparse16.size() == censusL.size());
    semidense16.create(censusL.size(), CV_16SC1);
    SparseColumns own;
    if (!points)
        own.build(sparse16);
    const SparseColumns& cols = points ? *points : own;

    parallel_for_(Range(0, H), [&](const Range& r) {
        runSemidensifyRows(censusL, censusR, sparse16, cols, p, semidense16, r);
    }, rowStripes(H));
}

}}} // namespace cv::lidarsgm::detail
