// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_RIG_HPP
#define OPENCV_LIDARSGM_RIG_HPP

#include "opencv2/core.hpp"
#include "opencv2/lidarsgm/datasets.hpp"

namespace cv {
namespace lidarsgm {

//! @addtogroup lidarsgm
//! @{

/** @brief A stereo camera with a LiDAR, from your own calibration files: rectifies the raw pairs and brings the LiDAR's
points into the rectified left view, where StereoLidarSGM works.

Read it from
 - a cv::FileStorage file (YAML, XML or JSON) with the names of OpenCV's stereo_calib sample: `M1`, `D1`, `M2`, `D2`
   (camera matrices and distortion of cv::stereoCalibrate), `R`, `T` (the right camera's pose: x_right = R x_left +
   T), optionally the rectification `R1`, `R2`, `P1`, `P2` it computed (else cv::stereoRectify's with
   CALIB_ZERO_DISPARITY and alpha 0 is computed), `image_width`, `image_height`, and `lidar_to_left` (4x4, LiDAR to
   the raw left camera): fromFile();
 - ROS camera_calibration's two YAML files (`image_width`, `image_height`, `camera_matrix`, `distortion_coefficients`,
   `rectification_matrix`, `projection_matrix`) and the LiDAR-to-left transform: fromRos();
 - a KITTI calibration, already rectified: fromKitti().
An already-rectified rig (a FileStorage file with `P1`, `P2` and no `M1`; KITTI) passes its images through unchanged.

The LiDAR-to-left transform goes before the rectification's rotation: points move as R1 * lidar_to_left into the
rectified left camera, the frame of every disparity, depth and point the module gives for this rig;
rectifiedToLeft() takes them back into the raw left camera's frame. Errors (a file that cannot be read, a missing or
malformed key named with its file, a rig that is not horizontal after rectification) raise cv::Exception.
 */
class CV_EXPORTS_W StereoRig : public Algorithm
{
public:
    /** @brief From a cv::FileStorage file with the names above. */
    CV_WRAP static Ptr<StereoRig> fromFile(const String& path);
    /** @brief From ROS camera_calibration's left and right YAML files and the 4x4 LiDAR-to-left-camera transform
    (CV_32F or CV_64F): the files' rectification and projection matrices are used as they are. */
    CV_WRAP static Ptr<StereoRig> fromRos(const String& leftYaml, const String& rightYaml, InputArray lidarToLeft);
    /** @brief From cv::stereoCalibrate's results, the image size and the LiDAR-to-left transform; the rectification is
    cv::stereoRectify's (CALIB_ZERO_DISPARITY, alpha 0: every rectified pixel comes from inside the raw image). */
    CV_WRAP static Ptr<StereoRig> create(InputArray M1, InputArray D1, InputArray M2, InputArray D2, InputArray R,
                                         InputArray T, Size imageSize, InputArray lidarToLeft);
    /** @brief A rectified rig from a KITTI calibration (projectPointsToDisparity's inputs) and the image size. */
    CV_WRAP static Ptr<StereoRig> fromKitti(const KittiCalibration& calibration, Size imageSize);

    /** @brief Writes the rig as fromFile() reads it (with its rectification), to a FileStorage file. */
    CV_WRAP virtual void writeFile(const String& path) const = 0;

    /** The images' size (raw and rectified alike). */
    CV_WRAP virtual Size getImageSize() const = 0;
    /** Whether the images are already rectified (rectify() copies them). */
    CV_WRAP virtual bool isRectified() const = 0;
    /** @brief The rectified pair: each image remapped (bilinear) through the rectification, in its own type. The
    images must have the rig's size. */
    CV_WRAP virtual void rectify(InputArray left, InputArray right, OutputArray leftRectified,
                                 OutputArray rightRectified) const = 0;
    /** The rectified left camera's 3x4 projection matrix (CV_64F). */
    CV_WRAP virtual Mat getProjectionLeft() const = 0;
    /** The rectified right camera's 3x4 projection matrix (CV_64F). */
    CV_WRAP virtual Mat getProjectionRight() const = 0;
    /** Focal length in pixels times the baseline: P1(0, 3) - P2(0, 3), as disparityToDepth takes it. */
    CV_WRAP virtual double getFocalBaseline() const = 0;
    /** The LiDAR to the rectified left camera, 4x4 CV_64F: [R1 0; 0 1] * lidar_to_left. */
    CV_WRAP virtual Mat getLidarToRectified() const = 0;
    /** The rectified left camera to the raw left camera, 4x4 CV_64F: [R1^T 0; 0 1]. */
    CV_WRAP virtual Mat getRectifiedToLeft() const = 0;
    /** @brief The calibration projectPointsToDisparity and loadKittiFrame take: P1, getLidarToRectified() and
    getFocalBaseline(). */
    CV_WRAP virtual KittiCalibration getCalibration() const = 0;
    /** @brief A LiDAR cloud (N x 3 or N x 4 CV_32F, as readPointCloud gives it) as the sparse disparity map of the
    rectified left view (projectPointsToDisparity with getCalibration()). */
    CV_WRAP virtual void projectCloud(InputArray points, OutputArray sparseDisparity, int dtype = CV_32F) const = 0;
    /** @brief Points of the rectified left camera (an N x 3 / H x W 3-channel CV_32F or CV_64F array, as
    disparityToPoints gives them; NaN stays NaN) moved into the raw left camera's frame. */
    CV_WRAP virtual void rectifiedToLeftCamera(InputArray points, OutputArray pointsLeft) const = 0;
};

//! @}

}} // namespace cv::lidarsgm

#endif
