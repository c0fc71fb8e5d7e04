// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// LiDAR-to-camera calibration from the data: each frame's stereo disparity map (the camera alone) against the
// disparities the LiDAR points get through the transform (calibration.hpp says what is estimated and why).

#include "../precomp.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/lidarsgm/calibration.hpp"
#include "../pipeline.hpp"
#include "../projection.hpp"
#include <mutex>

namespace cv { namespace lidarsgm {

namespace {

//! The coarse-to-fine schedule: the stereo maps smoothed by sigma pixels, the Cauchy loss's scale c (pixels of
//! disparity). Wide first, so that errors of a degree (13 px at f = 720) fall in the basin.
//! stride: every stride-th point takes part (the wide levels only have to find the basin).
struct Level { double sigma, c; int stride; };
const Level kLevels[] = { { 8, 4, 4 }, { 4, 2, 4 }, { 2, 1, 2 }, { 1, 1, 1 } };
const int kMaxIterations = 20;         // Gauss-Newton steps per level, at most
const double kStepTolerance = 1e-5;    // radians (and metres): a level ends when every step is below this (6e-4 deg)
const double kMaxStdDeg = 0.1;         // a larger standard error on any angle: refused as not told by the data
const double kMaxCorrectionDeg = 5;    // beyond this the linearised steps and the basin do not hold
const int kJackknifeStrips = 8;        // groups of a jackknife over fewer than four frames

//! A NaN-aware Gaussian smoothing of a disparity map (normalised convolution): a pixel keeps a value where at
//! least half of the kernel's weight falls on valid pixels.
Mat smoothDisparity(const Mat& disp, double sigma)
{
    if (sigma <= 0)
        return disp;
    Mat valid = disp == disp, value = disp.clone(), w, s;
    value.setTo(0, ~valid);
    valid.convertTo(w, CV_32F, 1.0 / 255);
    const int k = 2 * cvCeil(3 * sigma) + 1;
    GaussianBlur(value, s, Size(k, k), sigma, sigma, BORDER_CONSTANT);
    GaussianBlur(w, w, Size(k, k), sigma, sigma, BORDER_CONSTANT);
    Mat out(disp.size(), CV_32F);
    for (int y = 0; y < disp.rows; y++)
    {
        const float* a = s.ptr<float>(y);
        const float* b = w.ptr<float>(y);
        float* o = out.ptr<float>(y);
        for (int x = 0; x < disp.cols; x++)
            o[x] = b[x] >= 0.5f ? a[x] / b[x] : std::numeric_limits<float>::quiet_NaN();
    }
    return out;
}

//! The map at (u, v), bilinear; NaN where a neighbour has no disparity or (u, v) leaves the image.
inline double sampleBilinear(const Mat& m, double u, double v)
{
    if (!(u >= 0 && v >= 0 && u < m.cols - 1 && v < m.rows - 1))
        return std::numeric_limits<double>::quiet_NaN();
    const int x = (int)u, y = (int)v;
    const double a = u - x, b = v - y;
    const float* r0 = m.ptr<float>(y) + x;
    const float* r1 = m.ptr<float>(y + 1) + x;
    return (r0[0] * (1 - a) + r0[1] * a) * (1 - b) + (r1[0] * (1 - a) + r1[1] * a) * b;
}

//! The rotation of a rotation vector w (angle |w| about w / |w|), Rodrigues' formula (cv::Rodrigues is in calib3d).
Matx33d rotationOf(const Vec3d& w)
{
    const double a = norm(w);
    if (a < 1e-300)
        return Matx33d::eye();
    const Vec3d k = w * (1 / a);
    const Matx33d K(0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0);
    return Matx33d::eye() + K * std::sin(a) + K * K * (1 - std::cos(a));
}

//! The global parameters: rotation vector (3), then the translation along x where estimated.
struct Motion
{
    Matx33d R;
    Vec3d t;
    Motion(const double* p, int n)
    {
        R = rotationOf(Vec3d(p[0], p[1], p[2]));
        t = Vec3d(n > 3 ? p[3] : 0, 0, 0);
    }
};

struct FrameData
{
    Mat points;   //!< N x 4 CV_64F: x, y, z in the LiDAR frame, the point's time from the exposure (s)
    Mat disp;     //!< the stereo map, CV_32F pixels, NaN = none
};

/** One frame's (or strip's) Gauss-Newton sums: the global block A, g and, with the frame's speed s, the mixed column
b = J_g^T W J_s, a = J_s^T W J_s, h = J_s^T W r. */
struct Sums
{
    Matx44d A;
    Vec4d g, b;
    double a = 0, h = 0;
    int count = 0;
    void add(const double* j, double js, double w, double r, int n, bool speed)
    {
        for (int k = 0; k < n; k++)
        {
            g[k] += w * j[k] * r;
            for (int l = 0; l < n; l++)
                A(k, l) += w * j[k] * j[l];
            if (speed)
                b[k] += w * j[k] * js;
        }
        if (speed)
        {
            a += w * js * js;
            h += w * js * r;
        }
        count++;
    }
    //! The global system with the speed eliminated (Schur complement); unchanged where the speed is not seen.
    void reduced(Matx44d& Ar, Vec4d& gr) const
    {
        Ar = A;
        gr = g;
        if (a > 0)
            for (int k = 0; k < 4; k++)
            {
                gr[k] -= b[k] * h / a;
                for (int l = 0; l < 4; l++)
                    Ar(k, l) -= b[k] * b[l] / a;
            }
    }
};

class LidarCalibrationImpl CV_FINAL : public LidarCalibration
{
public:
    LidarCalibrationImpl(InputArray projection, double focalBaseline, int numDisparities, double scanRate)
        : fB_(focalBaseline), numDisparities_(numDisparities), scanRate_(scanRate)
    {
        LIDARSGM_Check(std::isfinite(focalBaseline) && focalBaseline > 0,
                       "lidarsgm: LidarCalibration: focalBaseline must be finite and > 0");
        LIDARSGM_Check(numDisparities >= 16 && numDisparities <= 512 && numDisparities % 16 == 0,
                       "lidarsgm: LidarCalibration: numDisparities must be a multiple of 16 in [16, 512]");
        LIDARSGM_Check(std::isfinite(scanRate) && std::abs(scanRate) <= 100,
                       "lidarsgm: LidarCalibration: scanRate must be finite, within [-100, 100] Hz (0: no sweep)");
        if (projection.rows() != 3)
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: LidarCalibration: projection must be 3x4");
        P_ = detail::toMatx34(projection, "projection");
        matcher_ = StereoLidarSGM::create(0, numDisparities, 10, 120, 5, 160, 0.7, StereoLidarSGM::MODE_SGM,
                                          StereoLidarSGM::CHECK_STEREO);
        matcher_->setOutputType(CV_32F);
        matcher_->setNumPaths(4);
    }

    void addFrame(InputArray left, InputArray right, InputArray points) CV_OVERRIDE
    {
        CV_INSTRUMENT_REGION();
        Mat pts = points.getMat();
        if (pts.empty())
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: LidarCalibration::addFrame: the scan has no points");
        int n = 0, stride = 0;
        detail::pointLayout(pts.rows, pts.cols, pts.channels(), pts.depth(), false, n, stride);
        if (!pts.isContinuous())
            pts = pts.clone();
        pts = pts.reshape(1, n);
        FrameData f;
        f.points.create(pts.rows, 4, CV_64F);
        int kept = 0;
        for (int i = 0; i < pts.rows; i++)
        {
            const float* q = pts.ptr<float>(i);
            if (std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]))
            {
                double* o = f.points.ptr<double>(kept++);
                o[0] = q[0];
                o[1] = q[1];
                o[2] = q[2];
                // A sweep at scanRate turns azimuth atan2(y, x) at -2 pi scanRate per second (clockwise seen from
                // above for scanRate > 0, as Velodyne sensors turn) and passes x (azimuth 0) at the exposure.
                o[3] = scanRate_ != 0 ? -std::atan2((double)q[1], (double)q[0]) / (2 * CV_PI * scanRate_) : 0;
            }
        }
        if (kept == 0)
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: LidarCalibration::addFrame: the scan has no finite point");
        f.points = f.points.rowRange(0, kept).clone();
        Mat disp;
        matcher_->compute(left, right, noArray(), disp);   // checks the images (sizes, types) itself
        // Only disparities inside the search range are measurements: one at either end may stand for a match
        // beyond it (and a flat image gives 0 everywhere).
        f.disp = disp;
        f.disp.setTo(std::numeric_limits<float>::quiet_NaN(), (disp <= 0) | (disp >= numDisparities_ - 1));
        std::lock_guard<std::mutex> lock(mutex_);   // the matcher serialises its own calls
        frames_.push_back(f);
    }

    int getNumFrames() const CV_OVERRIDE
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return (int)frames_.size();
    }

    void clear() CV_OVERRIDE
    {
        std::lock_guard<std::mutex> lock(mutex_);
        frames_.clear();
    }

    double residual(InputArray lidarToCamera) const CV_OVERRIDE
    {
        CV_INSTRUMENT_REGION();
        std::lock_guard<std::mutex> lock(mutex_);
        requireFrames("residual");
        const std::vector<Mat> pts = cameraPoints(checkedTransform(lidarToCamera));
        return medianResidual(pts, std::vector<double>(frames_.size(), 0.0), nullptr);
    }

    CalibrationCorrection refine(InputArray lidarToCamera, bool translation) const CV_OVERRIDE
    {
        CV_INSTRUMENT_REGION();
        std::lock_guard<std::mutex> lock(mutex_);
        requireFrames("refine");
        const Matx44d T = checkedTransform(lidarToCamera);
        const int n = translation ? 4 : 3;
        const size_t F = frames_.size();
        double p[4] = { 0, 0, 0, 0 };
        std::vector<double> speed(F, 0.0);
        const std::vector<Mat> pts = cameraPoints(T);
        std::vector<Mat> maps(F);
        int used = 0;
        std::vector<Mat> levelPts(F);
        for (const Level& L : kLevels)
        {
            for (size_t i = 0; i < F; i++)
            {
                maps[i] = smoothDisparity(frames_[i].disp, L.sigma);
                levelPts[i] = pts[i];
                if (L.stride > 1)
                {
                    levelPts[i] = Mat((pts[i].rows + L.stride - 1) / L.stride, 4, CV_64F);
                    for (int k = 0; k < levelPts[i].rows; k++)
                        pts[i].row(k * L.stride).copyTo(levelPts[i].row(k));
                }
            }
            for (int it = 0; it < kMaxIterations; it++)
            {
                std::vector<Sums> sums;
                used = frameSums(levelPts, maps, p, speed, n, L.c, false, sums);
                if (used * L.stride < detail::kMinCalibrationPoints)
                    LIDARSGM_Error_(Error::StsError, ("lidarsgm: LidarCalibration::refine: only %d LiDAR points land on "
                                                      "a stereo disparity (at least %d needed): the data cannot tell the "
                                                      "calibration (textureless or dark images, an empty scan, or a "
                                                      "transform far off)", used * L.stride,
                                                      detail::kMinCalibrationPoints));
                Matx44d A;
                Vec4d g;
                for (const Sums& s : sums)
                {
                    Matx44d Ar;
                    Vec4d gr;
                    s.reduced(Ar, gr);
                    A += Ar;
                    g += gr;
                }
                Vec4d step;
                if (!solve(A, g, n, step))
                    LIDARSGM_Error(Error::StsError, "lidarsgm: LidarCalibration::refine: the points do not constrain every "
                                                    "parameter (degenerate scene)");
                double largest = 0;
                for (int k = 0; k < n; k++)
                {
                    p[k] -= step[k];
                    largest = std::max(largest, std::abs(step[k]));
                }
                for (size_t fi = 0; fi < F; fi++)
                    if (sums[fi].a > 0)   // the frame's speed given the global step
                        speed[fi] -= (sums[fi].h - sums[fi].b.dot(step)) / sums[fi].a;
                if (std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) > kMaxCorrectionDeg * CV_PI / 180)
                    LIDARSGM_Error_(Error::StsError, ("lidarsgm: LidarCalibration::refine: the correction grew beyond %g "
                                                      "degrees: the data do not agree with any nearby calibration",
                                                      kMaxCorrectionDeg));
                if (largest < kStepTolerance)
                    break;
            }
        }

        CalibrationCorrection c;
        c.rotation = Vec3d(p[0], p[1], p[2]);
        c.translation = Vec3d(n > 3 ? p[3] : 0, 0, 0);
        const Vec4d sd = jackknifeStd(pts, maps, p, speed, n, kLevels[sizeof(kLevels) / sizeof(kLevels[0]) - 1].c);
        c.rotationStd = Vec3d(sd[0], sd[1], sd[2]);
        c.translationStd = Vec3d(n > 3 ? sd[3] : 0, 0, 0);
        c.points = used;
        c.frames = (int)F;
        if (scanRate_ != 0)
            c.speeds = speed;
        const Motion m(p, n);
        Matx44d C = Matx44d::eye();
        for (int i = 0; i < 3; i++)
        {
            for (int j = 0; j < 3; j++)
                C(i, j) = m.R(i, j);
            C(i, 3) = m.t[i];
        }
        c.lidarToCamera = Mat(C * T).clone();
        c.residualBefore = medianResidual(pts, std::vector<double>(F, 0.0), nullptr);
        c.residualAfter = medianResidual(pts, speed, p, n);
        for (int k = 0; k < 3; k++)
            if (!(sd[k] * 180 / CV_PI <= kMaxStdDeg))
                LIDARSGM_Error_(Error::StsError, ("lidarsgm: LidarCalibration::refine: the data cannot tell the rotation: "
                                                  "standard errors %.3f / %.3f / %.3f degrees (pitch / yaw / roll; %g "
                                                  "allowed) from %d points in %d frame(s); add frames with more structure",
                                                  sd[0] * 180 / CV_PI, sd[1] * 180 / CV_PI, sd[2] * 180 / CV_PI,
                                                  kMaxStdDeg, used, c.frames));
        return c;
    }

private:
    void requireFrames(const char* what) const
    {
        if (frames_.empty())
            LIDARSGM_Error_(Error::StsError, ("lidarsgm: LidarCalibration::%s: add frames first (addFrame)", what));
    }

    //! lidarToCamera checked as projectPointsToDisparity checks it, as a 4x4 transform.
    static Matx44d checkedTransform(InputArray lidarToCamera)
    {
        const Matx34d T = detail::toMatx34(lidarToCamera, "lidarToCamera");
        detail::checkRigidTransform(T);
        return Matx44d(T(0, 0), T(0, 1), T(0, 2), T(0, 3), T(1, 0), T(1, 1), T(1, 2), T(1, 3), T(2, 0), T(2, 1),
                       T(2, 2), T(2, 3), 0, 0, 0, 1);
    }

    /** The pixel (u, v) and depth z of camera-frame point Y through the projection (projectRow, as
    projectPointsToDisparity computes them); false for a point less than 1 m in front of the camera, whose disparity
    lies beyond any search range. */
    bool project(const Vec3d& Y, double& u, double& v, double& z) const
    {
        z = detail::projectRow(P_.val + 8, Y[0], Y[1], Y[2]);
        if (!(z > 1))
            return false;
        u = detail::projectRow(P_.val, Y[0], Y[1], Y[2]) / z;
        v = detail::projectRow(P_.val + 4, Y[0], Y[1], Y[2]) / z;
        return true;
    }

    /** The points of every frame in the camera frame of T (N x 4 CV_64F: x, y, z, time), keeping those in front of
    the camera whose pixel lies within kMargin of the image: the others cannot reach a stereo disparity within the
    correction's range. */
    std::vector<Mat> cameraPoints(const Matx44d& T) const
    {
        const double kMargin = 0.1;   // of the image's width and height
        std::vector<Mat> out(frames_.size());
        for (size_t fi = 0; fi < frames_.size(); fi++)
        {
            const FrameData& f = frames_[fi];
            const double W = f.disp.cols, H = f.disp.rows;
            Mat c(f.points.rows, 4, CV_64F);
            int kept = 0;
            for (int i = 0; i < f.points.rows; i++)
            {
                const double* q = f.points.ptr<double>(i);
                const Vec4d Y = T * Vec4d(q[0], q[1], q[2], 1);
                double u, v, z;
                if (!project(Vec3d(Y[0], Y[1], Y[2]), u, v, z))
                    continue;
                if (u < -kMargin * W || u > (1 + kMargin) * W || v < -kMargin * H || v > (1 + kMargin) * H)
                    continue;
                double* o = c.ptr<double>(kept++);
                o[0] = Y[0];
                o[1] = Y[1];
                o[2] = Y[2];
                o[3] = q[3];
            }
            out[fi] = c.rowRange(0, kept);
        }
        return out;
    }

    /** Calls out(point index, LiDAR disparity - stereo disparity, pixel column) for each camera-frame point of pts
    that m and the frame's speed (along the optical axis, over the point's time) move in front of the camera and
    onto a disparity of map. */
    template <typename Out>
    void residuals(const Mat& pts, const Mat& map, const Motion& m, double speed, Out out) const
    {
        for (int i = 0; i < pts.rows; i++)
        {
            const double* q = pts.ptr<double>(i);
            Vec3d Y = m.R * Vec3d(q[0], q[1], q[2]) + m.t;
            Y[2] += speed * q[3];   // the rig moved speed * time forward between the exposure and the point
            double u, v, z;
            if (!project(Y, u, v, z))
                continue;
            const double s = sampleBilinear(map, u, v);
            if (s == s)
                out(i, fB_ / z - s, u);
        }
    }

    //! The median |residual| against the unsmoothed maps at global parameters p (none: the transform as given).
    double medianResidual(const std::vector<Mat>& pts, const std::vector<double>& speed, const double* p,
                          int n = 3) const
    {
        const double zero[4] = { 0, 0, 0, 0 };
        const Motion m(p ? p : zero, n);
        std::vector<float> r;
        for (size_t fi = 0; fi < frames_.size(); fi++)
            residuals(pts[fi], frames_[fi].disp, m, speed[fi],
                      [&](int, double e, double) { r.push_back((float)std::abs(e)); });
        if (r.size() < (size_t)detail::kMinCalibrationPoints)
            LIDARSGM_Error_(Error::StsError, ("lidarsgm: LidarCalibration: only %d LiDAR points land on a stereo "
                                              "disparity (at least %d needed: textureless or dark images, an empty scan, "
                                              "or a wrong transform or projection)", (int)r.size(),
                                              detail::kMinCalibrationPoints));
        std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
        return r[r.size() / 2];
    }

    /** The Cauchy-weighted Gauss-Newton sums at (p, speed), numerical Jacobian by central differences of about one
    pixel (and 0.5 m/s), one Sums per frame, or per image strip of each frame (strips). Returns the points used. */
    int frameSums(const std::vector<Mat>& pts, const std::vector<Mat>& maps, const double* p,
                  const std::vector<double>& speed, int n, double c, bool strips, std::vector<Sums>& sums) const
    {
        const double hRot = 1.0 / std::max(P_(0, 0), 1.0), hT = 0.01, hS = 0.5;
        const bool withSpeed = scanRate_ != 0;
        const int groups = strips ? kJackknifeStrips : 1;
        sums.assign(frames_.size() * groups, Sums());
        parallel_for_(Range(0, (int)frames_.size()), [&](const Range& range) {
            for (int fi = range.start; fi < range.end; fi++)
            {
                const Mat& P = pts[fi];
                const int N = P.rows, nj = n + (withSpeed ? 1 : 0);
                const double nan = std::numeric_limits<double>::quiet_NaN();
                std::vector<double> r0(N, nan), u0(N, 0), J((size_t)N * nj, nan), rp(N);
                residuals(P, maps[fi], Motion(p, n), speed[fi], [&](int i, double e, double u) {
                    r0[i] = e;
                    u0[i] = u;
                });
                for (int k = 0; k < nj; k++)
                {
                    const double h = k < 3 ? hRot : k < n ? hT : hS;
                    double pp[4], pm[4];
                    std::copy(p, p + 4, pp);
                    std::copy(p, p + 4, pm);
                    double sp = speed[fi], sm = speed[fi];
                    if (k < n)
                    {
                        pp[k] += h;
                        pm[k] -= h;
                    }
                    else
                    {
                        sp += h;
                        sm -= h;
                    }
                    std::fill(rp.begin(), rp.end(), nan);
                    residuals(P, maps[fi], Motion(pp, n), sp, [&](int i, double e, double) { rp[i] = e; });
                    residuals(P, maps[fi], Motion(pm, n), sm, [&](int i, double e, double) {
                        if (rp[i] == rp[i])
                            J[(size_t)i * nj + k] = (rp[i] - e) / (2 * h);
                    });
                }
                const int W = maps[fi].cols;
                for (int i = 0; i < N; i++)
                {
                    const double* j = &J[(size_t)i * nj];
                    bool ok = r0[i] == r0[i];
                    for (int k = 0; k < nj && ok; k++)
                        ok = j[k] == j[k];
                    if (!ok)
                        continue;
                    const double w = 1 / (1 + (r0[i] / c) * (r0[i] / c));
                    const int s = strips ? std::min(std::max((int)(u0[i] * groups / W), 0), groups - 1) : 0;
                    sums[fi * groups + s].add(j, withSpeed ? j[n] : 0, w, r0[i], n, withSpeed);
                }
            }
        });
        int used = 0;
        for (const Sums& s : sums)
            used += s.count;
        return used;
    }

    //! The n x n system A step = g; false where A is singular.
    static bool solve(const Matx44d& A, const Vec4d& g, int n, Vec4d& step)
    {
        Mat a(n, n, CV_64F), b(n, 1, CV_64F), x;
        for (int k = 0; k < n; k++)
        {
            b.at<double>(k) = g[k];
            for (int l = 0; l < n; l++)
                a.at<double>(k, l) = A(k, l);
        }
        if (!cv::solve(a, b, x, DECOMP_CHOLESKY))
            return false;
        step = Vec4d();
        for (int k = 0; k < n; k++)
            step[k] = x.at<double>(k);
        return true;
    }

    /** Jackknife standard errors of the global parameters at the solution p: the estimate without group k (a frame,
    or an image strip when fewer than four frames are pooled) is one Gauss-Newton step from p with group k's reduced
    sums taken out, p_k = p - (A - A_k)^-1 (g - g_k); the variance is (K - 1) / K sum (p_k - mean)^2. */
    Vec4d jackknifeStd(const std::vector<Mat>& pts, const std::vector<Mat>& maps, const double* p,
                       const std::vector<double>& speed, int n, double c) const
    {
        std::vector<Sums> sums;
        frameSums(pts, maps, p, speed, n, c, frames_.size() < 4, sums);
        std::vector<Matx44d> As(sums.size());
        std::vector<Vec4d> gs(sums.size());
        Matx44d A;
        Vec4d g;
        for (size_t k = 0; k < sums.size(); k++)
        {
            sums[k].reduced(As[k], gs[k]);
            A += As[k];
            g += gs[k];
        }
        std::vector<Vec4d> est;
        for (size_t k = 0; k < sums.size(); k++)
        {
            Vec4d step;
            if (sums[k].count > 0 && solve(A - As[k], g - gs[k], n, step))
                est.push_back(Vec4d(p[0], p[1], p[2], p[3]) - step);
        }
        const double inf = std::numeric_limits<double>::infinity();
        if (est.size() < 2)
            return Vec4d(inf, inf, inf, inf);
        Vec4d mean, var;
        for (const Vec4d& e : est)
            mean += e * (1.0 / est.size());
        for (const Vec4d& e : est)
            for (int k = 0; k < 4; k++)
                var[k] += (e[k] - mean[k]) * (e[k] - mean[k]);
        const double K = (double)est.size();
        Vec4d sd;
        for (int k = 0; k < 4; k++)
            sd[k] = std::sqrt(var[k] * (K - 1) / K);
        return sd;
    }

    Matx34d P_;
    double fB_;
    int numDisparities_;
    double scanRate_;
    Ptr<StereoLidarSGM> matcher_;
    std::vector<FrameData> frames_;
    mutable std::mutex mutex_;   //!< guards frames_: the public calls of one instance run one at a time
};

} // namespace

Ptr<LidarCalibration> LidarCalibration::create(InputArray projection, double focalBaseline, int numDisparities,
                                               double scanRate)
{
    return makePtr<LidarCalibrationImpl>(projection, focalBaseline, numDisparities, scanRate);
}

}} // namespace cv::lidarsgm
