// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.cpp. One warp walks one path line; lane t holds the path
// costs of disparities t * DPT ... t * DPT + DPT - 1, and neighbours d - 1 / d + 1 across lanes come by shuffles.
// The directions run one after the other on the stream, each adding its path costs into the 16-bit sum volume
// (the first one writes it), so the volume is the only large buffer. Integer sums: the order does not matter.

#include "pipeline_cuda.hpp"
#include "matching_cost.cuh"
#include "opencv2/core/cuda/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int BIG = 0x3FFFFFFF;       // stands for "no such disparity": never the minimum
const int WARPS_PER_BLOCK = 4;

__device__ __forceinline__ int warpMin(int v)
{
    for (int o = 16; o > 0; o >>= 1)
        v = ::min(v, __shfl_xor_sync(0xFFFFFFFFu, v, o));
    return v;
}

/* Line `line` of direction (dx, dy): its first pixel and length. Horizontal lines are rows, vertical lines columns;
 diagonal lines start on the row the direction enters from (W lines), then on the column it enters from (H - 1). */
__device__ __forceinline__ bool lineStart(int line, int dx, int dy, int W, int H, int& x, int& y)
{
    if (dy == 0)
    {
        if (line >= H) return false;
        y = line; x = dx > 0 ? 0 : W - 1;
    }
    else if (dx == 0)
    {
        if (line >= W) return false;
        x = line; y = dy > 0 ? 0 : H - 1;
    }
    else
    {
        if (line >= W + H - 1) return false;
        if (line < W) { x = line; y = dy > 0 ? 0 : H - 1; }
        else { x = dx > 0 ? 0 : W - 1; y = dy > 0 ? line - W + 1 : H - 1 - (line - W + 1); }
    }
    return true;
}

template <int DPT>
__global__ void pathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                           PipelineParams p, int dx, int dy, bool first, PtrStepSz<ushort> sum)
{
    const int lane = threadIdx.x & 31;
    const int line = blockIdx.x * WARPS_PER_BLOCK + (threadIdx.x >> 5);
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    int x, y;
    if (!lineStart(line, dx, dy, W, H, x, y))
        return;
    const CostWeights w = p.w;
    const int d0 = lane * DPT;
    int L[DPT];
    int minPrev = 0;
    bool start = true;
    for (; x >= 0 && x < W && y >= 0 && y < H; x += dx, y += dy)
    {
        const unsigned l = (unsigned)censusL(y, x);
        const int* R = censusR.ptr(y);
        const int k = (prior16.data && prior16(y, x) != NO_DISP) ? roundDisp16(prior16(y, x)) - minD : -1;
        int C[DPT];
#pragma unroll
        for (int j = 0; j < DPT; j++)
            C[j] = d0 + j < D ? matchingCost(l, R, x, d0 + j, minD, W, k, w) : BIG;
        if (start)
        {
#pragma unroll
            for (int j = 0; j < DPT; j++)
                L[j] = C[j];
            start = false;
        }
        else
        {
            const int left = __shfl_up_sync(0xFFFFFFFFu, L[DPT - 1], 1);     // L(d0 - 1)
            const int right = __shfl_down_sync(0xFFFFFFFFu, L[0], 1);        // L(d0 + DPT)
            const int jump = minPrev + w.p2;
            int Ln[DPT];
#pragma unroll
            for (int j = 0; j < DPT; j++)
            {
                const int lm = j > 0 ? L[j - 1] : (lane > 0 ? left : BIG);
                const int lp = j < DPT - 1 ? L[j + 1] : (lane < 31 ? right : BIG);
                const int best = ::min(::min(L[j], jump), ::min(lm, lp) + w.p1);
                Ln[j] = d0 + j < D ? C[j] + best - minPrev : BIG;
            }
#pragma unroll
            for (int j = 0; j < DPT; j++)
                L[j] = Ln[j];
        }
        int m = BIG;
#pragma unroll
        for (int j = 0; j < DPT; j++)
            m = ::min(m, L[j]);
        minPrev = warpMin(m);
        ushort* S = sum.ptr(y) + (size_t)x * D;
#pragma unroll
        for (int j = 0; j < DPT; j++)
            if (d0 + j < D)
                S[d0 + j] = (ushort)(first ? L[j] : S[d0 + j] + L[j]);
    }
}

template <int DPT>
void runPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, const PipelineParams& p,
              PtrStepSz<ushort> sum, cudaStream_t stream)
{
    const int W = censusL.cols, H = censusL.rows;
    const int dirs[8][2] = { {1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1} };
    for (int r = 0; r < p.numPaths; r++)
    {
        const int dx = dirs[r][0], dy = dirs[r][1];
        const int lines = dy == 0 ? H : dx == 0 ? W : W + H - 1;
        const int blocks = (lines + WARPS_PER_BLOCK - 1) / WARPS_PER_BLOCK;
        pathKernel<DPT><<<blocks, 32 * WARPS_PER_BLOCK, 0, stream>>>(censusL, censusR, prior16, p, dx, dy, r == 0, sum);
        cudaSafeCall(cudaGetLastError());
    }
}

} // namespace

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    switch ((p.numDisparities + 31) / 32)
    {
    case 1: runPaths<1>(censusL, censusR, prior16, p, sum, stream); break;
    case 2: runPaths<2>(censusL, censusR, prior16, p, sum, stream); break;
    case 3: runPaths<3>(censusL, censusR, prior16, p, sum, stream); break;
    case 4: runPaths<4>(censusL, censusR, prior16, p, sum, stream); break;
    case 5: runPaths<5>(censusL, censusR, prior16, p, sum, stream); break;
    case 6: runPaths<6>(censusL, censusR, prior16, p, sum, stream); break;
    case 7: runPaths<7>(censusL, censusR, prior16, p, sum, stream); break;
    default: runPaths<8>(censusL, censusR, prior16, p, sum, stream); break;
    }
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
