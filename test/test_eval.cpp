// This file is part of the lidarsgm module (an OpenCV extra module).
// The evaluator the tool and the accuracy tests use (samples/lidarsgm_eval.hpp), checked against small cases
// computed by hand: the KITTI devkit's background interpolation and D1 rule, Middlebury bad-N, formats.
#include "test_precomp.hpp"
#include "lidarsgm_eval.hpp"

namespace opencv_test { namespace {

using namespace lidarsgm_eval;

static Mat row(std::initializer_list<float> v)
{
    return Mat(std::vector<float>(v), true).reshape(1, 1);
}

static void expectMat(const Mat& expected, const Mat& actual)
{
    ASSERT_EQ(expected.size(), actual.size());
    for (int y = 0; y < expected.rows; y++)
        for (int x = 0; x < expected.cols; x++)
            EXPECT_EQ(expected.at<float>(y, x), actual.at<float>(y, x)) << "at (" << x << ", " << y << ")";
}

TEST(Lidarsgm_Eval, background_interpolation_rows)
{
    // A gap with valid pixels on both sides takes the smaller of the two; the ends copy the nearest valid value.
    expectMat(row({ 5, 5, 3, 3, 3, 3 }), interpolateBackground(row({ -1, 5, -1, -1, 3, -1 })));
    expectMat(row({ 4, 4, 4, 4 }), interpolateBackground(row({ -1, -1, 4, -1 })));
    expectMat(row({ 2, 2, 2, 9, 9 }), interpolateBackground(row({ 2, -1, -1, 9, -1 })));
    expectMat(row({ 7, 1, 1, 8 }), interpolateBackground(row({ 7, -1, 1, 8 })));
    // Nothing valid in the whole map: stays empty.
    expectMat(row({ -1, -1, -1 }), interpolateBackground(row({ -1, -1, -1 })));
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
    expectMat(e, got);
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
    ErrorStats s = evaluate(row({ 13.5f, -1, 104, 50, 7 }), row({ 10, 10, 100, 50, -1 }), isD1Outlier);
    EXPECT_EQ(4, s.gt);
    EXPECT_EQ(3, s.est);
    EXPECT_EQ(1, s.estBad);
    EXPECT_EQ(2, s.totalBad);
    EXPECT_DOUBLE_EQ(75.0, s.coverage());
    EXPECT_NEAR(100.0 / 3, s.coveredError(), 1e-12);
    EXPECT_DOUBLE_EQ(50.0, s.totalError());

    // An empty estimate stays empty after interpolation; as in the devkit, its pixels are scored with d = -1:
    // against gt 5 and 6 that is an outlier (6 and 7 px), against gt 1.5 it is not (2.5 px).
    ErrorStats e = evaluate(row({ -1, -1, -1 }), row({ 5, 6, 1.5f }), isD1Outlier);
    EXPECT_EQ(0, e.est);
    EXPECT_EQ(2, e.totalBad);
    EXPECT_DOUBLE_EQ(0.0, e.coveredError());

    // Sums over frames are sums of counts, not means of percentages.
    ErrorStats sum;
    sum.add(s);
    sum.add(e);
    EXPECT_DOUBLE_EQ(100.0 * 3 / 7, sum.coverage());
    EXPECT_DOUBLE_EQ(100.0 * 4 / 7, sum.totalError());
}

TEST(Lidarsgm_Eval, bad_n_and_nonfinite_ground_truth)
{
    BadN bad2 = { 2.f };
    // gt: 5, inf (unknown, as in Middlebury PFM), 20, NaN; est: 7.5 (bad), 1, 21 (good), 3.
    ErrorStats s = evaluate(row({ 7.5f, 1, 21, 3 }),
                            row({ 5, std::numeric_limits<float>::infinity(), 20, std::numeric_limits<float>::quiet_NaN() }),
                            bad2);
    EXPECT_EQ(2, s.gt);
    EXPECT_EQ(2, s.est);
    EXPECT_EQ(1, s.estBad);
    EXPECT_DOUBLE_EQ(50.0, s.coveredError());
}

TEST(Lidarsgm_Eval, formats)
{
    // Matcher output (x16, invalid = (minD - 1) * 16) to float pixels with -1 = invalid.
    Mat d16 = (Mat_<short>(1, 4) << -16, 0, 37, 2040);
    expectMat(row({ -1, 0, 37 / 16.f, 127.5f }), disparityToFloat(d16, 0));
    // KITTI PNG: round(d * 256), 0 = invalid (so d = 0 cannot be stored and becomes invalid).
    Mat png = toKittiPng(row({ -1, 0, 2.3125f, 127.5f, 0.001f }));
    EXPECT_EQ(0, png.at<ushort>(0, 0));
    EXPECT_EQ(0, png.at<ushort>(0, 1));
    EXPECT_EQ(592, png.at<ushort>(0, 2));
    EXPECT_EQ(32640, png.at<ushort>(0, 3));
    EXPECT_EQ(1, png.at<ushort>(0, 4));  // a positive disparity stays valid

    // PFM (invalid written as +inf, Middlebury's "unknown") and raw CV_16S round trips.
    const std::string pfm = cv::tempfile(".pfm"), raw = cv::tempfile(".s16");
    ASSERT_TRUE(writePfm(pfm, Mat((Mat_<float>(2, 3) << -1, 0.5f, 37.0625f, 4, 5, 6))));
    Mat back = imread(pfm, IMREAD_UNCHANGED);
    ASSERT_EQ(CV_32FC1, back.type());
    expectMat((Mat_<float>(2, 3) << std::numeric_limits<float>::infinity(), 0.5f, 37.0625f, 4, 5, 6), back);
    ASSERT_TRUE(writeRawS16(raw, d16));
    std::ifstream in(raw.c_str(), std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(8u, bytes.size());
    short v[4];
    memcpy(v, bytes.data(), 8);
    EXPECT_EQ(-16, v[0]);
    EXPECT_EQ(2040, v[3]);
    remove(pfm.c_str());
    remove(raw.c_str());
}

TEST(Lidarsgm_Eval, colour_maps)
{
    // KITTI disparity colours: invalid black, 0 black, max white; error colours: no GT black, tiny error blue,
    // an error of 10x the D1 threshold red-ish (scale entry [8, 16)).
    Mat c = colorizeDisparity(row({ -1, 0, 128 }), 128.f);
    EXPECT_EQ(Vec3b(0, 0, 0), c.at<Vec3b>(0, 0));
    EXPECT_EQ(Vec3b(0, 0, 0), c.at<Vec3b>(0, 1));
    EXPECT_EQ(Vec3b(255, 255, 255), c.at<Vec3b>(0, 2));
    Mat e = colorizeError(row({ 10, 10.1f, 40 }), row({ -1, 10, 10 }));
    EXPECT_EQ(Vec3b(0, 0, 0), e.at<Vec3b>(0, 0));
    EXPECT_EQ(Vec3b(149, 54, 49), e.at<Vec3b>(0, 1));   // error 0.1 px: 0.033 of the threshold
    EXPECT_EQ(Vec3b(39, 48, 215), e.at<Vec3b>(0, 2));   // error 30 px: min(10, 60) = 10 of the threshold
    // LiDAR points over the image: the image in grey, each point a coloured dot.
    Mat grey(20, 30, CV_8UC1, Scalar::all(100)), sparse(20, 30, CV_32FC1, Scalar::all(0));
    sparse.at<float>(10, 15) = 128.f;
    Mat o = overlayPoints(grey, sparse, 128.f);
    ASSERT_EQ(CV_8UC3, o.type());
    EXPECT_EQ(Vec3b(100, 100, 100), o.at<Vec3b>(0, 0));
    EXPECT_EQ(Vec3b(255, 255, 255), o.at<Vec3b>(10, 15));
}

}} // namespace
