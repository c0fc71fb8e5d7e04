// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Builds without the CUDA sources (no CUDA, or no cudev): the CUDA pipeline exists (the front class holds one) and refuses every call.

#include "precomp.hpp"
#include "pipeline.hpp"

#ifndef LIDARSGM_CUDA
namespace cv { namespace lidarsgm { namespace detail {

static void noCuda()
{
    CV_Error(Error::GpuNotSupported, "lidarsgm: GpuMat input needs the CUDA path, but lidarsgm was built without CUDA");
}

struct CudaPipeline::Buffers {};

CudaPipeline::CudaPipeline() : b_(nullptr) {}
CudaPipeline::~CudaPipeline() {}

void CudaPipeline::run(const cuda::GpuMat&, const cuda::GpuMat&, const cuda::GpuMat&, const PipelineParams&, bool,
                       OutputArray, cuda::Stream*)
{
    noCuda();
}

void CudaPipeline::projectPoints(const cuda::GpuMat&, int, int, const double*, double, Size, int, OutputArray,
                                 cuda::Stream&)
{
    noCuda();
}

}}} // namespace cv::lidarsgm::detail
#endif
