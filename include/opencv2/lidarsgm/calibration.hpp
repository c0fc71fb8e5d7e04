// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_CALIBRATION_HPP
#define OPENCV_LIDARSGM_CALIBRATION_HPP

#include "opencv2/core.hpp"

namespace cv {
namespace lidarsgm {

//! @addtogroup lidarsgm
//! @{

/** @brief A correction of the LiDAR-to-camera transform, estimated by LidarCalibration::refine.

The correction is a rigid motion in the rectified left camera's frame (x right, y down, z forward): a point X that
the given transform puts at Y = lidarToCamera X moves to R(rotation) Y + translation, so the corrected transform is
[R | translation] * lidarToCamera. In the camera frame rotation[0] is the pitch (about x), rotation[1] the yaw
(about y), rotation[2] the roll (about the optical axis).
 */
struct CV_EXPORTS_W_SIMPLE CalibrationCorrection
{
    CV_WRAP CalibrationCorrection() {}
    CV_PROP_RW Vec3d rotation;        //!< rotation vector of the correction, radians (cv::Rodrigues)
    CV_PROP_RW Vec3d translation;     //!< metres; (0, 0, 0) unless the translation was estimated
    CV_PROP_RW Vec3d rotationStd;     //!< standard error of each rotation component, radians
    CV_PROP_RW Vec3d translationStd;  //!< standard error of each translation component, metres
    CV_PROP_RW Mat lidarToCamera;     //!< the corrected transform, 4x4 CV_64F
    CV_PROP_RW double residualBefore = 0;  //!< calibration residual (LidarCalibration::residual) before, pixels
    CV_PROP_RW double residualAfter = 0;   //!< and after the correction
    CV_PROP_RW int points = 0;        //!< LiDAR points that entered the estimate (stereo disparity at their pixel)
    CV_PROP_RW int frames = 0;        //!< frames pooled
    //! Each frame's speed along the optical axis while the LiDAR swept, m/s (a sweeping scan only, see create())
    CV_PROP_RW std::vector<double> speeds;
};

/** @brief Measures and refines the LiDAR-to-camera transform from the data: stereo pairs and the LiDAR scans taken
with them.

Each frame's stereo pair gives a disparity map of its own (StereoLidarSGM in MODE_SGM with the left-right check: the
camera alone, no LiDAR). A LiDAR point X projects through the transform to a pixel (u, v) with disparity
focalBaseline / z; where the calibration is right, that disparity agrees with the stereo map at (u, v). residual()
is the median of |LiDAR disparity - stereo disparity| over the points (pixels). refine() finds the small rigid
correction of the transform that minimises a robust sum of those differences (a Cauchy loss) over all frames,
by iteratively reweighted Gauss-Newton, coarse to fine: first against the stereo maps smoothed by 8, 4, 2 and 1
pixels (a wide basin: a one-degree error moves points by 13 pixels at KITTI's focal length), then against the map
itself. Its standard errors come from a jackknife over the frames (over eight image strips when fewer than four
frames are pooled).

What it sees: pitch and roll move points across the ground and other surfaces whose disparity changes with the row;
yaw moves them along rows, which only surfaces slanted in depth along the row and depth edges reveal, so yaw is the
least certain angle. Where the stereo pair or the LiDAR cannot tell (too few points with a stereo disparity: night,
fog, a textureless scene, an empty or misaimed scan; or a standard error above 0.1 degree), refine() raises
cv::Exception saying so instead of returning a guess.

Frames must come from one rig with one calibration: the projection and focalBaseline are given at create(). The
calls of one instance may come from several threads; they run one at a time.
 */
class CV_EXPORTS_W LidarCalibration : public Algorithm
{
public:
    /** @brief Creates an empty calibration refiner.
    @param projection 3x4 projection matrix (CV_32F or CV_64F) of the rectified left camera.
    @param focalBaseline focal length (pixels) times baseline (metres), > 0.
    @param numDisparities disparities the stereo maps search: a multiple of 16 in [16, 512].
    @param scanRate the LiDAR's sweep rate in Hz for scans that are not motion-compensated, 0 for scans that are
    (or a still rig). A sweeping LiDAR measures a point at azimuth a = atan2(y, x) (LiDAR frame) at
    t = -a / (2 pi scanRate) from the camera's exposure: it passes its x axis at the exposure and turns clockwise seen
    from above where scanRate > 0 (as Velodyne sensors do; KITTI: 10), counter-clockwise where < 0. refine() then
    estimates each frame's speed along the camera's optical axis beside the correction, so that the rig's motion
    during the sweep (points ahead of the rig on one side of the image, behind on the other) is not taken for a
    rotation.
     */
    CV_WRAP static Ptr<LidarCalibration> create(InputArray projection, double focalBaseline, int numDisparities = 128,
                                                double scanRate = 0);

    /** @brief Adds a frame: computes its stereo disparity map and keeps it with the points.
    @param left left image, CV_8UC1 or CV_16UC1 (rectified).
    @param right right image, same size and type.
    @param points the LiDAR scan in the LiDAR's frame, N x 3 or N x 4 CV_32F (x, y, z[, reflectance]), as for
    projectPointsToDisparity.
     */
    CV_WRAP virtual void addFrame(InputArray left, InputArray right, InputArray points) = 0;

    /** Frames added since create() or clear(). */
    CV_WRAP virtual int getNumFrames() const = 0;
    /** Forgets the frames. */
    CV_WRAP virtual void clear() CV_OVERRIDE = 0;

    /** @brief How well the LiDAR agrees with the stereo pairs under a transform: the median of
    |LiDAR disparity - stereo disparity| (pixels) over the points, of all frames, that land on a stereo disparity.
    @param lidarToCamera 3x4 or 4x4 rigid transform from LiDAR to rectified camera coordinates.
     */
    CV_WRAP virtual double residual(InputArray lidarToCamera) const = 0;

    /** @brief Estimates the correction of lidarToCamera from every frame added.
    @param lidarToCamera the transform to correct (3x4 or 4x4).
    @param translation false: the rotation alone (3 parameters); true: the rotation and the translation along the
    camera's x axis, the baseline's direction (4 parameters). The other two translations are left alone: pitch and a
    vertical or forward offset move ground points alike, so the data cannot tell them apart.
     */
    CV_WRAP virtual CalibrationCorrection refine(InputArray lidarToCamera, bool translation = false) const = 0;
};

//! @}

}} // namespace cv::lidarsgm

#endif // OPENCV_LIDARSGM_CALIBRATION_HPP
