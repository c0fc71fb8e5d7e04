// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// LiDAR point cloud to sparse disparity map of the reference camera.

#include "precomp.hpp"
#include "pipeline.hpp"
#include "projection.hpp"

namespace cv { namespace lidarsgm {

namespace detail {

Matx34d toMatx34(InputArray m, const char* name)
{
    // Python's cv2.cuda entry points take every array as a GpuMat (the binding generator's rule), the small matrices
    // too: those are read back here.
    Mat a;
    if (m.kind() == _InputArray::CUDA_GPU_MAT)
        m.getGpuMat().download(a);
    else
        a = m.getMat();
    if (a.channels() != 1 || (a.depth() != CV_32F && a.depth() != CV_64F))
        LIDARSGM_Error_(Error::StsUnsupportedFormat, ("lidarsgm: %s must be a single-channel CV_32F or CV_64F matrix", name));
    Mat d;
    a.convertTo(d, CV_64F);
    Matx34d r;
    if (d.rows == 3 && d.cols == 4)
        r = Matx34d(d.ptr<double>());
    else if (d.rows == 4 && d.cols == 4)
    {
        const double* last = d.ptr<double>(3);
        if (!(last[0] == 0 && last[1] == 0 && last[2] == 0 && last[3] == 1))
            LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm: the last row of the 4x4 %s must be [0 0 0 1]", name));
        r = Matx34d(d.ptr<double>());
    }
    else
        LIDARSGM_Error_(Error::StsBadSize, ("lidarsgm: %s must be 3x4 or 4x4, got %dx%d", name, d.rows, d.cols));
    for (int i = 0; i < 12; i++)
        if (!std::isfinite(r.val[i]))
            LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm: %s has a NaN or infinite entry", name));
    return r;
}

void checkRigidTransform(const Matx34d& T)
{
    const Matx33d R = T.get_minor<3, 3>(0, 0);
    const double orthErr = norm(R * R.t() - Matx33d::eye(), NORM_INF);
    LIDARSGM_Check(orthErr < 1e-3 && std::abs(determinant(R) - 1.0) < 1e-3,
                   "lidarsgm: lidarToCamera must be a rigid transform (its 3x3 block a rotation)");
}

void pointLayout(int rows, int cols, int channels, int depth, bool empty, int& n, int& stride)
{
    n = 0;
    stride = 0;
    if (empty)
        return;
    LIDARSGM_Check(depth == CV_32F, "lidarsgm: points must be CV_32F (N x 3, N x 4, or N x 1 with 3 or 4 channels)");
    if (channels == 1 && (cols == 3 || cols == 4))
    {
        n = rows;
        stride = cols;
    }
    else if ((channels == 3 || channels == 4) && (cols == 1 || rows == 1))
    {
        n = rows * cols;
        stride = channels;
    }
    else
        LIDARSGM_Error_(Error::StsBadSize, ("lidarsgm: points must be N x 3 or N x 4 (or N x 1 with 3 or 4 channels), got %dx%d with %d channels",
                                            rows, cols, channels));
}

} // namespace detail

using detail::pointLayout;
using detail::toMatx34;

//! Checks the calibration arguments and returns projection * lidarToCamera (3x4).
static Matx34d checkedProjection(InputArray _projection, InputArray _lidarToCamera, double focalBaseline, Size imageSize,
                                 int dtype)
{
    LIDARSGM_Check(dtype == CV_32F || dtype == CV_16U,
                   "lidarsgm: projectPointsToDisparity: dtype must be CV_32F or CV_16U");
    LIDARSGM_Check(imageSize.width > 0 && imageSize.height > 0,
                   "lidarsgm: projectPointsToDisparity: imageSize must be positive");
    LIDARSGM_Check(std::isfinite(focalBaseline) && focalBaseline > 0,
                   "lidarsgm: projectPointsToDisparity: focalBaseline must be finite and > 0");
    const Matx34d P = toMatx34(_projection, "projection");
    const Matx34d T = toMatx34(_lidarToCamera, "lidarToCamera");
    {
        Matx33d M(P(0, 0), P(0, 1), P(0, 2), P(1, 0), P(1, 1), P(1, 2), P(2, 0), P(2, 1), P(2, 2));
        const double scale = std::max(norm(M, NORM_INF), DBL_MIN);
        LIDARSGM_Check(std::abs(determinant(M)) > 1e-9 * scale * scale * scale,
                       "lidarsgm: the projection's left 3x3 block is singular");
    }
    detail::checkRigidTransform(T);
    return Matx44d(P(0, 0), P(0, 1), P(0, 2), P(0, 3), P(1, 0), P(1, 1), P(1, 2), P(1, 3),
                   P(2, 0), P(2, 1), P(2, 2), P(2, 3), 0, 0, 0, 1).get_minor<3, 4>(0, 0) *
           Matx44d(T(0, 0), T(0, 1), T(0, 2), T(0, 3), T(1, 0), T(1, 1), T(1, 2), T(1, 3),
                   T(2, 0), T(2, 1), T(2, 2), T(2, 3), 0, 0, 0, 1);
}

void projectPointsToDisparity(InputArray _points, InputArray _projection, InputArray _lidarToCamera,
                              double focalBaseline, Size imageSize, OutputArray _sparse, int dtype)
{
    CV_INSTRUMENT_REGION();
    if (_points.kind() == _InputArray::CUDA_GPU_MAT)
    {
        cuda::projectPointsToDisparity(_points, _projection, _lidarToCamera, focalBaseline, imageSize, _sparse, dtype);
        return;
    }
    const Matx34d PT = checkedProjection(_projection, _lidarToCamera, focalBaseline, imageSize, dtype);
    Mat pts = _points.getMat();
    int n = 0, stride = 0;
    pointLayout(pts.rows, pts.cols, pts.channels(), pts.depth(), pts.empty(), n, stride);
    if (n > 0)
        pts = pts.reshape(1, n);   // one point a row; rows may be pitched (a view of a PointCloud2's records)

    // Each point's pixel (-1: none) and disparity, in parallel; then the nearest point wins: the largest disparity
    // per pixel, which no order of the points changes.
    std::vector<int> pixel(n);
    std::vector<float> value(n);
    const int chunk = 8192;
    parallel_for_(Range(0, (n + chunk - 1) / chunk), [&](const Range& chunks) {
        for (int i = chunks.start * chunk, end = std::min(n, chunks.end * chunk); i < end; i++)
        {
            pixel[i] = -1;
            const float* q = pts.ptr<float>(i);
            const double X = q[0], Y = q[1], Z = q[2];
            if (!std::isfinite(X) || !std::isfinite(Y) || !std::isfinite(Z))
                continue;
            const double z = detail::projectRow(PT.val + 8, X, Y, Z);
            if (!(z > 0))
                continue;
            const double u = detail::projectRow(PT.val, X, Y, Z), v = detail::projectRow(PT.val + 4, X, Y, Z);
            const double ui = detail::projectPixel(u, z), vi = detail::projectPixel(v, z);
            if (ui < 0 || vi < 0 || ui >= imageSize.width || vi >= imageSize.height)
                continue;
            pixel[i] = (int)vi * imageSize.width + (int)ui;
            value[i] = detail::projectDisparity(focalBaseline, z);
        }
    });
    // Into the output itself where it is a continuous CV_32F Mat (the points are read by now, should it be theirs).
    Mat disp;
    if (dtype == CV_32F && _sparse.kind() == _InputArray::MAT)
    {
        _sparse.create(imageSize, CV_32FC1);
        disp = _sparse.getMat();
        if (!disp.isContinuous())
            disp = Mat();
    }
    const bool direct = !disp.empty();
    if (!direct)
        disp = Mat(imageSize, CV_32FC1);
    disp.setTo(Scalar::all(0));
    float* map = disp.ptr<float>();
    for (int i = 0; i < n; i++)
        if (pixel[i] >= 0 && value[i] > map[pixel[i]])
            map[pixel[i]] = value[i];

    if (dtype == CV_32F)
    {
        if (!direct)
            disp.copyTo(_sparse);
    }
    else
    {
        Mat out(imageSize, CV_16UC1);
        for (int y = 0; y < imageSize.height; y++)
        {
            const float* s = disp.ptr<float>(y);
            ushort* o = out.ptr<ushort>(y);
            for (int x = 0; x < imageSize.width; x++)
                o[x] = detail::kittiEncode(s[x]);
        }
        out.copyTo(_sparse);
    }
}

}} // namespace cv::lidarsgm

namespace cv { namespace cuda {

void projectPointsToDisparity(InputArray points, InputArray projection, InputArray lidarToCamera,
                              double focalBaseline, Size imageSize, OutputArray sparseDisparity, int dtype, Stream& stream)
{
    CV_INSTRUMENT_REGION();
    if (points.kind() != _InputArray::CUDA_GPU_MAT)
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm: cv::cuda::projectPointsToDisparity needs the points in a cv::cuda::GpuMat");
    const Matx34d PT = cv::lidarsgm::checkedProjection(projection, lidarToCamera, focalBaseline, imageSize, dtype);
    const GpuMat pts = points.getGpuMat();
    int n = 0, stride = 0;
    cv::lidarsgm::pointLayout(pts.rows, pts.cols, pts.channels(), pts.depth(), pts.empty(), n, stride);
    // Point i starts a row of its own (N x k, N x 1 x C: rows may be pitched) or sits in the single row (1 x N x C).
    const int strideFloats = n == 0 ? 0 : (pts.rows == n ? (int)(pts.step / sizeof(float)) : stride);
    cv::lidarsgm::detail::CudaPipeline::projectPoints(pts, n, strideFloats, PT.val, focalBaseline, imageSize, dtype,
                                                      sparseDisparity, stream);
}

}} // namespace cv::cuda
