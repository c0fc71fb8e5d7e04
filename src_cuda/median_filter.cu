// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// 3x3 median of the disparity maps, CUDA twin of src/median_filter.cpp: the same rule (pipeline.hpp: "no disparity"
// ranks above every value, clamped border, median of the sorted columns), all maps in one launch.

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

__device__ __forceinline__ void sortedColumn(const PtrStepSz<short>& s, int x, int y, int& lo, int& mid, int& hi)
{
    const int xc = ::min(::max(x, 0), s.cols - 1);
    lo = medianKey(s(::max(y - 1, 0), xc));
    mid = medianKey(s(y, xc));
    hi = medianKey(s(::min(y + 1, s.rows - 1), xc));
    sortColumn3<ScalarMinMax>(lo, mid, hi);
}

//! blockIdx.z picks the map.
__global__ void medianKernel(MedianMaps maps)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const PtrStepSz<short> src = maps.src[blockIdx.z];
    if (x >= src.cols || y >= src.rows)
        return;
    int l0, m0, h0, l1, m1, h1, l2, m2, h2;
    sortedColumn(src, x - 1, y, l0, m0, h0);
    sortedColumn(src, x, y, l1, m1, h1);
    sortedColumn(src, x + 1, y, l2, m2, h2);
    maps.dst[blockIdx.z](y, x) = (short)medianValue(medianOfColumns<ScalarMinMax>(l0, l1, l2, m0, m1, m2, h0, h1, h2));
}

} // namespace

void medianFilter(const MedianMaps& maps, int count, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cudev::divUp(maps.src[0].cols, block.x), cv::cudev::divUp(maps.src[0].rows, block.y),
                    count);
    medianKernel<<<grid, block, 0, stream>>>(maps);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
