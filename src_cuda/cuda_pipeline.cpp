// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CUDA pipeline (host code): the stage calls in the order of src/cpu_pipeline.cpp, the GpuMat work buffers, the
// choice of each stage's overload by element type, and the ordering of calls made on different streams. The buffers
// are only (re)allocated when the size, disparity count or types change; everything else is enqueued on the stream
// without synchronising.

#include "precomp.hpp"
#include "opencv2/core/cuda_stream_accessor.hpp"
#include "cpu_stages.hpp"
#include "cuda_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace ci = cuda_impl;

namespace {

void cudaCheck(cudaError_t err)
{
    if (err != cudaSuccess)
        LIDARSGM_Error_(Error::GpuApiCallError, ("lidarsgm: %s", cudaGetErrorString(err)));
}

/* A CV_16S map of size sz inside the memory of m (any type, wide enough), from 16-bit column c0 of each of its rows:
for buffers that share memory (CudaPipeline::Buffers). */
cuda::GpuMat shortMap(const cuda::GpuMat& m, Size sz, int c0)
{
    CV_DbgAssert(m.rows >= sz.height && (int)(m.cols * m.elemSize() / 2) >= c0 + sz.width);
    return cuda::GpuMat(sz.height, (int)(m.cols * m.elemSize() / 2), CV_16SC1, m.data, m.step)
        .colRange(c0, c0 + sz.width);
}

/* The coarse pass up to its sums, for the images' element type T: left and right reduced into cl and cr, their census
strings into w.censusL and censusR (padded as rightCensusPadBefore / After of q say), the paths into w.sum. */
template <typename T>
void coarsePaths(const cuda::GpuMat& L, const cuda::GpuMat& R, const cuda::GpuMat& cl, const cuda::GpuMat& cr,
                 const PipelineParams& q, ci::WindowBuffers& w, const cuda::GpuMat& censusR, int padBefore,
                 int padAfter, cudaStream_t st)
{
    ci::coarseImages(cuda::PtrStepSz<T>(L), cuda::PtrStepSz<T>(R), cuda::PtrStepSz<T>(cl), cuda::PtrStepSz<T>(cr), st);
    ci::censusTransform(cuda::PtrStepSz<T>(cl), cuda::PtrStepSz<T>(cr), w.censusL, censusR, padBefore, padAfter, st);
    ci::aggregateCosts(w.censusL, censusR, cuda::PtrStepSz<short>(), cuda::PtrStepSz<T>(cl), q,
                       cuda::PtrStepSz<short>(), nullptr, cuda::PtrStepSz<ushort>(), ci::WindowMap(), w.sum, st);
}

} // namespace

void ci::enqueueSearchWindows(const cuda::GpuMat& prior16, const cuda::GpuMat& L, const cuda::GpuMat& R,
                              const PipelineParams& p, ci::WindowBuffers& w, cudaStream_t st)
{
    const int S = COARSE_SCALE, T = WINDOW_TILE;
    const PipelineParams q = coarseParams(p);
    const Size cs(std::max(L.cols / S, 1), std::max(L.rows / S, 1));
    w.images.create(2 * cs.height, cs.width, L.type());
    const cuda::GpuMat cl = w.images.rowRange(0, cs.height), cr = w.images.rowRange(cs.height, 2 * cs.height);
    const int padBefore = ci::rightCensusPadBefore(q), padAfter = ci::rightCensusPadAfter(q);
    w.censusL.create(cs, CV_32SC1);
    w.censusRPadded.create(cs.height, padBefore + cs.width + padAfter, CV_32SC1);
    const cuda::GpuMat censusR = w.censusRPadded.colRange(padBefore, padBefore + cs.width);
    w.sum.create(cs.height, cs.width * q.numDisparities, CV_16UC1);
    w.disp.create(3 * cs.height, cs.width, CV_16SC1);
    w.key.create(cs, CV_32SC1);
    const cuda::GpuMat d16 = w.disp.rowRange(0, cs.height), dInt = w.disp.rowRange(cs.height, 2 * cs.height),
                       dRight = w.disp.rowRange(2 * cs.height, 3 * cs.height);
    const Size tiles((L.cols + T - 1) / T, (L.rows + T - 1) / T);
    w.ranges.create(2 * tiles.height, tiles.width, CV_32SC2);
    w.windows.create(tiles, CV_16SC2);
    if (L.depth() == CV_8U)
        coarsePaths<uchar>(L, R, cl, cr, q, w, censusR, padBefore, padAfter, st);
    else
        coarsePaths<ushort>(L, R, cl, cr, q, w, censusR, padBefore, padAfter, st);
    ci::winnerTakesAll(w.sum, cs.width, cs.height, q, ci::WindowMap(), d16, dInt, w.key, dRight,
                       cuda::PtrStepSz<short>(), st);
    ci::searchWindows(prior16.empty() ? cuda::PtrStepSz<short>() : cuda::PtrStepSz<short>(prior16), dInt, p,
                      w.ranges.rowRange(0, tiles.height), w.ranges.rowRange(tiles.height, 2 * tiles.height),
                      w.windows, st);
    w.bases.create(1, tiles.area() + 1, CV_32SC1);
    ci::windowLayout(ci::windowWords(w.windows), w.bases.ptr<int>(), st);
}

struct CudaPipeline::Buffers
{
    /* The only allocations. Maps whose lifetimes do not overlap share memory (the stages run in stream order): the
    converted sparse map before the visibility filter lives in censusL's memory (the census transform runs after the
    filter); the path kernel's per-pixel facts overwrite the semidense prior they are made from (the aggregation reads
    it last); after the aggregation the census strings are dead, so the winner-takes-all's right-view keys take
    censusL's memory and its disparity maps censusRPadded's, its non-unique winners (for the ring check) the memory of
    the semidense prior; after the winner-takes-all the sum volume is dead, so the right-view disparities and the
    median's outputs take its memory. */
    cuda::GpuMat censusL, censusR, sparse16, semidense16, sum;
    cuda::GpuMat facts;              //!< the path kernel's per-pixel facts where the semidense map does not hold them
    cuda::GpuMat censusRPadded;      //!< censusR is its middle (censusTransform)
    cuda::GpuMat ring, ringStats;    //!< ring interpolation's maps (above, then below) and gap statistics
    cuda::GpuMat scanStats;          //!< the visibility filter's scan test (gap histograms and result)
    ci::WindowBuffers windows;       //!< the disparity windows and their coarse pass
    int* windowUnits = nullptr;      //!< pinned host memory: the compact volume's size (windowLayout's total)
    cuda::GpuMat unitsCounts;        //!< the units check's SparseCounts, on the device
    SparseCounts* hostCounts = nullptr;   //!< pinned host memory: their copy
    cudaEvent_t countsReady = nullptr;    //!< recorded after that copy
    bool windowed = false;           //!< the last call searched windows (windows.windows holds them)
    Size lastSize;
    int lastD = 0;
    cudaEvent_t done = nullptr;      //!< recorded at the end of the last call
    cudaStream_t lastStream = 0;     //!< the stream of the last call

    /* The buffers are shared by all calls, so a call must not start on the GPU before the previous call has finished
    with them. On the same stream that holds by stream order; on another stream the new stream first waits (on the
    GPU, not the host) for the event recorded at the end of the previous call. Inside a CUDA graph capture there is no
    event to wait for or record: a captured call must follow calls on the stream it captures (see the class
    documentation). Returns whether st is capturing. */
    bool orderAfterLastCall(cudaStream_t st)
    {
        cudaStreamCaptureStatus capture = cudaStreamCaptureStatusNone;
        cudaCheck(cudaStreamIsCapturing(st, &capture));
        const bool capturing = capture != cudaStreamCaptureStatusNone;
        if (done && st != lastStream)
        {
            if (capturing)
                LIDARSGM_Error(Error::StsBadArg, "lidarsgm: a call captured into a CUDA graph must follow this instance's "
                                                 "previous call on the same stream (the work buffers are shared)");
            cudaCheck(cudaStreamWaitEvent(st, done, 0));
        }
        return capturing;
    }

    void markCallEnd(cudaStream_t st, bool capturing)
    {
        lastStream = st;
        if (capturing)
            return;
        if (!done)
            cudaCheck(cudaEventCreateWithFlags(&done, cudaEventDisableTiming));
        cudaCheck(cudaEventRecord(done, st));
    }
};

CudaPipeline::CudaPipeline() : b_(new Buffers) {}

CudaPipeline::~CudaPipeline()
{
    if (b_->done)
        cudaEventDestroy(b_->done);
    if (b_->windowUnits)
        cudaFreeHost(b_->windowUnits);
    if (b_->hostCounts)
        cudaFreeHost(b_->hostCounts);
    if (b_->countsReady)
        cudaEventDestroy(b_->countsReady);
    delete b_;
}

void CudaPipeline::run(const cuda::GpuMat& L, const cuda::GpuMat& R, const cuda::GpuMat& Sp, const PipelineParams& p,
                       bool semidenseOnly, OutputArray out, cuda::Stream* stream, bool& warned,
                       OutputArray confidence)
{
    // No stream given: the default stream (not cuda::Stream::Null() up front: that needs a working driver).
    cudaStream_t st = stream ? cuda::StreamAccessor::getStream(*stream) : 0;
    Buffers& b = *b_;
    const bool capturing = b.orderAfterLastCall(st);
    const Size sz = L.size();
    b.censusL.create(sz, CV_32SC1);
    const int padBefore = ci::rightCensusPadBefore(p), padAfter = ci::rightCensusPadAfter(p);
    b.censusRPadded.create(sz.height, padBefore + sz.width + padAfter, CV_32SC1);
    b.censusR = b.censusRPadded.colRange(padBefore, padBefore + sz.width);
    int* scanStats = nullptr;
    if (!Sp.empty())
    {
        b.sparse16.create(sz, CV_16SC1);
        const bool filter = visibilityFilterOn(p);
        const cuda::GpuMat converted = filter ? shortMap(b.censusL, sz, 0) : b.sparse16;
        // The units check's counts: read on the host at the end of the call (checkUnits), which a graph cannot do.
        int* counts = nullptr;
        if (!capturing)
        {
            b.unitsCounts.create(1, (int)(sizeof(SparseCounts) / sizeof(int)), CV_32SC1);
            counts = b.unitsCounts.ptr<int>();
            cudaCheck(cudaMemsetAsync(counts, 0, sizeof(SparseCounts), st));
        }
        if (Sp.depth() == CV_16U)
            ci::convertSparse(cuda::PtrStepSz<ushort>(Sp), p.minDisparity, p.numDisparities, converted, counts, st);
        else
            ci::convertSparse(cuda::PtrStepSz<float>(Sp), p.minDisparity, p.numDisparities, converted, counts, st);
        if (counts)
        {
            if (!b.hostCounts)
                cudaCheck(cudaHostAlloc((void**)&b.hostCounts, sizeof(SparseCounts), cudaHostAllocDefault));
            if (!b.countsReady)
                cudaCheck(cudaEventCreateWithFlags(&b.countsReady, cudaEventDisableTiming));
            cudaCheck(cudaMemcpyAsync(b.hostCounts, counts, sizeof(SparseCounts), cudaMemcpyDeviceToHost, st));
            cudaCheck(cudaEventRecord(b.countsReady, st));
        }
        // The scan test, once for the stages that need it (on the map as given), read by them on the device.
        if (p.visibilityParallax256 > 0 || p.weighCopies)
        {
            b.scanStats.create(1, 2 * SCAN_GAP_BINS + 1, CV_32SC1);
            scanStats = b.scanStats.ptr<int>();
            ci::testScan(converted, scanStats, st);
        }
        if (filter)
            ci::filterHiddenPoints(converted, p, b.sparse16, scanStats, st);
    }
    if (L.depth() == CV_8U)
        ci::censusTransform(cuda::PtrStepSz<uchar>(L), cuda::PtrStepSz<uchar>(R), b.censusL, b.censusR, padBefore,
                            padAfter, st);
    else
        ci::censusTransform(cuda::PtrStepSz<ushort>(L), cuda::PtrStepSz<ushort>(R), b.censusL, b.censusR, padBefore,
                            padAfter, st);
    // At the end of the call, with the rest of its work queued: the counts are long copied by then.
    const bool counted = !Sp.empty() && !capturing;
    auto checkUnits = [&]() {
        if (!counted)
            return;
        cudaCheck(cudaEventSynchronize(b.countsReady));
        checkSparseUnits(*b.hostCounts, Sp.type(), p, warned);
    };
    const bool rings = (semidenseOnly || p.semidense) && p.ringGapFactor16 > 0 && !Sp.empty();
    cuda::GpuMat ringAbove, ringBelow;
    if (semidenseOnly || p.semidense)
    {
        b.semidense16.create(sz, CV_16SC1);
        ci::semidensify(b.censusL, b.censusR, b.sparse16, p, b.semidense16, st);
        if (rings)
        {
            b.ring.create(2 * sz.height, sz.width, CV_16SC1);
            b.ringStats.create(1, RING_GAP_BINS + 1, CV_32SC1);
            ringAbove = b.ring.rowRange(0, sz.height);
            ringBelow = b.ring.rowRange(sz.height, 2 * sz.height);
            ci::interpolateRings(b.censusL, b.censusR, b.sparse16, p, b.semidense16, ringAbove, ringBelow,
                                 b.ringStats.ptr<int>(), st);
        }
    }

    out.create(sz, p.floatOutput ? CV_32FC1 : CV_16SC1);
    cuda::GpuMat o = out.getGpuMat();
    if (semidenseOnly)
    {
        if (p.floatOutput)
            ci::encodeOutput(b.semidense16, p.minDisparity, cuda::PtrStepSz<float>(o), st);
        else
            ci::encodeOutput(b.semidense16, p.minDisparity, cuda::PtrStepSz<short>(o), st);
        b.markCallEnd(st, capturing);
        checkUnits();
        return;
    }

    const cuda::GpuMat prior = p.semidense ? b.semidense16 : p.ddc ? b.sparse16 : cuda::GpuMat();
    // The windows from the priors the call has (in plain SGM, the LiDAR's values where given), before the facts
    // overwrite the semidense map.
    b.windowed = searchWindowOn(p);
    b.lastSize = sz;
    b.lastD = p.numDisparities;
    ci::WindowMap windows = ci::WindowMap();
    // The sum volume; after the winner-takes-all it holds the right-view and median maps (4 W shorts a row).
    cuda::GpuMat volume;
    void* graphVolume = nullptr;
    if (b.windowed)
    {
        ci::enqueueSearchWindows(p.semidense ? b.semidense16 : Sp.empty() ? cuda::GpuMat() : b.sparse16, L, R, p,
                                 b.windows, st);
        windows = ci::windowMap(b.windows);
        // The compact volume (WindowMap) takes the windows' total, which only the device knows: the call waits for
        // it and allocates what it needs (a continuous buffer, kept while large enough). A captured call cannot
        // wait: its graph allocates (and frees) a volume of the full range's size, which any windows fit.
        const Size tiles(b.windows.windows.cols, b.windows.windows.rows);
        size_t units = (size_t)tiles.area() * (p.numDisparities / WINDOW_ALIGN);
        if (!capturing)
        {
            if (!b.windowUnits)
                cudaCheck(cudaHostAlloc((void**)&b.windowUnits, sizeof(int), cudaHostAllocDefault));
            cudaCheck(cudaMemcpyAsync(b.windowUnits, b.windows.bases.ptr<int>() + tiles.area(), sizeof(int),
                                      cudaMemcpyDeviceToHost, st));
            cudaCheck(cudaStreamSynchronize(st));
            units = (size_t)*b.windowUnits;
        }
        const size_t cols = std::max((units * ci::WINDOW_VOLUME_UNIT + sz.height - 1) / sz.height, (size_t)4 * sz.width);
        CV_Assert(cols <= (size_t)INT_MAX);
        const bool fits = !b.sum.empty() && b.sum.isContinuous() && b.sum.type() == CV_16UC1 &&
                          b.sum.rows == sz.height && (size_t)b.sum.cols >= cols;
        if (fits)
            volume = b.sum;
        else if (capturing)
        {
            cudaCheck(cudaMallocAsync(&graphVolume, cols * sz.height * sizeof(ushort), st));
            volume = cuda::GpuMat(sz.height, (int)cols, CV_16UC1, graphVolume);
        }
        else
        {
            // An eighth more than this call needs, so that the next frames' windows seldom grow it.
            b.sum.release();
            cuda::createContinuous(sz.height, (int)std::min(cols + cols / 8, (size_t)INT_MAX), CV_16UC1, b.sum);
            volume = b.sum;
        }
    }
    else
    {
        b.sum.create(sz.height, sz.width * p.numDisparities, CV_16UC1);
        volume = b.sum;
    }
    const cuda::PtrStepSz<short> prior16 = prior.empty() ? cuda::PtrStepSz<short>() : cuda::PtrStepSz<short>(prior);
    const bool weigh = p.weighCopies && scanStats;
    const cuda::PtrStepSz<short> own16 = weigh ? cuda::PtrStepSz<short>(b.sparse16) : cuda::PtrStepSz<short>();
    const int* scan = weigh ? scanStats + 2 * SCAN_GAP_BINS : nullptr;
    // The path kernel's per-pixel facts: in the semidense map's memory, which the aggregation reads for the last
    // time (the winner-takes-all reuses it); DSGM's prior, the sparse map, is read by the check later.
    cuda::GpuMat facts;
    if (p.semidense)
        facts = b.semidense16;
    else if (!prior.empty() || p.edgeThreshold > 0)
    {
        b.facts.create(sz, CV_16UC1);
        facts = b.facts;
    }
    const cuda::PtrStepSz<ushort> facts16 = facts.empty() ? cuda::PtrStepSz<ushort>() : cuda::PtrStepSz<ushort>(facts);
    if (L.depth() == CV_8U)
        ci::aggregateCosts(b.censusL, b.censusR, prior16, cuda::PtrStepSz<uchar>(L), p, own16, scan, facts16, windows,
                           volume, st);
    else
        ci::aggregateCosts(b.censusL, b.censusR, prior16, cuda::PtrStepSz<ushort>(L), p, own16, scan, facts16, windows,
                           volume, st);
    const cuda::GpuMat rightKey = b.censusL, disp16 = shortMap(b.censusRPadded, sz, 0),
                       dispInt = shortMap(b.censusRPadded, sz, sz.width), dispRight = shortMap(volume, sz, 0);
    ci::RingCheckMaps ringCheck = {};
    if (rings && ringCheckOn(p))
        ringCheck = { ringAbove, ringBelow, b.semidense16, b.ringStats.ptr<int>() + RING_GAP_BINS };
    ci::winnerTakesAll(volume, sz.width, sz.height, p, windows, disp16, dispInt, rightKey, dispRight,
                       ringCheck.nonUnique16, st);
    cuda::GpuMat d16 = disp16, dInt = dispInt, dRight = dispRight;
    if (p.medianSize == 3)
    {
        const cuda::GpuMat med16 = shortMap(volume, sz, sz.width), medInt = shortMap(volume, sz, 2 * sz.width),
                           medRight = shortMap(volume, sz, 3 * sz.width);
        const ci::MedianMaps maps = { { disp16, dispInt, dispRight }, { med16, medInt, medRight } };
        ci::medianFilter(maps, 3, st);
        d16 = med16;
        dInt = medInt;
        dRight = medRight;
    }
    const cuda::PtrStepSz<short> sparse = b.sparse16.empty() || Sp.empty() ? cuda::PtrStepSz<short>()
                                                                           : cuda::PtrStepSz<short>(b.sparse16);
    cuda::PtrStepSz<float> conf;
    if (p.confidence)
    {
        confidence.create(sz, CV_32FC1);
        conf = confidence.getGpuMat();
    }
    if (p.floatOutput)
        ci::consistencyCheck(d16, dInt, dRight, sparse, ringCheck, p, cuda::PtrStepSz<float>(o), conf, st);
    else
        ci::consistencyCheck(d16, dInt, dRight, sparse, ringCheck, p, cuda::PtrStepSz<short>(o), conf, st);
    if (graphVolume)
        cudaCheck(cudaFreeAsync(graphVolume, st));
    b.markCallEnd(st, capturing);
    checkUnits();
}

double CudaPipeline::searchedFraction() const
{
    if (!b_->windowed)
        return b_->lastD ? 1.0 : 0.0;
    if (b_->done)
        cudaCheck(cudaEventSynchronize(b_->done));   // the call that made them has finished
    Mat windows;
    b_->windows.windows.download(windows);
    return (double)windowCells(windows, b_->lastSize) / ((double)b_->lastSize.area() * b_->lastD);
}

void CudaPipeline::projectPoints(const cuda::GpuMat& points, int n, int strideFloats, const double PT[12],
                                 double focalBaseline, Size imageSize, int dtype, OutputArray out,
                                 cuda::Stream& stream)
{
    out.create(imageSize, dtype == CV_32F ? CV_32FC1 : CV_16UC1);
    cuda::GpuMat o = out.getGpuMat();
    // CV_16U output needs the float map first: a temporary (the projection keeps no buffers between calls).
    cuda::GpuMat disp = dtype == CV_32F ? o : cuda::GpuMat(imageSize, CV_32FC1);
    ci::projectPoints(n ? points.ptr<float>() : nullptr, n, strideFloats, PT, focalBaseline, disp,
                      dtype == CV_16U ? cuda::PtrStepSz<ushort>(o) : cuda::PtrStepSz<ushort>(),
                      cuda::StreamAccessor::getStream(stream));
}

}}} // namespace cv::lidarsgm::detail
