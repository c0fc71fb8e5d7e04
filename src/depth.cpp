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

void disparityToDepth(InputArray disparity, double focalBaseline, OutputArray _depth, int minDisparity)
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
                o[x] = d > 0 ? (float)(focalBaseline / d) : 0.f;
            }
        }
    });
}

void disparityToPoints(InputArray disparity, InputArray _Q, OutputArray _points, int minDisparity)
{
    CV_INSTRUMENT_REGION();
    const DisparityReader disp(disparity, minDisparity, "disparityToPoints");
    Mat q = _Q.getMat();
    if (q.rows != 4 || q.cols != 4 || q.channels() != 1 || (q.depth() != CV_32F && q.depth() != CV_64F))
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm::disparityToPoints: Q must be a 4x4 CV_32F or CV_64F matrix");
    Matx44d Q;
    q.convertTo(Mat(4, 4, CV_64F, Q.val), CV_64F);
    for (int i = 0; i < 16; i++)
        if (!std::isfinite(Q.val[i]))
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm::disparityToPoints: Q has a NaN or infinite entry");
    _points.create(disp.m.size(), CV_32FC3);
    Mat points = _points.getMat();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    parallel_for_(Range(0, points.rows), [&](const Range& r) {
        for (int y = r.start; y < r.end; y++)
        {
            Vec3f* o = points.ptr<Vec3f>(y);
            for (int x = 0; x < points.cols; x++)
            {
                const double d = disp.at(y, x);
                const Vec4d h = d > 0 ? Q * Vec4d(x, y, d, 1.0) : Vec4d(0, 0, 0, 0);
                o[x] = h[3] > 0 ? Vec3f((float)(h[0] / h[3]), (float)(h[1] / h[3]), (float)(h[2] / h[3]))
                                : Vec3f(nan, nan, nan);
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
