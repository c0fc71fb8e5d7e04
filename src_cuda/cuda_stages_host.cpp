// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CUDA stages one at a time (src/cuda_stages_host.hpp): each allocates what the pipeline's buffers would hold,
// calls the stage on the default stream and waits for it.

#include "precomp.hpp"
#include "cuda_stages_host.hpp"
#include "cuda_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail { namespace cuda_host {

namespace ci = cuda_impl;

namespace {

void finish()
{
    const cudaError_t err = cudaDeviceSynchronize();
    if (err == cudaSuccess)
        return;
    LIDARSGM_Error_(Error::GpuApiCallError, ("lidarsgm: %s", cudaGetErrorString(err)));
}

/* The windows' compact volume (WindowMap) against the full layout (rows of width * D sums) that the tests compare:
bases receives the layout (device memory); forEachWindowSum(f) calls f(full index, compact index) for every sum of every
pixel's window. */
struct CompactVolume
{
    GpuMat bases;
    Mat hostBases, windows;
    Size size;
    int D;

    CompactVolume(const GpuMat& gpuWindows, Size sz, int numDisparities) : size(sz), D(numDisparities)
    {
        bases.create(1, gpuWindows.size().area() + 1, CV_32SC1);
        ci::windowLayout(ci::windowWords(gpuWindows), bases.ptr<int>(), 0);
        finish();
        bases.download(hostBases);
        gpuWindows.download(windows);
    }
    size_t units() const { return (size_t)hostBases.at<int>((int)windows.total()); }
    size_t sums() const { return ci::windowVolumeShorts(units()); }
    ci::WindowMap map(const GpuMat& gpuWindows) const { return { ci::windowWords(gpuWindows), bases.ptr<int>() }; }
    template <typename F> void forEachWindowSum(const F& f) const
    {
        for (int y = 0; y < size.height; y++)
            for (int x = 0; x < size.width; x++)
            {
                const int t = y / WINDOW_TILE * windows.cols + x / WINDOW_TILE;
                const Vec2s w = windows.at<Vec2s>(t);
                const size_t c = 2 * ci::windowPairOffset(hostBases.at<int>(t), x, y, w[0], w[1]);
                for (int d = w[0]; d < w[1]; d++)
                    f(((size_t)y * size.width + x) * D + d, c + (d - w[0]));
            }
    }
};

//! The scan test's result on the device: stats as the pipeline holds them, the result at stats[2 SCAN_GAP_BINS].
GpuMat scanStats(const GpuMat& sparse16)
{
    GpuMat stats(1, 2 * SCAN_GAP_BINS + 1, CV_32SC1);
    ci::testScan(sparse16, stats.ptr<int>(), 0);
    return stats;
}

//! sparse16's points row by row, in chunks and entries.
ci::SparseRows sparseRows(const GpuMat& sparse16, GpuMat& chunks, GpuMat& entries)
{
    const ci::SparseRows rows = ci::sparseRowsBuffers(sparse16.size(), chunks, entries);
    ci::listSparseRows(sparse16, rows, 0);
    return rows;
}

} // namespace

void convertSparse(const GpuMat& sparse, int minDisparity, int numDisparities, GpuMat& sparse16)
{
    CV_Assert(sparse.type() == CV_16UC1 || sparse.type() == CV_32FC1);
    sparse16.create(sparse.size(), CV_16SC1);
    if (sparse.type() == CV_16UC1)
        ci::convertSparse(cuda::PtrStepSz<ushort>(sparse), minDisparity, numDisparities, sparse16, nullptr, 0);
    else
        ci::convertSparse(cuda::PtrStepSz<float>(sparse), minDisparity, numDisparities, sparse16, nullptr, 0);
    finish();
}

Mat scanGapHistograms(const GpuMat& sparse16)
{
    const GpuMat stats = scanStats(sparse16);
    finish();
    Mat s;
    stats.colRange(0, 2 * SCAN_GAP_BINS).download(s);
    return s;
}

bool isLidarScan(const GpuMat& sparse16)
{
    const GpuMat stats = scanStats(sparse16);
    finish();
    Mat s;
    stats.download(s);
    return s.at<int>(0, 2 * SCAN_GAP_BINS) != 0;
}

void filterHiddenPoints(const GpuMat& sparse16, const PipelineParams& p, GpuMat& visible16)
{
    const GpuMat stats = scanStats(sparse16);
    visible16.create(sparse16.size(), CV_16SC1);
    GpuMat chunks, entries;
    const ci::SparseRows rows = sparseRows(sparse16, chunks, entries);
    ci::filterHiddenPoints(sparse16, rows, p, visible16, stats.ptr<int>(), 0);
    finish();
}

void censusTransform(const GpuMat& left, const GpuMat& right, const PipelineParams& p, GpuMat& censusL,
                     GpuMat& censusR)
{
    CV_Assert(left.type() == right.type() && left.size() == right.size());
    CV_Assert(left.type() == CV_8UC1 || left.type() == CV_16UC1);
    const int before = ci::rightCensusPadBefore(p), after = ci::rightCensusPadAfter(p);
    censusL.create(left.size(), CV_32SC1);
    GpuMat padded(left.rows, before + left.cols + after, CV_32SC1);
    censusR = padded.colRange(before, before + left.cols);
    if (left.type() == CV_8UC1)
        ci::censusTransform(cuda::PtrStepSz<uchar>(left), cuda::PtrStepSz<uchar>(right), censusL, censusR, before,
                            after, 0);
    else
        ci::censusTransform(cuda::PtrStepSz<ushort>(left), cuda::PtrStepSz<ushort>(right), censusL, censusR, before,
                            after, 0);
    finish();
}

void semidensify(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& sparse16, const PipelineParams& p,
                 GpuMat& semidense16)
{
    semidense16.create(sparse16.size(), CV_16SC1);
    GpuMat chunks, entries;
    const ci::SparseRows rows = sparseRows(sparse16, chunks, entries);
    ci::semidensify(censusL, censusR, sparse16, rows, p, semidense16, 0);
    finish();
}

void interpolateRings(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& sparse16, const PipelineParams& p,
                      GpuMat& semidense16, GpuMat& above16, GpuMat& below16, int& gap)
{
    above16.create(sparse16.size(), CV_16SC1);
    below16.create(sparse16.size(), CV_16SC1);
    GpuMat stats(1, RING_GAP_BINS + 1, CV_32SC1);
    ci::interpolateRings(censusL, censusR, sparse16, p, semidense16, above16, below16, stats.ptr<int>(), 0);
    finish();
    Mat s;
    stats.download(s);
    gap = s.at<int>(0, RING_GAP_BINS);
}

void searchWindows(const GpuMat& prior16, const GpuMat& left, const GpuMat& right, const PipelineParams& p,
                   GpuMat& windows, GpuMat* coarse)
{
    ci::WindowBuffers w;
    ci::enqueueSearchWindows(prior16, left, right, p, w, 0);
    finish();
    windows = w.windows;
    if (coarse)
        *coarse = w.disp.rowRange(w.disp.rows / 3, 2 * w.disp.rows / 3);
}

/* The stage's inputs for a left image of element type T (the stage's overloads); own16 empty: no copied priors (then
scanFlag is not read). */
template <typename T>
static ci::AggregationInputs<T> aggregationInputs(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& prior16,
                                                  const GpuMat& left, const GpuMat& own16, const GpuMat& scanFlag)
{
    ci::AggregationInputs<T> in;
    in.censusL = censusL;
    in.censusR = censusR;
    if (!prior16.empty())
        in.prior16 = prior16;
    in.left = left;
    if (!own16.empty())
    {
        in.own16 = own16;
        in.scan = scanFlag.ptr<int>();
    }
    return in;
}

void aggregateCosts(const GpuMat& censusL, const GpuMat& censusR, const GpuMat& prior16, const GpuMat& left,
                    const PipelineParams& p, const GpuMat& own16, bool scan, GpuMat& sum, const GpuMat& windows,
                    int smCount)
{
    sum.create(left.rows, left.cols * p.numDisparities, CV_16UC1);
    GpuMat scanFlag(1, 1, CV_32SC1, Scalar::all(scan ? 1 : 0));
    GpuMat facts(left.size(), CV_16UC1);
    // With windows the stage fills the compact volume, copied here into sum's full layout (0 outside the windows).
    std::unique_ptr<CompactVolume> compact(windows.empty() ? nullptr
                                                           : new CompactVolume(windows, left.size(), p.numDisparities));
    // Its own memory: never an alias of sum, which receives the full layout below.
    GpuMat volume;
    const bool costs = compact && ci::windowCostsStored(p, left.size(), smCount > 0 ? smCount : ci::streamSmCount(0));
    if (compact)
        cuda::createContinuous(1, (int)ci::windowVolumeShorts(compact->units(), costs), CV_16UC1, volume);
    else
        volume = sum;
    ci::AggregationOutputs out;
    out.sum = volume;
    out.facts = facts;
    if (costs)
        out.costs = ci::windowCostsOf(volume.data, (size_t)volume.rows * volume.cols);
    if (left.type() == CV_8UC1)
    {
        ci::AggregationInputs<uchar> in = aggregationInputs<uchar>(censusL, censusR, prior16, left, own16, scanFlag);
        in.smCount = smCount;
        if (compact)
            in.windows = compact->map(windows);
        ci::aggregateCosts(in, p, out, 0);
    }
    else
    {
        ci::AggregationInputs<ushort> in = aggregationInputs<ushort>(censusL, censusR, prior16, left, own16, scanFlag);
        in.smCount = smCount;
        if (compact)
            in.windows = compact->map(windows);
        ci::aggregateCosts(in, p, out, 0);
    }
    finish();
    if (!compact)
        return;
    Mat c, full(sum.size(), CV_16UC1, Scalar::all(0));
    volume.download(c);
    compact->forEachWindowSum([&](size_t f, size_t i) { full.ptr<ushort>()[f] = c.ptr<ushort>()[i]; });
    sum.upload(full);
}

void winnerTakesAll(const GpuMat& sum, int width, const PipelineParams& p, GpuMat& disp16, GpuMat& dispInt,
                    GpuMat& dispRight, GpuMat& nonUnique16, const GpuMat& windows)
{
    const Size sz(width, sum.rows);
    disp16.create(sz, CV_16SC1);
    dispInt.create(sz, CV_16SC1);
    dispRight.create(sz, CV_16SC1);
    GpuMat rightKey(sz, CV_32SC1);
    if (ringCheckOn(p))
        nonUnique16.create(sz, CV_16SC1);
    else
        nonUnique16.release();
    // With windows: sum (full layout) into the compact volume the stage reads (its own memory, not sum's).
    GpuMat volume = windows.empty() ? sum : GpuMat();
    ci::WinnerInputs in;
    in.width = width;
    in.height = sz.height;
    std::unique_ptr<CompactVolume> compact;
    if (!windows.empty())
    {
        compact.reset(new CompactVolume(windows, sz, p.numDisparities));
        Mat full, c(1, (int)compact->sums(), CV_16UC1, Scalar::all(0));
        sum.download(full);
        CV_Assert(full.isContinuous());
        compact->forEachWindowSum([&](size_t f, size_t i) { c.ptr<ushort>()[i] = full.ptr<ushort>()[f]; });
        volume.upload(c);
        in.windows = compact->map(windows);
    }
    in.sum = volume;
    ci::WinnerMaps out;
    out.disp16 = disp16;
    out.dispInt = dispInt;
    out.dispRight = dispRight;
    if (!nonUnique16.empty())
        out.nonUnique16 = nonUnique16;
    ci::winnerTakesAll(in, p, out, rightKey, 0);
    finish();
}

void medianFilter(const GpuMat& src, GpuMat& dst)
{
    CV_Assert(src.type() == CV_16SC1);
    dst.create(src.size(), CV_16SC1);
    ci::MedianMaps maps = {};
    maps.src[0] = src;
    maps.dst[0] = dst;
    ci::medianFilter(maps, 1, 0);
    finish();
}

void consistencyCheck(const GpuMat& disp16, const GpuMat& dispInt, const GpuMat& dispRight, const GpuMat& sparse16,
                      const GpuMat& nonUnique16, const GpuMat& above16, const GpuMat& below16, int gap,
                      const PipelineParams& p, GpuMat& out, GpuMat& confidence)
{
    GpuMat gapBuf(1, 1, CV_32SC1, Scalar::all(gap));
    ci::RingCheckMaps rings = {};
    if (!above16.empty() && ringCheckOn(p))
        rings = { above16, below16, nonUnique16, gapBuf.ptr<int>() };
    const cuda::PtrStepSz<short> sparse = sparse16.empty() ? cuda::PtrStepSz<short>() : cuda::PtrStepSz<short>(sparse16);
    GpuMat chunks, entries;
    const ci::SparseRows rows = sparse16.empty() ? ci::SparseRows() : sparseRows(sparse16, chunks, entries);
    out.create(disp16.size(), p.floatOutput ? CV_32FC1 : CV_16SC1);
    cuda::PtrStepSz<float> conf;
    if (p.confidence)
    {
        confidence.create(disp16.size(), CV_32FC1);
        conf = confidence;
    }
    if (p.floatOutput)
        ci::consistencyCheck(disp16, dispInt, dispRight, sparse, rows, rings, p, cuda::PtrStepSz<float>(out), conf,
                             0);
    else
        ci::consistencyCheck(disp16, dispInt, dispRight, sparse, rows, rings, p, cuda::PtrStepSz<short>(out), conf,
                             0);
    finish();
}

}}}} // namespace cv::lidarsgm::detail::cuda_host
