// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Matching cost, CUDA twin of src/matching_cost.cpp. The GPU never stores the cost volume (it would double the
// memory held): the path kernels call this as they walk, from the census strings and the prior.

#ifndef OPENCV_LIDARSGM_MATCHING_COST_CUH
#define OPENCV_LIDARSGM_MATCHING_COST_CUH

#include "pipeline_cuda.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! C(p, d) for disparity index d (absolute disparity minD + d); k = prior index or -1.
__device__ __forceinline__ int matchingCost(unsigned l, const int* rightRow, int x, int d, int minD, int W, int k,
                                            const CostWeights& w)
{
    const int xr = ::min(::max(x - minD - d, 0), W - 1);
    int c = censusTerm(w.census256, popcount32(l ^ (unsigned)rightRow[xr]));
    if (k >= 0)
        c += d == k ? 0 : (d == k - 1 || d == k + 1) ? w.q1 : w.q2;
    return c;
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
