// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// A statistic of a histogram that a whole grid counts, taken by the grid's last block to finish instead of a launch of
// its own (ring interpolation's gap limit: one thread in a launch of its own took 6.6 us of a 1 ms call).

#ifndef OPENCV_LIDARSGM_HISTOGRAM_STATS_CUH
#define OPENCV_LIDARSGM_HISTOGRAM_STATS_CUH

#include "cuda_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

/** Called by every thread of the block after its last write to the histogram: true in the grid's last block to get
 here, whose threads then see every block's writes. *done counts the blocks; it is zero before the launch (the stats'
 memset). */
__device__ __forceinline__ bool lastBlockDone(int* done)
{
    __shared__ bool last;
    __threadfence();
    __syncthreads();
    if (threadIdx.x == 0 && threadIdx.y == 0)
        last = atomicAdd(done, 1) == (int)(gridDim.x * gridDim.y) - 1;
    __syncthreads();
    return last;
}

/** histogramLowerMedian (pipeline.hpp) of bins (a multiple of 32) counts in global memory, by one warp, all its lanes
 calling: lane t holds bins [t k, t k + k), k = bins / 32; a scan over the lanes finds the lane whose run holds the
 median, which finds its bin. The counts are read from L2 (other blocks' atomics). */
__device__ __forceinline__ int warpLowerMedian(const int* hist, int bins)
{
    const int lane = threadIdx.x & 31, k = bins / 32;
    int own = 0;
    for (int j = 0; j < k; j++)
        own += __ldcg(hist + lane * k + j);
    int below = own;   // inclusive prefix sum over the lanes
    for (int o = 1; o < 32; o <<= 1)
    {
        const int v = __shfl_up_sync(0xFFFFFFFFu, below, o);
        if (lane >= o)
            below += v;
    }
    const int n = __shfl_sync(0xFFFFFFFFu, below, 31);
    if (n == 0)
        return 0;
    const int half = (n - 1) / 2;
    const int t = __ffs(__ballot_sync(0xFFFFFFFFu, below > half)) - 1;
    int bin = 0;
    if (lane == t)
    {
        int c = below - own;
        for (int j = 0; j < k; j++)
            if ((c += __ldcg(hist + lane * k + j)) > half)
            {
                bin = lane * k + j;
                break;
            }
    }
    return __shfl_sync(0xFFFFFFFFu, bin, t);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl

#endif
