// This file is part of the lidarsgm module (an OpenCV extra module).
// The evaluator (opencv2/lidarsgm/evaluation.hpp), checked against small cases computed by hand: the KITTI devkit's
// background interpolation and D1 rule, Middlebury bad-N, the colour maps and the sparse overlay.
#include "test_precomp.hpp"
#include "test_common.hpp"

namespace opencv_test { namespace {

using cv::lidarsgm::DisparityErrors;
using cv::lidarsgm::evaluateDisparity;

static Mat interpolateBackground(const Mat& d)
{
    Mat out;
    cv::lidarsgm::interpolateBackground(d, out);
    return out;
}

static bool isD1Outlier(float d, float gt)
{
    return evaluateDisparity(Mat(1, 1, CV_32F, Scalar(d)), Mat(1, 1, CV_32F, Scalar(gt))).estimatedOutliers == 1;
}


TEST(Lidarsgm_Eval, background_interpolation_rows)
{
    // A gap with valid pixels on both sides takes the smaller of the two; the ends copy the nearest valid value.
    expectSameFloats(floatRow({ 5, 5, 3, 3, 3, 3 }), interpolateBackground(floatRow({ -1, 5, -1, -1, 3, -1 })));
    expectSameFloats(floatRow({ 4, 4, 4, 4 }), interpolateBackground(floatRow({ -1, -1, 4, -1 })));
    expectSameFloats(floatRow({ 2, 2, 2, 9, 9 }), interpolateBackground(floatRow({ 2, -1, -1, 9, -1 })));
    expectSameFloats(floatRow({ 7, 1, 1, 8 }), interpolateBackground(floatRow({ 7, -1, 1, 8 })));
    // Nothing valid in the whole map: stays empty.
    expectSameFloats(floatRow({ -1, -1, -1 }), interpolateBackground(floatRow({ -1, -1, -1 })));
}

TEST(Lidarsgm_Eval, background_interpolation_columns)
{
    // Rows without any valid pixel are filled column by column from the nearest valid row above or below,
    // after the rows with values were interpolated.
    Mat d = (Mat_<float>(4, 3) << -1, -1, -1,
                                   1, -1, 3,
                                  -1, -1, -1,
                                  -1, 6, -1);
    Mat e = (Mat_<float>(4, 3) << 1, 1, 3,
                                  1, 1, 3,
                                  -1, -1, -1,
                                  6, 6, 6);
    // Row 1: the gap between 1 and 3 takes min = 1; row 3 is extrapolated to 6 6 6. Columns: row 0 copies row 1.
    // The devkit only extrapolates columns to the top and bottom ends, so row 2, between two filled rows, stays empty.
    Mat got = interpolateBackground(d);
    expectSameFloats(e, got);
}

TEST(Lidarsgm_Eval, d1_rule_and_totals)
{
    // D1 outlier: |d - gt| > 3 and > 5 % of gt.
    EXPECT_FALSE(isD1Outlier(104.f, 100.f));  // 4 px, 4 %
    EXPECT_TRUE(isD1Outlier(106.f, 100.f));   // 6 px, 6 %
    EXPECT_TRUE(isD1Outlier(13.5f, 10.f));    // 3.5 px, 35 %
    EXPECT_FALSE(isD1Outlier(12.9f, 10.f));   // 2.9 px
    EXPECT_FALSE(isD1Outlier(13.f, 10.f));    // exactly 3 px is not more than 3

    // gt:  10   10   100   50   none
    // est: 13.5 none 104   50   7
    // est covers 3 of the 4 GT pixels (75 %), one of them an outlier (33.33 %). Interpolated: the gap at x = 1 takes
    // min(13.5, 104) = 13.5, an outlier against 10: total 2 of 4 (50 %).
    DisparityErrors s = evaluateDisparity(floatRow({ 13.5f, -1, 104, 50, 7 }), floatRow({ 10, 10, 100, 50, -1 }));
    EXPECT_EQ(4, s.groundTruthPixels);
    EXPECT_EQ(3, s.estimatedPixels);
    EXPECT_EQ(1, s.estimatedOutliers);
    EXPECT_EQ(2, s.totalOutliers);
    EXPECT_DOUBLE_EQ(75.0, s.coverage());
    EXPECT_NEAR(100.0 / 3, s.coveredError(), 1e-12);
    EXPECT_DOUBLE_EQ(50.0, s.totalError());

    // An empty estimate stays empty after interpolation; as in the devkit, its pixels are scored with d = -1:
    // against gt 5 and 6 that is an outlier (6 and 7 px), against gt 1.5 it is not (2.5 px).
    DisparityErrors e = evaluateDisparity(floatRow({ -1, -1, -1 }), floatRow({ 5, 6, 1.5f }));
    EXPECT_EQ(0, e.estimatedPixels);
    EXPECT_EQ(2, e.totalOutliers);
    EXPECT_DOUBLE_EQ(0.0, e.coveredError());

    // Sums over frames are sums of counts, not means of percentages.
    DisparityErrors sum;
    sum.add(s);
    sum.add(e);
    EXPECT_DOUBLE_EQ(100.0 * 3 / 7, sum.coverage());
    EXPECT_DOUBLE_EQ(100.0 * 4 / 7, sum.totalError());
}

TEST(Lidarsgm_Eval, bad_n_and_nonfinite_ground_truth)
{
    // gt: 5, inf (unknown, as in Middlebury PFM), 20, NaN; est: 7.5 (bad), 1, 21 (good), 3.
    DisparityErrors s = evaluateDisparity(floatRow({ 7.5f, 1, 21, 3 }),
                                          floatRow({ 5, std::numeric_limits<float>::infinity(), 20,
                                                std::numeric_limits<float>::quiet_NaN() }),
                                          cv::lidarsgm::METRIC_BAD, 2.0);
    EXPECT_EQ(2, s.groundTruthPixels);
    EXPECT_EQ(2, s.estimatedPixels);
    EXPECT_EQ(1, s.estimatedOutliers);
    EXPECT_DOUBLE_EQ(50.0, s.coveredError());
}

TEST(Lidarsgm_Eval, matcher_output_and_kitti_ground_truth)
{
    // The matcher's CV_16S output (x16, invalid = (minD - 1) * 16) and KITTI-encoded ground truth (x256, 0 = none)
    // score as their float forms do.
    Mat d16 = (Mat_<short>(1, 4) << -16, 160, 1600, 328);
    Mat gt16 = (Mat_<ushort>(1, 4) << 2560, 2560, 0, 5120);
    DisparityErrors a = evaluateDisparity(d16, gt16);
    DisparityErrors b = evaluateDisparity(floatRow({ -1, 10, 100, 20.5f }), floatRow({ 10, 10, -1, 20 }));
    EXPECT_EQ(3, a.groundTruthPixels);
    EXPECT_EQ(2, a.estimatedPixels);
    EXPECT_EQ(b.estimatedPixels, a.estimatedPixels);
    EXPECT_EQ(b.estimatedOutliers, a.estimatedOutliers);
    EXPECT_EQ(b.totalOutliers, a.totalOutliers);
    // With minDisparity 12 the invalid value is 11 (x16: 176): below minDisparity means no estimate.
    DisparityErrors c = evaluateDisparity(Mat((Mat_<short>(1, 2) << 176, 320)), floatRow({ 11, 20 }),
                                          cv::lidarsgm::METRIC_KITTI_D1, 0, 12);
    EXPECT_EQ(1, c.estimatedPixels);
    EXPECT_THROW(evaluateDisparity(Mat(1, 2, CV_8U), floatRow({ 1, 2 })), cv::Exception);
    EXPECT_THROW(evaluateDisparity(floatRow({ 1, 2, 3 }), floatRow({ 1, 2 })), cv::Exception);
}

TEST(Lidarsgm_Eval, colour_maps)
{
    // KITTI disparity colours: invalid black, 0 black, max white; error colours: no GT black, tiny error blue,
    // an error of 10x the D1 threshold red-ish (scale entry [8, 16)).
    Mat c, e;
    cv::lidarsgm::colorizeDisparity(floatRow({ -1, 0, 128 }), c, 128.0);
    EXPECT_EQ(Vec3b(0, 0, 0), c.at<Vec3b>(0, 0));
    EXPECT_EQ(Vec3b(0, 0, 0), c.at<Vec3b>(0, 1));
    EXPECT_EQ(Vec3b(255, 255, 255), c.at<Vec3b>(0, 2));
    cv::lidarsgm::colorizeDisparityError(floatRow({ 10, 10.1f, 40 }), floatRow({ -1, 10, 10 }), e);
    EXPECT_EQ(Vec3b(0, 0, 0), e.at<Vec3b>(0, 0));
    EXPECT_EQ(Vec3b(149, 54, 49), e.at<Vec3b>(0, 1));   // error 0.1 px: 0.033 of the threshold
    EXPECT_EQ(Vec3b(39, 48, 215), e.at<Vec3b>(0, 2));   // error 30 px: min(10, 60) = 10 of the threshold
    // LiDAR points over the image: the image in grey, each point a coloured dot.
    Mat grey(20, 30, CV_8UC1, Scalar::all(100)), sparse(20, 30, CV_32FC1, Scalar::all(0));
    sparse.at<float>(10, 15) = 128.f;
    Mat o;
    cv::lidarsgm::drawSparseDisparity(grey, sparse, o, 128.0);
    ASSERT_EQ(CV_8UC3, o.type());
    EXPECT_EQ(Vec3b(100, 100, 100), o.at<Vec3b>(0, 0));
    EXPECT_EQ(Vec3b(255, 255, 255), o.at<Vec3b>(10, 15));
}

// The confidence's sparsification counts (evaluateConfidence, ConfidenceErrors): four covered pixels, one outlier at
// the lowest confidence; a pixel without ground truth or estimate is left out; ties are removed in proportion.
TEST(Lidarsgm_Eval, confidence_sparsification)
{
    const Mat d = floatRow({ 10, 10, 10, 10, 10, 10 }), gt = floatRow({ 10, 10, 10, 20, -1, 10 });
    Mat est = d.clone();
    est.at<float>(0, 5) = -1;   // no estimate
    const Mat conf = floatRow({ 1.f, 1.f, 0.5f, 0.25f, 0.75f, 0.f });
    cv::lidarsgm::ConfidenceErrors c = cv::lidarsgm::evaluateConfidence(est, conf, gt);
    EXPECT_EQ(4.0, c.total());
    EXPECT_EQ(1.0, c.totalOutliers());
    EXPECT_EQ(1.0, c.outliers[cvRound(0.25 * 65535)]);
    EXPECT_DOUBLE_EQ(100.0, c.leastConfidentShare(0.25));   // the least confident pixel is the outlier
    EXPECT_DOUBLE_EQ(0.0, c.keptError(0.75));
    EXPECT_DOUBLE_EQ(25.0, c.keptError(1.0));
    // The oracle's area for an error rate e is e + (1 - e) ln(1 - e); this order is the oracle's.
    EXPECT_NEAR(0.25 + 0.75 * std::log(0.75), c.oracleAuc(), 1e-12);
    EXPECT_NEAR(c.oracleAuc(), c.auc(), 2e-3);
    // Ties: two pixels of one level, one an outlier: keeping one of them keeps half an outlier.
    cv::lidarsgm::ConfidenceErrors t = cv::lidarsgm::evaluateConfidence(floatRow({ 10, 10 }), floatRow({ 0.5f, 0.5f }),
                                                                        floatRow({ 10, 20 }));
    EXPECT_DOUBLE_EQ(50.0, t.keptError(0.5));
    // Counts add up over frames.
    c.add(t);
    EXPECT_EQ(6.0, c.total());
    EXPECT_EQ(2.0, c.totalOutliers());
    EXPECT_THROW(cv::lidarsgm::evaluateConfidence(est, Mat(1, 6, CV_8UC1), gt), cv::Exception);
}

}} // namespace
