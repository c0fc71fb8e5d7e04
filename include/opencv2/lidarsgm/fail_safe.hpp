// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_FAIL_SAFE_HPP
#define OPENCV_LIDARSGM_FAIL_SAFE_HPP

#include "opencv2/core.hpp"
#include <limits>

namespace cv {
namespace lidarsgm {

class StereoLidarSGM;

//! @addtogroup lidarsgm
//! @{

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
    //! false where the map is judged misplaced: fuse the frame as stereo alone and check the calibration
    CV_PROP_RW bool trusted = true;
    //! LidarFailSafe::check's decision: fuse the frame as stereo alone (not trusted, and the fail-safe not told to
    //! trust the LiDAR); checkLidar() leaves it false
    CV_PROP_RW bool stereoAlone = false;
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
@param maxResidual the residual (pixels) up to which the map is trusted without a search, in (0, 64); 0 (default):
LidarFailSafe::maxResidual(), the DDC's Q1 band.
@param maxShift the largest move searched, pixels, in [0, 1024]; 0: a 32nd of the image width.
 */
CV_EXPORTS_W LidarCheck checkLidar(InputArray left, InputArray right, InputArray sparseDisparity,
                                   double maxResidual = 0, int maxShift = 0);

/** @brief The fail-safe: whether a frame's LiDAR may be fused with its images, and the stereo-alone matcher that fuses
it where it may not.

A frame's sparse map is judged with checkLidar() at maxResidual(). Where it is misplaced (a LiDAR-to-camera
transform that is off), the frame is fused as stereo alone: the matcher's settings in MODE_SGM, without the sparse
map (DSGM and SDSGM weigh the census by 1 - alpha even without a prior: smoother than SGM, and worse; in MODE_SGM a
sparse map would still draw the disparity windows). The tool, the ROS 2 node, the bag command and the samples use
this class, so that all of them decide alike.

@code
    Ptr<lidarsgm::LidarFailSafe> failSafe = lidarsgm::LidarFailSafe::create();
    lidarsgm::LidarCheck verdict = failSafe->compute(matcher, left, right, sparse, disparity);
    if (verdict.stereoAlone)
        ;  // fused without the LiDAR: check the calibration (LidarCalibration)
@endcode
 */
class CV_EXPORTS_W LidarFailSafe : public Algorithm
{
public:
    /** @param trustLidar judge and report, but never fall back: the LiDAR is fused even where it is misplaced (the
    tool's --trust-lidar, the node's trust_lidar). */
    CV_WRAP static Ptr<LidarFailSafe> create(bool trustLidar = false);
    /** The matching residual (pixels) above which a map is searched for a misplacement: 1, the DDC's Q1 band; beyond
    it the LiDAR pulls the fusion off the images by more than a disparity. */
    CV_WRAP static double maxResidual();
    /** The matcher that fuses a frame as stereo alone: a new matcher with `matcher`'s settings in MODE_SGM, and
    CHECK_STEREO where it has CHECK_STEREO_LIDAR (without a map the LiDAR's part of the check keeps nothing: the same
    output, named for what it does). Pass it no sparse map. */
    CV_WRAP static Ptr<StereoLidarSGM> stereoAloneMatcher(const Ptr<StereoLidarSGM>& matcher);

    /** Whether the LiDAR is fused even where it is misplaced (see create()). */
    CV_WRAP virtual bool getTrustLidar() const = 0;
    /** Sets whether the LiDAR is fused even where it is misplaced (see create()). */
    CV_WRAP virtual void setTrustLidar(bool trust) = 0;
    /** checkLidar() at maxResidual(), with its decision in LidarCheck::stereoAlone. A map the images cannot judge
    (residual NaN: fewer than 200 comparable pixels) is fused. CPU inputs (cv::Mat), as for checkLidar(). */
    CV_WRAP virtual LidarCheck check(InputArray left, InputArray right, InputArray sparseDisparity) const = 0;
    /** check(), then matcher->compute(): on the LiDAR where it may be fused, else as stereo alone (a
    stereoAloneMatcher() kept by this object and given `matcher`'s settings on each call). Returns the verdict.
    CPU inputs and output (cv::Mat); on the CUDA path call check() on the host images and compute with the matcher
    it names. */
    CV_WRAP virtual LidarCheck compute(const Ptr<StereoLidarSGM>& matcher, InputArray left, InputArray right,
                                       InputArray sparseDisparity, OutputArray disparity) = 0;
};

//! @}

}} // namespace cv::lidarsgm

#endif // OPENCV_LIDARSGM_FAIL_SAFE_HPP
