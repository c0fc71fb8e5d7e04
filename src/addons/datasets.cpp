// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The datasets a user of the module evaluates on (KITTI 2015 folders, KITTI raw drives, Middlebury scenes) and the
// file formats of their results: opencv2/lidarsgm/datasets.hpp. The tool, the tests, the perf tests and the Python
// samples read them with this one copy.

#include "../precomp.hpp"
#include "opencv2/lidarsgm/datasets.hpp"
#include "../pipeline.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace cv { namespace lidarsgm {

namespace {

//! The numeric entries of a KITTI calibration file ("NAME: v0 v1 ..." per line).
class CalibFile
{
public:
    explicit CalibFile(const String& path) : path_(path)
    {
        std::ifstream f(path.c_str());
        if (!f)
            LIDARSGM_Error(Error::StsObjectNotFound, "cannot open calibration file " + path);
        std::string line;
        while (std::getline(f, line))
        {
            const size_t colon = line.find(':');
            if (colon == std::string::npos)
                continue;
            std::istringstream vals(line.substr(colon + 1));
            std::vector<double>& v = entries_[line.substr(0, colon)];
            double x;
            while (vals >> x)
                v.push_back(x);
        }
    }

    bool has(const std::string& name) const { return entries_.count(name) != 0; }

    //! Entry `name` as a rows x cols CV_64F matrix.
    Mat matrix(const std::string& name, int rows, int cols) const
    {
        auto it = entries_.find(name);
        if (it == entries_.end())
            LIDARSGM_Error(Error::StsParseError, "calibration file " + path_ + " has no key " + name);
        if ((int)it->second.size() != rows * cols)
            LIDARSGM_Error_(Error::StsParseError, ("calibration entry %s in %s has %d numbers, expected %d",
                                                   name.c_str(), path_.c_str(), (int)it->second.size(), rows * cols));
        return Mat(rows, cols, CV_64F, (void*)it->second.data()).clone();
    }

private:
    String path_;
    std::map<std::string, std::vector<double> > entries_;
};

//! [R | t] (3x3, 3x1 or 3x4) as a 4x4 rigid transform.
Mat homogeneous(const Mat& R, const Mat& t = Mat())
{
    Mat T = Mat::eye(4, 4, CV_64F);
    R.copyTo(T(Rect(0, 0, R.cols, 3)));
    if (!t.empty())
        t.reshape(1, 3).copyTo(T(Rect(3, 0, 1, 3)));
    return T;
}

KittiCalibration calibrationOf(const Mat& P2, const Mat& P3, const Mat& R0, const Mat& veloToCamera)
{
    KittiCalibration k;
    k.projection = P2;
    k.rightProjection = P3;
    k.rectification = R0;
    k.veloToCamera = veloToCamera;
    k.lidarToCamera = homogeneous(R0) * homogeneous(veloToCamera);
    k.focalBaseline = P2.at<double>(0, 3) - P3.at<double>(0, 3);
    return k;
}

//! The image file at path as stored, what it holds named in the messages ("cannot read <what> <path>: why").
static Mat readImageFile(const String& path, const String& what)
{
    // Tested first: imread would log its own warning before this message.
    if (!std::ifstream(path).good())
        LIDARSGM_Error(Error::StsObjectNotFound, "cannot read " + what + " " + path + ": no such file, or not readable");
    Mat img = imread(path, IMREAD_UNCHANGED);
    if (img.empty())
        LIDARSGM_Error(Error::StsObjectNotFound, "cannot read " + what + " " + path + ": not an image format OpenCV "
                                                 "decodes");
    return img;
}

Mat readImage(const String& path)
{
    return readImageFile(path, "image");
}

Mat toGrey(const Mat& img)
{
    Mat g;
    if (img.channels() == 3)
        cvtColor(img, g, COLOR_BGR2GRAY);
    else if (img.channels() == 4)
        cvtColor(img, g, COLOR_BGRA2GRAY);
    else
        g = img;
    return g;
}

bool fileExists(const String& path) { return std::ifstream(path.c_str()).good(); }

/* A frame from its three files: the grey pair, the images' sizes checked, the scan projected with *given or, where
 none is given, the calibration read from calibPath (after the images, so that a missing folder names its first
 image). */
StereoLidarFrame loadFrame(const String& name, const String& leftPath, const String& rightPath,
                           const String& scanPath, const KittiCalibration* given, const String& calibPath,
                           int lidarEvery, int firstRing)
{
    StereoLidarFrame f;
    f.name = name;
    f.leftImage = readImage(leftPath);
    f.left = toGrey(f.leftImage);
    f.right = toGrey(readImage(rightPath));
    if (f.right.size() != f.left.size())
        LIDARSGM_Error(Error::StsBadSize, "the images " + leftPath + " and " + rightPath + " differ in size");
    f.calibration = given ? *given : readKittiCalibration(calibPath);
    f.calibration.imageSize = f.left.size();
    const KittiCalibration& c = f.calibration;
    const Mat pts = selectLidarRings(readVelodyneScan(scanPath), lidarEvery, firstRing);
    projectPointsToDisparity(pts, c.projection, c.lidarToCamera, c.focalBaseline, f.left.size(), f.sparse);
    return f;
}

} // namespace

KittiCalibration readKittiCalibration(const String& path)
{
    const CalibFile c(path);
    return calibrationOf(c.matrix("P2", 3, 4), c.matrix("P3", 3, 4), c.matrix("R0_rect", 3, 3),
                         c.matrix("Tr_velo_to_cam", 3, 4));
}

KittiCalibration readKittiRawCalibration(const String& camToCamPath, const String& veloToCamPath)
{
    const CalibFile cam(camToCamPath), velo(veloToCamPath);
    Mat veloToCamera;
    hconcat(velo.matrix("R", 3, 3), velo.matrix("T", 3, 1), veloToCamera);
    KittiCalibration k = calibrationOf(cam.matrix("P_rect_02", 3, 4), cam.matrix("P_rect_03", 3, 4),
                                       cam.matrix("R_rect_00", 3, 3), veloToCamera);
    if (cam.has("S_rect_02"))   // KITTI's raw files have it; a file without it leaves the size to the frames
    {
        const Mat size = cam.matrix("S_rect_02", 1, 2);
        k.imageSize = Size(cvRound(size.at<double>(0)), cvRound(size.at<double>(1)));
    }
    return k;
}

KittiCalibration readKittiRawDriveCalibration(const String& drive)
{
    std::string d = drive;
    while (d.size() > 1 && (d.back() == '/' || d.back() == '\\'))
        d.pop_back();
    const size_t slash = d.find_last_of("/\\");
    const std::string parent = slash == std::string::npos ? std::string(".") : d.substr(0, slash == 0 ? 1 : slash);
    return readKittiRawCalibration(parent + "/calib_cam_to_cam.txt", parent + "/calib_velo_to_cam.txt");
}

Mat readVelodyneScan(const String& path)
{
    std::ifstream f(path.c_str(), std::ios::binary | std::ios::ate);
    if (!f)
        LIDARSGM_Error(Error::StsObjectNotFound, "cannot open Velodyne scan " + path);
    const std::streamsize bytes = f.tellg();
    if (bytes % 16 != 0)
        LIDARSGM_Error(Error::StsParseError, "Velodyne scan " + path + " is not a whole number of 16-byte points");
    Mat pts((int)(bytes / 16), 4, CV_32F);
    f.seekg(0);
    f.read((char*)pts.data, bytes);
    if (!f)
        LIDARSGM_Error(Error::StsParseError, "cannot read Velodyne scan " + path);
    return pts;
}

Mat readKittiDisparity(const String& path)
{
    Mat raw = readImageFile(path, "KITTI disparity PNG");
    if (raw.type() != CV_16UC1)
        LIDARSGM_Error(Error::StsBadArg, "cannot read KITTI disparity PNG " + path + ": not 16-bit single-channel");
    Mat d;
    raw.convertTo(d, CV_32F, 1.0 / 256);
    d.setTo(-1.f, raw == 0);
    return d;
}

Mat readKittiDepthAsDisparity(const String& path, double focalBaseline)
{
    Mat raw = readImageFile(path, "KITTI depth PNG");
    if (raw.type() != CV_16UC1)
        LIDARSGM_Error(Error::StsBadArg, "cannot read KITTI depth PNG " + path + ": not 16-bit single-channel");
    Mat d(raw.size(), CV_32F);
    for (int y = 0; y < raw.rows; y++)
        for (int x = 0; x < raw.cols; x++)
        {
            const ushort v = raw.at<ushort>(y, x);
            d.at<float>(y, x) = v ? (float)(focalBaseline * 256.0 / v) : -1.f;
        }
    return d;
}

std::vector<String> readKittiFrameIds(const String& dir)
{
    std::ifstream list((dir + "/frames.txt").c_str());
    if (!list)
        LIDARSGM_Error(Error::StsObjectNotFound, "cannot open " + dir + "/frames.txt");
    std::vector<String> ids;
    std::string id;
    while (list >> id)
        ids.push_back(id);
    return ids;
}

namespace {

StereoLidarFrame kittiFrame(const String& dir, const String& id, const KittiCalibration* calibration, int lidarEvery,
                            int firstRing)
{
    StereoLidarFrame f = loadFrame(id, dir + "/image_2/" + id + "_10.png", dir + "/image_3/" + id + "_10.png",
                                   dir + "/velodyne/" + id + ".bin", calibration, dir + "/calib.txt", lidarEvery,
                                   firstRing);
    const String gt = dir + "/disp_occ_0/" + id + "_10.png";
    if (fileExists(gt))
        f.groundTruth = readKittiDisparity(gt);
    return f;
}

} // namespace

StereoLidarFrame loadKittiFrame(const String& dir, const String& id, const KittiCalibration& calibration,
                                int lidarEvery, int firstRing)
{
    return kittiFrame(dir, id, &calibration, lidarEvery, firstRing);
}

StereoLidarFrame loadKittiFrame(const String& dir, const String& id, int lidarEvery, int firstRing)
{
    return kittiFrame(dir, id, nullptr, lidarEvery, firstRing);
}

std::vector<String> readKittiRawFrameNames(const String& drive)
{
    std::vector<String> files;
    glob(drive + "/image_02/data/*.png", files, false);
    std::vector<String> names;
    for (const String& p : files)
    {
        const size_t slash = p.find_last_of("/\\");
        const String file = p.substr(slash == String::npos ? 0 : slash + 1);
        names.push_back(file.substr(0, file.size() - 4));
    }
    std::sort(names.begin(), names.end());
    if (names.empty())
        LIDARSGM_Error(Error::StsObjectNotFound, "KITTI raw drive " + drive + " has no image_02/data/*.png");
    return names;
}

StereoLidarFrame loadKittiRawFrame(const String& drive, const String& name, const KittiCalibration& calibration,
                                   int lidarEvery, int firstRing)
{
    return loadFrame(name, drive + "/image_02/data/" + name + ".png", drive + "/image_03/data/" + name + ".png",
                     drive + "/velodyne_points/data/" + name + ".bin", &calibration, String(), lidarEvery, firstRing);
}

void loadMiddleburyScene(const String& dir, OutputArray left, OutputArray right, OutputArray groundTruth)
{
    struct Layout { const char *l, *r, *gt; double scale; };
    static const Layout layouts[] = { { "im2.png", "im6.png", "disp2.png", 4.0 },
                                      { "view1.png", "view5.png", "disp1.png", 2.0 },
                                      { "im0.png", "im1.png", "disp0.pfm", 1.0 },
                                      { "aloeL.jpg", "aloeR.jpg", "aloeGT.png", 1.0 } };
    for (const Layout& layout : layouts)
    {
        const String g = dir + "/" + layout.gt;
        if (!fileExists(g))
            continue;
        const Mat raw = readImage(g);
        imread(dir + "/" + layout.l, IMREAD_GRAYSCALE).copyTo(left);
        imread(dir + "/" + layout.r, IMREAD_GRAYSCALE).copyTo(right);
        if (left.empty() || right.empty())
            LIDARSGM_Error(Error::StsObjectNotFound, "lidarsgm: cannot read the images " + String(layout.l) + " and " +
                                                         layout.r + " of the Middlebury scene " + dir);
        Mat gt;
        raw.convertTo(gt, CV_32F, 1.0 / layout.scale);
        if (raw.depth() == CV_32F)
            gt.setTo(-1.f, ~(raw < std::numeric_limits<float>::infinity()));   // PFM: inf = unknown
        else
            gt.setTo(-1.f, raw == 0);
        gt.copyTo(groundTruth);
        return;
    }
    LIDARSGM_Error(Error::StsObjectNotFound, "lidarsgm: " + dir + " is not a Middlebury scene (no disp2.png, disp1.png, "
                                             "disp0.pfm or aloeGT.png)");
}

Mat sampleGroundTruth(InputArray groundTruth, double fraction, int64 seed)
{
    const Mat gt = groundTruth.getMat();
    LIDARSGM_Check(gt.type() == CV_32FC1, "lidarsgm: the ground truth must be CV_32FC1");
    RNG rng((uint64)seed);
    Mat sparse(gt.size(), CV_32F, Scalar::all(0));
    for (int y = 0; y < gt.rows; y++)
        for (int x = 0; x < gt.cols; x++)
            if (gt.at<float>(y, x) > 0 && rng.uniform(0.0, 1.0) < fraction)
                sparse.at<float>(y, x) = gt.at<float>(y, x);
    return sparse;
}

Mat encodeKittiDisparity(InputArray disparity)
{
    const Mat d = disparity.getMat();
    LIDARSGM_Check(d.type() == CV_32FC1, "lidarsgm: the disparity must be CV_32FC1 pixels");
    Mat out(d.size(), CV_16UC1);
    for (int y = 0; y < d.rows; y++)
        for (int x = 0; x < d.cols; x++)
            out.at<ushort>(y, x) = detail::kittiEncode(d.at<float>(y, x));   // the projection's encoding
    return out;
}

Mat encodeKittiDepth(InputArray depth_)
{
    const Mat depth = depth_.getMat();
    LIDARSGM_Check(depth.type() == CV_32FC1, "lidarsgm: the depth must be CV_32FC1 metres");
    Mat out(depth.size(), CV_16UC1, Scalar::all(0));
    for (int y = 0; y < depth.rows; y++)
        for (int x = 0; x < depth.cols; x++)
        {
            const double v = std::floor(depth.at<float>(y, x) * 256.0 + 0.5);
            if (v >= 1 && v <= 65535)
                out.at<ushort>(y, x) = (ushort)v;
        }
    return out;
}

void writePfm(const String& path, InputArray disparity)
{
    const Mat src = disparity.getMat();
    LIDARSGM_Check(src.type() == CV_32FC1, "lidarsgm: the disparity must be CV_32FC1 pixels");
    Mat d = src.clone();
    d.setTo(std::numeric_limits<float>::infinity(), src < 0);
    if (!imwrite(path, d))
        LIDARSGM_Error(Error::StsError, "lidarsgm: cannot write " + path);
}

void writePly(const String& path, InputArray points_, InputArray colors)
{
    const Mat points = points_.getMat();
    Mat bgr = colors.getMat();
    LIDARSGM_Check(points.type() == CV_32FC3, "lidarsgm: the points must be CV_32FC3 (disparityToPoints)");
    LIDARSGM_Check(bgr.size() == points.size(), "lidarsgm: the colours must be an image of the points' size");
    if (bgr.depth() == CV_16U)
        bgr.convertTo(bgr, CV_8U, 1.0 / 256);
    if (bgr.channels() == 1)
        cvtColor(bgr, bgr, COLOR_GRAY2BGR);
    else if (bgr.channels() == 4)
        cvtColor(bgr, bgr, COLOR_BGRA2BGR);
    LIDARSGM_Check(bgr.type() == CV_8UC3, "lidarsgm: the colours must be grey or BGR(A), 8 or 16 bits");
    size_t n = 0;
    for (int y = 0; y < points.rows; y++)
        for (int x = 0; x < points.cols; x++)
        {
            const Vec3f& p = points.at<Vec3f>(y, x);
            n += std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
        }
    std::ofstream out(path.c_str(), std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\ncomment lidarsgm: left camera frame, metres\n"
        << "element vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    for (int y = 0; y < points.rows && out; y++)
        for (int x = 0; x < points.cols; x++)
        {
            const Vec3f& p = points.at<Vec3f>(y, x);
            if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
                continue;
            const Vec3b& c = bgr.at<Vec3b>(y, x);
            char rec[15];
            for (int k = 0; k < 3; k++)   // little-endian float32, whatever the host's byte order
            {
                uint32_t bits;
                std::memcpy(&bits, &p[k], 4);
                for (int b = 0; b < 4; b++)
                    rec[4 * k + b] = (char)((bits >> (8 * b)) & 0xFF);
            }
            rec[12] = (char)c[2];
            rec[13] = (char)c[1];
            rec[14] = (char)c[0];
            out.write(rec, sizeof(rec));
        }
    if (!out)
        LIDARSGM_Error(Error::StsError, "lidarsgm: cannot write " + path);
}

}} // namespace cv::lidarsgm
