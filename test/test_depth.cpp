// This file is part of the lidarsgm module (an OpenCV extra module).
// Disparity to metric depth and 3D points (opencv2/lidarsgm/depth.hpp): the x16 scale of the CV_16S output, the
// invalid value, minDisparity, the reprojection formula (the Python test compares with cv2.reprojectImageTo3D), and
// the refusals of bad input.
#include "test_precomp.hpp"
#include <cstring>
#include <fstream>

namespace opencv_test { namespace {

using namespace cv::lidarsgm;

TEST(Lidarsgm_Depth, x16_output_and_invalid_pixels)
{
    const double fb = 389.0;
    // The matcher's CV_16S output: -16 is "invalid" (minDisparity 0), 0 a valid disparity of 0 px (no depth).
    const Mat_<short> disp16 = (Mat_<short>(2, 3) << -16, 0, 16, 32 * 16, 1, 100 * 16 + 8);
    Mat depth;
    disparityToDepth(disp16, fb, depth);
    ASSERT_EQ(CV_32FC1, depth.type());
    const float expected[6] = { 0.f, 0.f, (float)fb, (float)(fb / 32), (float)(fb * 16), (float)(fb / 100.5) };
    for (int i = 0; i < 6; i++)
        EXPECT_FLOAT_EQ(expected[i], depth.at<float>(i / 3, i % 3)) << i;
    // The same in pixels (CV_32F), with NaN and infinity as "invalid".
    const Mat_<float> dispF = (Mat_<float>(1, 4) << 2.f, -1.f, std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity());
    disparityToDepth(dispF, fb, depth);
    EXPECT_FLOAT_EQ((float)(fb / 2), depth.at<float>(0, 0));
    EXPECT_EQ(0.f, depth.at<float>(0, 1));
    EXPECT_EQ(0.f, depth.at<float>(0, 2));
    EXPECT_EQ(0.f, depth.at<float>(0, 3));
    // minDisparity 2: its invalid code (2 - 1) * 16 and everything below 2 px give no depth.
    disparityToDepth(disp16, fb, depth, 2);
    EXPECT_EQ(0.f, depth.at<float>(0, 2));
    EXPECT_EQ(0.f, depth.at<float>(1, 1));
    EXPECT_FLOAT_EQ((float)(fb / 32), depth.at<float>(1, 0));
    // REP 118's NaN for the invalid pixels: the same depths elsewhere.
    Mat zero, nan;
    disparityToDepth(disp16, fb, zero);
    disparityToDepth(disp16, fb, nan, 0, std::numeric_limits<float>::quiet_NaN());
    for (int i = 0; i < 6; i++)
        if (i < 2)
            EXPECT_TRUE(cvIsNaN(nan.at<float>(0, i))) << i;
        else
            EXPECT_EQ(zero.at<float>(i / 3, i % 3), nan.at<float>(i / 3, i % 3)) << i;
}

TEST(Lidarsgm_Depth, points_match_the_reprojection_formula)
{
    const double fb = 384.3815, f = 721.5377, cx = 609.5593, cy = 172.854;
    const Matx34d P2(f, 0, cx, 44.85728, 0, f, cy, 0.2163791, 0, 0, 1, 0.002745884);
    const Mat Q = reprojectionMatrix(P2, fb);
    ASSERT_EQ(CV_64FC1, Q.type());
    RNG rng(7);
    Mat_<short> disp16(37, 53);
    for (int y = 0; y < disp16.rows; y++)
        for (int x = 0; x < disp16.cols; x++)
            disp16(y, x) = rng.uniform(0, 5) == 0 ? (short)-16 : (short)rng.uniform(1, 128 * 16);
    Mat points;
    disparityToPoints(disp16, Q, points);
    ASSERT_EQ(CV_32FC3, points.type());
    for (int y = 0; y < disp16.rows; y++)
        for (int x = 0; x < disp16.cols; x++)
        {
            const Vec3f p = points.at<Vec3f>(y, x);
            if (disp16(y, x) < 0)
            {
                EXPECT_TRUE(cvIsNaN(p[0]) && cvIsNaN(p[1]) && cvIsNaN(p[2])) << x << ", " << y;
                continue;
            }
            const double z = fb / (disp16(y, x) / 16.0);
            EXPECT_NEAR(z, p[2], 1e-5 * z);
            EXPECT_NEAR((x - cx) * z / f, p[0], 1e-5 * z);
            EXPECT_NEAR((y - cy) * z / f, p[1], 1e-5 * z);
        }
}

TEST(Lidarsgm_Depth, coloured_points_are_the_points_and_packed_rgb)
{
    const Matx34d P2(721.5377, 0, 609.5593, 44.85728, 0, 721.5377, 172.854, 0.2163791, 0, 0, 1, 0.002745884);
    const Mat Q = reprojectionMatrix(P2, 384.3815);
    RNG rng(11);
    Mat_<short> disp16(29, 41);
    Mat bgr(disp16.size(), CV_8UC3), grey(disp16.size(), CV_8UC1);
    rng.fill(bgr, RNG::UNIFORM, 0, 256);
    rng.fill(grey, RNG::UNIFORM, 0, 256);
    for (int y = 0; y < disp16.rows; y++)
        for (int x = 0; x < disp16.cols; x++)
            disp16(y, x) = rng.uniform(0, 4) == 0 ? (short)-16 : (short)rng.uniform(1, 128 * 16);
    for (int minD : { 0, 20 })
    {
        Mat points, cloud, cloudGrey;
        disparityToPoints(disp16, Q, points, minD);
        disparityToColoredPoints(disp16, Q, bgr, cloud, minD);
        disparityToColoredPoints(disp16, Q, grey, cloudGrey, minD);
        ASSERT_EQ(CV_32FC4, cloud.type());
        for (int y = 0; y < disp16.rows; y++)
            for (int x = 0; x < disp16.cols; x++)
            {
                const Vec3f p = points.at<Vec3f>(y, x);
                const Vec4f c = cloud.at<Vec4f>(y, x), g = cloudGrey.at<Vec4f>(y, x);
                for (int k = 0; k < 3; k++)  // bit for bit, NaN included
                {
                    EXPECT_EQ(0, memcmp(&p[k], &c[k], 4)) << x << ", " << y;
                    EXPECT_EQ(0, memcmp(&p[k], &g[k], 4)) << x << ", " << y;
                }
                const Vec3b b = bgr.at<Vec3b>(y, x);
                const unsigned v = grey.at<uchar>(y, x);
                unsigned rgb = 0, rgbGrey = 0;
                memcpy(&rgb, &c[3], 4);
                memcpy(&rgbGrey, &g[3], 4);
                EXPECT_EQ(((unsigned)b[2] << 16) | ((unsigned)b[1] << 8) | b[0], rgb) << x << ", " << y;
                EXPECT_EQ((v << 16) | (v << 8) | v, rgbGrey) << x << ", " << y;
            }
    }
    Mat out;
    EXPECT_THROW(disparityToColoredPoints(disp16, Q, bgr(Rect(0, 0, 40, 29)), out), cv::Exception);
    EXPECT_THROW(disparityToColoredPoints(disp16, Q, Mat(disp16.size(), CV_8UC4, Scalar(0)), out), cv::Exception);
    EXPECT_THROW(disparityToColoredPoints(disp16, Q, Mat(), out), cv::Exception);
    EXPECT_THROW(disparityToColoredPoints(disp16, Mat::eye(3, 3, CV_64F), bgr, out), cv::Exception);
}

TEST(Lidarsgm_Depth, bad_input_is_refused)
{
    const Mat disp(4, 4, CV_16SC1, Scalar(160));
    Mat out;
    EXPECT_THROW(disparityToDepth(Mat(), 389.0, out), cv::Exception);
    EXPECT_THROW(disparityToDepth(Mat(4, 4, CV_32SC1, Scalar(1)), 389.0, out), cv::Exception);
    EXPECT_THROW(disparityToDepth(Mat(4, 4, CV_16SC2, Scalar(1)), 389.0, out), cv::Exception);
    EXPECT_THROW(disparityToDepth(disp, 0.0, out), cv::Exception);
    EXPECT_THROW(disparityToDepth(disp, std::numeric_limits<double>::quiet_NaN(), out), cv::Exception);
    EXPECT_THROW(disparityToPoints(disp, Mat::eye(3, 3, CV_64F), out), cv::Exception);
    Mat Qnan = Mat::eye(4, 4, CV_64F);
    Qnan.at<double>(0, 3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(disparityToPoints(disp, Qnan, out), cv::Exception);
    EXPECT_THROW(reprojectionMatrix(Mat::eye(2, 3, CV_64F), 389.0), cv::Exception);
    EXPECT_THROW(reprojectionMatrix(Mat::zeros(3, 4, CV_64F), 389.0), cv::Exception);
    EXPECT_THROW(reprojectionMatrix(Mat::eye(3, 4, CV_64F), -1.0), cv::Exception);
    try
    {
        disparityToDepth(Mat(4, 4, CV_8UC1, Scalar(1)), 389.0, out);
        ADD_FAILURE() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("CV_16SC1 (x16) or CV_32FC1")) << e.err;
    }
}

}} // namespace
