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
for buffers that share memory (CudaPipeline::Buffers::BufferPlan). */
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
    // Plain SGM over the full range: no prior, no copied priors, no windows, so no facts.
    ci::AggregationInputs<T> in;
    in.censusL = w.censusL;
    in.censusR = censusR;
    in.left = cl;
    ci::AggregationOutputs out;
    out.sum = w.sum;
    ci::aggregateCosts(in, q, out, st);
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
    ci::WinnerInputs sums;
    sums.sum = w.sum;
    sums.width = cs.width;
    sums.height = cs.height;
    ci::WinnerMaps winners;
    winners.disp16 = d16;
    winners.dispInt = dInt;
    winners.dispRight = dRight;
    ci::winnerTakesAll(sums, q, winners, w.key, st);
    ci::searchWindows(prior16.empty() ? cuda::PtrStepSz<short>() : cuda::PtrStepSz<short>(prior16), dInt, p,
                      w.ranges.rowRange(0, tiles.height), w.ranges.rowRange(tiles.height, 2 * tiles.height),
                      w.windows, st);
    w.bases.create(1, tiles.area() + 1, CV_32SC1);
    ci::windowLayout(ci::windowWords(w.windows), w.bases.ptr<int>(), st);
}

struct CudaPipeline::Buffers
{
    // The only allocations (BufferPlan says which of them a call's maps share).
    cuda::GpuMat censusL, censusR, sparse16, semidense16, sum;
    cuda::GpuMat facts;              //!< the path kernel's per-pixel facts where the semidense map does not hold them
    cuda::GpuMat censusRPadded;      //!< censusR is its middle (censusTransform)
    cuda::GpuMat ring, ringStats;    //!< ring interpolation's maps (above, then below) and gap statistics
    cuda::GpuMat scanStats;          //!< the visibility filter's scan test (gap histograms and result)
    cuda::GpuMat sparseChunks, sparseEntries;   //!< the sparse map's points row by row (ci::SparseRows)
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

    /* Which memory each map of a call takes. Maps whose lifetimes do not overlap share memory (the stages run in
    stream order):
    - the converted sparse map before the visibility filter lives in censusL's memory (the census transform runs
      after the filter);
    - the path kernel's per-pixel facts overwrite the semidense prior they are made from (the aggregation reads it
      last); DSGM's prior, the sparse map, is read by the check later, so DSGM (and SGM with the edge rule) keeps
      them in a map of their own;
    - after the aggregation the census strings are dead, so the winner-takes-all's right-view keys take censusL's
      memory and its disparity maps censusRPadded's, its non-unique winners (for the ring check) the memory of the
      semidense prior;
    - after the winner-takes-all the sum volume is dead, so the right-view disparities and the median's outputs take
      its memory (4 W shorts a row). */
    struct BufferPlan
    {
        Buffers& b;
        Size sz;
        cuda::GpuMat convertedSparse() const { return shortMap(b.censusL, sz, 0); }
        //! The facts of a call with a prior or the edge rule (else none).
        cuda::GpuMat facts(const PipelineParams& p, bool prior) const
        {
            if (p.semidense)
                return b.semidense16;
            if (!(prior || p.edgeThreshold > 0))
                return cuda::GpuMat();
            b.facts.create(sz, CV_16UC1);
            return b.facts;
        }
        cuda::GpuMat rightKey() const { return b.censusL; }
        cuda::GpuMat disp16() const { return shortMap(b.censusRPadded, sz, 0); }
        cuda::GpuMat dispInt() const { return shortMap(b.censusRPadded, sz, sz.width); }
        cuda::GpuMat nonUnique16() const { return b.semidense16; }
        //! In the volume: 0 the right view, 1 to 3 the median's outputs of disp16, dispInt and dispRight.
        cuda::GpuMat afterSums(const cuda::GpuMat& volume, int k) const { return shortMap(volume, sz, k * sz.width); }
    };

    //! One call: its arguments, and what its stages hand on.
    struct Call
    {
        Call(const cuda::GpuMat& L_, const cuda::GpuMat& R_, const cuda::GpuMat& Sp_, const PipelineParams& p_,
             cudaStream_t st_, bool capturing_)
            : L(L_), R(R_), Sp(Sp_), p(p_), st(st_), capturing(capturing_), sz(L_.size())
        {
        }
        const cuda::GpuMat& L;
        const cuda::GpuMat& R;
        const cuda::GpuMat& Sp;
        const PipelineParams& p;
        cudaStream_t st;
        bool capturing;
        Size sz;
        int* scanStats = nullptr;         //!< the scan test's statistics where it ran
        ci::SparseRows sparseRows = {};   //!< sparse16's points row by row, where the call has a sparse map
        bool rings = false;               //!< ring interpolation ran: ringAbove, ringBelow and ringStats hold its maps
        cuda::GpuMat ringAbove, ringBelow;
        ci::WindowMap windows = ci::WindowMap();
        cuda::GpuMat volume;              //!< the sum volume (sum, or a captured call's own)
        void* graphVolume = nullptr;      //!< a captured call's volume, freed at its end
        bool costsStored = false;         //!< the volume's second half holds the windows' costs (windowCostsStored)
    };

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

    //! The census strings' buffers; censusR is padded as the path kernel reads it (rightCensusPadBefore / After).
    void censusBuffers(const Call& c)
    {
        censusL.create(c.sz, CV_32SC1);
        const int padBefore = ci::rightCensusPadBefore(c.p), padAfter = ci::rightCensusPadAfter(c.p);
        censusRPadded.create(c.sz.height, padBefore + c.sz.width + padAfter, CV_32SC1);
        censusR = censusRPadded.colRange(padBefore, padBefore + c.sz.width);
    }

    /* The sparse input: conversion (with the units check's counts, copied to the host for checkUnits, which a graph
    cannot do), the scan test, the visibility filter. */
    void sparseInput(Call& c, const BufferPlan& plan)
    {
        const PipelineParams& p = c.p;
        sparse16.create(c.sz, CV_16SC1);
        const bool filter = visibilityFilterOn(p);
        const cuda::GpuMat converted = filter ? plan.convertedSparse() : sparse16;
        int* counts = nullptr;
        if (!c.capturing)
        {
            unitsCounts.create(1, (int)(sizeof(SparseCounts) / sizeof(int)), CV_32SC1);
            counts = unitsCounts.ptr<int>();
            cudaCheck(cudaMemsetAsync(counts, 0, sizeof(SparseCounts), c.st));
        }
        if (c.Sp.depth() == CV_16U)
            ci::convertSparse(cuda::PtrStepSz<ushort>(c.Sp), p.minDisparity, p.numDisparities, converted, counts, c.st);
        else
            ci::convertSparse(cuda::PtrStepSz<float>(c.Sp), p.minDisparity, p.numDisparities, converted, counts, c.st);
        if (counts)
        {
            if (!hostCounts)
                cudaCheck(cudaHostAlloc((void**)&hostCounts, sizeof(SparseCounts), cudaHostAllocDefault));
            if (!countsReady)
                cudaCheck(cudaEventCreateWithFlags(&countsReady, cudaEventDisableTiming));
            cudaCheck(cudaMemcpyAsync(hostCounts, counts, sizeof(SparseCounts), cudaMemcpyDeviceToHost, c.st));
            cudaCheck(cudaEventRecord(countsReady, c.st));
        }
        // The scan test, once for the stages that need it (on the map as given), read by them on the device.
        if (p.visibilityParallax256 > 0 || p.weighCopies)
        {
            scanStats.create(1, 2 * SCAN_GAP_BINS + 1, CV_32SC1);
            c.scanStats = scanStats.ptr<int>();
            ci::testScan(converted, c.scanStats, c.st);
        }
        // The points row by row for the stages that list a tile's points: of the converted map for the filter,
        // then (in the same memory, which the filter has read by then in stream order) of the map it keeps.
        c.sparseRows = ci::sparseRowsBuffers(c.sz, sparseChunks, sparseEntries);
        ci::listSparseRows(converted, c.sparseRows, c.st);
        if (filter)
        {
            ci::filterHiddenPoints(converted, c.sparseRows, p, sparse16, c.scanStats, c.st);
            ci::listSparseRows(sparse16, c.sparseRows, c.st);
        }
    }

    void census(const Call& c)
    {
        const int padBefore = ci::rightCensusPadBefore(c.p), padAfter = ci::rightCensusPadAfter(c.p);
        if (c.L.depth() == CV_8U)
            ci::censusTransform(cuda::PtrStepSz<uchar>(c.L), cuda::PtrStepSz<uchar>(c.R), censusL, censusR, padBefore,
                                padAfter, c.st);
        else
            ci::censusTransform(cuda::PtrStepSz<ushort>(c.L), cuda::PtrStepSz<ushort>(c.R), censusL, censusR,
                                padBefore, padAfter, c.st);
    }

    //! Semidensification and ring interpolation (SDSGM, or the semidense map alone).
    void semidense(Call& c)
    {
        semidense16.create(c.sz, CV_16SC1);
        ci::semidensify(censusL, censusR, sparse16, c.sparseRows, c.p, semidense16, c.st);
        if (!c.rings)
            return;
        ring.create(2 * c.sz.height, c.sz.width, CV_16SC1);
        ringStats.create(1, RING_GAP_BINS + 1, CV_32SC1);
        c.ringAbove = ring.rowRange(0, c.sz.height);
        c.ringBelow = ring.rowRange(c.sz.height, 2 * c.sz.height);
        ci::interpolateRings(censusL, censusR, sparse16, c.p, semidense16, c.ringAbove, c.ringBelow,
                             ringStats.ptr<int>(), c.st);
    }

    /* The windows from the priors the call has (in plain SGM, the LiDAR's values where given), before the facts
    overwrite the semidense map; then the compact volume (WindowMap), which takes the windows' total, which only the
    device knows: the call waits for it and allocates what it needs (a continuous buffer, kept while large enough). A
    captured call cannot wait: its graph allocates (and frees) a volume of the full range's size, which any windows
    fit. */
    void windowedVolume(Call& c)
    {
        const PipelineParams& p = c.p;
        const Size sz = c.sz;
        ci::enqueueSearchWindows(p.semidense ? semidense16 : c.Sp.empty() ? cuda::GpuMat() : sparse16, c.L, c.R, p,
                                 windows, c.st);
        c.windows = ci::windowMap(windows);
        const Size tiles(windows.windows.cols, windows.windows.rows);
        size_t units = (size_t)tiles.area() * (p.numDisparities / WINDOW_ALIGN);
        if (!c.capturing)
        {
            if (!windowUnits)
                cudaCheck(cudaHostAlloc((void**)&windowUnits, sizeof(int), cudaHostAllocDefault));
            cudaCheck(cudaMemcpyAsync(windowUnits, windows.bases.ptr<int>() + tiles.area(), sizeof(int),
                                      cudaMemcpyDeviceToHost, c.st));
            cudaCheck(cudaStreamSynchronize(c.st));
            units = (size_t)*windowUnits;
        }
        c.costsStored = ci::windowCostsStored(p, sz, ci::streamSmCount(c.st));
        const size_t shorts = ci::windowVolumeShorts(units, c.costsStored);
        const size_t cols = std::max((shorts + sz.height - 1) / sz.height, (size_t)4 * sz.width);
        CV_Assert(cols <= (size_t)INT_MAX);
        const bool fits = !sum.empty() && sum.isContinuous() && sum.type() == CV_16UC1 && sum.rows == sz.height &&
                          (size_t)sum.cols >= cols;
        if (fits)
            c.volume = sum;
        else if (c.capturing)
        {
            cudaCheck(cudaMallocAsync(&c.graphVolume, cols * sz.height * sizeof(ushort), c.st));
            c.volume = cuda::GpuMat(sz.height, (int)cols, CV_16UC1, c.graphVolume);
        }
        else
        {
            // An eighth more than this call needs, so that the next frames' windows seldom grow it.
            sum.release();
            cuda::createContinuous(sz.height, (int)std::min(cols + cols / 8, (size_t)INT_MAX), CV_16UC1, sum);
            c.volume = sum;
        }
    }

    //! The sum volume: the windows' compact one, or the full range's (4 W shorts a row at least: BufferPlan).
    void sumVolume(Call& c)
    {
        windowed = searchWindowOn(c.p);
        lastSize = c.sz;
        lastD = c.p.numDisparities;
        if (windowed)
            windowedVolume(c);
        else
        {
            sum.create(c.sz.height, c.sz.width * c.p.numDisparities, CV_16UC1);
            c.volume = sum;
        }
    }

    //! The aggregation's inputs for images of element type T.
    template <typename T>
    ci::AggregationInputs<T> aggregationInputs(const Call& c, const cuda::GpuMat& prior) const
    {
        ci::AggregationInputs<T> in;
        in.censusL = censusL;
        in.censusR = censusR;
        if (!prior.empty())
            in.prior16 = prior;
        in.left = c.L;
        if (c.p.weighCopies && c.scanStats)
        {
            in.own16 = sparse16;
            in.scan = c.scanStats + 2 * SCAN_GAP_BINS;
        }
        in.windows = c.windows;
        return in;
    }

    void aggregate(const Call& c, const BufferPlan& plan)
    {
        const PipelineParams& p = c.p;
        const cuda::GpuMat prior = p.semidense ? semidense16 : p.ddc ? sparse16 : cuda::GpuMat();
        ci::AggregationOutputs out;
        out.sum = c.volume;
        const cuda::GpuMat factsMap = plan.facts(p, !prior.empty());
        if (!factsMap.empty())
            out.facts = factsMap;
        if (c.costsStored)
            out.costs = ci::windowCostsOf(c.volume.data, (size_t)c.volume.rows * c.volume.cols);
        if (c.L.depth() == CV_8U)
            ci::aggregateCosts(aggregationInputs<uchar>(c, prior), p, out, c.st);
        else
            ci::aggregateCosts(aggregationInputs<ushort>(c, prior), p, out, c.st);
    }

    /* The winner-takes-all, then (medianSize 3) the median of its three maps: returns the maps the check takes, and
    in ringCheck the ring check's inputs. */
    ci::WinnerMaps winners(const Call& c, const BufferPlan& plan, ci::RingCheckMaps& ringCheck)
    {
        ci::WinnerInputs sums;
        sums.sum = c.volume;
        sums.width = c.sz.width;
        sums.height = c.sz.height;
        sums.windows = c.windows;
        ci::WinnerMaps maps;
        maps.disp16 = plan.disp16();
        maps.dispInt = plan.dispInt();
        maps.dispRight = plan.afterSums(c.volume, 0);
        if (c.rings && ringCheckOn(c.p))
        {
            ringCheck = { c.ringAbove, c.ringBelow, plan.nonUnique16(), ringStats.ptr<int>() + RING_GAP_BINS };
            maps.nonUnique16 = ringCheck.nonUnique16;
        }
        const bool median = c.p.medianSize == 3;
        // With the median, it reads the right view's keys itself: no pass converts them first.
        ci::WinnerMaps unfiltered = maps;
        if (median)
            unfiltered.dispRight = cuda::PtrStepSz<short>();
        ci::winnerTakesAll(sums, c.p, unfiltered, plan.rightKey(), c.st);
        if (!median)
            return maps;
        ci::WinnerMaps med = maps;
        med.disp16 = plan.afterSums(c.volume, 1);
        med.dispInt = plan.afterSums(c.volume, 2);
        med.dispRight = plan.afterSums(c.volume, 3);
        const ci::MedianMaps filter = { { maps.disp16, maps.dispInt, cuda::PtrStepSz<short>() },
                                        { med.disp16, med.dispInt, med.dispRight },
                                        plan.rightKey(), c.p.minDisparity };
        ci::medianFilter(filter, 3, c.st);
        return med;
    }

    void check(const Call& c, const ci::WinnerMaps& maps, const ci::RingCheckMaps& ringCheck, const cuda::GpuMat& o,
               OutputArray confidence)
    {
        const cuda::PtrStepSz<short> sparse = sparse16.empty() || c.Sp.empty() ? cuda::PtrStepSz<short>()
                                                                               : cuda::PtrStepSz<short>(sparse16);
        cuda::PtrStepSz<float> conf;
        if (c.p.confidence)
        {
            confidence.create(c.sz, CV_32FC1);
            conf = confidence.getGpuMat();
        }
        if (c.p.floatOutput)
            ci::consistencyCheck(maps.disp16, maps.dispInt, maps.dispRight, sparse, c.sparseRows, ringCheck, c.p,
                                 cuda::PtrStepSz<float>(o), conf, c.st);
        else
            ci::consistencyCheck(maps.disp16, maps.dispInt, maps.dispRight, sparse, c.sparseRows, ringCheck, c.p,
                                 cuda::PtrStepSz<short>(o), conf, c.st);
    }

    //! The end of a call, with the rest of its work queued: the units check's counts are long copied by then.
    void endCall(const Call& c, bool& warned)
    {
        markCallEnd(c.st, c.capturing);
        if (c.Sp.empty() || c.capturing)
            return;
        cudaCheck(cudaEventSynchronize(countsReady));
        checkSparseUnits(*hostCounts, c.Sp.type(), c.p, warned);
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
    Buffers::Call c(L, R, Sp, p, st, b.orderAfterLastCall(st));
    const Buffers::BufferPlan plan = { b, c.sz };
    b.censusBuffers(c);
    if (!Sp.empty())
        b.sparseInput(c, plan);
    b.census(c);
    c.rings = (semidenseOnly || p.semidense) && p.ringGapFactor16 > 0 && !Sp.empty();
    if (semidenseOnly || p.semidense)
        b.semidense(c);
    out.create(c.sz, p.floatOutput ? CV_32FC1 : CV_16SC1);
    const cuda::GpuMat o = out.getGpuMat();
    if (semidenseOnly)
    {
        if (p.floatOutput)
            ci::encodeOutput(b.semidense16, p.minDisparity, cuda::PtrStepSz<float>(o), st);
        else
            ci::encodeOutput(b.semidense16, p.minDisparity, cuda::PtrStepSz<short>(o), st);
        b.endCall(c, warned);
        return;
    }
    b.sumVolume(c);
    b.aggregate(c, plan);
    ci::RingCheckMaps ringCheck = {};
    const ci::WinnerMaps maps = b.winners(c, plan, ringCheck);
    b.check(c, maps, ringCheck, o, confidence);
    if (c.graphVolume)
        cudaCheck(cudaFreeAsync(c.graphVolume, st));
    b.endCall(c, warned);
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
