// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.cpp, with the matching cost (src/matching_cost.cpp on the
// CPU) computed as the paths walk. One warp walks one path line; lane t holds the path
// costs of a run of disparities, and neighbours d - 1 / d + 1 across lanes come by shuffles. Every direction adds
// into the one 16-bit sum volume, the only large buffer. Integer sums: the order does not matter.

#include "cuda_stages.hpp"
#include "opencv2/core/cuda/common.hpp"
#include <algorithm>

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

const int BIG = 0x3FFFFFFF;       // stands for "no such disparity": never the minimum
const int WARPS_PER_BLOCK = 4;

/* Line `line` of direction (dx, dy): its first pixel. Horizontal lines are rows, vertical lines columns; diagonal
 lines start on the row the direction enters from (W lines), then on the column it enters from (H - 1 lines). */
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

/* All directions in one launch (blockIdx.y = direction), adding into the zeroed sum volume with 32-bit reductions on
 pairs of 16-bit costs: exact, since each 16-bit half stays below 65536 (the weights are scaled for that), so no
 carry crosses into the other half. Lane t holds disparities [t * DPT, t * DPT + DPT), DPT = 2 * PPT.
 The horizontal lines (1 row each, the longest walks: they are the critical path) stage their row of right census
 strings in shared memory when it fits (rowSmem); the left census and prior are warp-uniform loads. The loads for
 the next pixel are issued before the current step's recurrence, to hide their latency. The left image is read
 (warp-uniform) only for the edge rule of the jump penalty (jumpPenalty). */
template <int PPT, typename T>
__global__ void pathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                           PtrStepSz<T> image, PipelineParams p, PtrStepSz<ushort> sum, bool rowSmem)
{
    const int DPT = 2 * PPT;
    // Directions 0..7: (1,0) (-1,0) (0,1) (0,-1) (1,1) (-1,1) (1,-1) (-1,-1); computed, not a table (a table
    // indexed by blockIdx would live in local memory).
    const int dir = blockIdx.y;
    const int dx = dir < 2 ? 1 - 2 * dir : dir < 4 ? 0 : 1 - 2 * (dir & 1);
    const int dy = dir < 2 ? 0 : dir < 4 ? 5 - 2 * dir : dir < 6 ? 1 : -1;
    const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
    const int line = blockIdx.x * WARPS_PER_BLOCK + warp;
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    int x, y;
    if (!lineStart(line, dx, dy, W, H, x, y))
        return;
    const CostWeights w = p.w;
    const int d0 = lane * DPT;
    const bool active = d0 < D;   // D is a multiple of 16, so pairs never straddle D

    extern __shared__ int rowBuf[];
    const bool staged = rowSmem && dy == 0;
    const int* rowR = censusR.ptr(y);
    if (staged)
    {
        int* sR = rowBuf + warp * W;
        for (int i = lane; i < W; i += 32)
            sR[i] = rowR[i];
        __syncwarp();
        rowR = sR;
    }

    // Values of the current pixel, loaded one step ahead. A horizontal line stays on row y; the others move.
    const bool edges = p.edgeThreshold > 0;
    unsigned l = (unsigned)censusL(y, x);
    int pr = prior16.data ? prior16(y, x) : NO_DISP;
    int intensity = edges ? (int)image(y, x) : 0, prevIntensity = intensity;
    unsigned r[DPT];
#pragma unroll
    for (int j = 0; j < DPT; j++)
        r[j] = (unsigned)(staged ? rowR[::min(::max(x - minD - d0 - j, 0), W - 1)]
                                 : censusR(y, ::min(::max(x - minD - d0 - j, 0), W - 1)));

    int L[DPT];
    int minPrev = 0;
    for (bool start = true; ; start = false)
    {
        const int k = pr != NO_DISP ? roundDisp16(pr) - minD : -1;
        int C[DPT];
#pragma unroll
        for (int j = 0; j < DPT; j++)
        {
            const int d = d0 + j;
            C[j] = active ? matchingCost(popcount32(l ^ r[j]), d, k, w) : BIG;
        }
        const int cx = x, cy = y, curIntensity = intensity;
        x += dx; y += dy;
        const bool more = x >= 0 && x < W && y >= 0 && y < H;
        if (more)
        {
            l = (unsigned)censusL(y, x);
            pr = prior16.data ? prior16(y, x) : NO_DISP;
            if (edges)
                intensity = image(y, x);
#pragma unroll
            for (int j = 0; j < DPT; j++)
                r[j] = (unsigned)(staged ? rowR[::min(::max(x - minD - d0 - j, 0), W - 1)]
                                         : censusR(y, ::min(::max(x - minD - d0 - j, 0), W - 1)));
        }
        if (start)
        {
#pragma unroll
            for (int j = 0; j < DPT; j++)
                L[j] = C[j];
        }
        else
        {
            const int left = __shfl_up_sync(0xFFFFFFFFu, L[DPT - 1], 1);     // L(d0 - 1)
            const int right = __shfl_down_sync(0xFFFFFFFFu, L[0], 1);        // L(d0 + DPT)
            const int jump = minPrev + jumpPenalty(curIntensity, prevIntensity, p.edgeThreshold, w);
            int Ln[DPT];
#pragma unroll
            for (int j = 0; j < DPT; j++)
            {
                const int lm = j > 0 ? L[j - 1] : (lane > 0 ? left : BIG);
                const int lp = j < DPT - 1 ? L[j + 1] : (lane < 31 ? right : BIG);
                const int best = ::min(::min(L[j], jump), ::min(lm, lp) + w.p1);
                Ln[j] = active ? C[j] + best - minPrev : BIG;
            }
#pragma unroll
            for (int j = 0; j < DPT; j++)
                L[j] = Ln[j];
        }
        int m = BIG;
#pragma unroll
        for (int j = 0; j < DPT; j++)
            m = ::min(m, L[j]);
        minPrev = __reduce_min_sync(0xFFFFFFFFu, m);
        if (active)
        {
            unsigned* S = (unsigned*)(sum.ptr(cy) + (size_t)cx * D + d0);
#pragma unroll
            for (int i = 0; i < PPT; i++)
                atomicAdd(S + i, (unsigned)L[2 * i] | ((unsigned)L[2 * i + 1] << 16));
        }
        prevIntensity = curIntensity;
        if (!more)
            break;
    }
}

template <int PPT, typename T>
void runPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
              const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    const int W = censusL.cols, H = censusL.rows;
    const int maxLines = p.numPaths == 8 ? W + H - 1 : std::max(W, H);
    const dim3 grid((maxLines + WARPS_PER_BLOCK - 1) / WARPS_PER_BLOCK, p.numPaths);
    // Every block gets the shared memory of 4 rows; up to 24 KB (rows up to 1536 pixels) it costs no occupancy
    // worth having, beyond that the rows are read through the caches.
    const size_t smem = (size_t)WARPS_PER_BLOCK * W * sizeof(int);
    const bool rowSmem = smem <= 24 * 1024;
    pathKernel<PPT, T><<<grid, 32 * WARPS_PER_BLOCK, rowSmem ? smem : 0, stream>>>(censusL, censusR, prior16, image, p,
                                                                                   sum, rowSmem);
    cudaSafeCall(cudaGetLastError());
}

template <typename T>
void aggregate(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<T> image,
               const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    cudaSafeCall(cudaMemset2DAsync(sum.data, sum.step, 0, sum.cols * sizeof(ushort), sum.rows, stream));
    switch ((p.numDisparities + 63) / 64)
    {
    case 1: runPaths<1>(censusL, censusR, prior16, image, p, sum, stream); break;
    case 2: runPaths<2>(censusL, censusR, prior16, image, p, sum, stream); break;
    case 3: runPaths<3>(censusL, censusR, prior16, image, p, sum, stream); break;
    default: runPaths<4>(censusL, censusR, prior16, image, p, sum, stream); break;
    }
}

} // namespace

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<uchar> left,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, sum, stream);
}

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, PtrStepSz<ushort> left,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream)
{
    aggregate(censusL, censusR, prior16, left, p, sum, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
