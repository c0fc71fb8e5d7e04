// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CUDA stages (src_cuda/cuda_stages.hpp) one at a time with GpuMats, each the twin of the CPU stage of the same
// name (src/cpu_stages.hpp), so that a test can hold every stage against the CPU's and a mismatch names the stage.
// Exported for the per-stage tests; not part of the public API. Each call allocates its outputs and scratch and
// waits for the GPU (the pipeline itself does neither). Built without CUDA, every call raises GpuNotSupported.

#ifndef OPENCV_LIDARSGM_CUDA_STAGES_HOST_HPP
#define OPENCV_LIDARSGM_CUDA_STAGES_HOST_HPP

#include "pipeline.hpp"
#include "opencv2/core/cuda.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_host {

using cv::cuda::GpuMat;

//! sparse: CV_16UC1 (x256) or CV_32FC1 pixels; sparse16 receives the internal map.
CV_EXPORTS void convertSparse(const GpuMat& sparse, int minDisparity, int numDisparities, GpuMat& sparse16);
//! The scan test on the device (isLidarScan).
CV_EXPORTS bool isLidarScan(const GpuMat& sparse16);
//! The scan test's histograms on the device (scanGapHistograms): 1 x 2 SCAN_GAP_BINS ints, the rows' then the columns'.
CV_EXPORTS Mat scanGapHistograms(const GpuMat& sparse16);
//! The visibility filter, with the scan test run on the device first, as the pipeline runs them.
CV_EXPORTS void filterHiddenPoints(const GpuMat& sparse16, const PipelineParams& p, GpuMat& visible16);
/** Both images' census strings (CV_8UC1 or CV_16UC1 in); censusR is a view of a padded buffer, as the pipeline's
(the padding the path kernel reads for p's disparity range). */
CV_EXPORTS void censusTransform(const GpuMat& left, const GpuMat& right, const PipelineParams& p, GpuMat& censusL,
                                GpuMat& censusR);
//! censusL and censusR from censusTransform.
CV_EXPORTS void semidensify(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& sparse16,
                            const PipelineParams& p, GpuMat& semidense16);
//! semidense16: in and out (the pixels without a value get the rule's); above, below and gap as RingMaps holds them.
CV_EXPORTS void interpolateRings(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& sparse16,
                                 const PipelineParams& p, GpuMat& semidense16, GpuMat& above16, GpuMat& below16,
                                 int& gap);
/** The disparity windows (CV_16SC2 per tile, as the CPU's searchWindows); coarse (where given): the coarse pass's
integer disparities, which the CUDA path computes on every call. */
CV_EXPORTS void searchWindows(const GpuMat& prior16, const GpuMat& left, const GpuMat& right, const PipelineParams& p,
                              GpuMat& windows, GpuMat* coarse = nullptr);
/** The aggregated costs (the CPU's finalSum; where windows are given, within them only: the rest is not written). own16 and
scan: copied priors take p.wCopy where scan is true (copiedPrior); own16 empty: w everywhere. smCount: the path kernel's
layout as for a stream on that many multiprocessors (0: the device's). */
CV_EXPORTS void aggregateCosts(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& prior16,
                               const GpuMat& left, const PipelineParams& p, const GpuMat& own16, bool scan,
                               GpuMat& sum, const GpuMat& windows = GpuMat(), int smCount = 0);
//! nonUnique16 is written only where ringCheckOn(p), as on the CPU.
CV_EXPORTS void winnerTakesAll(const GpuMat& sum, int width, const PipelineParams& p, GpuMat& disp16,
                               GpuMat& dispInt, GpuMat& dispRight, GpuMat& nonUnique16,
                               const GpuMat& windows = GpuMat());
CV_EXPORTS void medianFilter(const GpuMat& src, GpuMat& dst);
/** rings: above16, below16 and gap of interpolateRings, or empty maps for none (as RingMaps with valid false).
confidence: written where p.confidence. */
CV_EXPORTS void consistencyCheck(const GpuMat& disp16, const GpuMat& dispInt, const GpuMat& dispRight,
                                 const GpuMat& sparse16, const GpuMat& nonUnique16, const GpuMat& above16,
                                 const GpuMat& below16, int gap, const PipelineParams& p, GpuMat& out,
                                 GpuMat& confidence);

}}}} // namespace cv::lidarsgm::detail::cuda_host

#endif
