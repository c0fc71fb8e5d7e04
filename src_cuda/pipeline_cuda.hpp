// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Host entry points of the CUDA stages (src_cuda/<stage>.cu), called by src/stereo_lidar_sgm.cpp. Each follows the
// integer definitions of its CPU twin in src/<stage>.cpp (see src/pipeline.hpp), so the outputs are identical.
// All calls only enqueue work on the given stream: no allocation, no synchronisation.

#ifndef OPENCV_LIDARSGM_PIPELINE_CUDA_HPP
#define OPENCV_LIDARSGM_PIPELINE_CUDA_HPP

#include "opencv2/core/cuda_types.hpp"
#include <cuda_runtime.h>
#include "pipeline.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

using cv::cuda::PtrStepSz;

void convertSparse(PtrStepSz<ushort> sparse16u, PtrStepSz<float> sparse32f, int minDisparity, int numDisparities,
                   PtrStepSz<short> sparse16, cudaStream_t stream);

//! Both images; the 8-bit or the 16-bit pair is given, the other left empty.
void censusTransform(PtrStepSz<uchar> left8, PtrStepSz<uchar> right8, PtrStepSz<ushort> left16,
                     PtrStepSz<ushort> right16, PtrStepSz<int> censusL, PtrStepSz<int> censusR, cudaStream_t stream);

void semidensify(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                 const PipelineParams& p, PtrStepSz<short> semidense16, cudaStream_t stream);

//! All paths, matching cost computed on the fly; sum: rows = image rows, cols = width * numDisparities.
void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream);

/** rightKey (rows x width, int): scratch for the right view's (cost << 16 | d) minima; dispRight receives the
right-view disparity as on the CPU. */
void winnerTakesAll(PtrStepSz<ushort> sum, int width, const PipelineParams& p, PtrStepSz<short> disp16,
                    PtrStepSz<short> dispInt, PtrStepSz<int> rightKey, PtrStepSz<short> dispRight,
                    cudaStream_t stream);

//! Up to three maps filtered in one launch (same size): dst[i] = median3x3(src[i]).
struct MedianMaps
{
    PtrStepSz<short> src[3], dst[3];
};
void medianFilter(const MedianMaps& maps, int count, cudaStream_t stream);

//! The check and the conversion to the output format (CV_16S x16 or CV_32F) in one pass.
void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                      PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> out16,
                      PtrStepSz<float> out32, cudaStream_t stream);

/** LiDAR points (float, each `stride` floats after the previous, x y z first) to a sparse disparity map: disp (CV_32F, written, 0 =
none); with out16 given, also its KITTI 16-bit encoding. PT = projection * lidarToCamera, row-major 3x4. */
void projectPoints(const float* points, int n, int stride, const double PT[12], double focalBaseline,
                   PtrStepSz<float> disp, PtrStepSz<ushort> out16, cudaStream_t stream);

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
