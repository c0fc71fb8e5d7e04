// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Disparity to metric depth and 3D points, with the x16 scale of the CV_16S output and the invalid value handled
// here once, so that users need not remember either.

#include "precomp.hpp"
#include "opencv2/lidarsgm/depth.hpp"
#include <limits>

namespace cv { namespace lidarsgm {

namespace {

//! The disparity in pixels, or a negative value where it is invalid (below minD, not positive, not finite).
struct DisparityReader
{
    Mat m;
    int minD;

    DisparityReader(InputArray d, int minDisparity, const char* fn) : m(d.getMat()), minD(minDisparity)
    {
        if (m.empty())
            LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm::%s: the disparity map is empty", fn));
        if (m.type() != CV_16SC1 && m.type() != CV_32FC1)
            LIDARSGM_Error_(Error::StsUnsupportedFormat,
                            ("lidarsgm::%s: the disparity map must be CV_16SC1 (x16) or CV_32FC1 (pixels), got %s", fn,
                             typeToString(m.type()).c_str()));
    }

    double at(int y, int x) const
    {
        const double d = m.type() == CV_16SC1 ? m.at<short>(y, x) / 16.0 : (double)m.at<float>(y, x);
        return std::isfinite(d) && d >= minD && d > 0 ? d : -1.0;
    }
};

void checkFocalBaseline(double fb, const char* fn)
{
    if (!(fb > 0) || !std::isfinite(fb))
        LIDARSGM_Error_(Error::StsOutOfRange, ("lidarsgm::%s: focalBaseline must be positive and finite, got %g", fn, fb));
}

} // namespace

void disparityToDepth(InputArray disparity, double focalBaseline, OutputArray _depth, int minDisparity,
                      float invalidDepth)
{
    CV_INSTRUMENT_REGION();
    checkFocalBaseline(focalBaseline, "disparityToDepth");
    const DisparityReader disp(disparity, minDisparity, "disparityToDepth");
    _depth.create(disp.m.size(), CV_32FC1);
    Mat depth = _depth.getMat();
    parallel_for_(Range(0, depth.rows), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            float* o = depth.ptr<float>(y);
            for (int x = 0; x < depth.cols; x++)
            {
                const double d = disp.at(y, x);
                o[x] = d > 0 ? (float)(focalBaseline / d) : invalidDepth;
            }
        }
    });
}

namespace {

//! Q as 4x4 doubles, checked: what disparityToPoints and disparityToColoredPoints take.
Matx44d reprojection(InputArray _Q, const char* fn)
{
    Mat q = _Q.getMat();
    if (q.rows != 4 || q.cols != 4 || q.channels() != 1 || (q.depth() != CV_32F && q.depth() != CV_64F))
        LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm::%s: Q must be a 4x4 CV_32F or CV_64F matrix", fn));
    Matx44d Q;
    q.convertTo(Mat(4, 4, CV_64F, Q.val), CV_64F);
    for (int i = 0; i < 16; i++)
        if (!std::isfinite(Q.val[i]))
            LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm::%s: Q has a NaN or infinite entry", fn));
    return Q;
}

//! The point of pixel (x, y): Q [x y d 1]^T over its fourth component; NaN where d is invalid or that is not positive.
//! One division a point, not three: the points are compute-bound, and the reciprocal's rounding (in double) stays far
//! below float's.
inline Vec3f pointAt(const Matx44d& Q, const DisparityReader& disp, int x, int y)
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const double d = disp.at(y, x);
    const Vec4d h = d > 0 ? Q * Vec4d(x, y, d, 1.0) : Vec4d(0, 0, 0, 0);
    if (!(h[3] > 0))
        return Vec3f(nan, nan, nan);
    const double w = 1.0 / h[3];
    return Vec3f((float)(h[0] * w), (float)(h[1] * w), (float)(h[2] * w));
}

} // namespace

void disparityToPoints(InputArray disparity, InputArray _Q, OutputArray _points, int minDisparity)
{
    CV_INSTRUMENT_REGION();
    const DisparityReader disp(disparity, minDisparity, "disparityToPoints");
    const Matx44d Q = reprojection(_Q, "disparityToPoints");
    _points.create(disp.m.size(), CV_32FC3);
    Mat points = _points.getMat();
    parallel_for_(Range(0, points.rows), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            Vec3f* o = points.ptr<Vec3f>(y);
            for (int x = 0; x < points.cols; x++)
                o[x] = pointAt(Q, disp, x, y);
        }
    });
}

void disparityToColoredPoints(InputArray disparity, InputArray _Q, InputArray _image, OutputArray _cloud,
                              int minDisparity)
{
    CV_INSTRUMENT_REGION();
    const DisparityReader disp(disparity, minDisparity, "disparityToColoredPoints");
    const Matx44d Q = reprojection(_Q, "disparityToColoredPoints");
    const Mat image = _image.getMat();
    if (image.type() != CV_8UC3 && image.type() != CV_8UC1)
        LIDARSGM_Error_(Error::StsUnsupportedFormat,
                        ("lidarsgm::disparityToColoredPoints: the image must be CV_8UC3 (BGR) or CV_8UC1, got %s",
                         image.empty() ? "an empty one" : typeToString(image.type()).c_str()));
    if (image.size() != disp.m.size())
        LIDARSGM_Error_(Error::StsUnmatchedSizes,
                        ("lidarsgm::disparityToColoredPoints: the image is %dx%d, the disparity map %dx%d",
                         image.cols, image.rows, disp.m.cols, disp.m.rows));
    _cloud.create(disp.m.size(), CV_32FC4);
    Mat cloud = _cloud.getMat();
    const bool bgr = image.channels() == 3;
    parallel_for_(Range(0, cloud.rows), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            Vec4f* o = cloud.ptr<Vec4f>(y);
            const uchar* c = image.ptr<uchar>(y);
            for (int x = 0; x < cloud.cols; x++)
            {
                const Vec3f p = pointAt(Q, disp, x, y);
                const uint32_t b = bgr ? c[3 * x] : c[x], g = bgr ? c[3 * x + 1] : c[x], rr = bgr ? c[3 * x + 2] : c[x];
                Cv32suf rgb;
                rgb.u = (rr << 16) | (g << 8) | b;  // PCL's packed rgb: the float whose bits are 0x00RRGGBB
                o[x] = Vec4f(p[0], p[1], p[2], rgb.f);
            }
        }
    });
}

Mat reprojectionMatrix(InputArray projection, double focalBaseline)
{
    checkFocalBaseline(focalBaseline, "reprojectionMatrix");
    Mat p = projection.getMat();
    if (p.rows != 3 || (p.cols != 3 && p.cols != 4) || p.channels() != 1 ||
        (p.depth() != CV_32F && p.depth() != CV_64F))
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm::reprojectionMatrix: projection must be a 3x3 or 3x4 CV_32F or CV_64F "
                                         "matrix");
    Mat pd;
    p.convertTo(pd, CV_64F);
    const double f = pd.at<double>(0, 0), cx = pd.at<double>(0, 2), cy = pd.at<double>(1, 2);
    if (!(f > 0) || !std::isfinite(f) || !std::isfinite(cx) || !std::isfinite(cy))
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm::reprojectionMatrix: the projection's focal length must be positive and "
                                         "its principal point finite");
    Mat Q = (Mat_<double>(4, 4) << 1, 0, 0, -cx,
                                   0, 1, 0, -cy,
                                   0, 0, 0, f,
                                   0, 0, f / focalBaseline, 0);
    return Q;
}

}} // namespace cv::lidarsgm
