// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "opencv2/lidarsgm/rig.hpp"
#include <fstream>
#if CV_VERSION_MAJOR >= 5
#include "opencv2/stereo.hpp"
#include "opencv2/geometry/3d.hpp"
#else
#include "opencv2/calib3d.hpp"
#endif

namespace opencv_test { namespace {

using cv::lidarsgm::StereoRig;

/* A synthetic raw rig: two cameras with radial and tangential distortion (k1 about -0.2), the right one turned by
about a degree and 0.5 m to the right, and a LiDAR (x forward, y left, z up) above the left camera. */
struct SyntheticRig
{
    Mat M1, D1, M2, D2, R, T, lidarToLeft;
    Size size = Size(1280, 720);
    SyntheticRig()
    {
        M1 = (Mat_<double>(3, 3) << 700, 0, 640, 0, 702, 360, 0, 0, 1);
        M2 = (Mat_<double>(3, 3) << 705, 0, 633, 0, 706, 364, 0, 0, 1);
        D1 = (Mat_<double>(1, 5) << -0.2, 0.05, 0.001, -0.0005, 0);
        D2 = (Mat_<double>(1, 5) << -0.18, 0.04, -0.001, 0.0005, 0);
        Rodrigues(Vec3d(0.008, -0.015, 0.006), R);
        T = (Mat_<double>(3, 1) << -0.5, 0.01, 0.004);
        // LiDAR axes to camera axes (camera x = -LiDAR y, y = -z, z = x), turned a little, 0.1 m above.
        const Mat axes = (Mat_<double>(3, 3) << 0, -1, 0, 0, 0, -1, 1, 0, 0);
        Mat turn;
        Rodrigues(Vec3d(0.01, 0.02, -0.005), turn);
        lidarToLeft = Mat::eye(4, 4, CV_64F);
        Mat(turn * axes).copyTo(lidarToLeft(Rect(0, 0, 3, 3)));
        lidarToLeft.at<double>(1, 3) = -0.1;
        lidarToLeft.at<double>(2, 3) = 0.05;
    }
    //! Writes the stereo_calib sample's names (with the rectification where given) and lidar_to_left.
    void write(const std::string& path, const Mat& R1 = Mat(), const Mat& R2 = Mat(), const Mat& P1 = Mat(),
               const Mat& P2 = Mat()) const
    {
        FileStorage fs(path, FileStorage::WRITE);
        fs << "image_width" << size.width << "image_height" << size.height << "M1" << M1 << "D1" << D1 << "M2" << M2
           << "D2" << D2 << "R" << R << "T" << T;
        if (!R1.empty())
            fs << "R1" << R1 << "R2" << R2 << "P1" << P1 << "P2" << P2;
        fs << "lidar_to_left" << lidarToLeft;
    }
};

//! Bilinear sample of a CV_32FC1 map at (x, y).
static double sampleMap(const Mat& m, double x, double y)
{
    Mat patch;
    getRectSubPix(m, Size(1, 1), Point2f((float)x, (float)y), patch);
    return patch.at<float>(0, 0);
}

//! Random points in the LiDAR's frame, 4 to 40 m ahead, within the cameras' view.
static Mat lidarPoints(RNG& rng, int n)
{
    Mat pts(n, 4, CV_32F);
    for (int i = 0; i < n; i++)
    {
        const double x = rng.uniform(4.0, 40.0);
        pts.at<float>(i, 0) = (float)x;
        pts.at<float>(i, 1) = (float)(rng.uniform(-0.5, 0.5) * x);
        pts.at<float>(i, 2) = (float)(rng.uniform(-0.25, 0.25) * x);
        pts.at<float>(i, 3) = 0.f;
    }
    return pts;
}

/* The round trip of the un-rectification: a point seen by the raw cameras (cv::projectPoints with the distortion)
lies, at the pixel where the rig's rectified views put it, on the rig's rectification maps within 0.05 px; the two
rectified views put it on one row, its disparity is f B / Z, and projectCloud writes that disparity there. */
TEST(Lidarsgm_Rig, unrectification_round_trip)
{
    const SyntheticRig s;
    const std::string file = cv::tempfile(".yml");
    s.write(file);
    Ptr<StereoRig> rig = StereoRig::fromFile(file);
    ASSERT_FALSE(rig.empty());
    EXPECT_FALSE(rig->isRectified());
    EXPECT_EQ(s.size, rig->getImageSize());
    // The rectification is stereoRectify's (CALIB_ZERO_DISPARITY, alpha 0).
    Mat R1, R2, P1, P2, Q;
    stereoRectify(s.M1, s.D1, s.M2, s.D2, s.size, s.R, s.T, R1, R2, P1, P2, Q, 0x400, 0);
    EXPECT_LE(cvtest::norm(rig->getProjectionLeft(), P1, NORM_INF), 1e-9);
    EXPECT_LE(cvtest::norm(rig->getProjectionRight(), P2, NORM_INF), 1e-9);
    const double fB = rig->getFocalBaseline();
    EXPECT_NEAR(P1.at<double>(0, 0) * 0.5, fB, 0.5 * 0.05 * P1.at<double>(0, 0));   // about f x 0.5 m

    RNG rng(7);
    const Mat pts = lidarPoints(rng, 400);
    Mat sparse;
    rig->projectCloud(pts, sparse);
    ASSERT_EQ(s.size, sparse.size());
    // The maps of the rectified views, through the raw images (a blank image's rectification gives nothing).
    Mat map1x, map1y, map2x, map2y;
    initUndistortRectifyMap(s.M1, s.D1, R1, P1(Rect(0, 0, 3, 3)), s.size, CV_32FC1, map1x, map1y);
    initUndistortRectifyMap(s.M2, s.D2, R2, P2(Rect(0, 0, 3, 3)), s.size, CV_32FC1, map2x, map2y);
    const Mat toRect = rig->getLidarToRectified();
    int checked = 0, valued = 0;
    double worst = 0;
    for (int i = 0; i < pts.rows; i++)
    {
        const Mat X = (Mat_<double>(4, 1) << pts.at<float>(i, 0), pts.at<float>(i, 1), pts.at<float>(i, 2), 1);
        const Mat Xl = Mat(s.lidarToLeft * X).rowRange(0, 3);
        const Mat Xr = s.R * Xl + s.T;
        std::vector<Point2d> rawL, rawR;
        projectPoints(std::vector<Point3d>{ Point3d(Xl) }, Vec3d(), Vec3d(), s.M1, s.D1, rawL);
        projectPoints(std::vector<Point3d>{ Point3d(Xr) }, Vec3d(), Vec3d(), s.M2, s.D2, rawR);
        // Where the rig's rectified views put it.
        const Mat Xrect = toRect * X;
        const Mat ul = P1 * Xrect, ur = P2 * Xrect;
        const double xl = ul.at<double>(0) / ul.at<double>(2), yl = ul.at<double>(1) / ul.at<double>(2);
        const double xr = ur.at<double>(0) / ur.at<double>(2), yr = ur.at<double>(1) / ur.at<double>(2);
        if (xl < 2 || xl > s.size.width - 3 || yl < 2 || yl > s.size.height - 3 || xr < 2 || xr > s.size.width - 3 ||
            rawL[0].x < 0 || rawL[0].x > s.size.width - 1 || rawL[0].y < 0 || rawL[0].y > s.size.height - 1)
            continue;
        checked++;
        EXPECT_NEAR(yl, yr, 1e-6);
        EXPECT_NEAR(xl - xr, fB / Xrect.at<double>(2), 1e-6);
        const double eL = std::hypot(sampleMap(map1x, xl, yl) - rawL[0].x, sampleMap(map1y, xl, yl) - rawL[0].y);
        const double eR = std::hypot(sampleMap(map2x, xr, yr) - rawR[0].x, sampleMap(map2y, xr, yr) - rawR[0].y);
        worst = std::max(worst, std::max(eL, eR));
        // projectCloud's value at the point's pixel (the points lie far apart: no other point covers it).
        const float d = sparse.at<float>(cvRound(yl), cvRound(xl));
        if (d > 0)
        {
            valued++;
            EXPECT_NEAR(fB / Xrect.at<double>(2), d, 0.01);
        }
    }
    EXPECT_GT(checked, 200);
    EXPECT_GT(valued, checked * 9 / 10);
    std::cout << "rectified -> raw through the maps: worst " << worst << " px of " << checked << " points" << std::endl;
    EXPECT_LT(worst, 0.05) << "rectified pixel -> raw pixel through the maps, worst of " << checked;
    // And the rig's own maps are those: a textured raw pair rectifies as remap does.
    Mat rawL(s.size, CV_8UC1), rawR(s.size, CV_8UC1), rectL, rectR, expectL;
    rng.fill(rawL, RNG::UNIFORM, 0, 256);
    rng.fill(rawR, RNG::UNIFORM, 0, 256);
    rig->rectify(rawL, rawR, rectL, rectR);
    remap(rawL, expectL, map1x, map1y, INTER_LINEAR, BORDER_CONSTANT);
    EXPECT_EQ(0, cvtest::norm(rectL, expectL, NORM_INF));
    // Rectified points back in the raw left camera's frame.
    Mat back;
    const Mat pRect = (Mat_<float>(1, 3) << 1.f, -2.f, 10.f);
    rig->rectifiedToLeftCamera(pRect, back);
    const Mat expect = R1.t() * (Mat_<double>(3, 1) << 1, -2, 10);
    EXPECT_NEAR(expect.at<double>(0), back.at<float>(0, 0), 1e-5);
    EXPECT_NEAR(expect.at<double>(2), back.at<float>(0, 2), 1e-5);
    remove(file.c_str());
}

/* The same rig written with its rectification (the stereo_calib sample's R1 R2 P1 P2), written back by writeFile, and
as ROS camera_calibration's two files: one rig. */
TEST(Lidarsgm_Rig, file_forms_agree)
{
    const SyntheticRig s;
    Mat R1, R2, P1, P2, Q;
    stereoRectify(s.M1, s.D1, s.M2, s.D2, s.size, s.R, s.T, R1, R2, P1, P2, Q, 0x400, 0);
    const std::string withRect = cv::tempfile(".yml"), copy = cv::tempfile(".xml");
    s.write(withRect, R1, R2, P1, P2);
    Ptr<StereoRig> a = StereoRig::fromFile(withRect);
    a->writeFile(copy);
    Ptr<StereoRig> b = StereoRig::fromFile(copy);
    Ptr<StereoRig> c = StereoRig::create(s.M1, s.D1, s.M2, s.D2, s.R, s.T, s.size, s.lidarToLeft);
    // ROS camera_calibration's layout: rows, cols, data.
    const std::string left = cv::tempfile(".yaml"), right = cv::tempfile(".yaml");
    const auto rosFile = [&](const std::string& path, const Mat& K, const Mat& D, const Mat& Rr, const Mat& P) {
        std::ofstream f(path.c_str());
        const auto data = [&](const Mat& m) {
            std::string t = "[";
            for (int i = 0; i < (int)m.total(); i++)
                t += format("%s%.17g", i ? ", " : "", m.at<double>(i / m.cols, i % m.cols));
            return t + "]";
        };
        f << "image_width: " << s.size.width << "\nimage_height: " << s.size.height << "\ncamera_name: narrow_stereo\n"
          << "camera_matrix:\n  rows: 3\n  cols: 3\n  data: " << data(K) << "\ndistortion_model: plumb_bob\n"
          << "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: " << data(D) << "\n"
          << "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: " << data(Rr) << "\n"
          << "projection_matrix:\n  rows: 3\n  cols: 4\n  data: " << data(P) << "\n";
    };
    rosFile(left, s.M1, s.D1, R1, P1);
    rosFile(right, s.M2, s.D2, R2, P2);
    Ptr<StereoRig> d = StereoRig::fromRos(left, right, s.lidarToLeft);
    for (const Ptr<StereoRig>& r : { b, c, d })
    {
        EXPECT_LE(cvtest::norm(r->getProjectionLeft(), a->getProjectionLeft(), NORM_INF), 1e-9);
        EXPECT_LE(cvtest::norm(r->getProjectionRight(), a->getProjectionRight(), NORM_INF), 1e-9);
        EXPECT_LE(cvtest::norm(r->getLidarToRectified(), a->getLidarToRectified(), NORM_INF), 1e-12);
        EXPECT_NEAR(a->getFocalBaseline(), r->getFocalBaseline(), 1e-9);
        Mat raw(s.size, CV_8UC1), x1, x2, y1, y2;
        RNG(3).fill(raw, RNG::UNIFORM, 0, 256);
        a->rectify(raw, raw, x1, x2);
        r->rectify(raw, raw, y1, y2);
        EXPECT_EQ(0, cvtest::norm(x1, y1, NORM_INF));
        EXPECT_EQ(0, cvtest::norm(x2, y2, NORM_INF));
    }
    for (const std::string& f : { withRect, copy, left, right })
        remove(f.c_str());
}

// A rectified rig passes its images through; from a KITTI calibration it projects as projectPointsToDisparity does.
TEST(Lidarsgm_Rig, rectified_rigs_pass_through)
{
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    const cv::lidarsgm::KittiCalibration calib =
        cv::lidarsgm::readKittiCalibration(cvtest::findDataDirectory("kitti") + "/calib.txt");
    Ptr<StereoRig> rig = StereoRig::fromKitti(calib, l.size());
    EXPECT_TRUE(rig->isRectified());
    Mat a, b;
    rig->rectify(l, r, a, b);
    EXPECT_EQ(0, cvtest::norm(a, l, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(b, r, NORM_INF));
    EXPECT_DOUBLE_EQ(calib.focalBaseline, rig->getFocalBaseline());
    const Mat scan = cv::lidarsgm::readVelodyneScan(cvtest::findDataDirectory("kitti") + "/velodyne/000002.bin");
    Mat viaRig, direct;
    rig->projectCloud(scan, viaRig);
    cv::lidarsgm::projectPointsToDisparity(scan, calib.projection, calib.lidarToCamera, calib.focalBaseline, l.size(),
                                           direct);
    EXPECT_EQ(0, cvtest::norm(viaRig, direct, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(direct, s, NORM_INF));
    // A FileStorage file with P1 and P2 only is a rectified rig too.
    const std::string file = cv::tempfile(".yml");
    rig->writeFile(file);
    Ptr<StereoRig> again = StereoRig::fromFile(file);
    EXPECT_TRUE(again->isRectified());
    again->projectCloud(scan, viaRig);
    EXPECT_EQ(0, cvtest::norm(viaRig, direct, NORM_INF));
    remove(file.c_str());
}

//! The exception's message (empty when none is raised).
static std::string rigError(const std::function<void()>& f)
{
    try { f(); }
    catch (const cv::Exception& e) { return e.msg; }
    return std::string();
}

// Bad files and inputs are refused with what is wrong, naming the file and the key.
TEST(Lidarsgm_Rig, refusals_name_the_fault)
{
    const SyntheticRig s;
    const std::string file = cv::tempfile(".yml");
    const auto writeWith = [&](const std::function<void(FileStorage&)>& body) {
        FileStorage fs(file, FileStorage::WRITE);
        fs << "image_width" << s.size.width << "image_height" << s.size.height;
        body(fs);
    };
    writeWith([&](FileStorage& fs) { fs << "M1" << s.M1 << "D1" << s.D1 << "M2" << s.M2 << "R" << s.R << "T" << s.T
                                        << "lidar_to_left" << s.lidarToLeft; });
    std::string m = rigError([&] { StereoRig::fromFile(file); });
    EXPECT_NE(std::string::npos, m.find("no D2")) << m;
    EXPECT_NE(std::string::npos, m.find(file)) << m;
    writeWith([&](FileStorage& fs) { fs << "M1" << Mat::eye(2, 3, CV_64F) << "D1" << s.D1 << "M2" << s.M2 << "D2"
                                        << s.D2 << "R" << s.R << "T" << s.T << "lidar_to_left" << s.lidarToLeft; });
    m = rigError([&] { StereoRig::fromFile(file); });
    EXPECT_NE(std::string::npos, m.find("M1 must be 3x3")) << m;
    writeWith([&](FileStorage& fs) { fs << "M1" << s.M1 << "D1" << s.D1 << "M2" << s.M2 << "D2" << s.D2 << "R" << s.R
                                        << "T" << s.T << "lidar_to_left" << Mat(2 * s.lidarToLeft); });
    m = rigError([&] { StereoRig::fromFile(file); });
    EXPECT_NE(std::string::npos, m.find("not a rigid transform")) << m;
    writeWith([&](FileStorage& fs) { fs << "lidar_to_left" << s.lidarToLeft; });
    m = rigError([&] { StereoRig::fromFile(file); });
    EXPECT_NE(std::string::npos, m.find("neither a raw calibration")) << m;
    // A vertical rig (the right camera below the left one).
    const Mat Tdown = (Mat_<double>(3, 1) << 0.0, -0.5, 0.0);
    m = rigError([&] { StereoRig::create(s.M1, s.D1, s.M2, s.D2, Mat::eye(3, 3, CV_64F), Tdown, s.size,
                                         s.lidarToLeft); });
    EXPECT_NE(std::string::npos, m.find("horizontal")) << m;
    // A NaN anywhere, distortion coefficients and the translation included.
    Mat nanD = s.D1.clone(), nanT = s.T.clone();
    nanD.at<double>(0, 1) = std::numeric_limits<double>::quiet_NaN();
    nanT.at<double>(2, 0) = std::numeric_limits<double>::quiet_NaN();
    m = rigError([&] { StereoRig::create(s.M1, nanD, s.M2, s.D2, s.R, s.T, s.size, s.lidarToLeft); });
    EXPECT_NE(std::string::npos, m.find("D1 holds a NaN")) << m;
    m = rigError([&] { StereoRig::create(s.M1, s.D1, s.M2, s.D2, s.R, nanT, s.size, s.lidarToLeft); });
    EXPECT_NE(std::string::npos, m.find("T holds a NaN")) << m;
    m = rigError([&] { StereoRig::fromFile(file + ".missing"); });
    EXPECT_NE(std::string::npos, m.find("does not exist")) << m;
    // A misspelt key is refused (an optional one would otherwise pass unread), naming the nearest known key.
    writeWith([&](FileStorage& fs) { fs << "M1" << s.M1 << "D1" << s.D1 << "M2" << s.M2 << "D2" << s.D2 << "R" << s.R
                                        << "T" << s.T << "lidar_to_lft" << s.lidarToLeft; });
    m = rigError([&] { StereoRig::fromFile(file); });
    EXPECT_NE(std::string::npos, m.find("unknown key 'lidar_to_lft' in " + file + " (did you mean 'lidar_to_left'?)"))
        << m;
    Ptr<StereoRig> rig = StereoRig::create(s.M1, s.D1, s.M2, s.D2, s.R, s.T, s.size, s.lidarToLeft);
    Mat small(100, 100, CV_8UC1, Scalar::all(0)), a, b;
    m = rigError([&] { rig->rectify(small, small, a, b); });
    EXPECT_NE(std::string::npos, m.find("the rig's size is 1280x720")) << m;
    // A fisheye model in ROS's files.
    {
        std::ofstream f(file.c_str());
        f << "image_width: 1280\nimage_height: 720\ndistortion_model: equidistant\n";
    }
    m = rigError([&] { StereoRig::fromRos(file, file, s.lidarToLeft); });
    EXPECT_NE(std::string::npos, m.find("equidistant")) << m;
    remove(file.c_str());
}

}} // namespace
