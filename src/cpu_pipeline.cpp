// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU pipeline: the stage calls in order (src_cuda/cuda_pipeline.cpp makes the same calls on the GPU). The work
// buffers are members, so repeated calls at one size allocate nothing.

#include "precomp.hpp"
#include "cpu_stages.hpp"
#include "sparse_window.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void CpuPipeline::run(const Mat& left, const Mat& right, const Mat& sparse, const PipelineParams& p,
                      bool semidenseOnly, OutputArray out, bool& warned, OutputArray confidence)
{
    bool scan = false;   // the scan test, run once where a stage needs it (on the map as given)
    if (!sparse.empty())
    {
        // First, so that a map in the wrong units is refused before any other work.
        SparseCounts counts;
        convertSparse(sparse, p.minDisparity, p.numDisparities, sparse16_, &counts);
        checkSparseUnits(counts, sparse.type(), p, warned);
        if (p.visibilityParallax256 > 0 || p.weighCopies)
            scan = isLidarScan(sparse16_);
        if (visibilityFilterOn(p))
        {
            filterHiddenPoints(sparse16_, p, visible16_, scan);
            std::swap(sparse16_, visible16_);
        }
    }
    else
        sparse16_.release();
    censusTransform(left, censusL_);
    censusTransform(right, censusR_);
    if (!points_)
        points_ = makePtr<SparseColumns>();
    points_->build(sparse16_);
    if (semidenseOnly || p.semidense)
    {
        semidensify(censusL_, censusR_, sparse16_, p, semidense16_, points_.get());
        interpolateRings(censusL_, censusR_, sparse16_, p, semidense16_, rings_, points_.get());
    }
    else
        rings_.valid = false;
    if (semidenseOnly)
    {
        encodeOutput(semidense16_, p, out);
        return;
    }

    // The windows from the priors the call has (in plain SGM, the LiDAR's values where given).
    if (searchWindowOn(p))
    {
        searchWindows(p.semidense ? semidense16_ : sparse16_, left, right, p, windows_, &coarseAggregation_);
        searched_ = (double)windowCells(windows_, left.size()) / ((double)left.total() * p.numDisparities);
    }
    else
    {
        windows_.release();
        searched_ = 1.0;
    }
    AggregationInputs in;
    in.censusL = censusL_;
    in.censusR = censusR_;
    if (p.semidense || p.ddc)
        in.prior16 = p.semidense ? semidense16_ : sparse16_;
    in.left = left;
    if (p.weighCopies && scan)
        in.own16 = sparse16_;
    in.windows = windows_;
    aggregateCosts(in, p, winners_, &aggregation_);
    const WinnerMaps& w = winners_;
    if (p.medianSize == 3)
    {
        medianFilter(w.disp16, med16_);
        medianFilter(w.dispInt, medInt_);
        medianFilter(w.dispRight, medRight_);
        consistencyCheck(med16_, medInt_, medRight_, sparse16_, w.nonUnique16, rings_, p, out, confidence,
                         points_.get());
    }
    else
        consistencyCheck(w.disp16, w.dispInt, w.dispRight, sparse16_, w.nonUnique16, rings_, p, out, confidence,
                         points_.get());
}

}}} // namespace cv::lidarsgm::detail
