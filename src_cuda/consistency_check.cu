// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Stereo-LiDAR consistency check fused with the conversion to the output format, CUDA twin of
// src/consistency_check.cpp (with the ring check of pipeline.hpp and the confidence); encodeOutput converts without
// checking (semidensify).
// Tile coordinates are packed in 16 bits each (images below 32768 pixels a side).

#include "sparse_window.cuh"
#include "opencv2/cudev/common.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {

namespace {

__device__ __forceinline__ void store(PtrStepSz<short>& out, int x, int y, int d16, int minD)
{
    out(y, x) = encodeOutput16(d16, minD);
}
__device__ __forceinline__ void store(PtrStepSz<float>& out, int x, int y, int d16, int minD)
{
    out(y, x) = encodeOutput32(d16, minD);
}

//! Whether the kernel runs the LiDAR test: for the check, or for the confidence's evidence where there is a sparse map.
__host__ __device__ __forceinline__ bool lidarTestOn(const PipelineParams& p, const PtrStepSz<short>& sparse16)
{
    return p.lidarCheck || (p.confidence && sparse16.data);
}

//! The radius of the tile's point list: the check's window and, with the confidence, its evidence window.
__host__ __device__ __forceinline__ int listRadius(const PipelineParams& p)
{
    return p.confidence && p.semidenseRadius > p.checkRadius ? p.semidenseRadius : p.checkRadius;
}

/* One block = 8 x 32 pixels (CHECK_BLOCK), a warp 8 x 4 of them. For the LiDAR test each pixel scans the sparse points
 of its block's tile (sparse_window.cuh) in its window's rows, the warp together those of its four rows: at rc 20 a
 band of 44 rows of a 48 pixels wide tile, where a warp of 32 x 1 would scan 41 rows of a 72 wide one. The test is
 "does any point qualify", so the list's order cannot change the result. With p.confidence both tests run wherever
 they can (the confidence's evidence), whatever the check keeps. */
template <typename T>
__global__ void checkKernel(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                            PtrStepSz<short> sparse16, SparseRows sparseRows, RingCheckMaps rings, PipelineParams p,
                            PtrStepSz<T> out, PtrStepSz<float> confidence)
{
    extern __shared__ int smem[];   // listTilePoints
    const int W = disp16.cols, H = disp16.rows;
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    const int rc = p.checkRadius, tc = p.checkThreshold16, rs = p.semidenseRadius;
    const bool conf = p.confidence, lidarTest = lidarTestOn(p, sparse16);
    const bool inside = x < W && y < H;
    int v = inside ? disp16(y, x) : NO_DISP;
    bool lr = false, li = false, ln = false;   // left-right; LiDAR in the check's window; in rs's (outputConfidence)
    if (v != NO_DISP && (p.stereoCheck || conf))
    {
        // A match outside the right image cannot be verified: it fails (the LiDAR test may keep it).
        const int di = dispInt(y, x);
        const int xr = x - di;
        if (xr >= 0 && xr < W)
        {
            const int dr = dispRight(y, xr);
            lr = dr != NO_DISP && abs(di - dr) <= p.lrMaxDiff;
        }
    }
    const bool needCheck = p.lidarCheck && !(p.stereoCheck && lr), needNear = conf && lidarTest;
    // The tile's points within the larger of the two windows (the check's rc, the confidence's rs), listed where a
    // pixel of the block needs them (most pixels pass the left-right check).
    TilePoints tile = {};
    if (lidarTest && __syncthreads_or(v != NO_DISP && (needCheck || needNear)))
        tile = listTilePoints(sparseRows, listRadius(p), smem);
    if (!inside)
        return;
    const bool useRings = rings.gap != nullptr;
    const auto ringSupports = [&](int v16) {
        return ringLineSupports(v16, rings.above.data, rings.below.data, rings.above.step / sizeof(short),
                                sparse16.data, sparse16.step / sizeof(short), x, y, W, *rings.gap, tc);
    };
    const auto range16 = [&]() {
        return confidenceRange16([&](int u, int r) { return (int)disp16(r, u); }, x, y, W, H);
    };
    if (v == NO_DISP)
    {
        // A non-unique winner that the ring check keeps: LiDAR evidence alone.
        const int nu = useRings ? rings.nonUnique16(y, x) : NO_DISP;
        const bool rescued = nu != NO_DISP && ringSupports(nu);
        store(out, x, y, rescued ? nu : NO_DISP, p.minDisparity);
        if (conf)
            confidence(y, x) = rescued ? confidenceValue(outputConfidence(checkEvidence(false, true), range16())) : 0.f;
        return;
    }
    if (needCheck || needNear)
    {
        // The points in this pixel's band of the window.
        const int r = listRadius(p), * const points = tile.points;
        for (int k = tile.begin(y - r), k1 = tile.end(y + r); k < k1; k++)
        {
            const int pos = points[2 * k];
            if (abs(v - points[2 * k + 1]) > tc)
                continue;
            const int dx = abs((pos & 0xFFFF) - x), dy = abs((pos >> 16) - y);
            li = li || (dx <= rc && dy <= rc);
            ln = ln || (dx <= rs && dy <= rs);
            if ((li || !needCheck) && (ln || !needNear))
                break;
        }
        if (useRings && ((needCheck && !li) || (needNear && !ln)) && ringSupports(v))
            li = ln = true;
    }
    const bool ok = (!p.stereoCheck && !p.lidarCheck) || (p.stereoCheck && lr) || (p.lidarCheck && li);
    if (!ok)
        v = NO_DISP;
    store(out, x, y, v, p.minDisparity);
    if (conf)
        confidence(y, x) = ok ? confidenceValue(outputConfidence(checkEvidence(lr, ln), range16())) : 0.f;
}

template <typename T>
__global__ void encodeKernel(PtrStepSz<short> disp16, int minD, PtrStepSz<T> out)
{
    const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < out.cols && y < out.rows)
        store(out, x, y, disp16(y, x), minD);
}

const dim3 BLOCK(32, 8), CHECK_BLOCK(8, 32);

static dim3 gridFor(int cols, int rows, dim3 block)
{
    return dim3(cv::cudev::divUp(cols, block.x), cv::cudev::divUp(rows, block.y));
}

template <typename T>
void runCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
              PtrStepSz<short> sparse16, const SparseRows& sparseRows, const RingCheckMaps& rings,
              const PipelineParams& p, PtrStepSz<T> out, PtrStepSz<float> confidence, cudaStream_t stream)
{
    const size_t smem = lidarTestOn(p, sparse16) ? tileKernelSmem(checkKernel<T>, CHECK_BLOCK, listRadius(p)) : 0;
    checkKernel<T><<<gridFor(disp16.cols, disp16.rows, CHECK_BLOCK), CHECK_BLOCK, smem, stream>>>(
        disp16, dispInt, dispRight, sparse16, sparseRows, rings, p, out, confidence);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

template <typename T>
void runEncode(PtrStepSz<short> disp16, int minD, PtrStepSz<T> out, cudaStream_t stream)
{
    encodeKernel<T><<<gridFor(disp16.cols, disp16.rows, BLOCK), BLOCK, 0, stream>>>(disp16, minD, out);
    CV_CUDEV_SAFE_CALL(cudaGetLastError());
}

} // namespace

void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                      PtrStepSz<short> sparse16, const SparseRows& rows, const RingCheckMaps& rings,
                      const PipelineParams& p, PtrStepSz<short> out, PtrStepSz<float> confidence, cudaStream_t stream)
{
    runCheck(disp16, dispInt, dispRight, sparse16, rows, rings, p, out, confidence, stream);
}

void consistencyCheck(PtrStepSz<short> disp16, PtrStepSz<short> dispInt, PtrStepSz<short> dispRight,
                      PtrStepSz<short> sparse16, const SparseRows& rows, const RingCheckMaps& rings,
                      const PipelineParams& p, PtrStepSz<float> out, PtrStepSz<float> confidence, cudaStream_t stream)
{
    runCheck(disp16, dispInt, dispRight, sparse16, rows, rings, p, out, confidence, stream);
}

void encodeOutput(PtrStepSz<short> disp16, int minDisparity, PtrStepSz<short> out, cudaStream_t stream)
{
    runEncode(disp16, minDisparity, out, stream);
}

void encodeOutput(PtrStepSz<short> disp16, int minDisparity, PtrStepSz<float> out, cudaStream_t stream)
{
    runEncode(disp16, minDisparity, out, stream);
}

}}}} // namespace cv::lidarsgm::detail::cuda_impl
