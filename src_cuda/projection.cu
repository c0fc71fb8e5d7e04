// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// LiDAR projection, CUDA twin of src/projection.cpp: the same double-precision arithmetic (projectRow, projectPixel,
// projectDisparity, kittiEncode in pipeline.hpp), hence the same pixels and disparities. "Nearest wins" is an atomicMax on the float's bits: positive floats order like their bit patterns, so
// the result does not depend on the order the points are processed in.

#include "cuda_stages.hpp"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

struct Projection34 { double m[12]; };

__global__ void projectKernel(const float* points, int n, int stride, Projection34 PT, double focalBaseline,
                              PtrStepSz<int> dispBits)
{
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n)
        return;
    const float* q = points + (size_t)i * stride;
    const double X = q[0], Y = q[1], Z = q[2];
    if (!isfinite(X) || !isfinite(Y) || !isfinite(Z))
        return;
    const double u = projectRow(PT.m, X, Y, Z), v = projectRow(PT.m + 4, X, Y, Z), z = projectRow(PT.m + 8, X, Y, Z);
    if (!(z > 0))
        return;
    const double ui = projectPixel(u, z), vi = projectPixel(v, z);
    if (ui < 0 || vi < 0 || ui >= dispBits.cols || vi >= dispBits.rows)
        return;
    const float d = projectDisparity(focalBaseline, z);
    atomicMax(&dispBits((int)vi, (int)ui), __float_as_int(d));
}

__global__ void toKitti16Kernel(PtrStepSz<float> disp, PtrStepSz<ushort> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x >= out.cols || y >= out.rows)
        return;
    out(y, x) = kittiEncode(disp(y, x));
}

void projectPoints(const float* points, int n, int stride, const double PT[12], double focalBaseline,
                   PtrStepSz<float> disp, PtrStepSz<ushort> out16, cudaStream_t stream)
{
    CV_CUDEV_SAFE_CALL(cudaMemset2DAsync(disp.data, disp.step, 0, disp.cols * sizeof(float), disp.rows, stream));
    Projection34 P;
    for (int k = 0; k < 12; k++)
        P.m[k] = PT[k];
    if (n > 0)
        projectKernel<<<(n + 255) / 256, 256, 0, stream>>>(points, n, stride, P, focalBaseline,
                                                           PtrStepSz<int>(disp.rows, disp.cols, (int*)disp.data, disp.step));
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
    if (out16.data)
    {
        const dim3 block(32, 8);
        const dim3 grid(cv::cudev::divUp(out16.cols, block.x), cv::cudev::divUp(out16.rows, block.y));
        toKitti16Kernel<<<grid, block, 0, stream>>>(disp, out16);
        CV_CUDEV_SAFE_CALL(cudaGetLastError());
    }
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
