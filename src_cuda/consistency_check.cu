// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Stereo-LiDAR consistency check, CUDA twin of src/consistency_check.cpp, fused with the conversion to the output
// format (what StereoLidarSGMImpl::writeOutput does on the CPU). With dispInt empty it only converts (semidensify).

#include "opencv2/lidarsgm.hpp"
#include "pipeline_cuda.hpp"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

__global__ void checkKernel(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<int> rightKey,
                            PtrStepSz<short> sparse16, PipelineParams p, PtrStepSz<short> out16, PtrStepSz<float> out32)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const int W = disp16.cols, H = disp16.rows;
    if (x >= W || y >= H)
        return;
    typedef StereoLidarSGM S;
    int v = disp16(y, x);
    if (v != NO_DISP && dispInt.data && p.check != S::CHECK_NONE)
    {
        const bool useStereo = p.check == S::CHECK_STEREO || p.check == S::CHECK_STEREO_LIDAR;
        const bool useLidar = p.check == S::CHECK_CAMERA_LIDAR || p.check == S::CHECK_STEREO_LIDAR;
        bool ok = false;
        if (useStereo)
        {
            const int di = dispInt(y, x);
            const int xr = x - di;
            if (xr >= 0 && xr < W)
            {
                const unsigned key = (unsigned)rightKey(y, xr);
                ok = key != 0xFFFFFFFFu && abs(di - ((int)(key & 0xFFFFu) + p.minDisparity)) <= p.lrMaxDiff;
            }
        }
        if (!ok && useLidar)
        {
            const int rc = p.checkRadius, tc = p.checkThreshold16;
            const int r0 = ::max(0, y - rc), r1 = ::min(H - 1, y + rc), c0 = ::max(0, x - rc), c1 = ::min(W - 1, x + rc);
            for (int q = r0; q <= r1 && !ok; q++)
            {
                const short* s = sparse16.ptr(q);
                for (int c = c0; c <= c1; c++)
                {
                    const int sv = s[c];
                    if (sv != NO_DISP && abs(v - sv) <= tc)
                    {
                        ok = true;
                        break;
                    }
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

void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<int> rightKey,
                      PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> out16,
                      PtrStepSz<float> out32, cudaStream_t stream)
{
    const dim3 block(32, 8);
    const dim3 grid(cv::cuda::device::divUp(disp16.cols, block.x), cv::cuda::device::divUp(disp16.rows, block.y));
    checkKernel<<<grid, block, 0, stream>>>(disp16, dispInt, rightKey, sparse16, p, out16, out32);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
