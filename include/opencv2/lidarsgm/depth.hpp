// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_DEPTH_HPP
#define OPENCV_LIDARSGM_DEPTH_HPP

#include "opencv2/core.hpp"

namespace cv {
namespace lidarsgm {

//! @addtogroup lidarsgm
//! @{

/** @brief Metric depth from a disparity map: depth = focalBaseline / d, in metres.

The matcher's CV_16S output holds disparity x 16 (4 fractional bits): this function divides by 16 itself, so pass
the output as it is. (Passing it to cv::reprojectImageTo3D without dividing by 16 first gives 16 times too small a
depth, and its invalid value -16 a point far behind the camera.)

@param disparity CV_16SC1 (disparity x 16, a StereoLidarSGM or cv::StereoSGBM output) or CV_32FC1 (pixels).
@param focalBaseline focal length in pixels times the baseline in metres, > 0 (KITTI: P2[0,3] - P3[0,3]).
@param depth output, CV_32FC1, metres. Invalid pixels are invalidDepth: a disparity below minDisparity (the matchers' invalid
value is minDisparity - 1), not positive, or not finite. There is no huge depth for a tiny disparity other than
focalBaseline / d itself.
@param minDisparity the matcher's minDisparity.
@param invalidDepth the value of invalid pixels: 0, or NaN as REP 118 (ROS) marks them in 32-bit depth images.
 */
CV_EXPORTS_W void disparityToDepth(InputArray disparity, double focalBaseline, OutputArray depth,
                                   int minDisparity = 0, float invalidDepth = 0.f);

/** @brief 3D points of a disparity map in the left camera's frame (x right, y down, z forward, metres).

Each valid pixel (x, y) with disparity d gives Q [x y d 1]^T divided by its fourth component, as
cv::reprojectImageTo3D computes it, but with the x16 scale of a CV_16S map taken into account and invalid pixels
left invalid.

@param disparity CV_16SC1 (disparity x 16) or CV_32FC1 (pixels).
@param Q 4x4 reprojection matrix (CV_32F or CV_64F), as cv::stereoRectify returns it or reprojectionMatrix() builds
it from a projection matrix and focalBaseline.
@param points output, CV_32FC3. Invalid pixels (as for disparityToDepth) and pixels whose fourth component
Q [x y d 1]^T is not positive (no point in front of the camera) are NaN in all three coordinates.
@param minDisparity the matcher's minDisparity.
 */
CV_EXPORTS_W void disparityToPoints(InputArray disparity, InputArray Q, OutputArray points, int minDisparity = 0);

/** @brief An organised coloured point cloud of a disparity map: x, y, z and the pixel's colour, 16 bytes a point.

The layout of a sensor_msgs/PointCloud2 with the float32 fields x, y, z, rgb at offsets 0, 4, 8, 12 (point step 16)
and of PCL's packed rgb: the fourth float holds the bits 0x00RRGGBB of the pixel's colour (grey: R = G = B), on every
pixel, so that its bytes in memory are B, G, R, 0. The points are disparityToPoints()'s, bit for bit. One pass over
the map instead of disparityToPoints() and a merge with the image, which write the points twice.

@param disparity CV_16SC1 (disparity x 16) or CV_32FC1 (pixels).
@param Q 4x4 reprojection matrix (CV_32F or CV_64F), as for disparityToPoints().
@param image the left image, CV_8UC3 (BGR, as cv::imread gives it) or CV_8UC1, the disparity map's size.
@param cloud output, CV_32FC4 (x, y, z, packed rgb); x, y, z NaN where disparityToPoints() has no point.
@param minDisparity the matcher's minDisparity.
 */
CV_EXPORTS_W void disparityToColoredPoints(InputArray disparity, InputArray Q, InputArray image, OutputArray cloud,
                                           int minDisparity = 0);

/** @brief The reprojection matrix Q of a rectified pair for disparityToPoints and cv::reprojectImageTo3D.

Q = [1 0 0 -cx; 0 1 0 -cy; 0 0 0 f; 0 0 f/focalBaseline 0] with f = projection(0,0), cx = projection(0,2),
cy = projection(1,2): a pixel's point is ((x - cx) z / f, (y - cy) z / f, z) with z = focalBaseline / d.

@param projection 3x3 or 3x4 matrix (CV_32F or CV_64F) of the rectified left camera (KITTI: P2, or P_rect_02).
@param focalBaseline focal length in pixels times the baseline in metres, > 0.
@return Q, 4x4 CV_64F.
 */
CV_EXPORTS_W Mat reprojectionMatrix(InputArray projection, double focalBaseline);

//! @}

}} // namespace cv::lidarsgm

#endif // OPENCV_LIDARSGM_DEPTH_HPP
