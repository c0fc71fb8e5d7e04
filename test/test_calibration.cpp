// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"

namespace opencv_test { namespace {

using cv::lidarsgm::CalibrationCorrection;
using cv::lidarsgm::LidarCalibration;

//! Rx(pitch) Ry(yaw) Rz(roll) in degrees, as tools/perturb_calibration.py applies it, as a 4x4 motion with t.
Matx44d cameraMotion(double pitch, double yaw, double roll, Vec3d t = Vec3d())
{
    const double a = pitch * CV_PI / 180, b = yaw * CV_PI / 180, c = roll * CV_PI / 180;
    const Matx33d rx(1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a));
    const Matx33d ry(std::cos(b), 0, std::sin(b), 0, 1, 0, -std::sin(b), 0, std::cos(b));
    const Matx33d rz(std::cos(c), -std::sin(c), 0, std::sin(c), std::cos(c), 0, 0, 0, 1);
    const Matx33d R = rx * ry * rz;
    return Matx44d(R(0, 0), R(0, 1), R(0, 2), t[0], R(1, 0), R(1, 1), R(1, 2), t[1], R(2, 0), R(2, 1), R(2, 2), t[2],
                   0, 0, 0, 1);
}

//! The angles (degrees, rotation vector) of the rotation that takes transform a to transform b.
Vec3d rotationBetween(const Mat& a, const Mat& b)
{
    Matx44d A(a), B(b);
    const Matx33d R = B.get_minor<3, 3>(0, 0) * A.get_minor<3, 3>(0, 0).t();
    const double angle = std::acos(std::min(1.0, std::max(-1.0, (R(0, 0) + R(1, 1) + R(2, 2) - 1) / 2)));
    if (angle < 1e-12)
        return Vec3d();
    const double k = angle / (2 * std::sin(angle)) * 180 / CV_PI;
    return Vec3d(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)) * k;
}

/** The shipped KITTI frames (testdata/kitti) added to one refiner; the calibration of calib.txt. scanRate: 10 (the
HDL-64E's sweep, each frame's speed estimated) or 0 (the scans taken as compensated). */
Ptr<LidarCalibration> shippedFrames(cv::lidarsgm::KittiCalibration& calib, double scanRate = 10)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    calib = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    Ptr<LidarCalibration> cal = LidarCalibration::create(calib.projection, calib.focalBaseline, 128, scanRate);
    for (const std::string& id : cv::lidarsgm::readKittiFrameIds(dir))
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(dir, id);
        cal->addFrame(f.left, f.right, cv::lidarsgm::readVelodyneScan(dir + "/velodyne/" + id + ".bin"));
    }
    return cal;
}

class Lidarsgm_Calibration_Sweep : public ::testing::TestWithParam<double> {};

TEST_P(Lidarsgm_Calibration_Sweep, rotation_errors_are_undone)
{
    cv::lidarsgm::KittiCalibration calib;
    Ptr<LidarCalibration> cal = shippedFrames(calib, GetParam());
    ASSERT_EQ(2, cal->getNumFrames());
    const Matx44d T(calib.lidarToCamera);
    const CalibrationCorrection exact = cal->refine(calib.lidarToCamera);
    // The pooled estimate stays near calib.txt: the 20 shared frames put it 0.1 degree away (doc/design.md).
    for (int k = 0; k < 3; k++)
    {
        EXPECT_LE(std::abs(exact.rotation[k]) * 180 / CV_PI, 0.2) << "axis " << k;
        EXPECT_GT(exact.rotationStd[k], 0.0);
        EXPECT_LE(exact.rotationStd[k] * 180 / CV_PI, 0.1);
    }
    EXPECT_EQ(2, exact.frames);
    EXPECT_GT(exact.points, 10000);
    // A speed per frame where the scans sweep, each a car's (the shipped frames were taken driving), none otherwise.
    ASSERT_EQ(GetParam() != 0 ? 2u : 0u, exact.speeds.size());
    for (double v : exact.speeds)
        EXPECT_LE(std::abs(v), 40.0);
    const Vec3d errors[] = { Vec3d(0, 0.5, 0), Vec3d(0.5, 0, 0), Vec3d(0, 0, 0.5), Vec3d(-0.6, 1.0, 0.4) };
    for (const Vec3d& e : errors)
    {
        SCOPED_TRACE(cv::format("pitch %g yaw %g roll %g", e[0], e[1], e[2]));
        const Mat wrong(cameraMotion(e[0], e[1], e[2]) * T);
        const CalibrationCorrection c = cal->refine(wrong);
        // Every start reaches the same transform: the error applied is undone.
        const Vec3d left = rotationBetween(exact.lidarToCamera, c.lidarToCamera);
        for (int k = 0; k < 3; k++)
            EXPECT_LE(std::abs(left[k]), 0.01) << "axis " << k;
        EXPECT_NEAR(c.residualAfter, exact.residualAfter, 0.005);
        EXPECT_GT(c.residualBefore, c.residualAfter);
        EXPECT_NEAR(c.residualBefore, cal->residual(wrong), 1e-9);
    }
    // A pitch error shows in the residual: ground points land on other rows.
    EXPECT_GT(cal->residual(Mat(cameraMotion(0.5, 0, 0) * T)), 2 * cal->residual(calib.lidarToCamera));
}

INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_Calibration_Sweep, testing::Values(0.0, 10.0));

TEST(Lidarsgm_Calibration, translation_along_the_baseline)
{
    cv::lidarsgm::KittiCalibration calib;
    Ptr<LidarCalibration> cal = shippedFrames(calib);
    const Matx44d T(calib.lidarToCamera);
    const CalibrationCorrection exact = cal->refine(calib.lidarToCamera, true);
    const CalibrationCorrection c = cal->refine(Mat(cameraMotion(0, 0, 0, Vec3d(0.05, 0, 0)) * T), true);
    // The 5 cm applied comes back as a correction of -5 cm beside the estimate from calib.txt.
    EXPECT_NEAR(c.translation[0] - exact.translation[0], -0.05, 0.01);
    EXPECT_EQ(0, c.translation[1]);
    EXPECT_EQ(0, c.translation[2]);
    EXPECT_GT(c.translationStd[0], 0.0);
    const Vec3d left = rotationBetween(exact.lidarToCamera, c.lidarToCamera);
    for (int k = 0; k < 3; k++)
        EXPECT_LE(std::abs(left[k]), 0.02) << "axis " << k;
}

TEST(Lidarsgm_Calibration, refuses_what_the_data_cannot_tell)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    const cv::lidarsgm::KittiCalibration calib = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    const cv::lidarsgm::StereoLidarFrame frame = cv::lidarsgm::loadKittiFrame(dir, "000002");
    const Mat left = frame.left, right = frame.right;
    const Mat scan = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/000002.bin");

    // A textureless pair (a flat grey wall): no stereo disparity, so nothing to compare the LiDAR with.
    Ptr<LidarCalibration> flat = LidarCalibration::create(calib.projection, calib.focalBaseline);
    const Mat grey(left.size(), CV_8UC1, Scalar(128));
    flat->addFrame(grey, grey, scan);
    EXPECT_THROW(flat->refine(calib.lidarToCamera), cv::Exception);
    EXPECT_THROW(flat->residual(calib.lidarToCamera), cv::Exception);

    // A scan aimed away from the camera (every point behind it).
    Ptr<LidarCalibration> away = LidarCalibration::create(calib.projection, calib.focalBaseline);
    Mat behind = scan.clone();
    behind.col(0) = -abs(scan.col(0)) - 1;   // the Velodyne's x points forward
    away->addFrame(left, right, behind);
    EXPECT_THROW(away->refine(calib.lidarToCamera), cv::Exception);

    // No frames, an empty scan, images of different sizes.
    Ptr<LidarCalibration> cal = LidarCalibration::create(calib.projection, calib.focalBaseline);
    EXPECT_THROW(cal->refine(calib.lidarToCamera), cv::Exception);
    EXPECT_THROW(cal->addFrame(left, right, Mat()), cv::Exception);
    EXPECT_THROW(cal->addFrame(left, right, Mat(10, 3, CV_32F, Scalar(std::numeric_limits<float>::quiet_NaN()))),
                 cv::Exception);
    EXPECT_THROW(cal->addFrame(left, right, Mat(10, 2, CV_32F, Scalar(1))), cv::Exception);
    EXPECT_THROW(cal->addFrame(left, right.colRange(0, 100), scan), cv::Exception);
    EXPECT_EQ(0, cal->getNumFrames());
    cal->addFrame(left, right, scan);
    EXPECT_EQ(1, cal->getNumFrames());
    // Not a rigid transform.
    EXPECT_THROW(cal->residual(Mat(2 * Matx44d(calib.lidarToCamera))), cv::Exception);
    cal->clear();
    EXPECT_EQ(0, cal->getNumFrames());
}

TEST(Lidarsgm_Calibration, bad_arguments)
{
    const Matx34d P(700, 0, 600, 0, 0, 700, 180, 0, 0, 0, 1, 0);
    EXPECT_THROW(LidarCalibration::create(P, 0), cv::Exception);
    EXPECT_THROW(LidarCalibration::create(P, 380, 100), cv::Exception);
    EXPECT_THROW(LidarCalibration::create(Matx33d::eye(), 380), cv::Exception);
    EXPECT_NO_THROW(LidarCalibration::create(P, 380, 64));
}

}} // namespace
