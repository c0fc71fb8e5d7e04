// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_CALIBRATION_HPP
#define OPENCV_LIDARSGM_CALIBRATION_HPP

#include "opencv2/core.hpp"
#include <limits>

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

/** @brief How well a sparse (LiDAR) disparity map matches the stereo pair it comes with, from the images alone: a
calibration check cheap enough for every frame.

Each sparse pixel's disparity is compared with the disparity at which the left pixel matches the right image best
within searchRadius of it: the Hamming distances of the pipeline's census strings summed over the pixel's 3x3
neighbourhood, the minimum refined by the pipeline's subpixel parabola. The result is the median
|sparse - matched| in pixels over the sparse pixels whose best match passes the matcher's uniqueness check at its
default ratio (an ambiguous block, on faint or repetitive texture, has no match to compare with); a best match at
either end of the search counts as far as it lies. It rises with a calibration error
(doc/accuracy.md, "Calibration": figures on the KITTI frames). Above 1 px, the DDC's Q1 band, the LiDAR pulls the
fusion off the stereo pair by more than a disparity: check the calibration with LidarCalibration before trusting
the depth. LidarCalibration::residual() measures against a stereo map instead, more precisely and at the cost of
one: this is for every frame, that for a calibration run.

Runs on the CPU (Mat inputs). Raises cv::Exception where fewer than 200 sparse pixels can be compared (a
textureless pair, an empty or misaimed scan): the images cannot tell the calibration then.
@param left left image, CV_8UC1 or CV_16UC1 (rectified), as for StereoLidarSGM::compute.
@param right right image, same size and type.
@param sparseDisparity sparse left-view disparity, CV_16UC1 (KITTI, value / 256, 0 = none) or CV_32FC1 (pixels,
<= 0 or NaN = none), as for StereoLidarSGM::compute.
@param searchRadius disparities searched on each side of each sparse value, in [1, 64].
 */
CV_EXPORTS_W double matchingResidual(InputArray left, InputArray right, InputArray sparseDisparity,
                                     int searchRadius = 6);

/** @brief What checkLidar() found: whether a frame's sparse (LiDAR) map can be fused with its images. */
struct CV_EXPORTS_W_SIMPLE LidarCheck
{
    CV_WRAP LidarCheck() : residual(std::numeric_limits<double>::quiet_NaN()), shiftedResidual(residual) {}
    //! matchingResidual() of the map as given, pixels; NaN where the images cannot tell (too few comparable pixels)
    CV_PROP_RW double residual;
    //! the lowest residual of the map moved by `shift`; equal to residual where no move was searched
    CV_PROP_RW double shiftedResidual;
    //! the move (pixels, x right, y down) of the sparse values that gives shiftedResidual (after `turn`)
    CV_PROP_RW Point shift;
    //! the turn (degrees, about the image centre, from x toward y: clockwise on the image) that gives
    //! shiftedResidual with `shift`; 0 where turns were not searched or none helped
    CV_PROP_RW double turn = 0;
    //! false where the map is judged misplaced: fuse the frame as stereo alone (MODE_SGM without the sparse map;
    //! DSGM and SDSGM weigh the census by 1 - alpha even without a prior) and check the calibration
    CV_PROP_RW bool trusted = true;
};

/** @brief Whether a frame's sparse (LiDAR) map can be fused with its images: the fail-safe for a LiDAR-to-camera
transform that is off.

A wrong transform pulls the fusion off the images wherever the LiDAR speaks: with a rotation error of two degrees,
SDSGM's error on KITTI rises to ten times stereo alone's. Its matching residual (matchingResidual()) rises with the
error, but so it does on images that match poorly (high resolution, compression, motion blur), where the LiDAR is
right and helps most. checkLidar() tells the two apart. Where the residual is at most maxResidual, the map is trusted.
Above it, the sparse values are moved together by up to maxShift pixels in each direction (a rotation error moves
the points on the image by about f x angle), coarse to fine, and the lowest residual of a moved map is found: a map
whose residual a move lowers by a fifth or more is misplaced (not trusted). Where no move does, the map is also
turned about the image centre by up to 3 degrees, the move refined around the best one at each turn: a roll of the
LiDAR about the camera's optical axis moves the points in opposite directions on the two sides of the image. A map
whose residual neither lowers is at the images' own floor (trusted).

Cost: one matchingResidual() where the residual is within maxResidual; about a hundred evaluations on the same census
strings where it is not, and about 80 more where no move condemns the map (on KITTI at 64 lines tens of
milliseconds on two cores).
@param left left image, CV_8UC1 or CV_16UC1 (rectified), as for StereoLidarSGM::compute.
@param right right image, same size and type.
@param sparseDisparity sparse left-view disparity, CV_16UC1 (KITTI, value / 256, 0 = none) or CV_32FC1 (pixels,
<= 0 or NaN = none).
@param maxResidual the residual (pixels) up to which the map is trusted without a search; 1, the DDC's Q1 band, by
default: beyond it the LiDAR pulls the fusion off the images by more than a disparity.
@param maxShift the largest move searched, pixels, in [0, 1024]; 0: a 32nd of the image width.
 */
CV_EXPORTS_W LidarCheck checkLidar(InputArray left, InputArray right, InputArray sparseDisparity,
                                   double maxResidual = 1.0, int maxShift = 0);

//! @}

}} // namespace cv::lidarsgm

#endif // OPENCV_LIDARSGM_CALIBRATION_HPP
