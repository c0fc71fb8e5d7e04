// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_EVALUATION_HPP
#define OPENCV_LIDARSGM_EVALUATION_HPP

#include "opencv2/core.hpp"

namespace cv {
namespace lidarsgm {

//! @addtogroup lidarsgm
//! @{

/** @brief Error counts of a disparity map against ground truth, as the KITTI stereo devkit reports them.

Counts add up over frames (add()), and the percentages are taken over the sums, not averaged per frame.
 */
struct CV_EXPORTS_W_SIMPLE DisparityErrors
{
    CV_WRAP DisparityErrors() {}
    CV_PROP_RW int64 groundTruthPixels = 0;   //!< pixels with ground truth
    CV_PROP_RW int64 estimatedPixels = 0;     //!< of those, pixels with an estimate
    CV_PROP_RW int64 estimatedOutliers = 0;   //!< of those, outliers
    CV_PROP_RW int64 totalOutliers = 0;       //!< outliers over all ground-truth pixels, missing estimates filled

    /** Adds another frame's counts. */
    CV_WRAP void add(const DisparityErrors& other);
    /** estimatedPixels / groundTruthPixels, in percent. */
    CV_WRAP double coverage() const;
    /** estimatedOutliers / estimatedPixels, in percent (the "covered error"). */
    CV_WRAP double coveredError() const;
    /** totalOutliers / groundTruthPixels, in percent (the "total error"). */
    CV_WRAP double totalError() const;
};

//! Outlier rules of evaluateDisparity().
enum DisparityErrorMetric
{
    METRIC_KITTI_D1 = 0, //!< KITTI's D1: |d - gt| > 3 px and > 5 % of gt
    METRIC_BAD = 1       //!< Middlebury's bad-N: |d - gt| > N px
};

/** @brief Scores a disparity map against ground truth with the KITTI devkit's rules.

@param disparity the estimate: CV_32FC1 in pixels, or a matcher's CV_16SC1 output (disparity x 16). A value below
minDisparity, or not finite, means "no estimate" (the matchers' invalid value is minDisparity - 1).
@param groundTruth CV_32FC1 in pixels (negative or not finite: no ground truth) or CV_16UC1 in KITTI's encoding
(value / 256, 0: no ground truth); same size.
@param metric METRIC_KITTI_D1 or METRIC_BAD.
@param badThreshold N of METRIC_BAD, in pixels.
@param minDisparity see disparity.
@return the counts; totalOutliers scores the map after interpolateBackground() filled the missing estimates
(a pixel it cannot fill is scored with disparity -1, as the devkit does).
 */
CV_EXPORTS_W DisparityErrors evaluateDisparity(InputArray disparity, InputArray groundTruth,
                                               int metric = METRIC_KITTI_D1, double badThreshold = 2.0,
                                               int minDisparity = 0);

/** @brief How a confidence map ranks a disparity map's errors: the counts of its sparsification curve.

The covered pixels (an estimate and ground truth) and their outliers, per confidence level (round(confidence x 65535),
the levels of the tool's 16-bit confidence PNG); counts add up over frames (add()). The curve removes the least
confident pixels first; pixels of one level are removed together in proportion, so that the order among ties cannot
flatter it.
 */
struct CV_EXPORTS_W_SIMPLE ConfidenceErrors
{
    CV_WRAP ConfidenceErrors() {}
    CV_PROP_RW std::vector<double> pixels;     //!< covered pixels per level (65536 levels; empty: none yet)
    CV_PROP_RW std::vector<double> outliers;   //!< their outliers per level

    /** Adds another frame's counts. */
    CV_WRAP void add(const ConfidenceErrors& other);
    /** Covered pixels in all. */
    CV_WRAP double total() const;
    /** Outliers among the covered pixels in all. */
    CV_WRAP double totalOutliers() const;
    /** The share of all outliers that the given fraction of least confident pixels holds, in percent. */
    CV_WRAP double leastConfidentShare(double fraction) const;
    /** The covered error of the given fraction of most confident pixels, in percent. */
    CV_WRAP double keptError(double fraction) const;
    /** The area under the curve of keptError (as a fraction, not percent) over the fraction kept, in (0, 1]. */
    CV_WRAP double auc() const;
    /** The same area for the oracle order (the outliers removed first): e + (1 - e) ln(1 - e), e the error rate. */
    CV_WRAP double oracleAuc() const;
};

/** @brief The counts of a confidence map's sparsification curve (ConfidenceErrors) for one disparity map.

@param disparity, groundTruth, metric, badThreshold, minDisparity as evaluateDisparity (covered pixels and outliers
by the same rules).
@param confidence CV_32FC1 in [0, 1], the disparity's size (StereoLidarSGM::compute with a confidence output).
 */
CV_EXPORTS_W ConfidenceErrors evaluateConfidence(InputArray disparity, InputArray confidence, InputArray groundTruth,
                                                 int metric = METRIC_KITTI_D1, double badThreshold = 2.0,
                                                 int minDisparity = 0);

/** @brief The KITTI devkit's background interpolation of missing disparities.

In each row, a gap with estimates on both sides takes the smaller of the two (the background); then each row's first
and last estimates are copied out to its ends; then, column by column, the first and last estimates to the top and
bottom. A row without estimates between two filled rows stays empty (the devkit only extrapolates to the borders).
@param disparity CV_32FC1 in pixels, negative = missing.
@param filled output, CV_32FC1, missing pixels that cannot be filled stay negative.
 */
CV_EXPORTS_W void interpolateBackground(InputArray disparity, OutputArray filled);

/** @brief The KITTI devkit's disparity colour map (black, blue, magenta, red, yellow, white over [0, maxDisparity]).
@param disparity CV_32FC1 in pixels; negative or not finite = black.
@param color output, CV_8UC3 (BGR).
@param maxDisparity the disparity drawn white.
 */
CV_EXPORTS_W void colorizeDisparity(InputArray disparity, OutputArray color, double maxDisparity);

/** @brief The KITTI devkit's error colour map: the error relative to the D1 threshold, min(|d - gt| / 3,
|d - gt| / gt / 0.05), on a log scale from blue (far below 1) to red (far above); black without ground truth.
@param disparity CV_32FC1 in pixels (negative = none, scored as 0; pass interpolateBackground()'s result to show the
total error).
@param groundTruth CV_32FC1 in pixels, negative or not finite = none.
@param color output, CV_8UC3 (BGR).
 */
CV_EXPORTS_W void colorizeDisparityError(InputArray disparity, InputArray groundTruth, OutputArray color);

/** @brief Sparse disparities over an image (for example a projected LiDAR scan, to see how it lines up): the image in
grey, each sparse disparity a 3x3 dot in the colours of colorizeDisparity, the nearest points (largest disparity) on
top.
@param image grey or BGR, 8 or 16 bits.
@param sparse CV_32FC1 pixels of the image's size, > 0 = a point.
@param dst output, CV_8UC3 (BGR).
@param maxDisparity the disparity drawn white.
 */
CV_EXPORTS_W void drawSparseDisparity(InputArray image, InputArray sparse, OutputArray dst, double maxDisparity);

/** @brief The picture over a legend for people: a white band below its rows (which stay as they are) with the title, a
colour bar of colorizeDisparity from 0 to maxDisparity with ticks in pixels and, with showNone, the black of pixels
without a disparity. The tool and the Python samples put it under every disparity picture.
@param picture CV_8UC3: colorizeDisparity's or drawSparseDisparity's output.
@param withLegend output, CV_8UC3, the picture's width and more rows.
@param maxDisparity the disparity the picture draws white.
@param title what the colours show, for example "disparity (px)".
@param showNone a swatch for "no disparity" (black).
 */
CV_EXPORTS_W void addDisparityLegend(InputArray picture, OutputArray withLegend, double maxDisparity,
                                     const String& title = "disparity (px)", bool showNone = true);

/** @brief The picture over colorizeDisparityError's legend: its ten bands of the error relative to the D1 threshold,
max(3 px, 5 % of the true disparity), from below 1/16 to 16 and above (1 and above: D1 outliers), each in its colour.
@param picture CV_8UC3: colorizeDisparityError's output.
@param withLegend output, CV_8UC3, the picture's width and more rows.
 */
CV_EXPORTS_W void addErrorLegend(InputArray picture, OutputArray withLegend);

//! @}

}} // namespace cv::lidarsgm

#endif
