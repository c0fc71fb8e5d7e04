// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Builds without the CUDA sources (no CUDA, or no cudev): the CUDA pipeline exists (the front class holds one) and
// refuses every call; so do the CUDA stages of the per-stage tests (cuda_stages_host.hpp).

#include "precomp.hpp"
#include "pipeline.hpp"
#include "cuda_stages_host.hpp"

#ifndef LIDARSGM_CUDA
namespace cv { namespace lidarsgm { namespace detail {

static void noCuda()
{
    LIDARSGM_Error(Error::GpuNotSupported, "lidarsgm: GpuMat input needs the CUDA path, but lidarsgm was built without CUDA");
}

struct CudaPipeline::Buffers {};

CudaPipeline::CudaPipeline() : b_(nullptr) {}
CudaPipeline::~CudaPipeline() {}

void CudaPipeline::run(const cuda::GpuMat&, const cuda::GpuMat&, const cuda::GpuMat&, const PipelineParams&, bool,
                       OutputArray, cuda::Stream*, bool&, OutputArray)
{
    noCuda();
}

void CudaPipeline::projectPoints(const cuda::GpuMat&, int, int, const double*, double, Size, int, OutputArray,
                                 cuda::Stream&)
{
    noCuda();
}

double CudaPipeline::searchedFraction() const
{
    return 0.0;   // no call ever ran here
}

namespace cuda_host {

void convertSparse(const GpuMat&, int, int, GpuMat&) { noCuda(); }
bool isLidarScan(const GpuMat&) { noCuda(); return false; }
Mat scanGapHistograms(const GpuMat&) { noCuda(); return Mat(); }
void filterHiddenPoints(const GpuMat&, const PipelineParams&, GpuMat&) { noCuda(); }
void censusTransform(const GpuMat&, const GpuMat&, const PipelineParams&, GpuMat&, GpuMat&) { noCuda(); }
void semidensify(const GpuMat&, const GpuMat&, const GpuMat&, const PipelineParams&, GpuMat&) { noCuda(); }
void interpolateRings(const GpuMat&, const GpuMat&, const GpuMat&, const PipelineParams&, GpuMat&, GpuMat&, GpuMat&,
                      int&)
{
    noCuda();
}
void searchWindows(const GpuMat&, const GpuMat&, const GpuMat&, const PipelineParams&, GpuMat&, GpuMat*) { noCuda(); }
void aggregateCosts(const GpuMat&, const GpuMat&, const GpuMat&, const GpuMat&, const PipelineParams&, const GpuMat&,
                    bool, GpuMat&, const GpuMat&, int)
{
    noCuda();
}
void winnerTakesAll(const GpuMat&, int, const PipelineParams&, GpuMat&, GpuMat&, GpuMat&, GpuMat&, const GpuMat&)
{
    noCuda();
}
void medianFilter(const GpuMat&, GpuMat&) { noCuda(); }
void consistencyCheck(const GpuMat&, const GpuMat&, const GpuMat&, const GpuMat&, const GpuMat&, const GpuMat&,
                      const GpuMat&, int, const PipelineParams&, GpuMat&, GpuMat&)
{
    noCuda();
}

} // namespace cuda_host

}}} // namespace cv::lidarsgm::detail
#endif
