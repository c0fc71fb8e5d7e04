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

//! A textured pair whose right image is the left shifted by `shift` pixels (left x matches right x - shift).
void shiftedPair(int shift, Mat& left, Mat& right)
{
    RNG rng(7);
    Mat noise(120, 200, CV_8UC1);
    rng.fill(noise, RNG::UNIFORM, 0, 256);
    GaussianBlur(noise, left, Size(3, 3), 0.8);
    right = Mat(left.size(), CV_8UC1, Scalar(0));
    left.colRange(shift, left.cols).copyTo(right.colRange(0, left.cols - shift));
}

TEST(Lidarsgm_MatchingResidual, measures_the_offset_from_the_images)
{
    Mat left, right;
    shiftedPair(20, left, right);
    // Sparse values on every third pixel of every third row, away from the right image's blank border.
    Mat sparse(left.size(), CV_32FC1, Scalar(0));
    for (int y = 2; y < sparse.rows - 2; y += 3)
        for (int x = 40; x < sparse.cols - 2; x += 3)
            sparse.at<float>(y, x) = 20.f;
    const double exact = cv::lidarsgm::matchingResidual(left, right, sparse);
    EXPECT_LE(exact, 0.25);
    // Off by 2 px and by 2.5 px: the residual says by how much. Off by 10 px, beyond the search radius of 6: the
    // best match found is chance, some pixels away (about half the radius); a radius of 12 finds the true one.
    Mat off2;
    cv::add(sparse, 2, off2, sparse > 0);
    EXPECT_NEAR(2.0, cv::lidarsgm::matchingResidual(left, right, off2), 0.25);
    EXPECT_NEAR(2.5, cv::lidarsgm::matchingResidual(left, right, sparse * (22.5 / 20)), 0.3);
    EXPECT_GE(cv::lidarsgm::matchingResidual(left, right, sparse * (30.0 / 20)), 2.0);
    EXPECT_NEAR(10.0, cv::lidarsgm::matchingResidual(left, right, sparse * (30.0 / 20), 12), 0.25);
    // Points in the last columns, where 16 right strings from the lowest one would leave the row: the scalar loop
    // (the vector loop takes the others).
    Mat left6, right6;
    shiftedPair(6, left6, right6);
    Mat border(left6.size(), CV_32FC1, Scalar(0)), border2;
    border.colRange(border.cols - 4, border.cols - 1).rowRange(2, border.rows - 2).setTo(6);
    EXPECT_LE(cv::lidarsgm::matchingResidual(left6, right6, border), 0.25);
    cv::add(border, 2, border2, border > 0);
    EXPECT_NEAR(2.0, cv::lidarsgm::matchingResidual(left6, right6, border2), 0.25);
    // The KITTI encoding gives the same values.
    Mat sparse16;
    sparse.convertTo(sparse16, CV_16U, 256);
    EXPECT_EQ(exact, cv::lidarsgm::matchingResidual(left, right, sparse16));
}

TEST(Lidarsgm_MatchingResidual, rises_with_a_calibration_error)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    const cv::lidarsgm::KittiCalibration calib = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    for (const std::string& id : cv::lidarsgm::readKittiFrameIds(dir))
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(dir, id);
        const Mat scan = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/" + id + ".bin");
        double r[3];
        const double pitch[3] = { 0, 0.5, 1 };
        for (int k = 0; k < 3; k++)
        {
            Mat sparse;
            cv::lidarsgm::projectPointsToDisparity(scan, calib.projection,
                                                   Mat(cameraMotion(pitch[k], 0, 0) * Matx44d(calib.lidarToCamera)),
                                                   calib.focalBaseline, f.left.size(), sparse);
            r[k] = cv::lidarsgm::matchingResidual(f.left, f.right, sparse);
        }
        EXPECT_LE(r[0], 1.0) << id;   // KITTI's calibration: not above the DDC's Q1 band, where the tool warns
        EXPECT_GT(r[1], 1.0) << id;
        EXPECT_GT(r[2], r[1]) << id;
    }
}

/** A ground-like pair: row y's disparity is 8 + y / 8 (so a vertical move of the sparse values changes what they say),
the right image the left moved by it. Weak images where noise > 0: a faint texture (0-31) and the right image with
Gaussian noise of that standard deviation, then blurred. sparse gets the true disparity on every third pixel of every
third row. */
void slantedPair(double noise, Mat& left, Mat& right, Mat& sparse)
{
    RNG rng(11);
    Mat tex(160, 240, CV_8UC1);
    rng.fill(tex, RNG::UNIFORM, 0, noise > 0 ? 32 : 256);
    GaussianBlur(tex, left, Size(3, 3), 0.8);
    right = Mat(left.size(), CV_8UC1, Scalar(0));
    sparse = Mat(left.size(), CV_32FC1, Scalar(0));
    for (int y = 0; y < left.rows; y++)
    {
        const int d = 8 + y / 8;
        left.row(y).colRange(d, left.cols).copyTo(right.row(y).colRange(0, left.cols - d));
        for (int x = 60; y % 3 == 1 && x < left.cols - 2; x += 3)
            sparse.at<float>(y, x) = (float)d;
    }
    if (noise > 0)
    {
        Mat n(right.size(), CV_16SC1), r16;
        rng.fill(n, RNG::NORMAL, 0, noise);
        right.convertTo(r16, CV_16S);
        cv::add(r16, n, r16);
        r16.convertTo(right, CV_8U);
        GaussianBlur(right, right, Size(), 1.5);
    }
}

Mat moved(const Mat& sparse, int dx, int dy)
{
    Mat out(sparse.size(), sparse.type(), Scalar(0));
    const Matx23d m(1, 0, dx, 0, 1, dy);
    warpAffine(sparse, out, Mat(m), sparse.size(), INTER_NEAREST, BORDER_CONSTANT, Scalar(0));
    return out;
}

TEST(Lidarsgm_CheckLidar, tells_a_misplaced_map_from_weak_images)
{
    Mat left, right, sparse;
    slantedPair(0, left, right, sparse);
    // Right: within the band, no search.
    cv::lidarsgm::LidarCheck c = cv::lidarsgm::checkLidar(left, right, sparse);
    EXPECT_TRUE(c.trusted);
    EXPECT_LE(c.residual, 0.25);
    EXPECT_EQ(c.residual, c.shiftedResidual);
    EXPECT_EQ(c.residual, cv::lidarsgm::matchingResidual(left, right, sparse));
    EXPECT_EQ(Point(0, 0), c.shift);
    // Moved by (5, -16): the values are 2 px off where they land; the search finds the move back.
    c = cv::lidarsgm::checkLidar(left, right, moved(sparse, 5, -16), 1.0, 24);
    EXPECT_FALSE(c.trusted);
    EXPECT_NEAR(2.0, c.residual, 0.3);
    EXPECT_LE(c.shiftedResidual, 0.25);
    EXPECT_NEAR(0, c.shift.y - 16, 4);   // the rows within one disparity step (8 rows) of the move back
    // The default search reaches a 32nd of the width (7 px here), not the move back; it finds the move halfway.
    c = cv::lidarsgm::checkLidar(left, right, moved(sparse, 0, -16));
    EXPECT_LE(std::abs(c.shift.x), 7);
    EXPECT_LE(std::abs(c.shift.y), 7);
    // One that reaches a pixel: trusted, as the best it finds lowers the residual too little.
    c = cv::lidarsgm::checkLidar(left, right, moved(sparse, 0, -16), 1.0, 1);
    EXPECT_TRUE(c.trusted);
    EXPECT_LE(std::abs(c.shift.x), 1);
    EXPECT_LE(std::abs(c.shift.y), 1);
    // Weak images: the right one noisy, the map right. The residual is above the band, but no move lowers it.
    Mat noisy;
    slantedPair(30, left, noisy, sparse);
    c = cv::lidarsgm::checkLidar(left, noisy, sparse, 1.0, 24);
    EXPECT_GT(c.residual, 1.5);
    EXPECT_TRUE(c.trusted) << c.residual << " " << c.shiftedResidual << " " << c.shift;
    EXPECT_GE(c.shiftedResidual, 0.8 * c.residual);
    // A higher band takes the same map without a search.
    c = cv::lidarsgm::checkLidar(left, noisy, sparse, c.residual);
    EXPECT_EQ(c.residual, c.shiftedResidual);
    EXPECT_TRUE(c.trusted);
}

TEST(Lidarsgm_CheckLidar, kitti_frames_with_a_rotation_error)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    const cv::lidarsgm::KittiCalibration calib = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    for (const std::string& id : cv::lidarsgm::readKittiFrameIds(dir))
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(dir, id);
        const Mat scan = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/" + id + ".bin");
        // The exact calibration, at the frame's size and at twice it with JPEG compression (weaker matches: a
        // residual above the band, at the images' floor).
        Mat big[2], sparse, bigSparse;
        for (int k = 0; k < 2; k++)
        {
            resize(k ? f.right : f.left, big[k], Size(), 2, 2, INTER_CUBIC);
            std::vector<uchar> jpeg;
            imencode(".jpg", big[k], jpeg, { IMWRITE_JPEG_QUALITY, 75 });
            big[k] = imdecode(jpeg, IMREAD_GRAYSCALE);
        }
        Matx34d P2 = Matx34d(Mat(calib.projection)) * 2;
        for (int c = 0; c < 4; c++)
            P2(2, c) /= 2;
        // None, the mix of pitch 1.2, yaw -1.5 and roll 0.8 degrees, and rolls of 2 degrees either way (about the
        // optical axis: the points move in opposite directions on the two sides of the image, which no move matches).
        const Vec3d errors[4] = { Vec3d(0, 0, 0), Vec3d(1.2, -1.5, 0.8), Vec3d(0, 0, 2), Vec3d(0, 0, -2) };
        for (int error = 0; error < 4; error++)
        {
            const Vec3d e = errors[error];
            const Mat T(cameraMotion(e[0], e[1], e[2]) * Matx44d(calib.lidarToCamera));
            cv::lidarsgm::projectPointsToDisparity(scan, calib.projection, T, calib.focalBaseline, f.left.size(), sparse);
            cv::lidarsgm::projectPointsToDisparity(scan, P2, T, 2 * calib.focalBaseline, big[0].size(), bigSparse);
            const cv::lidarsgm::LidarCheck c = cv::lidarsgm::checkLidar(f.left, f.right, sparse);
            const cv::lidarsgm::LidarCheck cb = cv::lidarsgm::checkLidar(big[0], big[1], bigSparse);
            EXPECT_EQ(!error, c.trusted) << id << " " << error << " " << c.residual << " " << c.shiftedResidual;
            EXPECT_EQ(!error, cb.trusted) << id << " x2 " << error << " " << cb.residual << " " << cb.shiftedResidual;
            if (!error)
            {
                EXPECT_GT(cb.residual, 1.0) << id;   // the floor of the weaker images, above the band
            }
            if (error >= 2)
            {
                // The turn found undoes the roll, to a quarter degree.
                EXPECT_NEAR(-e[2], c.turn, 0.25) << id;
                EXPECT_NEAR(-e[2], cb.turn, 0.25) << id << " x2";
            }
        }
    }
}

TEST(Lidarsgm_CheckLidar, refusals)
{
    Mat left, right, sparse;
    slantedPair(0, left, right, sparse);
    // Nothing to compare: the images cannot tell, and the map is not condemned.
    const cv::lidarsgm::LidarCheck c = cv::lidarsgm::checkLidar(left, right, Mat::zeros(left.size(), CV_32FC1));
    EXPECT_TRUE(c.trusted);
    EXPECT_TRUE(cvIsNaN(c.residual));
    EXPECT_TRUE(cvIsNaN(c.shiftedResidual));
    EXPECT_THROW(cv::lidarsgm::checkLidar(left, right, Mat()), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::checkLidar(left, right, sparse, -1), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::checkLidar(left, right, sparse, 1, -1), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::checkLidar(left, right, sparse, 1, 1025), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::checkLidar(left, right, sparse.colRange(0, 100)), cv::Exception);
    try
    {
        cv::lidarsgm::checkLidar(left, right, sparse, std::numeric_limits<double>::quiet_NaN());
        ADD_FAILURE() << "a NaN band was taken";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("maxResidual")) << e.err;
    }
}

TEST(Lidarsgm_FailSafe, decides_with_the_bound_and_falls_back_to_stereo_alone)
{
    Mat left, right, sparse;
    slantedPair(0, left, right, sparse);
    const Mat misplaced = moved(sparse, 5, -16);
    EXPECT_EQ(1.0, cv::lidarsgm::LidarFailSafe::maxResidual());
    // checkLidar's default band is the fail-safe's bound.
    const cv::lidarsgm::LidarCheck byDefault = cv::lidarsgm::checkLidar(left, right, misplaced, 0, 24);
    const cv::lidarsgm::LidarCheck atOne = cv::lidarsgm::checkLidar(left, right, misplaced, 1.0, 24);
    EXPECT_EQ(atOne.residual, byDefault.residual);
    EXPECT_EQ(atOne.shiftedResidual, byDefault.shiftedResidual);
    EXPECT_EQ(atOne.shift, byDefault.shift);
    EXPECT_FALSE(byDefault.stereoAlone);   // checkLidar measures; the fail-safe decides

    cv::Ptr<cv::lidarsgm::LidarFailSafe> failSafe = cv::lidarsgm::LidarFailSafe::create();
    EXPECT_FALSE(failSafe->getTrustLidar());
    cv::lidarsgm::LidarCheck c = failSafe->check(left, right, sparse);
    EXPECT_TRUE(c.trusted);
    EXPECT_FALSE(c.stereoAlone);
    c = failSafe->check(left, right, misplaced);
    EXPECT_FALSE(c.trusted);
    EXPECT_TRUE(c.stereoAlone);
    EXPECT_EQ(cv::lidarsgm::checkLidar(left, right, misplaced).residual, c.residual);
    failSafe->setTrustLidar(true);
    c = failSafe->check(left, right, misplaced);
    EXPECT_FALSE(c.trusted);
    EXPECT_FALSE(c.stereoAlone);   // judged, reported, fused anyway
    failSafe->setTrustLidar(false);
    // Nothing to compare: the images cannot tell, and the LiDAR is fused.
    c = failSafe->check(left, right, Mat::zeros(left.size(), CV_32FC1));
    EXPECT_TRUE(cvIsNaN(c.residual));
    EXPECT_FALSE(c.stereoAlone);

    // compute(): the matcher on the LiDAR where it may be fused; else the stereo-alone matcher, on a map without
    // values, bit for bit as that matcher called by hand.
    cv::Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(0, 64);
    m->setSearchWindow(4);
    Mat d, ref;
    c = failSafe->compute(m, left, right, sparse, d);
    EXPECT_FALSE(c.stereoAlone);
    m->compute(left, right, sparse, ref);
    EXPECT_EQ(0, cvtest::norm(d, ref, NORM_INF));
    c = failSafe->compute(m, left, right, misplaced, d);
    EXPECT_TRUE(c.stereoAlone);
    cv::Ptr<cv::lidarsgm::StereoLidarSGM> alone = cv::lidarsgm::LidarFailSafe::stereoAloneMatcher(m);
    alone->compute(left, right, Mat::zeros(left.size(), CV_32FC1), ref);
    EXPECT_EQ(0, cvtest::norm(d, ref, NORM_INF));
    Mat withLidar;
    m->compute(left, right, misplaced, withLidar);
    EXPECT_GT(cvtest::norm(d, withLidar, NORM_INF), 0);   // the LiDAR was left out
    // A changed setting reaches the stereo-alone matcher of the next call.
    m->setUniquenessRatio(0.8);
    failSafe->compute(m, left, right, misplaced, d);
    cv::lidarsgm::LidarFailSafe::stereoAloneMatcher(m)->compute(left, right, Mat::zeros(left.size(), CV_32FC1), ref);
    EXPECT_EQ(0, cvtest::norm(d, ref, NORM_INF));
    EXPECT_THROW(failSafe->compute(cv::Ptr<cv::lidarsgm::StereoLidarSGM>(), left, right, sparse, d), cv::Exception);
}

TEST(Lidarsgm_FailSafe, the_stereo_alone_matcher)
{
    // Settings away from the defaults, kitti_best.yml's kind.
    cv::Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(-4, 96, 8, 100, 4, 150, 0.6);
    m->setNumPaths(4);
    m->setSearchWindow(4);
    m->setVisibilityRadiusX(2);
    m->setVisibilityParallax(0.25);
    m->setSemidenseWeight(0.5);
    m->setRingGapFactor(1.5);
    m->setEdgeThreshold(12);
    m->setOutputType(CV_32F);
    const int checks[4][2] = { { cv::lidarsgm::StereoLidarSGM::CHECK_NONE, cv::lidarsgm::StereoLidarSGM::CHECK_NONE },
                               { cv::lidarsgm::StereoLidarSGM::CHECK_STEREO, cv::lidarsgm::StereoLidarSGM::CHECK_STEREO },
                               { cv::lidarsgm::StereoLidarSGM::CHECK_CAMERA_LIDAR,
                                 cv::lidarsgm::StereoLidarSGM::CHECK_STEREO },
                               { cv::lidarsgm::StereoLidarSGM::CHECK_STEREO_LIDAR,
                                 cv::lidarsgm::StereoLidarSGM::CHECK_STEREO } };
    for (const auto& c : checks)
    {
        m->setConsistencyCheck(c[0]);
        const cv::Ptr<cv::lidarsgm::StereoLidarSGM> a = cv::lidarsgm::LidarFailSafe::stereoAloneMatcher(m);
        EXPECT_EQ(cv::lidarsgm::StereoLidarSGM::MODE_SGM, a->getMode());
        EXPECT_EQ(c[1], a->getConsistencyCheck());
        EXPECT_EQ(cv::lidarsgm::StereoLidarSGM::MODE_SDSGM, m->getMode());   // the matcher itself as it was
        EXPECT_EQ(c[0], m->getConsistencyCheck());
        // Every other setting as the matcher's: the two save the same text but for mode and check.
        a->setMode(m->getMode());
        a->setConsistencyCheck(m->getConsistencyCheck());
        FileStorage fa(".yml", FileStorage::WRITE | FileStorage::MEMORY), fm(".yml", FileStorage::WRITE | FileStorage::MEMORY);
        a->write(fa);
        m->write(fm);
        EXPECT_EQ(fm.releaseAndGetString(), fa.releaseAndGetString());
    }
    EXPECT_THROW(cv::lidarsgm::LidarFailSafe::stereoAloneMatcher(cv::Ptr<cv::lidarsgm::StereoLidarSGM>()), cv::Exception);
}

TEST(Lidarsgm_MatchingResidual, refuses_what_the_images_cannot_tell)
{
    Mat left, right;
    shiftedPair(20, left, right);
    Mat sparse(left.size(), CV_32FC1, Scalar(0));
    sparse.rowRange(10, 100).colRange(40, 190).setTo(20);
    EXPECT_NO_THROW(cv::lidarsgm::matchingResidual(left, right, sparse));
    // A flat grey pair: every cost is equal, nothing to compare.
    const Mat grey(left.size(), CV_8UC1, Scalar(128));
    EXPECT_THROW(cv::lidarsgm::matchingResidual(grey, grey, sparse), cv::Exception);
    // No sparse values, too few, or only values whose match leaves the right image.
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, Mat::zeros(left.size(), CV_32FC1)), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, Mat()), cv::Exception);
    Mat few(left.size(), CV_32FC1, Scalar(0));
    few.rowRange(10, 20).colRange(40, 59).setTo(20);   // 190 values
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, few), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, Mat(left.size(), CV_32FC1, Scalar(195))), cv::Exception);
    // Bad arguments.
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, sparse, 0), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, sparse, 65), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right.colRange(0, 100), sparse), cv::Exception);
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, sparse.colRange(0, 100)), cv::Exception);
    Mat sparse64;
    sparse.convertTo(sparse64, CV_64F);
    EXPECT_THROW(cv::lidarsgm::matchingResidual(left, right, sparse64), cv::Exception);
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
