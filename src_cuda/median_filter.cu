// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// 3x3 median of the disparity maps, CUDA twin of src/median_filter.cpp: the same rule (pipeline.hpp: "no disparity"
// ranks above every value, clamped border, median of the sorted columns), all maps in one launch.

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

// A warp takes 32 columns and ROWS rows, and writes the middle 30 columns: the outer two only give their sorted
// columns to their neighbours.
const int ROWS = 4, WARPS = 8, OUT_COLS = 30;

/* blockIdx.z picks the map. Each lane loads its column's ROWS + 2 values once, sorts each output row's column of
 three and takes its neighbours' sorted columns by shuffles, so a column is loaded and sorted once, not three times. */
__global__ void __launch_bounds__(32 * WARPS) medianKernel(MedianMaps maps)
{
    const PtrStepSz<short> src = maps.src[blockIdx.z];
    PtrStepSz<short> dst = maps.dst[blockIdx.z];
    const bool keys = blockIdx.z == 2 && maps.rightKey.data;   // the whole block
    const int lane = threadIdx.x, x = (int)blockIdx.x * OUT_COLS - 1 + lane;
    const int y0 = ((int)blockIdx.y * WARPS + (int)threadIdx.y) * ROWS;
    if (y0 >= dst.rows)   // the whole warp
        return;
    const int xc = ::min(::max(x, 0), dst.cols - 1);
    int v[ROWS + 2];
#pragma unroll
    for (int i = 0; i < ROWS + 2; i++)
    {
        const int yc = ::min(::max(y0 - 1 + i, 0), dst.rows - 1);
        v[i] = medianKey(keys ? rightKeyDisparity((unsigned)maps.rightKey(yc, xc), maps.minDisparity) : src(yc, xc));
    }
    const bool writes = lane >= 1 && lane <= OUT_COLS && x < dst.cols;
#pragma unroll
    for (int r = 0; r < ROWS; r++)
    {
        if (y0 + r >= dst.rows)   // the whole warp
            break;
        int l = v[r], m = v[r + 1], h = v[r + 2];
        sortColumn3<ScalarMinMax>(l, m, h);
        const unsigned all = 0xFFFFFFFFu;
        const int l0 = __shfl_up_sync(all, l, 1), m0 = __shfl_up_sync(all, m, 1), h0 = __shfl_up_sync(all, h, 1);
        const int l2 = __shfl_down_sync(all, l, 1), m2 = __shfl_down_sync(all, m, 1), h2 = __shfl_down_sync(all, h, 1);
        if (writes)
            dst(y0 + r, x) = (short)medianValue(medianOfColumns<ScalarMinMax>(l0, l, l2, m0, m, m2, h0, h, h2));
    }
}

} // namespace

void medianFilter(const MedianMaps& maps, int count, cudaStream_t stream)
{
    const dim3 block(32, WARPS);
    const dim3 grid(cv::cudev::divUp(maps.dst[0].cols, OUT_COLS), cv::cudev::divUp(maps.dst[0].rows, WARPS * ROWS),
                    count);
    medianKernel<<<grid, block, 0, stream>>>(maps);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
