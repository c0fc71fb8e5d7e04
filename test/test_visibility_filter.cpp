// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

static PipelineParams visibilityParams(int rx, int ry, int tc16)
{
    PipelineParams p = PipelineParams();
    p.visibilityRadiusX = rx;
    p.visibilityRadiusY = ry;
    p.checkThreshold16 = tc16;
    return p;
}

TEST(Lidarsgm_Visibility, nearer_points_hide_farther_ones_in_the_window)
{
    // A near object (disparity 40 px) whose points surround a background point (10 px) seen past its edge, and a
    // background point outside the window.
    Mat s(20, 20, CV_16SC1, Scalar::all(NO_DISP)), out;
    s.at<short>(10, 10) = 10 * 16;                  // background, among the object's points
    s.at<short>(10, 12) = 40 * 16;                  // 2 px right: inside rx = 2
    s.at<short>(6, 10) = 40 * 16;                   // 4 px up: inside ry = 4
    s.at<short>(10, 16) = 10 * 16;                  // background, 4 px right of the nearest object point: visible
    s.at<short>(3, 3) = 11 * 16;                    // a neighbour nearer by only 1 px (Tc = 2): both stay
    s.at<short>(4, 4) = 12 * 16;
    filterHiddenPoints(s, visibilityParams(2, 4, 32), out);
    EXPECT_EQ(NO_DISP, out.at<short>(10, 10));
    EXPECT_EQ(40 * 16, out.at<short>(10, 12));
    EXPECT_EQ(40 * 16, out.at<short>(6, 10));
    EXPECT_EQ(10 * 16, out.at<short>(10, 16));
    EXPECT_EQ(11 * 16, out.at<short>(3, 3));
    EXPECT_EQ(12 * 16, out.at<short>(4, 4));
    EXPECT_EQ(5, countNonZero(out != NO_DISP));
    // Exactly Tc nearer does not hide; 1/16 px more does.
    s.at<short>(4, 4) = 11 * 16 + 32;
    filterHiddenPoints(s, visibilityParams(2, 4, 32), out);
    EXPECT_EQ(11 * 16, out.at<short>(3, 3));
    s.at<short>(4, 4) = 11 * 16 + 33;
    filterHiddenPoints(s, visibilityParams(2, 4, 32), out);
    EXPECT_EQ(NO_DISP, out.at<short>(3, 3));
    // A smaller window no longer reaches the object's points.
    filterHiddenPoints(s, visibilityParams(1, 3, 32), out);
    EXPECT_EQ(10 * 16, out.at<short>(10, 10));
}

TEST(Lidarsgm_Visibility, window_grows_with_the_disparity_step)
{
    // Parallax 0.25: the window grows by 1 px per 4 px of disparity step, at most VISIBILITY_MAX_GROWTH.
    PipelineParams p = visibilityParams(2, 4, 32);
    p.numDisparities = 256;
    p.visibilityParallax256 = 64;
    Mat s(80, 90, CV_16SC1, Scalar::all(NO_DISP)), out;
    s.at<short>(10, 10) = 10 * 16;   // 3 px right of a point nearer by 4 px (growth 1): hidden
    s.at<short>(10, 13) = 14 * 16;
    s.at<short>(10, 60) = 10 * 16;   // 3 px right of a point nearer by 3.9375 px (growth 0.98): stays
    s.at<short>(10, 63) = 14 * 16 - 1;
    s.at<short>(50, 10) = 10 * 16;   // 12 px below a point nearer by 32 px (growth 8 reaches ry + 8): hidden
    s.at<short>(38, 10) = 42 * 16;
    s.at<short>(50, 40) = 10 * 16;   // 13 px below the same step: stays
    s.at<short>(37, 40) = 42 * 16;
    filterHiddenPoints(s, p, out);
    EXPECT_EQ(NO_DISP, out.at<short>(10, 10));
    EXPECT_EQ(10 * 16, out.at<short>(10, 60));
    EXPECT_EQ(NO_DISP, out.at<short>(50, 10));
    EXPECT_EQ(10 * 16, out.at<short>(50, 40));
    EXPECT_EQ(6, countNonZero(out != NO_DISP));
    // Without the parallax growth only the base window counts.
    p.visibilityParallax256 = 0;
    filterHiddenPoints(s, p, out);
    EXPECT_EQ(8, countNonZero(out != NO_DISP));
    // The growth stops at VISIBILITY_MAX_GROWTH: a step of 200 px would grow the window by 50 px at parallax 0.25.
    p.visibilityParallax256 = 64;
    s.setTo(NO_DISP);
    s.at<short>(0, 60) = 5 * 16;
    s.at<short>(0, 60 - 2 - VISIBILITY_MAX_GROWTH) = 205 * 16;       // at the largest growth: hidden
    s.at<short>(79, 60) = 5 * 16;
    s.at<short>(79, 60 - 2 - VISIBILITY_MAX_GROWTH - 1) = 205 * 16;   // one further: stays
    filterHiddenPoints(s, p, out);
    EXPECT_EQ(NO_DISP, out.at<short>(0, 60));
    EXPECT_EQ(5 * 16, out.at<short>(79, 60));
}

TEST(Lidarsgm_Visibility, matcher_drops_hidden_points_before_every_stage)
{
    // With the filter on, the matcher behaves as if the hidden points were not in the input.
    RNG rng(3);
    Mat l(60, 90, CV_8UC1), r, s(60, 90, CV_32FC1, Scalar::all(0));
    rng.fill(l, RNG::UNIFORM, 0, 256);
    GaussianBlur(l, l, Size(3, 3), 0);
    r = Mat(l.size(), CV_8UC1, Scalar::all(0));
    l(Rect(8, 0, 82, 60)).copyTo(r(Rect(0, 0, 82, 60)));
    for (int k = 0; k < 200; k++)
        s.at<float>(rng.uniform(0, 60), rng.uniform(0, 90)) = (float)rng.uniform(2.0, 30.0);
    Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(0, 32);
    m->setVisibilityRadiusX(2);
    m->setVisibilityRadiusY(4);
    m->setVisibilityParallax(0.25);
    EXPECT_THROW(m->setVisibilityParallax(1.5), cv::Exception);
    EXPECT_THROW(m->setVisibilityParallax(std::numeric_limits<double>::quiet_NaN()), cv::Exception);
    EXPECT_DOUBLE_EQ(0.25, m->getVisibilityParallax());
    Mat s16, visible16, withFilter, byHand;
    convertSparse(s, 0, 32, s16);
    PipelineParams p = visibilityParams(2, 4, 32);
    p.numDisparities = 32;
    p.visibilityParallax256 = 64;
    filterHiddenPoints(s16, p, visible16);
    ASSERT_LT(countNonZero(visible16 != NO_DISP), countNonZero(s16 != NO_DISP));
    Mat visible(s.size(), CV_32FC1, Scalar::all(0));
    s.copyTo(visible, visible16 != NO_DISP);
    m->compute(l, r, s, withFilter);
    m->setVisibilityRadiusX(0);
    m->setVisibilityRadiusY(0);
    m->setVisibilityParallax(0);
    m->compute(l, r, visible, byHand);
    EXPECT_EQ(0, cvtest::norm(withFilter, byHand, NORM_INF));
}

}} // namespace
