// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Helpers of the lidarsgm tools and tests: KITTI calibration and Velodyne files, the KITTI devkit's evaluation
// rules (D1 outliers, background interpolation), Middlebury bad-N, and the KITTI colour maps.

#ifndef LIDARSGM_SAMPLES_EVAL_HPP
#define LIDARSGM_SAMPLES_EVAL_HPP

#include "opencv2/core.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace lidarsgm_eval {

//! KITTI-object-style calibration: "NAME: v0 v1 ..." per line.
inline std::map<std::string, std::vector<double> > readCalib(const std::string& path)
{
    std::map<std::string, std::vector<double> > calib;
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
        std::vector<double> v;
        double x;
        while (vals >> x)
            v.push_back(x);
        calib[line.substr(0, colon)] = v;
    }
    return calib;
}

inline cv::Mat calibMatrix(const std::map<std::string, std::vector<double> >& calib, const std::string& name,
                           int rows, int cols)
{
    std::map<std::string, std::vector<double> >::const_iterator it = calib.find(name);
    if (it == calib.end() || (int)it->second.size() != rows * cols)
        CV_Error(cv::Error::StsParseError, "calibration entry " + name + " is missing or has the wrong size");
    return cv::Mat(rows, cols, CV_64F, (void*)it->second.data()).clone();
}

//! The LiDAR-to-rectified-camera transform (R0_rect * Tr_velo_to_cam), P2, and f * baseline = P2[0,3] - P3[0,3].
struct KittiCalib
{
    cv::Mat P2, lidarToCamera;
    double focalBaseline;
};

inline KittiCalib readKittiCalib(const std::string& path)
{
    std::map<std::string, std::vector<double> > c = readCalib(path);
    KittiCalib k;
    k.P2 = calibMatrix(c, "P2", 3, 4);
    cv::Mat P3 = calibMatrix(c, "P3", 3, 4);
    cv::Mat R0 = cv::Mat::eye(4, 4, CV_64F), Tr = cv::Mat::eye(4, 4, CV_64F);
    calibMatrix(c, "R0_rect", 3, 3).copyTo(R0(cv::Rect(0, 0, 3, 3)));
    calibMatrix(c, "Tr_velo_to_cam", 3, 4).copyTo(Tr(cv::Rect(0, 0, 4, 3)));
    k.lidarToCamera = R0 * Tr;
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
    return pts;
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

/** The KITTI devkit's background interpolation, on a float map with d < 0 meaning "missing": in each row, a gap with
valid pixels on both sides takes the smaller of those two values; then each row's first and last valid values are
copied out to its ends; then, column by column, the first and last valid values to the top and bottom. */
inline cv::Mat interpolateBackground(const cv::Mat& disp)
{
    cv::Mat d = disp.clone();
    const int W = d.cols, H = d.rows;
    for (int y = 0; y < H; y++)
    {
        float* r = d.ptr<float>(y);
        int x = 0;
        while (x < W)
        {
            if (r[x] >= 0) { x++; continue; }
            int e = x;
            while (e < W && r[e] < 0)
                e++;
            if (x > 0 && e < W)
            {
                const float v = std::min(r[x - 1], r[e]);
                for (int k = x; k < e; k++)
                    r[k] = v;
            }
            x = e;
        }
        int first = 0;
        while (first < W && r[first] < 0)
            first++;
        if (first == W)
            continue;
        for (int k = 0; k < first; k++)
            r[k] = r[first];
        int last = W - 1;
        while (r[last] < 0)
            last--;
        for (int k = last + 1; k < W; k++)
            r[k] = r[last];
    }
    for (int x = 0; x < W; x++)
    {
        int first = 0;
        while (first < H && d.at<float>(first, x) < 0)
            first++;
        if (first == H)
            continue;
        for (int k = 0; k < first; k++)
            d.at<float>(k, x) = d.at<float>(first, x);
        int last = H - 1;
        while (d.at<float>(last, x) < 0)
            last--;
        for (int k = last + 1; k < H; k++)
            d.at<float>(k, x) = d.at<float>(last, x);
    }
    return d;
}

//! Counts behind coverage, covered error and total error; sums over frames, as the KITTI devkit reports them.
struct ErrorStats
{
    long long gt = 0;        //!< pixels with ground truth
    long long est = 0;       //!< of those, pixels with an estimate
    long long estBad = 0;    //!< of those, outliers
    long long totalBad = 0;  //!< outliers over all ground-truth pixels after background interpolation
    void add(const ErrorStats& o) { gt += o.gt; est += o.est; estBad += o.estBad; totalBad += o.totalBad; }
    double coverage() const { return gt ? 100.0 * est / gt : 0.0; }
    double coveredError() const { return est ? 100.0 * estBad / est : 0.0; }
    double totalError() const { return gt ? 100.0 * totalBad / gt : 0.0; }
};

//! KITTI D1 outlier: |d - gt| > 3 px and > 5 % of gt.
inline bool isD1Outlier(float d, float gt)
{
    const float e = std::abs(d - gt);
    return e > 3.f && e > 0.05f * gt;
}

//! Middlebury bad-N outlier: |d - gt| > N px.
struct BadN
{
    float n;
    bool operator()(float d, float gt) const { return std::abs(d - gt) > n; }
};

/** Scores a float disparity map (d < 0: no estimate) against float ground truth (gt < 0 or non-finite: none).
With total = true, the background-interpolated map is scored as well. */
template <typename Outlier>
inline ErrorStats evaluate(const cv::Mat& est, const cv::Mat& gt, Outlier isOutlier, bool total = true)
{
    CV_Assert(est.type() == CV_32FC1 && gt.type() == CV_32FC1 && est.size() == gt.size());
    ErrorStats s;
    cv::Mat ipol = total ? interpolateBackground(est) : cv::Mat();
    for (int y = 0; y < est.rows; y++)
        for (int x = 0; x < est.cols; x++)
        {
            const float g = gt.at<float>(y, x);
            if (!(g >= 0) || !std::isfinite(g))
                continue;
            s.gt++;
            const float d = est.at<float>(y, x);
            if (d >= 0)
            {
                s.est++;
                if (isOutlier(d, g))
                    s.estBad++;
            }
            if (total)
            {
                // As the devkit: a pixel the interpolation could not fill keeps -1 and is scored as such.
                if (isOutlier(ipol.at<float>(y, x), g))
                    s.totalBad++;
            }
        }
    return s;
}

/** A Middlebury scene folder in one of the layouts of ../shared/data/middlebury (2003: im2/im6 + disp2 / 4;
2005-06 half size: view1/view5 + disp1 / 2; 2014: im0/im1 + disp0.pfm; 2006 full size: aloeL/aloeR + aloeGT).
Images are read as grey; the ground truth as float pixels with -1 for "unknown". False if no layout matches. */
inline bool loadMiddlebury(const std::string& sceneDir, cv::Mat& left, cv::Mat& right, cv::Mat& gt)
{
    struct Layout { const char *l, *r, *gt; double scale; };
    static const Layout layouts[] = { {"im2.png", "im6.png", "disp2.png", 4.0}, {"view1.png", "view5.png", "disp1.png", 2.0},
                                      {"im0.png", "im1.png", "disp0.pfm", 1.0}, {"aloeL.jpg", "aloeR.jpg", "aloeGT.png", 1.0} };
    for (size_t i = 0; i < sizeof(layouts) / sizeof(layouts[0]); i++)
    {
        const std::string g = sceneDir + "/" + layouts[i].gt;
        if (!std::ifstream(g.c_str()).good())
            continue;
        cv::Mat raw = cv::imread(g, cv::IMREAD_UNCHANGED);
        left = cv::imread(sceneDir + "/" + layouts[i].l, cv::IMREAD_GRAYSCALE);
        right = cv::imread(sceneDir + "/" + layouts[i].r, cv::IMREAD_GRAYSCALE);
        if (raw.empty() || left.empty() || right.empty())
            return false;
        raw.convertTo(gt, CV_32F, 1.0 / layouts[i].scale);
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

/** The KITTI devkit's disparity colour map (black-blue-magenta-red-yellow-white ramp over [0, maxDisp]); pixels with
d < 0 are black. */
inline cv::Mat colorizeDisparity(const cv::Mat& disp, float maxDisp)
{
    // Control colours (r, g, b) and the share of the ramp each segment takes.
    static const float ramp[8][4] = { {0, 0, 0, 114}, {0, 0, 1, 185}, {1, 0, 0, 114}, {1, 0, 1, 174},
                                      {0, 1, 0, 114}, {0, 1, 1, 185}, {1, 1, 0, 114}, {1, 1, 1, 0} };
    float total = 0, bounds[8];
    for (int i = 0; i < 7; i++)
        total += ramp[i][3];
    bounds[0] = 0;
    for (int i = 1; i < 8; i++)
        bounds[i] = bounds[i - 1] + ramp[i - 1][3] / total;
    cv::Mat out(disp.size(), CV_8UC3, cv::Scalar::all(0));
    for (int y = 0; y < disp.rows; y++)
        for (int x = 0; x < disp.cols; x++)
        {
            const float d = disp.at<float>(y, x);
            if (!(d >= 0))
                continue;
            const float v = std::min(d / maxDisp, 1.f);
            int i = 0;
            while (i < 6 && v >= bounds[i + 1])
                i++;
            const float w = 1.f - (v - bounds[i]) / (bounds[i + 1] - bounds[i]);
            cv::Vec3b& px = out.at<cv::Vec3b>(y, x);  // BGR
            for (int c = 0; c < 3; c++)
                px[2 - c] = cv::saturate_cast<uchar>((w * ramp[i][c] + (1 - w) * ramp[i + 1][c]) * 255);
        }
    return out;
}

/** LiDAR points over the image: the (grey) image, each sparse disparity (CV_32F pixels, > 0) drawn as a 3x3 dot in
the KITTI disparity colours, nearest points (largest disparity) on top. */
inline cv::Mat overlayPoints(const cv::Mat& image, const cv::Mat& sparse, float maxDisp)
{
    cv::Mat grey8, out;
    if (image.depth() == CV_16U)
        image.convertTo(grey8, CV_8U, 1.0 / 256);
    else
        grey8 = image;
    if (grey8.channels() == 1)
        cv::cvtColor(grey8, out, cv::COLOR_GRAY2BGR);
    else
        out = grey8.clone();
    cv::Mat colours = colorizeDisparity(sparse, maxDisp);
    std::vector<std::pair<float, cv::Point> > pts;
    for (int y = 0; y < sparse.rows; y++)
        for (int x = 0; x < sparse.cols; x++)
            if (sparse.at<float>(y, x) > 0)
                pts.push_back(std::make_pair(sparse.at<float>(y, x), cv::Point(x, y)));
    std::sort(pts.begin(), pts.end(), [](const std::pair<float, cv::Point>& a, const std::pair<float, cv::Point>& b) {
        return a.first < b.first; });
    for (size_t i = 0; i < pts.size(); i++)
    {
        const cv::Point p = pts[i].second;
        const cv::Vec3b c = colours.at<cv::Vec3b>(p);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++)
            {
                const cv::Point q(p.x + dx, p.y + dy);
                if (q.x >= 0 && q.y >= 0 && q.x < out.cols && q.y < out.rows)
                    out.at<cv::Vec3b>(q) = c;
            }
    }
    return out;
}

/** The KITTI devkit's error colour scale: the error relative to the D1 threshold, min(|d - gt| / 3, |d - gt| / gt
/ 0.05), on a log scale from blue (far below) to red (far above 1); black where there is no ground truth. */
inline cv::Mat colorizeError(const cv::Mat& est, const cv::Mat& gt)
{
    static const float scale[10][5] = {
        {0.f, 0.0625f, 49, 54, 149}, {0.0625f, 0.125f, 69, 117, 180}, {0.125f, 0.25f, 116, 173, 209},
        {0.25f, 0.5f, 171, 217, 233}, {0.5f, 1.f, 224, 243, 248}, {1.f, 2.f, 254, 224, 144},
        {2.f, 4.f, 253, 174, 97}, {4.f, 8.f, 244, 109, 67}, {8.f, 16.f, 215, 48, 39}, {16.f, 1e30f, 165, 0, 38} };
    cv::Mat out(est.size(), CV_8UC3, cv::Scalar::all(0));
    for (int y = 0; y < est.rows; y++)
        for (int x = 0; x < est.cols; x++)
        {
            const float g = gt.at<float>(y, x), d = est.at<float>(y, x);
            if (!(g >= 0) || !std::isfinite(g))
                continue;
            const float e = std::abs((d >= 0 ? d : 0.f) - g);
            const float v = std::min(e / 3.f, g > 0 ? e / g / 0.05f : e / 3.f);
            for (int i = 0; i < 10; i++)
                if (v >= scale[i][0] && v < scale[i][1])
                {
                    out.at<cv::Vec3b>(y, x) = cv::Vec3b((uchar)scale[i][4], (uchar)scale[i][3], (uchar)scale[i][2]);
                    break;
                }
        }
    return out;
}

} // namespace lidarsgm_eval

#endif
