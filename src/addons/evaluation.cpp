// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The KITTI stereo devkit's evaluation rules (D1 outliers, background interpolation, colour maps) and Middlebury's
// bad-N, as public functions: the tool, the tests, the perf tests and the Python sample score with this one copy.

#include "../precomp.hpp"
#include "opencv2/lidarsgm/evaluation.hpp"
#include "error_bands.hpp"
#include "opencv2/imgproc.hpp"

namespace cv { namespace lidarsgm {

void DisparityErrors::add(const DisparityErrors& o)
{
    groundTruthPixels += o.groundTruthPixels;
    estimatedPixels += o.estimatedPixels;
    estimatedOutliers += o.estimatedOutliers;
    totalOutliers += o.totalOutliers;
}

double DisparityErrors::coverage() const
{
    return groundTruthPixels ? 100.0 * estimatedPixels / groundTruthPixels : 0.0;
}

double DisparityErrors::coveredError() const
{
    return estimatedPixels ? 100.0 * estimatedOutliers / estimatedPixels : 0.0;
}

double DisparityErrors::totalError() const
{
    return groundTruthPixels ? 100.0 * totalOutliers / groundTruthPixels : 0.0;
}

namespace {

//! An estimate as float pixels with -1 for "none" (the devkit's convention: disparities are non-negative).
Mat estimateToFloat(InputArray _disp, int minDisparity)
{
    const Mat disp = _disp.getMat();
    LIDARSGM_Check(disp.type() == CV_32FC1 || disp.type() == CV_16SC1,
                   "lidarsgm: the disparity to evaluate must be CV_32FC1 (pixels) or CV_16SC1 (x16)");
    Mat d;
    disp.convertTo(d, CV_32F, disp.type() == CV_16SC1 ? 1.0 / 16 : 1.0);
    const float lo = (float)std::max(minDisparity, 0);
    for (int y = 0; y < d.rows; y++)
    {
        float* r = d.ptr<float>(y);
        for (int x = 0; x < d.cols; x++)
            if (!(r[x] >= lo) || !std::isfinite(r[x]))
                r[x] = -1.f;
    }
    return d;
}

//! Ground truth as float pixels with -1 for "none".
Mat groundTruthToFloat(InputArray _gt)
{
    const Mat gt = _gt.getMat();
    LIDARSGM_Check(gt.type() == CV_32FC1 || gt.type() == CV_16UC1,
                   "lidarsgm: the ground truth must be CV_32FC1 (pixels) or CV_16UC1 (KITTI, value / 256)");
    Mat g;
    gt.convertTo(g, CV_32F, gt.type() == CV_16UC1 ? 1.0 / 256 : 1.0);
    for (int y = 0; y < g.rows; y++)
    {
        float* r = g.ptr<float>(y);
        const ushort* raw = gt.type() == CV_16UC1 ? gt.ptr<ushort>(y) : nullptr;
        for (int x = 0; x < g.cols; x++)
            if ((raw && raw[x] == 0) || !(r[x] >= 0) || !std::isfinite(r[x]))
                r[x] = -1.f;
    }
    return g;
}

bool isOutlier(float d, float gt, int metric, float bad)
{
    const float e = std::abs(d - gt);
    return metric == METRIC_KITTI_D1 ? (e > 3.f && e > 0.05f * gt) : e > bad;
}

} // namespace

enum { CONFIDENCE_LEVELS = 65536 };

void ConfidenceErrors::add(const ConfidenceErrors& o)
{
    if (o.pixels.empty())
        return;
    if (pixels.empty())
    {
        pixels.assign(CONFIDENCE_LEVELS, 0.0);
        outliers.assign(CONFIDENCE_LEVELS, 0.0);
    }
    LIDARSGM_Check(o.pixels.size() == pixels.size(), "lidarsgm: ConfidenceErrors of another layout");
    LIDARSGM_Check(o.outliers.size() == outliers.size(), "lidarsgm: ConfidenceErrors of another layout");
    for (size_t i = 0; i < pixels.size(); i++)
    {
        pixels[i] += o.pixels[i];
        outliers[i] += o.outliers[i];
    }
}

double ConfidenceErrors::total() const
{
    double n = 0;
    for (double v : pixels)
        n += v;
    return n;
}

double ConfidenceErrors::totalOutliers() const
{
    double n = 0;
    for (double v : outliers)
        n += v;
    return n;
}

namespace {

//! The outliers among the k most confident pixels: whole levels from the top, the last one in proportion.
double outliersKept(const ConfidenceErrors& c, double k)
{
    double n = 0, e = 0;
    for (size_t i = c.pixels.size(); i-- > 0 && n < k;)
    {
        const double take = std::min(c.pixels[i], k - n);
        if (take > 0)
            e += c.outliers[i] * take / c.pixels[i];
        n += take;
    }
    return e;
}

} // namespace

double ConfidenceErrors::leastConfidentShare(double fraction) const
{
    const double n = total(), e = totalOutliers();
    return e > 0 ? 100.0 * (e - outliersKept(*this, (1.0 - fraction) * n)) / e : 0.0;
}

double ConfidenceErrors::keptError(double fraction) const
{
    const double k = fraction * total();
    return k > 0 ? 100.0 * outliersKept(*this, k) / k : 0.0;
}

double ConfidenceErrors::auc() const
{
    // keptError at 1000 fractions, trapezoids from the first one (the curve is flat below it).
    const int steps = 1000;
    double a = 0, prev = keptError(1.0 / steps) / 100;
    a += prev / steps;
    for (int i = 2; i <= steps; i++)
    {
        const double v = keptError((double)i / steps) / 100;
        a += 0.5 * (prev + v) / steps;
        prev = v;
    }
    return a;
}

double ConfidenceErrors::oracleAuc() const
{
    const double n = total(), e = n > 0 ? totalOutliers() / n : 0.0;
    return e >= 1 ? 1.0 : e + (1 - e) * std::log(1 - e);
}

ConfidenceErrors evaluateConfidence(InputArray disparity, InputArray confidence, InputArray groundTruth, int metric,
                                    double badThreshold, int minDisparity)
{
    LIDARSGM_Check(metric == METRIC_KITTI_D1 || metric == METRIC_BAD,
                   "lidarsgm: metric must be METRIC_KITTI_D1 or METRIC_BAD");
    LIDARSGM_Check(disparity.size() == groundTruth.size(),
                   "lidarsgm: the disparity and the ground truth differ in size");
    LIDARSGM_Check(confidence.type() == CV_32FC1, "lidarsgm: the confidence must be CV_32FC1");
    LIDARSGM_Check(confidence.size() == disparity.size(), "lidarsgm: the confidence and the disparity differ in size");
    const Mat est = estimateToFloat(disparity, minDisparity), gt = groundTruthToFloat(groundTruth);
    const Mat conf = confidence.getMat();
    const float bad = (float)badThreshold;
    ConfidenceErrors c;
    c.pixels.assign(CONFIDENCE_LEVELS, 0.0);
    c.outliers.assign(CONFIDENCE_LEVELS, 0.0);
    for (int y = 0; y < est.rows; y++)
    {
        const float* g = gt.ptr<float>(y);
        const float* d = est.ptr<float>(y);
        const float* q = conf.ptr<float>(y);
        for (int x = 0; x < est.cols; x++)
        {
            if (g[x] < 0 || d[x] < 0)
                continue;
            const int level = cvRound(std::min(1.f, std::max(0.f, q[x])) * (CONFIDENCE_LEVELS - 1));
            c.pixels[level]++;
            c.outliers[level] += isOutlier(d[x], g[x], metric, bad);
        }
    }
    return c;
}

void interpolateBackground(InputArray _disp, OutputArray _filled)
{
    LIDARSGM_Check(_disp.type() == CV_32FC1, "lidarsgm: interpolateBackground takes CV_32FC1 pixels");
    _disp.copyTo(_filled);
    Mat d = _filled.getMat();
    const int W = d.cols, H = d.rows;
    for (int y = 0; y < H; y++)
    {
        float* r = d.ptr<float>(y);
        int x = 0;
        while (x < W)
        {
            if (r[x] >= 0) { x++; continue; }
            int e = x;
            while (e < W && !(r[e] >= 0))
                e++;
            if (x > 0 && e < W)
                std::fill(r + x, r + e, std::min(r[x - 1], r[e]));
            x = e;
        }
        int first = 0;
        while (first < W && !(r[first] >= 0))
            first++;
        if (first == W)
            continue;
        std::fill(r, r + first, r[first]);
        int last = W - 1;
        while (!(r[last] >= 0))
            last--;
        std::fill(r + last + 1, r + W, r[last]);
    }
    for (int x = 0; x < W; x++)
    {
        int first = 0;
        while (first < H && !(d.at<float>(first, x) >= 0))
            first++;
        if (first == H)
            continue;
        for (int k = 0; k < first; k++)
            d.at<float>(k, x) = d.at<float>(first, x);
        int last = H - 1;
        while (!(d.at<float>(last, x) >= 0))
            last--;
        for (int k = last + 1; k < H; k++)
            d.at<float>(k, x) = d.at<float>(last, x);
    }
}

DisparityErrors evaluateDisparity(InputArray disparity, InputArray groundTruth, int metric, double badThreshold,
                                  int minDisparity)
{
    LIDARSGM_Check(metric == METRIC_KITTI_D1 || metric == METRIC_BAD,
                   "lidarsgm: metric must be METRIC_KITTI_D1 or METRIC_BAD");
    LIDARSGM_Check(disparity.size() == groundTruth.size(),
                   "lidarsgm: the disparity and the ground truth differ in size");
    const Mat est = estimateToFloat(disparity, minDisparity), gt = groundTruthToFloat(groundTruth);
    Mat ipol;
    interpolateBackground(est, ipol);
    const float bad = (float)badThreshold;
    DisparityErrors s;
    for (int y = 0; y < est.rows; y++)
    {
        const float* g = gt.ptr<float>(y);
        const float* d = est.ptr<float>(y);
        const float* f = ipol.ptr<float>(y);
        for (int x = 0; x < est.cols; x++)
        {
            if (g[x] < 0)
                continue;
            s.groundTruthPixels++;
            if (d[x] >= 0)
            {
                s.estimatedPixels++;
                s.estimatedOutliers += isOutlier(d[x], g[x], metric, bad);
            }
            // As the devkit: a pixel the interpolation could not fill keeps -1 and is scored as such.
            s.totalOutliers += isOutlier(f[x], g[x], metric, bad);
        }
    }
    return s;
}

void colorizeDisparity(InputArray _disp, OutputArray _color, double maxDisparity)
{
    LIDARSGM_Check(_disp.type() == CV_32FC1, "lidarsgm: colorizeDisparity takes CV_32FC1 pixels");
    LIDARSGM_Check(maxDisparity > 0, "lidarsgm: colorizeDisparity: maxDisparity must be > 0");
    // The devkit's control colours (r, g, b) and the share of the ramp each segment takes.
    static const float ramp[8][4] = { {0, 0, 0, 114}, {0, 0, 1, 185}, {1, 0, 0, 114}, {1, 0, 1, 174},
                                      {0, 1, 0, 114}, {0, 1, 1, 185}, {1, 1, 0, 114}, {1, 1, 1, 0} };
    float total = 0, bounds[8];
    for (int i = 0; i < 7; i++)
        total += ramp[i][3];
    bounds[0] = 0;
    for (int i = 1; i < 8; i++)
        bounds[i] = bounds[i - 1] + ramp[i - 1][3] / total;
    const Mat disp = _disp.getMat();
    _color.create(disp.size(), CV_8UC3);
    Mat out = _color.getMat();
    out.setTo(Scalar::all(0));
    const float maxD = (float)maxDisparity;
    for (int y = 0; y < disp.rows; y++)
        for (int x = 0; x < disp.cols; x++)
        {
            const float d = disp.at<float>(y, x);
            if (!(d >= 0) || !std::isfinite(d))
                continue;
            const float v = std::min(d / maxD, 1.f);
            int i = 0;
            while (i < 6 && v >= bounds[i + 1])
                i++;
            const float w = 1.f - (v - bounds[i]) / (bounds[i + 1] - bounds[i]);
            Vec3b& px = out.at<Vec3b>(y, x);  // BGR
            for (int c = 0; c < 3; c++)
                px[2 - c] = saturate_cast<uchar>((w * ramp[i][c] + (1 - w) * ramp[i + 1][c]) * 255);
        }
}

void colorizeDisparityError(InputArray _disp, InputArray _gt, OutputArray _color)
{
    LIDARSGM_Check(_disp.type() == CV_32FC1 && _gt.type() == CV_32FC1 && _disp.size() == _gt.size(),
                   "lidarsgm: colorizeDisparityError takes two CV_32FC1 maps of one size");
    const Mat est = _disp.getMat(), gt = _gt.getMat();
    _color.create(est.size(), CV_8UC3);
    Mat out = _color.getMat();
    out.setTo(Scalar::all(0));
    for (int y = 0; y < est.rows; y++)
        for (int x = 0; x < est.cols; x++)
        {
            const float g = gt.at<float>(y, x), d = est.at<float>(y, x);
            if (!(g >= 0) || !std::isfinite(g))
                continue;
            const float e = std::abs((d >= 0 ? d : 0.f) - g);
            const float v = std::min(e / 3.f, g > 0 ? e / g / 0.05f : e / 3.f);
            for (const detail::ErrorBand& band : detail::ERROR_BANDS)
                if (v >= band.lo && v < band.hi)
                {
                    out.at<Vec3b>(y, x) = Vec3b(band.b, band.g, band.r);
                    break;
                }
        }
}

void drawSparseDisparity(InputArray image_, InputArray sparse_, OutputArray dst, double maxDisparity)
{
    const Mat image = image_.getMat(), sparse = sparse_.getMat();
    LIDARSGM_Check(sparse.type() == CV_32FC1, "lidarsgm: the sparse disparities must be CV_32FC1 pixels");
    LIDARSGM_Check(sparse.size() == image.size(), "lidarsgm: the sparse map must have the image's size");
    Mat grey8, out, colours;
    if (image.depth() == CV_16U)
        image.convertTo(grey8, CV_8U, 1.0 / 256);
    else
        grey8 = image;
    LIDARSGM_Check(grey8.depth() == CV_8U, "lidarsgm: the image must have 8 or 16 bits");
    if (grey8.channels() == 1)
        cvtColor(grey8, out, COLOR_GRAY2BGR);
    else if (grey8.channels() == 4)
        cvtColor(grey8, out, COLOR_BGRA2BGR);
    else
        out = grey8.clone();
    colorizeDisparity(sparse, colours, maxDisparity);
    std::vector<std::pair<float, Point> > pts;
    for (int y = 0; y < sparse.rows; y++)
        for (int x = 0; x < sparse.cols; x++)
            if (sparse.at<float>(y, x) > 0)
                pts.push_back(std::make_pair(sparse.at<float>(y, x), Point(x, y)));
    // Nearest last, so on top; equal disparities in raster order.
    std::stable_sort(pts.begin(), pts.end(), [](const std::pair<float, Point>& a, const std::pair<float, Point>& b) {
        return a.first < b.first; });
    for (const auto& p : pts)
    {
        const Vec3b c = colours.at<Vec3b>(p.second);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++)
            {
                const Point q(p.second.x + dx, p.second.y + dy);
                if (q.x >= 0 && q.y >= 0 && q.x < out.cols && q.y < out.rows)
                    out.at<Vec3b>(q) = c;
            }
    }
    out.copyTo(dst);
}

}} // namespace cv::lidarsgm
