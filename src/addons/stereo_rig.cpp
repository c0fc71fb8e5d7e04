// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// StereoRig: a user's own stereo camera and LiDAR (opencv2/lidarsgm/rig.hpp). The rectification is OpenCV's
// (cv::stereoRectify, cv::initUndistortRectifyMap); this file reads the calibration formats, checks them, and keeps
// the one convention every output of the rig follows: the LiDAR moves as R1 * lidar_to_left into the rectified left
// camera.

#include "../precomp.hpp"
#include "../projection.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include "opencv2/lidarsgm/rig.hpp"
#include "opencv2/imgproc.hpp"
#include <fstream>
#include <iterator>
#if CV_VERSION_MAJOR >= 5
#include "opencv2/stereo.hpp"     // stereoRectify is in stereo in OpenCV 5, calib3d in 4
#else
#include "opencv2/calib3d.hpp"
#endif

namespace cv { namespace lidarsgm {

namespace {

#if CV_VERSION_MAJOR >= 5
const int ZERO_DISPARITY = STEREO_ZERO_DISPARITY;
#else
const int ZERO_DISPARITY = CALIB_ZERO_DISPARITY;
#endif

[[noreturn]] void fail(const String& file, const String& what)
{
    LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm: %s: %s", file.c_str(), what.c_str()));
}

//! A matrix of rows x cols (cols 0: a vector of 4, 5, 8, 12 or 14 values, as distortion coefficients), as CV_64F.
Mat checkedMatrix(const Mat& m, int rows, int cols, const String& file, const String& key)
{
    if (m.empty())
        fail(file, "no " + key);
    if (m.channels() != 1 || (m.depth() != CV_32F && m.depth() != CV_64F))
        fail(file, key + " must be a CV_32F or CV_64F matrix");
    Mat d;
    m.convertTo(d, CV_64F);
    if (!checkRange(d))
        fail(file, key + " holds a NaN or infinite value");
    if (cols == 0)
    {
        const int n = (int)d.total();
        if ((d.rows != 1 && d.cols != 1) || !(n == 4 || n == 5 || n == 8 || n == 12 || n == 14))
            fail(file, format("%s must hold 4, 5, 8, 12 or 14 distortion coefficients; got %dx%d", key.c_str(),
                              d.rows, d.cols));
        return d.reshape(1, 1);
    }
    if (rows == 3 && cols == 1 && d.total() == 3)
        return d.reshape(1, 3);
    if (d.rows != rows || d.cols != cols)
        fail(file, format("%s must be %dx%d; got %dx%d", key.c_str(), rows, cols, d.rows, d.cols));
    return d;
}

//! A FileStorage matrix, or (ROS's layout) a map with rows, cols and data; a missing key is refused.
Mat readMatrix(const FileNode& n, const String& file, const String& key, int rows, int cols)
{
    const FileNode node = n[key];
    if (node.empty())
        fail(file, "no " + key);
    Mat m;
    if (node.isMap() && !node["data"].empty())
    {
        std::vector<double> data;
        node["data"] >> data;
        const int r = (int)node["rows"], c = (int)node["cols"];
        if (r <= 0 || c <= 0 || (size_t)r * c != data.size())
            fail(file, format("%s: rows x cols (%d x %d) does not match its %zu values", key.c_str(), r, c,
                              data.size()));
        m = Mat(data, true).reshape(1, r);
    }
    else
    {
        try { node >> m; }
        catch (const cv::Exception&) { fail(file, key + " is not a matrix"); }
    }
    return checkedMatrix(m, rows, cols, file, key);
}

int readInt(const FileNode& n, const String& file, const String& key)
{
    const FileNode node = n[key];
    if (node.empty() || !node.isInt())
        fail(file, "no integer " + key);
    return (int)node;
}

Mat homogeneous(const Mat& R)
{
    Mat T = Mat::eye(4, 4, CV_64F);
    R.copyTo(T(Rect(0, 0, 3, 3)));
    return T;
}

class StereoRigImpl CV_FINAL : public StereoRig
{
public:
    // The raw calibration (empty where the rig is rectified), the rectification, the LiDAR.
    Mat M1, D1, M2, D2, R, T, R1, R2, P1, P2, lidarToLeft;
    Size size;
    Mat map1x, map1y, map2x, map2y;

    /** Checks the rectified geometry and makes the maps. where: the source, for the messages. */
    void finish(const String& where)
    {
        if (size.width <= 0 || size.height <= 0)
            fail(where, format("the image size must be positive; got %dx%d", size.width, size.height));
        // Rows and depth of the right camera's centre as the left's (KITTI's P matrices carry small offsets of
        // their own reference camera in both), one principal point, one focal length.
        if (std::abs(P2.at<double>(1, 3) - P1.at<double>(1, 3)) > 1e-6 ||
            std::abs(P2.at<double>(2, 3) - P1.at<double>(2, 3)) > 1e-9 ||
            std::abs(P1.at<double>(0, 2) - P2.at<double>(0, 2)) > 1e-6 ||
            std::abs(P1.at<double>(1, 2) - P2.at<double>(1, 2)) > 1e-6 ||
            std::abs(P1.at<double>(0, 0) - P2.at<double>(0, 0)) > 1e-6)
            fail(where, "P1 and P2 are not a horizontal rectified pair with one principal point (rectify with "
                        "CALIB_ZERO_DISPARITY; vertical rigs are not supported)");
        if (getFocalBaseline() <= 0)
            fail(where, format("P1(0,3) - P2(0,3) = %g: the right camera must lie to the right of the left one",
                               getFocalBaseline()));
        const Mat Rl = lidarToLeft(Rect(0, 0, 3, 3));
        if (norm(Rl.t() * Rl, Mat::eye(3, 3, CV_64F), NORM_INF) > 1e-3 ||
            norm(lidarToLeft.row(3), Mat(Matx14d(0, 0, 0, 1)), NORM_INF) > 1e-9)
            fail(where, "lidar_to_left is not a rigid transform (a rotation and a translation, last row 0 0 0 1)");
        if (!M1.empty())
        {
            const Mat newK1 = P1(Rect(0, 0, 3, 3)), newK2 = P2(Rect(0, 0, 3, 3));
            initUndistortRectifyMap(M1, D1, R1, newK1, size, CV_32FC1, map1x, map1y);
            initUndistortRectifyMap(M2, D2, R2, newK2, size, CV_32FC1, map2x, map2y);
        }
    }

    void writeFile(const String& path) const CV_OVERRIDE
    {
        FileStorage fs(path, FileStorage::WRITE);
        if (!fs.isOpened())
            fail(path, "cannot be written");
        fs << "image_width" << size.width << "image_height" << size.height;
        if (!M1.empty())
            fs << "M1" << M1 << "D1" << D1 << "M2" << M2 << "D2" << D2 << "R" << R << "T" << T << "R1" << R1
               << "R2" << R2;
        fs << "P1" << P1 << "P2" << P2 << "lidar_to_left" << lidarToLeft;
    }

    Size getImageSize() const CV_OVERRIDE { return size; }
    bool isRectified() const CV_OVERRIDE { return M1.empty(); }

    void rectify(InputArray left, InputArray right, OutputArray leftRectified,
                 OutputArray rightRectified) const CV_OVERRIDE
    {
        if (left.size() != size || right.size() != size)
            LIDARSGM_Error_(Error::StsUnmatchedSizes,
                            ("lidarsgm: StereoRig::rectify: the images are %dx%d and %dx%d; the rig's size is %dx%d",
                             left.size().width, left.size().height, right.size().width, right.size().height, size.width,
                             size.height));
        if (M1.empty())
        {
            left.copyTo(leftRectified);
            right.copyTo(rightRectified);
            return;
        }
        const Mat l = left.getMat(), r = right.getMat();
        remap(l, leftRectified, map1x, map1y, INTER_LINEAR, BORDER_CONSTANT);
        remap(r, rightRectified, map2x, map2y, INTER_LINEAR, BORDER_CONSTANT);
    }

    Mat getProjectionLeft() const CV_OVERRIDE { return P1.clone(); }
    Mat getProjectionRight() const CV_OVERRIDE { return P2.clone(); }
    double getFocalBaseline() const CV_OVERRIDE { return P1.at<double>(0, 3) - P2.at<double>(0, 3); }
    Mat getLidarToRectified() const CV_OVERRIDE { return homogeneous(R1) * lidarToLeft; }
    Mat getRectifiedToLeft() const CV_OVERRIDE { return homogeneous(R1.t()); }

    KittiCalibration getCalibration() const CV_OVERRIDE
    {
        KittiCalibration c;
        // P1 as it is: projectPointsToDisparity takes disparities as focalBaseline / depth, which holds for a
        // horizontal pair with one principal point (finish() checks it), P1's own fourth column included (KITTI's).
        c.projection = P1.clone();
        c.lidarToCamera = getLidarToRectified();
        c.focalBaseline = getFocalBaseline();
        return c;
    }

    void projectCloud(InputArray points, OutputArray sparseDisparity, int dtype) const CV_OVERRIDE
    {
        const KittiCalibration c = getCalibration();
        projectPointsToDisparity(points, c.projection, c.lidarToCamera, c.focalBaseline, size, sparseDisparity, dtype);
    }

    void rectifiedToLeftCamera(InputArray points, OutputArray pointsLeft) const CV_OVERRIDE
    {
        const Mat p = points.getMat();
        LIDARSGM_Check((p.channels() == 3 || (p.channels() == 1 && p.cols == 3)) &&
                           (p.depth() == CV_32F || p.depth() == CV_64F),
                       "lidarsgm: StereoRig::rectifiedToLeftCamera takes 3-channel points or an N x 3 matrix, CV_32F "
                       "or CV_64F");
        const Mat src = p.channels() == 3 ? p : p.reshape(3);
        Mat dst;
        transform(src, dst, R1.t());   // NaN stays NaN
        if (p.channels() == 3)
            dst.copyTo(pointsLeft);
        else
            dst.reshape(1).copyTo(pointsLeft);
    }
};

} // namespace

Ptr<StereoRig> StereoRig::create(InputArray M1, InputArray D1, InputArray M2, InputArray D2, InputArray R,
                                 InputArray T, Size imageSize, InputArray lidarToLeft)
{
    const String where = "StereoRig::create";
    Ptr<StereoRigImpl> rig = makePtr<StereoRigImpl>();
    rig->M1 = checkedMatrix(M1.getMat(), 3, 3, where, "M1");
    rig->D1 = checkedMatrix(D1.getMat(), 1, 0, where, "D1");
    rig->M2 = checkedMatrix(M2.getMat(), 3, 3, where, "M2");
    rig->D2 = checkedMatrix(D2.getMat(), 1, 0, where, "D2");
    rig->R = checkedMatrix(R.getMat(), 3, 3, where, "R");
    rig->T = checkedMatrix(T.getMat(), 3, 1, where, "T");
    rig->lidarToLeft = checkedMatrix(lidarToLeft.getMat(), 4, 4, where, "lidar_to_left");
    rig->size = imageSize;
    if (imageSize.width <= 0 || imageSize.height <= 0)
        fail(where, "the image size must be positive");
    Mat Q;
    stereoRectify(rig->M1, rig->D1, rig->M2, rig->D2, imageSize, rig->R, rig->T, rig->R1, rig->R2, rig->P1, rig->P2, Q,
                  ZERO_DISPARITY, 0);
    rig->finish(where);
    return rig;
}

Ptr<StereoRig> StereoRig::fromFile(const String& path)
{
    if (!utils::fs::exists(path))
        fail(path, "does not exist");
    FileStorage fs;
    try { fs.open(path, FileStorage::READ); }
    catch (const cv::Exception& e) { fail(path, "cannot be parsed: " + detail::parserMessage(e)); }
    if (!fs.isOpened())
        fail(path, "cannot be read as YAML, XML or JSON");
    const FileNode root = fs.root();
    // The rig's keys, and what OpenCV's calibration samples write beside them (kept, not read).
    static const std::vector<String> known = { "image_width", "image_height", "M1", "D1", "M2", "D2", "R", "T", "R1",
                                               "R2", "P1", "P2", "Q", "E", "F", "lidar_to_left", "calibration_time" };
    detail::refuseUnknownKeys(root, known, path);
    const Size size(readInt(root, path, "image_width"), readInt(root, path, "image_height"));
    const Mat lidar = readMatrix(root, path, "lidar_to_left", 4, 4);
    if (root["M1"].empty())
    {
        if (root["P1"].empty())
            fail(path, "holds neither a raw calibration (M1, D1, M2, D2, R, T) nor a rectified one (P1, P2)");
        Ptr<StereoRigImpl> rig = makePtr<StereoRigImpl>();
        rig->P1 = readMatrix(root, path, "P1", 3, 4);
        rig->P2 = readMatrix(root, path, "P2", 3, 4);
        rig->R1 = Mat::eye(3, 3, CV_64F);
        rig->R2 = Mat::eye(3, 3, CV_64F);
        rig->lidarToLeft = lidar;
        rig->size = size;
        rig->finish(path);
        return rig;
    }
    const Mat M1 = readMatrix(root, path, "M1", 3, 3), D1 = readMatrix(root, path, "D1", 1, 0),
              M2 = readMatrix(root, path, "M2", 3, 3), D2 = readMatrix(root, path, "D2", 1, 0),
              R = readMatrix(root, path, "R", 3, 3), T = readMatrix(root, path, "T", 3, 1);
    const bool any = !root["R1"].empty() || !root["R2"].empty() || !root["P1"].empty() || !root["P2"].empty();
    if (!any)
    {
        try { return create(M1, D1, M2, D2, R, T, size, lidar); }
        catch (const cv::Exception& e) { fail(path, detail::withoutModulePrefix(e.err)); }
    }
    Ptr<StereoRigImpl> rig = makePtr<StereoRigImpl>();
    rig->M1 = M1; rig->D1 = D1; rig->M2 = M2; rig->D2 = D2; rig->R = R; rig->T = T;
    rig->R1 = readMatrix(root, path, "R1", 3, 3);
    rig->R2 = readMatrix(root, path, "R2", 3, 3);
    rig->P1 = readMatrix(root, path, "P1", 3, 4);
    rig->P2 = readMatrix(root, path, "P2", 3, 4);
    rig->lidarToLeft = lidar;
    rig->size = size;
    rig->finish(path);
    return rig;
}

Ptr<StereoRig> StereoRig::fromRos(const String& leftYaml, const String& rightYaml, InputArray lidarToLeft)
{
    Ptr<StereoRigImpl> rig = makePtr<StereoRigImpl>();
    Size sizes[2];
    Mat* K[2] = { &rig->M1, &rig->M2 };
    Mat* Dist[2] = { &rig->D1, &rig->D2 };
    Mat* Rr[2] = { &rig->R1, &rig->R2 };
    Mat* P[2] = { &rig->P1, &rig->P2 };
    const String files[2] = { leftYaml, rightYaml };
    for (int i = 0; i < 2; i++)
    {
        // camera_calibration writes plain YAML; cv::FileStorage of OpenCV 4 wants its %YAML:1.0 directive first.
        std::ifstream in(files[i].c_str(), std::ios::binary);
        if (!in)
            fail(files[i], "cannot be opened");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (text.compare(0, 5, "%YAML") != 0)
            text = "%YAML:1.0\n---\n" + text;
        FileStorage fs;
        try { fs.open(text, FileStorage::READ | FileStorage::MEMORY | FileStorage::FORMAT_YAML); }
        catch (const cv::Exception& e) { fail(files[i], "cannot be parsed: " + detail::parserMessage(e)); }
        if (!fs.isOpened())
            fail(files[i], "cannot be parsed as YAML");
        const FileNode root = fs.root();
        const FileNode model = root["distortion_model"];
        if (!model.empty() && model.isString() && (String)model != "plumb_bob" &&
            (String)model != "rational_polynomial")
            fail(files[i], "distortion_model '" + (String)model + "' is not supported (plumb_bob or "
                           "rational_polynomial; rectify fisheye images with image_proc first)");
        sizes[i] = Size(readInt(root, files[i], "image_width"), readInt(root, files[i], "image_height"));
        *K[i] = readMatrix(root, files[i], "camera_matrix", 3, 3);
        *Dist[i] = readMatrix(root, files[i], "distortion_coefficients", 1, 0);
        *Rr[i] = readMatrix(root, files[i], "rectification_matrix", 3, 3);
        *P[i] = readMatrix(root, files[i], "projection_matrix", 3, 4);
    }
    if (sizes[0] != sizes[1])
        fail(rightYaml, format("its image size %dx%d differs from the left file's %dx%d", sizes[1].width,
                               sizes[1].height, sizes[0].width, sizes[0].height));
    rig->lidarToLeft = checkedMatrix(lidarToLeft.getMat(), 4, 4, "StereoRig::fromRos", "lidarToLeft");
    rig->size = sizes[0];
    // The pose of the right camera, for writeFile: x_right = R2^T (R1 x_left + t), t from P2's fourth column.
    rig->R = rig->R2.t() * rig->R1;
    rig->T = rig->R2.t() * (Mat_<double>(3, 1) << (rig->P2.at<double>(0, 3) - rig->P1.at<double>(0, 3)) /
                                                      rig->P2.at<double>(0, 0), 0, 0);
    rig->finish(leftYaml);
    return rig;
}

Ptr<StereoRig> StereoRig::fromKitti(const KittiCalibration& calibration, Size imageSize)
{
    const String where = "StereoRig::fromKitti";
    Ptr<StereoRigImpl> rig = makePtr<StereoRigImpl>();
    rig->P1 = checkedMatrix(calibration.projection, 3, 4, where, "projection");
    // KITTI's right camera: the same intrinsics, shifted by the focal baseline.
    rig->P2 = rig->P1.clone();
    rig->P2.at<double>(0, 3) = rig->P1.at<double>(0, 3) - calibration.focalBaseline;
    rig->R1 = Mat::eye(3, 3, CV_64F);
    rig->R2 = Mat::eye(3, 3, CV_64F);
    rig->lidarToLeft = checkedMatrix(calibration.lidarToCamera, 4, 4, where, "lidarToCamera");
    rig->size = imageSize;
    rig->finish(where);
    return rig;
}

}} // namespace cv::lidarsgm
