// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification, CUDA twin of src/semidensification.*: the same candidate order (semidenseKey), so ties resolve
// identically.

#include "sparse_window.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

/* One block = 8 x 32 pixels, a warp 8 x 4 of them; each pixel visits the sparse points of its block's tile
 (sparse_window.cuh) in its warp's rows plus rs above and below: a warp of 8 x 4 pixels visits 16 rows of a 20 pixels
 wide tile (at rs 6), where one of 32 x 1 visits 13 rows of a 44 wide one. The choice uses the full key (semidenseKey),
 so it does not depend on the order of the list. */
__global__ void semidenseKernel(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16,
                                SparseRows rows, int rs, int Ts, PtrStepSz<short> out)
{
    extern __shared__ int smem[];   // listTilePoints
    const int W = out.cols, H = out.rows;
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const TilePoints tile = listTilePoints(rows, rs, smem);
    // The warp's rows: blockDim.x is 8, so a warp is four rows.
    const int yw = (int)(blockIdx.y * blockDim.y + (threadIdx.y & ~3u));
    const int k0 = tile.begin(yw - rs), k1 = tile.end(yw + 3 + rs);
    if (x >= W || y >= H)
        return;
    const unsigned l = (unsigned)censusL(y, x);
    const int* R = censusR.ptr(y);
    unsigned best = 0xFFFFFFFFu;
    short bestVal = NO_DISP;
    const int* const points = tile.points;
    // Without branches: the warp's pixels nearly all take most of its points, so a branch around the rest would
    // save nothing and cost its own instructions; a point outside a pixel's window gets the key that never wins
    // (KITTI size on 8 H100 SMs: 255 against 286 us, 13.2 against 14.5 M warp instructions).
    for (int k = k0; k < k1; k++)
    {
        const int pos = points[2 * k];
        const int dx = (pos & 0xFFFF) - x, dy = (pos >> 16) - y;
        const bool inside = (unsigned)(dx + rs) <= (unsigned)(2 * rs) && (unsigned)(dy + rs) <= (unsigned)(2 * rs);
        const short v = (short)points[2 * k + 1];
        const int xr = ::min(::max(x - roundDisp16(v), 0), W - 1);
        const unsigned key = inside ? semidenseKey(popcount32(l ^ (unsigned)R[xr]), dx, dy, rs) : 0xFFFFFFFFu;
        bestVal = key < best ? v : bestVal;
        best = ::min(best, key);
    }
    out(y, x) = semidenseKeyCost(best) < Ts ? bestVal : sparse16(y, x);
}

void semidensify(PtrStepSz<int> censusL, PtrStepSz<int> censusR, PtrStepSz<short> sparse16, const SparseRows& rows,
                 const PipelineParams& p, PtrStepSz<short> semidense16, cudaStream_t stream)
{
    const dim3 block(8, 32);
    const dim3 grid(cv::cudev::divUp(semidense16.cols, block.x), cv::cudev::divUp(semidense16.rows, block.y));
    const int rs = p.semidenseRadius;
    const size_t smem = tileKernelSmem(semidenseKernel, block, rs);
    semidenseKernel<<<grid, block, smem, stream>>>(censusL, censusR, sparse16, rows, rs, p.semidenseThreshold,
                                                   semidense16);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
