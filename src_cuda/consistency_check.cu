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
    const int lane = threadIdx.x & 31;
    const bool inside = x < W && y < H;
    // Lanes whose pixel needs checking; all lanes of the warp stay to the end for the votes below.
    typedef StereoLidarSGM S;
    int v = inside ? disp16(y, x) : NO_DISP;
    const bool checking = v != NO_DISP && dispInt.data && p.check != S::CHECK_NONE;
    const unsigned active = __ballot_sync(0xFFFFFFFFu, checking);
    const bool useStereo = p.check == S::CHECK_STEREO || p.check == S::CHECK_STEREO_LIDAR;
    const bool useLidar = p.check == S::CHECK_CAMERA_LIDAR || p.check == S::CHECK_STEREO_LIDAR;
    if (checking)
    {
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
        if (useLidar)
        {
            // The warp scans the window of each of its pixels that still needs the LiDAR test together (32 lanes,
            // then a vote), instead of letting one pixel's 41 x 41 scan hold up the other 31 lanes.
            const int rc = p.checkRadius, tc = p.checkThreshold16;
            unsigned todo = __ballot_sync(active, !ok);
            while (todo)
            {
                const int src = __ffs(todo) - 1;
                todo &= todo - 1;
                const int px = __shfl_sync(active, x, src), py = __shfl_sync(active, y, src);
                const int pv = __shfl_sync(active, v, src);
                const int r0 = ::max(0, py - rc), r1 = ::min(H - 1, py + rc), c0 = ::max(0, px - rc), c1 = ::min(W - 1, px + rc);
                const int nc = c1 - c0 + 1, n = (r1 - r0 + 1) * nc;
                bool hit = false;
                for (int i = lane; i < n && !hit; i += 32)
                {
                    const int sv = sparse16(r0 + i / nc, c0 + i % nc);
                    hit = sv != NO_DISP && abs(pv - sv) <= tc;
                }
                if (__any_sync(active, hit) && lane == src)
                    ok = true;
            }
        }
        if (!ok)
            v = NO_DISP;
    }
    if (!inside)
        return;
    if (out16.data)
        out16(y, x) = (short)(v == NO_DISP ? (p.minDisparity - 1) * 16 : v);
    else
        out32(y, x) = v == NO_DISP ? (float)(p.minDisparity - 1) : v * (1.f / 16);
}

void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<int> rightKey,
                      PtrStepSz<short> sparse16, const PipelineParams& p, PtrStepSz<short> out16,
                      PtrStepSz<float> out32, cudaStream_t stream)
{
    const dim3 block(32, 8);  // a warp is one row segment of 32 pixels
    const dim3 grid(cv::cuda::device::divUp(disp16.cols, block.x), cv::cuda::device::divUp(disp16.rows, block.y));
    checkKernel<<<grid, block, 0, stream>>>(disp16, dispInt, rightKey, sparse16, p, out16, out32);
    cudaSafeCall(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
