// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Counting by one warp: a prefix sum over the lanes, and histogramLowerMedian (pipeline.hpp), so that the scan test's
// and the ring spacing's medians run in stream order on the device, where one thread's walk over the bins took a few
// microseconds of the call.

#ifndef OPENCV_LIDARSGM_HISTOGRAM_CUH
#define OPENCV_LIDARSGM_HISTOGRAM_CUH

#include "cuda_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

//! The inclusive prefix sum of v over the warp's lanes (lane: this thread's, from its linear index in the block).
__device__ __forceinline__ int warpInclusiveSum(int v, int lane)
{
#pragma unroll
    for (int o = 1; o < 32; o <<= 1)
    {
        const int u = __shfl_up_sync(0xFFFFFFFFu, v, o);
        v += lane >= o ? u : 0;
    }
    return v;
}

/** histogramLowerMedian(hist, BINS) for the whole warp (every lane gets it). Lane t holds bins [t PER, t PER + PER):
 a scan of the lanes' sums finds the lane where the cumulative count first exceeds (n - 1) / 2, and that lane its
 bin. */
template <int BINS> __device__ __forceinline__ int warpLowerMedian(const int* hist)
{
    static_assert(BINS % 32 == 0, "whole bins a lane");
    const int PER = BINS / 32, lane = threadIdx.x & 31;
    int v[PER], own = 0;
#pragma unroll
    for (int i = 0; i < PER; i++)
        own += v[i] = hist[lane * PER + i];
    const int upTo = warpInclusiveSum(own, lane);   // the bins up to this lane's last
    const int n = __shfl_sync(0xFFFFFFFFu, upTo, 31);
    if (n == 0)
        return 0;
    const int half = (n - 1) / 2;
    const int at = __ffs(__ballot_sync(0xFFFFFFFFu, upTo > half)) - 1;   // there is one: upTo is n at lane 31
    int bin = PER - 1;
    for (int i = 0, c = upTo - own; i < PER; i++)
        if ((c += v[i]) > half)
        {
            bin = i;
            break;
        }
    return at * PER + __shfl_sync(0xFFFFFFFFu, bin, at);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
