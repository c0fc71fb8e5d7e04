// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Stereo-LiDAR consistency check, CUDA twin of src/consistency_check.cpp, fused with the conversion to the output
// format (what StereoLidarSGMImpl::writeOutput does on the CPU). With dispInt empty it only converts (semidensify).
// Tile coordinates are packed in 16 bits each (images below 32768 pixels a side).

#include "opencv2/lidarsgm.hpp"
#include "sparse_window.cuh"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

/* One block = 32 x 8 pixels. For the LiDAR test each pixel scans the sparse points of its block's tile
 (sparse_window.cuh). The test is "does any point qualify", so the list's order cannot change the result. */
__global__ void checkKernel(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                            PtrStepSz<short> sparse16, PipelineParams p, PtrStepSz<short> out16, PtrStepSz<float> out32)
{
    extern __shared__ int points[];   // (y << 16 | x), value: 2 ints per sparse point of the tile
    __shared__ int count;
    typedef StereoLidarSGM S;
    const int W = disp16.cols, H = disp16.rows;
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const bool useStereo = p.check == S::CHECK_STEREO || p.check == S::CHECK_STEREO_LIDAR;
    const bool useLidar = dispInt.data && (p.check == S::CHECK_CAMERA_LIDAR || p.check == S::CHECK_STEREO_LIDAR);
    const int rc = p.checkRadius, tc = p.checkThreshold16;
    const int n = useLidar ? listTilePoints(sparse16, rc, points, &count) : 0;
    if (x >= W || y >= H)
        return;
    int v = disp16(y, x);
    if (v != NO_DISP && dispInt.data && p.check != S::CHECK_NONE)
    {
        bool ok = false;
        if (useStereo)
        {
            const int di = dispInt(y, x);
            const int xr = x - di;
            if (xr >= 0 && xr < W)
            {
                const int dr = dispRight(y, xr);
                ok = dr != NO_DISP && abs(di - dr) <= p.lrMaxDiff;
            }
        }
        if (!ok && useLidar)
        {
            for (int k = 0; k < n; k++)
            {
                const int pos = points[2 * k];
                const int px = pos & 0xFFFF, py = pos >> 16;
                if (abs(px - x) <= rc && abs(py - y) <= rc && abs(v - points[2 * k + 1]) <= tc)
                {
                    ok = true;
                    break;
                }
            }
        }
        if (!ok)
            v = NO_DISP;
    }
    if (out16.data)
        out16(y, x) = (short)(v == NO_DISP ? (p.minDisparity - 1) * 16 : v);
    else
        out32(y, x) = v == NO_DISP ? (float)(p.minDisparity - 1) : v * (1.f / 16);
}

void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                      PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> out16,
                      PtrStepSz<float> out32, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(disp16.cols, block.x), cv::cuda::device::divUp(disp16.rows, block.y));
    const size_t smem = tileKernelSmem(checkKernel, block, p.checkRadius);
    checkKernel<<<grid, block, smem, stream>>>(disp16, dispInt, dispRight, sparse16, p, out16, out32);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
