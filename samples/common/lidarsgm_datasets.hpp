// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The datasets as the tool, the tests and the perf tests read them: KITTI calibration, Velodyne scans and ground
// truth, one KITTI frame with its scan projected (optionally thinned to fewer laser rings), KITTI raw drives, the
// Middlebury layouts of ../shared/data, the paper's indoor sampling protocol, and the file formats the tool writes
// (disparity, KITTI depth, PLY). Scoring, colour maps, depth and points are the module's public API
// (opencv2/lidarsgm/evaluation.hpp, depth.hpp). Header-only: three executables include it.

#ifndef LIDARSGM_DATASETS_HPP
#define LIDARSGM_DATASETS_HPP

#include "opencv2/lidarsgm.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace lidarsgm_data {

//! The LiDAR-to-rectified-camera transform (R0_rect * Tr_velo_to_cam), P2, and f * baseline = P2[0,3] - P3[0,3].
struct KittiCalib
{
    cv::Mat P2, lidarToCamera;
    double focalBaseline;
};

//! The numeric entries of a KITTI calibration file ("NAME: v0 v1 ..." per line; lines without numbers are kept empty).
class CalibFile
{
public:
    explicit CalibFile(const std::string& path) : path_(path)
    {
        std::ifstream f(path.c_str());
        if (!f)
            CV_Error(cv::Error::StsObjectNotFound, "cannot open calibration file " + path);
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

    //! Entry name as a rows x cols CV_64F matrix; raises cv::Exception naming the file and the key when it is missing.
    cv::Mat matrix(const std::string& name, int rows, int cols) const
    {
        auto it = entries_.find(name);
        if (it == entries_.end())
            CV_Error(cv::Error::StsParseError, "calibration file " + path_ + " has no key " + name);
        if ((int)it->second.size() != rows * cols)
            CV_Error(cv::Error::StsParseError, cv::format("calibration entry %s in %s has %d numbers, expected %d",
                                                          name.c_str(), path_.c_str(), (int)it->second.size(),
                                                          rows * cols));
        return cv::Mat(rows, cols, CV_64F, (void*)it->second.data()).clone();
    }

private:
    std::string path_;
    std::map<std::string, std::vector<double> > entries_;
};

//! [R | t] (3x3, 3x1 or 3x4) as a 4x4 rigid transform.
inline cv::Mat homogeneous(const cv::Mat& R, const cv::Mat& t = cv::Mat())
{
    cv::Mat T = cv::Mat::eye(4, 4, CV_64F);
    R.copyTo(T(cv::Rect(0, 0, R.cols, 3)));
    if (!t.empty())
        t.reshape(1, 3).copyTo(T(cv::Rect(3, 0, 1, 3)));
    return T;
}

//! KITTI-object-style calibration (P2, P3, R0_rect, Tr_velo_to_cam in one file, as in the stereo benchmark).
inline KittiCalib readKittiCalib(const std::string& path)
{
    const CalibFile c(path);
    KittiCalib k;
    k.P2 = c.matrix("P2", 3, 4);
    const cv::Mat P3 = c.matrix("P3", 3, 4);
    k.lidarToCamera = homogeneous(c.matrix("R0_rect", 3, 3)) * homogeneous(c.matrix("Tr_velo_to_cam", 3, 4));
    k.focalBaseline = k.P2.at<double>(0, 3) - P3.at<double>(0, 3);
    return k;
}

/** KITTI raw calibration: calib_cam_to_cam.txt (P_rect_02, P_rect_03, R_rect_00) and calib_velo_to_cam.txt (R, T),
the two files beside a raw drive's folder. The LiDAR-to-rectified-camera transform is R_rect_00 [R | T]. */
inline KittiCalib readKittiRawCalib(const std::string& camToCamPath, const std::string& veloToCamPath)
{
    const CalibFile cam(camToCamPath), velo(veloToCamPath);
    KittiCalib k;
    k.P2 = cam.matrix("P_rect_02", 3, 4);
    const cv::Mat P3 = cam.matrix("P_rect_03", 3, 4);
    k.lidarToCamera = homogeneous(cam.matrix("R_rect_00", 3, 3)) *
                      homogeneous(velo.matrix("R", 3, 3), velo.matrix("T", 3, 1));
    k.focalBaseline = k.P2.at<double>(0, 3) - P3.at<double>(0, 3);
    return k;
}

//! Raw Velodyne scan: float32 x, y, z, reflectance per point.
inline cv::Mat readVelodyne(const std::string& path)
{
    std::ifstream f(path.c_str(), std::ios::binary | std::ios::ate);
    if (!f)
        CV_Error(cv::Error::StsObjectNotFound, "cannot open Velodyne scan " + path);
    const std::streamsize bytes = f.tellg();
    if (bytes % 16 != 0)
        CV_Error(cv::Error::StsParseError, "Velodyne scan " + path + " is not a whole number of 16-byte points");
    cv::Mat pts((int)(bytes / 16), 4, CV_32F);
    f.seekg(0);
    f.read((char*)pts.data, bytes);
    if (!f)
        CV_Error(cv::Error::StsParseError, "cannot read Velodyne scan " + path);
    return pts;
}

/** Thins a Velodyne scan to every keepEvery-th laser ring, counted from the top, starting with ring firstRing (0: the
top ring; the paper's Table VI simulates 32- and 16-line LiDARs from 64-line scans this way, without saying which rings
it keeps). The rings come from the scan's order: the driver writes the scan ring by
ring, each ring sweeping the azimuth once round from straight ahead (KITTI: counter-clockwise from +x), so a new
ring starts where the azimuth, taken in [0, 360), falls back by more than 90 degrees. Rings are then ranked by their
median elevation angle. (Elevation alone does not separate the rings: near points of neighbouring rings overlap in
elevation by up to a degree, as the lasers sit off the sensor's centre.) keepEvery 1 returns the scan unchanged. */
inline cv::Mat selectLidarRings(const cv::Mat& points, int keepEvery, int* ringCount = nullptr, int firstRing = 0)
{
    CV_Assert(points.type() == CV_32FC1 && points.cols >= 3 && keepEvery >= 1 && firstRing >= 0 &&
              firstRing < keepEvery);
    std::vector<int> start(1, 0);
    double prev = 0;
    for (int i = 0; i < points.rows; i++)
    {
        const float* p = points.ptr<float>(i);
        double az = std::atan2((double)p[1], (double)p[0]) * 180.0 / CV_PI;
        if (az < 0)
            az += 360.0;
        if (i > 0 && az < prev - 90.0)
            start.push_back(i);
        prev = az;
    }
    start.push_back(points.rows);
    const int rings = (int)start.size() - 1;
    if (ringCount)
        *ringCount = rings;
    if (keepEvery == 1)
        return points.clone();
    std::vector<std::pair<double, int> > order;   // (-median elevation, ring): top ring first
    for (int r = 0; r < rings; r++)
    {
        std::vector<double> el;
        for (int i = start[r]; i < start[r + 1]; i++)
        {
            const float* p = points.ptr<float>(i);
            el.push_back(std::atan2((double)p[2], std::hypot((double)p[0], (double)p[1])));
        }
        std::nth_element(el.begin(), el.begin() + el.size() / 2, el.end());
        order.push_back(std::make_pair(-el[el.size() / 2], r));
    }
    std::sort(order.begin(), order.end());
    cv::Mat out;
    for (int k = firstRing; k < rings; k += keepEvery)
        out.push_back(points.rowRange(start[order[k].second], start[order[k].second + 1]));
    return out.empty() ? cv::Mat(0, points.cols, CV_32FC1) : out;
}

//! KITTI ground truth (uint16 PNG, value / 256, 0 = none) as float pixels with -1 for "none".
inline cv::Mat readKittiDisparity(const std::string& path)
{
    cv::Mat raw = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (raw.empty() || raw.type() != CV_16UC1)
        CV_Error(cv::Error::StsObjectNotFound, "cannot read KITTI disparity PNG " + path);
    cv::Mat d;
    raw.convertTo(d, CV_32F, 1.0 / 256);
    d.setTo(-1.f, raw == 0);
    return d;
}

/** KITTI depth ground truth (uint16 PNG, metres x 256, 0 = none) as disparity focalBaseline / depth, float pixels
with -1 for "none". */
inline cv::Mat readKittiDepthAsDisparity(const std::string& path, double focalBaseline)
{
    cv::Mat raw = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (raw.empty() || raw.type() != CV_16UC1)
        CV_Error(cv::Error::StsObjectNotFound, "cannot read KITTI depth PNG " + path);
    cv::Mat d(raw.size(), CV_32F);
    for (int y = 0; y < raw.rows; y++)
        for (int x = 0; x < raw.cols; x++)
        {
            const ushort v = raw.at<ushort>(y, x);
            d.at<float>(y, x) = v ? (float)(focalBaseline * 256.0 / v) : -1.f;
        }
    return d;
}

//! An image as stored (grey or colour).
inline cv::Mat readImage(const std::string& path)
{
    cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (img.empty())
        CV_Error(cv::Error::StsObjectNotFound, "cannot read image " + path);
    return img;
}

//! An image as one grey channel, converted with cv::cvtColor.
inline cv::Mat toGrey(const cv::Mat& img)
{
    cv::Mat g;
    if (img.channels() == 3)
        cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
    else if (img.channels() == 4)
        cv::cvtColor(img, g, cv::COLOR_BGRA2GRAY);
    else
        g = img;
    return g;
}

//! An image as one grey channel: decoded as stored, colour converted with cv::cvtColor.
inline cv::Mat readGrey(const std::string& path) { return toGrey(readImage(path)); }

/** A stereo frame with its sparse disparity (CV_32F pixels, 0 = none) and ground truth (float, -1 = none; may be
empty). leftImage is the left image as stored (colour where it is), for coloured outputs; focalBaseline and P2 are
the calibration (KITTI layouts), for depth and points. */
struct Frame
{
    std::string name;
    cv::Mat left, right, sparse, gt, leftImage, P2;
    double focalBaseline = 0;
};

//! The frame's calibration for depth and points: P2 and f * baseline of c.
inline void useCalibration(Frame& f, const KittiCalib& c)
{
    f.P2 = c.P2;
    f.focalBaseline = c.focalBaseline;
}

//! Projects every lidarEvery-th ring of a Velodyne scan from ring firstRing (selectLidarRings) into f.sparse with
//! calibration c (and keeps c for depth and points); f.left must be read.
inline void projectScan(Frame& f, const std::string& scanPath, const KittiCalib& c, int lidarEvery, int firstRing = 0)
{
    const cv::Mat pts = selectLidarRings(readVelodyne(scanPath), lidarEvery, nullptr, firstRing);
    cv::lidarsgm::projectPointsToDisparity(pts, c.P2, c.lidarToCamera, c.focalBaseline, f.left.size(), f.sparse);
    useCalibration(f, c);
}

//! Where one frame's files lie: the left and right images and the raw Velodyne scan.
struct FramePaths
{
    std::string left, right, scan;
};

//! Frame `id` of a KITTI-layout folder: image_2/ID_10.png, image_3/ID_10.png, velodyne/ID.bin.
inline FramePaths kittiFramePaths(const std::string& dir, const std::string& id)
{
    return { dir + "/image_2/" + id + "_10.png", dir + "/image_3/" + id + "_10.png", dir + "/velodyne/" + id + ".bin" };
}

/** Frame `id` of a KITTI-layout folder (image_2/ID_10.png, image_3/ID_10.png, velodyne/ID.bin, calib.txt, optional
disp_occ_0/ID_10.png): the grey pair, the raw scan (every lidarEvery-th ring from ring firstRing, see selectLidarRings)
projected by cv::lidarsgm::projectPointsToDisparity, and the ground truth where it exists. calib, where given,
replaces calib.txt (a refined calibration). */
inline Frame loadKittiFrame(const std::string& dir, const std::string& id, int lidarEvery = 1, int firstRing = 0,
                            const KittiCalib* calib = nullptr)
{
    const FramePaths paths = kittiFramePaths(dir, id);
    Frame f;
    f.name = id;
    f.leftImage = readImage(paths.left);
    f.left = toGrey(f.leftImage);
    f.right = readGrey(paths.right);
    projectScan(f, paths.scan, calib ? *calib : readKittiCalib(dir + "/calib.txt"), lidarEvery, firstRing);
    const std::string gt = dir + "/disp_occ_0/" + id + "_10.png";
    if (std::ifstream(gt.c_str()).good())
        f.gt = readKittiDisparity(gt);
    return f;
}

//! The frame ids of a KITTI-layout folder (DIR/frames.txt, whitespace-separated).
inline std::vector<std::string> kittiFrameIds(const std::string& dir)
{
    std::ifstream list((dir + "/frames.txt").c_str());
    if (!list)
        CV_Error(cv::Error::StsObjectNotFound, "cannot open " + dir + "/frames.txt");
    std::vector<std::string> ids;
    std::string id;
    while (list >> id)
        ids.push_back(id);
    return ids;
}

/** A KITTI raw drive (DRIVE = <date>/<date>_drive_<n>_sync): its frame names, the stems of image_02/data/*.png in
order. Raises cv::Exception when the folder holds no such image. */
inline std::vector<std::string> kittiRawFrameNames(const std::string& drive)
{
    std::vector<cv::String> files;
    cv::glob(drive + "/image_02/data/*.png", files, false);
    std::vector<std::string> names;
    for (const cv::String& p : files)
    {
        const size_t slash = p.find_last_of("/\\");
        const std::string file = p.substr(slash == std::string::npos ? 0 : slash + 1);
        names.push_back(file.substr(0, file.size() - 4));
    }
    std::sort(names.begin(), names.end());
    if (names.empty())
        CV_Error(cv::Error::StsObjectNotFound, "KITTI raw drive " + drive + " has no image_02/data/*.png");
    return names;
}

//! The folder that holds a raw drive's calibration files: the drive folder's parent (<date>/).
inline std::string kittiRawCalibDir(const std::string& drive)
{
    std::string d = drive;
    while (d.size() > 1 && (d.back() == '/' || d.back() == '\\'))
        d.pop_back();
    const size_t slash = d.find_last_of("/\\");
    return slash == std::string::npos ? std::string(".") : d.substr(0, slash == 0 ? 1 : slash);
}

//! Frame `name` of a KITTI raw drive: image_02/data/NAME.png, image_03/data/NAME.png, velodyne_points/data/NAME.bin.
inline FramePaths kittiRawFramePaths(const std::string& drive, const std::string& name)
{
    return { drive + "/image_02/data/" + name + ".png", drive + "/image_03/data/" + name + ".png",
             drive + "/velodyne_points/data/" + name + ".bin" };
}

/** Frame `name` of a KITTI raw drive: image_02/data/NAME.png, image_03/data/NAME.png and velodyne_points/data/NAME.bin,
with the drive's calibration c (readKittiRawCalib); no ground truth. */
inline Frame loadKittiRawFrame(const std::string& drive, const KittiCalib& c, const std::string& name,
                               int lidarEvery = 1, int firstRing = 0)
{
    const FramePaths paths = kittiRawFramePaths(drive, name);
    Frame f;
    f.name = name;
    f.leftImage = readImage(paths.left);
    f.left = toGrey(f.leftImage);
    f.right = readGrey(paths.right);
    if (f.right.size() != f.left.size())
        CV_Error(cv::Error::StsBadSize, "the images of frame " + name + " in " + drive + " differ in size");
    projectScan(f, paths.scan, c, lidarEvery, firstRing);
    return f;
}

/** A Middlebury scene folder in one of the layouts of ../shared/data/middlebury (2003: im2/im6 + disp2 / 4;
2005-06 half size: view1/view5 + disp1 / 2; 2014: im0/im1 + disp0.pfm; 2006 full size: aloeL/aloeR + aloeGT).
Images are read as grey; the ground truth as float pixels with -1 for "unknown". False if no layout matches. */
inline bool loadMiddlebury(const std::string& sceneDir, cv::Mat& left, cv::Mat& right, cv::Mat& gt)
{
    struct Layout { const char *l, *r, *gt; double scale; };
    static const Layout layouts[] = { {"im2.png", "im6.png", "disp2.png", 4.0}, {"view1.png", "view5.png", "disp1.png", 2.0},
                                      {"im0.png", "im1.png", "disp0.pfm", 1.0}, {"aloeL.jpg", "aloeR.jpg", "aloeGT.png", 1.0} };
    for (const Layout& layout : layouts)
    {
        const std::string g = sceneDir + "/" + layout.gt;
        if (!std::ifstream(g.c_str()).good())
            continue;
        cv::Mat raw = cv::imread(g, cv::IMREAD_UNCHANGED);
        left = cv::imread(sceneDir + "/" + layout.l, cv::IMREAD_GRAYSCALE);
        right = cv::imread(sceneDir + "/" + layout.r, cv::IMREAD_GRAYSCALE);
        if (raw.empty() || left.empty() || right.empty())
            return false;
        raw.convertTo(gt, CV_32F, 1.0 / layout.scale);
        if (raw.depth() == CV_32F)
            gt.setTo(-1.f, ~(raw < std::numeric_limits<float>::infinity()));  // PFM: inf = unknown
        else
            gt.setTo(-1.f, raw == 0);
        return true;
    }
    return false;
}

//! The paper's indoor protocol: a fraction of the ground-truth pixels drawn with a fixed seed, as CV_32F (0 = none).
inline cv::Mat sampleGroundTruth(const cv::Mat& gt, double fraction, uint64 seed)
{
    cv::RNG rng(seed);
    cv::Mat sparse(gt.size(), CV_32F, cv::Scalar::all(0));
    for (int y = 0; y < gt.rows; y++)
        for (int x = 0; x < gt.cols; x++)
            if (gt.at<float>(y, x) > 0 && rng.uniform(0.0, 1.0) < fraction)
                sparse.at<float>(y, x) = gt.at<float>(y, x);
    return sparse;
}

//! A matcher's CV_16S (x16) output as float pixels with -1 for "invalid".
inline cv::Mat disparityToFloat(const cv::Mat& disp16, int minDisparity)
{
    cv::Mat d;
    disp16.convertTo(d, CV_32F, 1.0 / 16);
    d.setTo(-1.f, disp16 <= (minDisparity - 1) * 16);
    return d;
}

//! KITTI 16-bit PNG encoding: round(d * 256), 0 = invalid (d <= 0 cannot be stored).
inline cv::Mat toKittiPng(const cv::Mat& dispFloat)
{
    cv::Mat out(dispFloat.size(), CV_16UC1, cv::Scalar::all(0));
    for (int y = 0; y < dispFloat.rows; y++)
        for (int x = 0; x < dispFloat.cols; x++)
        {
            const float d = dispFloat.at<float>(y, x);
            if (d > 0)
                out.at<ushort>(y, x) = cv::saturate_cast<ushort>(std::max(1.0, std::floor(d * 256.0 + 0.5)));
        }
    return out;
}

//! A float disparity map (-1 = invalid) as PFM, invalid pixels written as +inf (the Middlebury convention).
inline bool writePfm(const std::string& path, const cv::Mat& dispFloat)
{
    cv::Mat d = dispFloat.clone();
    d.setTo(std::numeric_limits<float>::infinity(), dispFloat < 0);
    return cv::imwrite(path, d);
}

//! A CV_16S matcher output as raw little-endian int16, rows top to bottom, no header (numpy.fromfile(p, '<i2')).
inline bool writeRawS16(const std::string& path, const cv::Mat& disp16)
{
    CV_Assert(disp16.type() == CV_16SC1);
    std::ofstream out(path.c_str(), std::ios::binary);
    for (int y = 0; y < disp16.rows && out; y++)
        out.write(disp16.ptr<char>(y), (std::streamsize)disp16.cols * 2);
    return (bool)out;
}

/** Depth in the KITTI depth-completion encoding: uint16, round(metres x 256), 0 = none. A depth that does not fit
(beyond 65535 / 256 = 256 m) is written as none rather than clamped to a wrong value. */
inline cv::Mat toKittiDepthPng(const cv::Mat& depth)
{
    CV_Assert(depth.type() == CV_32FC1);
    cv::Mat out(depth.size(), CV_16UC1, cv::Scalar::all(0));
    for (int y = 0; y < depth.rows; y++)
        for (int x = 0; x < depth.cols; x++)
        {
            const double v = std::floor(depth.at<float>(y, x) * 256.0 + 0.5);
            if (v >= 1 && v <= 65535)
                out.at<ushort>(y, x) = (ushort)v;
        }
    return out;
}

/** A point cloud as binary little-endian PLY: one vertex (float x, y, z; uchar red, green, blue) per pixel whose point
is finite, in row order. points: CV_32FC3 (disparityToPoints); image: the colours, grey or BGR, 8 or 16 bits. */
inline bool writePly(const std::string& path, const cv::Mat& points, const cv::Mat& image)
{
    CV_Assert(points.type() == CV_32FC3 && image.size() == points.size());
    cv::Mat bgr = image;
    if (bgr.depth() == CV_16U)
        bgr.convertTo(bgr, CV_8U, 1.0 / 256);
    if (bgr.channels() == 1)
        cv::cvtColor(bgr, bgr, cv::COLOR_GRAY2BGR);
    else if (bgr.channels() == 4)
        cv::cvtColor(bgr, bgr, cv::COLOR_BGRA2BGR);
    CV_Assert(bgr.type() == CV_8UC3);
    size_t n = 0;
    for (int y = 0; y < points.rows; y++)
        for (int x = 0; x < points.cols; x++)
        {
            const cv::Vec3f& p = points.at<cv::Vec3f>(y, x);
            n += std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
        }
    std::ofstream out(path.c_str(), std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\ncomment lidarsgm: left camera frame, metres\n"
        << "element vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    for (int y = 0; y < points.rows && out; y++)
        for (int x = 0; x < points.cols; x++)
        {
            const cv::Vec3f& p = points.at<cv::Vec3f>(y, x);
            if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
                continue;
            const cv::Vec3b& c = bgr.at<cv::Vec3b>(y, x);
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
    return (bool)out;
}

/** LiDAR points over the image: the (grey) image, each sparse disparity (CV_32F pixels, > 0) drawn as a 3x3 dot in
the KITTI disparity colours, nearest points (largest disparity) on top. */
inline cv::Mat overlayPoints(const cv::Mat& image, const cv::Mat& sparse, float maxDisp)
{
    cv::Mat grey8, out, colours;
    if (image.depth() == CV_16U)
        image.convertTo(grey8, CV_8U, 1.0 / 256);
    else
        grey8 = image;
    if (grey8.channels() == 1)
        cv::cvtColor(grey8, out, cv::COLOR_GRAY2BGR);
    else
        out = grey8.clone();
    cv::lidarsgm::colorizeDisparity(sparse, colours, maxDisp);
    std::vector<std::pair<float, cv::Point> > pts;
    for (int y = 0; y < sparse.rows; y++)
        for (int x = 0; x < sparse.cols; x++)
            if (sparse.at<float>(y, x) > 0)
                pts.push_back(std::make_pair(sparse.at<float>(y, x), cv::Point(x, y)));
    std::sort(pts.begin(), pts.end(), [](const std::pair<float, cv::Point>& a, const std::pair<float, cv::Point>& b) {
        return a.first < b.first; });
    for (const auto& p : pts)
    {
        const cv::Vec3b c = colours.at<cv::Vec3b>(p.second);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++)
            {
                const cv::Point q(p.second.x + dx, p.second.y + dy);
                if (q.x >= 0 && q.y >= 0 && q.x < out.cols && q.y < out.rows)
                    out.at<cv::Vec3b>(q) = c;
            }
    }
    return out;
}

} // namespace lidarsgm_data

#endif
