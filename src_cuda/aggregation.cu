// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation, CUDA twin of src/aggregation.cpp. One warp walks one path line; lane t holds the path
// costs of a run of disparities, and neighbours d - 1 / d + 1 across lanes come by shuffles. Every direction adds
// into the one 16-bit sum volume, the only large buffer. Integer sums: the order does not matter.

#include "pipeline_cuda.hpp"
#include "matching_cost.cuh"
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
 The loads for the next pixel are issued before the current step's recurrence, to hide their latency. */
template <int PPT, bool ROW_IN_SMEM>
__global__ void pathKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                           PipelineParams p, PtrStepSz<ushort> sum, int firstDir)
{
    const int DPT = 2 * PPT;
    const int dirs[8][2] = { {1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1} };
    const int dx = dirs[firstDir + blockIdx.y][0], dy = dirs[firstDir + blockIdx.y][1];
    const int lane = threadIdx.x & 31;
    const int line = blockIdx.x * (blockDim.x >> 5) + (threadIdx.x >> 5);
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    int x, y;
    if (!lineStart(line, dx, dy, W, H, x, y))
        return;
    const CostWeights w = p.w;
    const int d0 = lane * DPT;
    const bool active = d0 < D;   // D is a multiple of 16, so pairs never straddle D

    // Horizontal lines (one warp per block) walk 1 row: stage its census strings and prior in shared memory, so
    // each step's loads are short. Other directions read through the caches.
    extern __shared__ int rowBuf[];
    const int* rowL = censusL.ptr(y);
    const int* rowR = censusR.ptr(y);
    const short* rowP = prior16.data ? prior16.ptr(y) : nullptr;
    if (ROW_IN_SMEM)
    {
        int* sL = rowBuf;
        int* sR = rowBuf + W;
        short* sP = (short*)(rowBuf + 2 * W);
        for (int i = lane; i < W; i += 32)
        {
            sL[i] = rowL[i];
            sR[i] = rowR[i];
            sP[i] = rowP ? rowP[i] : NO_DISP;
        }
        __syncwarp();
        rowL = sL; rowR = sR; rowP = sP;
    }
#define LIDARSGM_CENSUS_L(yy, xx) (ROW_IN_SMEM ? rowL[xx] : censusL(yy, xx))
#define LIDARSGM_CENSUS_R(yy, xx) (ROW_IN_SMEM ? rowR[xx] : censusR(yy, xx))
#define LIDARSGM_PRIOR(yy, xx) (ROW_IN_SMEM ? (int)rowP[xx] : (prior16.data ? (int)prior16(yy, xx) : (int)NO_DISP))

    // Values of the current pixel, loaded one step ahead.
    unsigned l = (unsigned)LIDARSGM_CENSUS_L(y, x);
    int pr = LIDARSGM_PRIOR(y, x);
    unsigned r[DPT];
#pragma unroll
    for (int j = 0; j < DPT; j++)
        r[j] = (unsigned)LIDARSGM_CENSUS_R(y, ::min(::max(x - minD - d0 - j, 0), W - 1));

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
            int c = censusTerm(w.census256, popcount32(l ^ r[j]));
            if (k >= 0)
                c += d == k ? 0 : (d == k - 1 || d == k + 1) ? w.q1 : w.q2;
            C[j] = active ? c : BIG;
        }
        const int cx = x, cy = y;
        x += dx; y += dy;
        const bool more = x >= 0 && x < W && y >= 0 && y < H;
        if (more)
        {
            l = (unsigned)LIDARSGM_CENSUS_L(y, x);
            pr = LIDARSGM_PRIOR(y, x);
#pragma unroll
            for (int j = 0; j < DPT; j++)
                r[j] = (unsigned)LIDARSGM_CENSUS_R(y, ::min(::max(x - minD - d0 - j, 0), W - 1));
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
            const int jump = minPrev + w.p2;
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
        if (!more)
            break;
    }
#undef LIDARSGM_CENSUS_L
#undef LIDARSGM_CENSUS_R
#undef LIDARSGM_PRIOR
}

template <int PPT>
void runPaths(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16, const PipelineParams& p,
              PtrStepSz<ushort> sum, cudaStream_t stream, cudaStream_t aux, cudaEvent_t fork, cudaEvent_t join)
{
    cudaSafeCall(cudaEventRecord(fork, stream));
    cudaSafeCall(cudaStreamWaitEvent(aux, fork, 0));
    const int W = censusL.cols, H = censusL.rows;
    // Horizontal lines: one warp per block, the row in shared memory (2 ints + 1 short per pixel). Their 1242-step
    // walks are the critical path, so they are launched first, on the caller's stream; the other directions
    // (many short lines) go on the auxiliary stream beside them.
    const size_t smem = (size_t)W * (2 * sizeof(int) + sizeof(short)) + 16;
    const size_t smemMax = 160 * 1024;
    if (smem <= smemMax)
    {
        if (smem > 48 * 1024)
            cudaSafeCall(cudaFuncSetAttribute(pathKernel<PPT, true>, cudaFuncAttributeMaxDynamicSharedMemorySize, (int)smemMax));
        pathKernel<PPT, true><<<dim3(H, 2), 32, smem, stream>>>(censusL, censusR, prior16, p, sum, 0);
    }
    else  // rows wider than ~16000 pixels: read them through the caches
        pathKernel<PPT, false><<<dim3((H + WARPS_PER_BLOCK - 1) / WARPS_PER_BLOCK, 2), 32 * WARPS_PER_BLOCK, 0, stream>>>(
            censusL, censusR, prior16, p, sum, 0);
    cudaSafeCall(cudaGetLastError());
    // The other directions: vertical (and the four diagonals), several warps per block.
    const int maxLines = p.numPaths == 8 ? W + H - 1 : W;
    const dim3 grid((maxLines + WARPS_PER_BLOCK - 1) / WARPS_PER_BLOCK, p.numPaths - 2);
    pathKernel<PPT, false><<<grid, 32 * WARPS_PER_BLOCK, 0, aux>>>(censusL, censusR, prior16, p, sum, 2);
    cudaSafeCall(cudaGetLastError());
    cudaSafeCall(cudaEventRecord(join, aux));
    cudaSafeCall(cudaStreamWaitEvent(stream, join, 0));
}

} // namespace

void aggregateCosts(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> prior16,
                    const PipelineParams& p, PtrStepSz<ushort> sum, cudaStream_t stream,
                    cudaStream_t aux, cudaEvent_t fork, cudaEvent_t join)
{
    cudaSafeCall(cudaMemset2DAsync(sum.data, sum.step, 0, sum.cols * sizeof(ushort), sum.rows, stream));
    switch ((p.numDisparities + 63) / 64)
    {
    case 1: runPaths<1>(censusL, censusR, prior16, p, sum, stream, aux, fork, join); break;
    case 2: runPaths<2>(censusL, censusR, prior16, p, sum, stream, aux, fork, join); break;
    case 3: runPaths<3>(censusL, censusR, prior16, p, sum, stream, aux, fork, join); break;
    default: runPaths<4>(censusL, censusR, prior16, p, sum, stream, aux, fork, join); break;
    }
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
