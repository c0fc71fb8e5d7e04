// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"

namespace opencv_test { namespace {

using cv::lidarsgm::projectPointsToDisparity;

static Matx34d simpleP() { return Matx34d(500, 0, 50, 0, 0, 500, 40, 0, 0, 0, 1, 0); }

TEST(Lidarsgm_Projection, hand_case)
{
    // Camera frame = LiDAR frame. A point 10 m ahead on the optical axis lands on the principal point.
    Mat pts = (Mat_<float>(5, 3) << 0, 0, 10,       // (50, 40), d = 250 / 10 = 25
                                    0, 0, 20,       // same pixel, farther: hidden
                                    0, 0, -5,       // behind the camera: dropped
                                    100, 0, 10,     // u = 50 + 5000: outside: dropped
                                    0.02f, 0, 10);  // u = 51: next pixel, d = 25
    Mat disp;
    projectPointsToDisparity(pts, simpleP(), Matx34d::eye(), 250.0, Size(100, 80), disp);
    ASSERT_EQ(CV_32FC1, disp.type());
    EXPECT_FLOAT_EQ(25.f, disp.at<float>(40, 50));
    EXPECT_FLOAT_EQ(25.f, disp.at<float>(40, 51));
    EXPECT_EQ(2, countNonZero(disp));

    // Nearest wins regardless of order; KITTI 16-bit encoding.
    Mat rev;
    flip(pts, rev, 0);
    Mat d16;
    projectPointsToDisparity(rev, simpleP(), Mat::eye(4, 4, CV_64F), 250.0, Size(100, 80), d16, CV_16U);
    ASSERT_EQ(CV_16UC1, d16.type());
    EXPECT_EQ(25 * 256, d16.at<ushort>(40, 50));

    // N x 1 with 4 channels (x, y, z, reflectance) works the same.
    Mat pts4(5, 1, CV_32FC4);
    for (int i = 0; i < 5; i++)
        pts4.at<Vec4f>(i) = Vec4f(pts.at<float>(i, 0), pts.at<float>(i, 1), pts.at<float>(i, 2), 0.5f);
    Mat disp4;
    projectPointsToDisparity(pts4, simpleP(), Matx34d::eye(), 250.0, Size(100, 80), disp4);
    EXPECT_EQ(0, cvtest::norm(disp, disp4, NORM_INF));
}

// Points in pitched rows (the x y z of wider records, as a view of a PointCloud2's data) and outputs that already
// hold values, or are part of a larger matrix, give the map of the plain call.
TEST(Lidarsgm_Projection, pitched_points_and_used_outputs)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    cv::lidarsgm::KittiCalibration c = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    Mat pts = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/000002.bin");
    ASSERT_GT(pts.rows, 100000);   // many chunks of the parallel pass
    const Size size(1242, 375);
    Mat ref;
    projectPointsToDisparity(pts, c.projection, c.lidarToCamera, c.focalBaseline, size, ref);

    Mat records(pts.rows, 8, CV_32F, Scalar::all(-7));
    pts.copyTo(records.colRange(0, 4));
    Mat pitched = records.colRange(0, 3), out;
    ASSERT_FALSE(pitched.isContinuous());
    projectPointsToDisparity(pitched, c.projection, c.lidarToCamera, c.focalBaseline, size, out);
    EXPECT_EQ(0, cvtest::norm(ref, out, NORM_INF));

    Mat used(size, CV_32F, Scalar::all(3));   // the right size and type: written over, its old values gone
    projectPointsToDisparity(pts, c.projection, c.lidarToCamera, c.focalBaseline, size, used);
    EXPECT_EQ(0, cvtest::norm(ref, used, NORM_INF));

    Mat big(size.height + 2, size.width + 2, CV_32F, Scalar::all(5));
    Mat roi = big(Rect(1, 1, size.width, size.height));
    projectPointsToDisparity(pts, c.projection, c.lidarToCamera, c.focalBaseline, size, roi);
    EXPECT_EQ(0, cvtest::norm(ref, roi, NORM_INF));
    EXPECT_EQ(5.f, big.at<float>(0, 0));
    EXPECT_EQ(5.f, big.at<float>(size.height + 1, size.width + 1));
}

TEST(Lidarsgm_Projection, non_finite_points_are_dropped)
{
    Mat pts = (Mat_<float>(2, 3) << std::numeric_limits<float>::quiet_NaN(), 0, 10, 0, 0, 10);
    Mat disp;
    projectPointsToDisparity(pts, simpleP(), Matx34d::eye(), 250.0, Size(100, 80), disp);
    EXPECT_EQ(1, countNonZero(disp));
}

TEST(Lidarsgm_Projection, bad_input)
{
    Mat pts = (Mat_<float>(1, 3) << 0, 0, 10), disp;
    EXPECT_THROW(projectPointsToDisparity(Mat(2, 5, CV_32F, Scalar::all(1)), simpleP(), Matx34d::eye(), 250.0, Size(100, 80), disp), cv::Exception);
    EXPECT_THROW(projectPointsToDisparity(Mat(2, 3, CV_64F, Scalar::all(1)), simpleP(), Matx34d::eye(), 250.0, Size(100, 80), disp), cv::Exception);
    EXPECT_THROW(projectPointsToDisparity(pts, Mat::eye(3, 3, CV_64F), Matx34d::eye(), 250.0, Size(100, 80), disp), cv::Exception);
    EXPECT_THROW(projectPointsToDisparity(pts, Matx34d::zeros(), Matx34d::eye(), 250.0, Size(100, 80), disp), cv::Exception);
    Matx34d notRigid = Matx34d::eye();
    notRigid(0, 0) = 2;
    EXPECT_THROW(projectPointsToDisparity(pts, simpleP(), notRigid, 250.0, Size(100, 80), disp), cv::Exception);
    Matx34d nanP = simpleP();
    nanP(1, 3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(projectPointsToDisparity(pts, nanP, Matx34d::eye(), 250.0, Size(100, 80), disp), cv::Exception);
    EXPECT_THROW(projectPointsToDisparity(pts, simpleP(), Matx34d::eye(), 0.0, Size(100, 80), disp), cv::Exception);
    EXPECT_THROW(projectPointsToDisparity(pts, simpleP(), Matx34d::eye(), 250.0, Size(0, 80), disp), cv::Exception);
    EXPECT_THROW(projectPointsToDisparity(pts, simpleP(), Matx34d::eye(), 250.0, Size(100, 80), disp, CV_8U), cv::Exception);
}

// The projected raw scans of the shipped KITTI frames agree with the ground truth (disp_occ_0).
TEST(Lidarsgm_Projection, kitti_against_ground_truth)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    cv::lidarsgm::KittiCalibration calib = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    const char* ids[] = { "000002", "000046" };
    for (int i = 0; i < 2; i++)
    {
        Mat gt = cv::lidarsgm::readKittiDisparity(dir + "/disp_occ_0/" + ids[i] + "_10.png");
        Mat pts = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/" + ids[i] + ".bin");
        Mat disp;
        projectPointsToDisparity(pts, calib.projection, calib.lidarToCamera, calib.focalBaseline, gt.size(), disp);
        std::vector<float> err;
        for (int y = 0; y < gt.rows; y++)
            for (int x = 0; x < gt.cols; x++)
                if (disp.at<float>(y, x) > 0 && gt.at<float>(y, x) > 0)
                    err.push_back(std::abs(disp.at<float>(y, x) - gt.at<float>(y, x)));
        ASSERT_GT(err.size(), 10000u) << ids[i];
        std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
        const float median = err[err.size() / 2];
        EXPECT_LT(median, 0.1f) << ids[i];
        std::cout << "frame " << ids[i] << ": " << err.size() << " LiDAR pixels with ground truth, median |d - gt| = "
                  << median << " px" << std::endl;
    }
}

}} // namespace
