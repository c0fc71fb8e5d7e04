// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The CPU stages, one file each (src/<stage>.cpp), in pipeline order; their CUDA twins carry the same names
// (src_cuda/cuda_stages.hpp). Exported for the per-stage unit tests; not part of the public API.

#ifndef OPENCV_LIDARSGM_CPU_STAGES_HPP
#define OPENCV_LIDARSGM_CPU_STAGES_HPP

#include "pipeline.hpp"
#include "opencv2/core/utility.hpp"

namespace cv { namespace lidarsgm { namespace detail {

/** The stripes of a parallel_for_ over the rows of an image: at least four per thread, so that the threads finish
together, and at least one per 16 rows, so that a thread held up (a busy core) leaves little for the others to wait on. */
inline double rowStripes(int rows)
{
    return std::max(1, std::min(rows, std::max(rows / 16, 4 * getNumThreads())));
}

/** Sparse input (CV_16UC1 x256 or CV_32FC1 pixels) to the internal CV_16SC1 1/16-pixel map with NO_DISP for "none"
(sparseFromKitti16, sparseFromFloat); counts, where given, receives the units check's counts. */
CV_EXPORTS void convertSparse(const Mat& sparse, int minDisparity, int numDisparities, Mat& sparse16,
                              SparseCounts* counts = nullptr);
/** The units check on convertSparse's counts, for both paths: raises the refusal where unitsLookWrong, and warns once
(warned: the matcher's flag) where a mode that needs priors got a map without a value in the range. */
CV_EXPORTS void checkSparseUnits(const SparseCounts& counts, int sparseType, const PipelineParams& p, bool& warned);

/** The visibility filter (hiddenBy): visible16 is sparse16 without the values that a value within the
(2 visibilityRadiusX + 1) x (2 visibilityRadiusY + 1) window hides. scan: isLidarScan(sparse16); the window's parallax
growth applies only where it is true. */
CV_EXPORTS void filterHiddenPoints(const Mat& sparse16, const PipelineParams& p, Mat& visible16, bool scan);
/** The scan test (visibilityGrowthApplies, pipeline.hpp): whether the sparse map's points are closer along the rows
than across them, as a LiDAR's rings are. Gates the parallax growth and the copied priors' weight. */
CV_EXPORTS bool isLidarScan(const Mat& sparse16);
//! The scan test's histograms of rowPointGap and columnPointGap (SCAN_GAP_BINS ints each).
CV_EXPORTS void scanGapHistograms(const Mat& sparse16, int* rowGaps, int* columnGaps);

//! Census transform (CV_8UC1 or CV_16UC1 in, CV_32SC1 bit strings out); pixels outside the image are clamped.
CV_EXPORTS void censusTransform(const Mat& image, Mat& census);

struct SparseColumns;   // sparse16's points by column and by row (sparse_window.hpp)

/** Semidensification (paper Eq. 5): among the sparse disparities q in the (2 rs + 1)^2 window of p, the best
candidate (semidenseKey: census cost H(p, round(q)) first) wins if its cost is below Ts; otherwise p keeps its own sparse
value (or none). points: sparse16's points where the caller has listed them (else listed here). */
CV_EXPORTS void semidensify(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                            Mat& semidense16, const SparseColumns* points = nullptr);

/** Ring interpolation (pipeline.hpp; off where p.ringGapFactor16 is 0): fills the pixels of semidense16 that have no
value. rings receives the maps and gap limit that the ring check reuses (valid false where the rule is off). points:
sparse16's points where the caller has listed them. */
CV_EXPORTS void interpolateRings(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                                 Mat& semidense16, RingMaps& rings, const SparseColumns* points = nullptr);
/** Ring interpolation's maps of a sparse map (RingMaps: above16, below16 and each pixel's nearestRingPoints in
nearest; the gap and valid are left as they are). */
CV_EXPORTS void ringNearestMaps(const Mat& sparse16, RingMaps& rings);

/** The disparity windows (tileWindow, pipeline.hpp): windows receives per WINDOW_TILE tile (lo, hi) as CV_16SC2.
prior16: the call's prior map (may be empty); where a tile has no prior around it, the coarse pass
(coarseDisparities) on left and right (CV_8UC1 or CV_16UC1) gives its range. work: the coarse aggregation's buffers
kept between calls (nullptr: temporaries). coarse (tests): the coarse map, empty where the pass did not run. */
CV_EXPORTS void searchWindows(const Mat& prior16, const Mat& left, const Mat& right, const PipelineParams& p,
                              Mat& windows, Ptr<AggregationState>* work = nullptr, Mat* coarse = nullptr);
/** The coarse pass: left and right reduced by COARSE_SCALE (coarseMean of each block, the border replicated), and
plain SGM on them with coarseParams(p); coarse receives its integer disparities (CV_16SC1, coarse pixels). work: the
coarse aggregation's buffers kept between calls (aggregateCosts). */
CV_EXPORTS void coarseDisparities(const Mat& left, const Mat& right, const PipelineParams& p, Mat& coarse,
                                  Ptr<AggregationState>* work = nullptr);
//! The cells the windows cover in an image of the given size (sum over the pixels of hi - lo).
CV_EXPORTS int64 windowCells(const Mat& windows, Size size);

//! aggregateCosts' inputs; what a call does not have stays empty.
struct AggregationInputs
{
    Mat censusL, censusR;   //!< censusTransform's strings
    Mat prior16;            //!< the prior (k = round(prior16) - minD where it has a value); empty: plain SGM
    Mat left;               //!< the jump penalty's intensity steps, read only when p.edgeThreshold > 0
    Mat own16;              //!< the filtered sparse map where copied priors take p.wCopy (copiedPrior); empty: w
    Mat windows;            //!< searchWindows' windows; empty: the full range
};

/** Semi-global aggregation (paper Eq. 2) over 4 or 8 paths and the winner-takes-all, fused: the matching cost
(matchingCost with the prior index round(prior16) - minD where prior16 has a value) is computed as the paths go, and
each pixel's winner is taken when its sum completes (aggregation.simd.hpp). out receives the winner's maps
(WinnerMaps). With windows each pixel searches its tile's window only (its sums there, the rest of finalSum
SENTINEL), paths reaching a disparity outside the previous pixel's window through the jump only.
work: the call's buffers (the 16-bit volume of partial sums, rows of costs and path costs, the right view), kept
between calls by the caller, so that repeated calls at one size neither allocate nor fault in 2 W H D bytes and more;
nullptr: temporaries. */
CV_EXPORTS void aggregateCosts(const AggregationInputs& in, const PipelineParams& p, WinnerMaps& out,
                               Ptr<AggregationState>* work = nullptr);
//! aggregateCosts, also writing the aggregated costs to finalSum (tests): rows = image rows, cols = width * D.
CV_EXPORTS void aggregateCosts(const AggregationInputs& in, const PipelineParams& p, WinnerMaps& out, Mat& finalSum,
                               Ptr<AggregationState>* work = nullptr);

/** The matching cost volume that aggregateCosts computes as it goes (for the tests): rows = image rows,
cols = width * numDisparities, CV_16UC1, d fastest. The right pixel x - minD - d is clamped to the image. */
CV_EXPORTS void computeMatchingCost(const Mat& censusL, const Mat& censusR, const Mat& prior16,
                                    const PipelineParams& p, Mat& cost);

//! The winner-takes-all of aggregateCosts on a given volume of aggregated costs (for the tests).
CV_EXPORTS void winnerTakesAll(const Mat& sum, int width, const PipelineParams& p, Mat& disp16, Mat& dispInt,
                               Mat& dispRight, Mat& nonUnique16);

/** 3x3 median of a CV_16SC1 disparity map (1/16 or whole pixels), "no disparity" ranked above every value,
coordinates clamped at the border (medianKey, medianOfColumns). src and dst must differ. */
CV_EXPORTS void medianFilter(const Mat& src, Mat& dst);

/** Consistency check (paper Eq. 6) and output encoding: a disparity of disp16 survives the left-right test
(|dL - dR(x - dL)| <= lrMaxDiff, dispInt against dispRight) and/or the LiDAR test (some sparse16 value within the
(2 rc + 1)^2 window is within checkThreshold16 of it), as p says; out receives the encoded result (encodeOutput).
With ringCheckOn(p) and valid rings, the LiDAR test includes the ring check (pipeline.hpp), which may also keep the
value of nonUnique16 where disp16 has none. With p.confidence, confidence receives each output pixel's confidence
(outputConfidence, CV_32FC1, 0 where out has no disparity). points: sparse16's points where the caller has listed them
(else listed here). */
CV_EXPORTS void consistencyCheck(const Mat& disp16, const Mat& dispInt, const Mat& dispRight, const Mat& sparse16,
                                 const Mat& nonUnique16, const RingMaps& rings, const PipelineParams& p,
                                 OutputArray out, OutputArray confidence = noArray(),
                                 const SparseColumns* points = nullptr);

//! A 1/16-pixel map in the output format without any check (the semidense map of semidensify()).
CV_EXPORTS void encodeOutput(const Mat& disp16, const PipelineParams& p, OutputArray out);

}}} // namespace cv::lidarsgm::detail

#endif
