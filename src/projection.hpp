// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The checks of the inputs, shared by the matcher (src/stereo_lidar_sgm.cpp), the projection (src/projection.cpp) and
// the calibration (src/addons/calibration.cpp).

#ifndef OPENCV_LIDARSGM_PROJECTION_HPP
#define OPENCV_LIDARSGM_PROJECTION_HPP

#include "opencv2/core.hpp"

namespace cv { namespace lidarsgm { namespace detail {

//! The fewest LiDAR points that can tell a calibration (LidarCalibration, matchingResidual): below, they refuse.
const int kMinCalibrationPoints = 200;

/** checkLidar: the moves of the sparse map searched reach a 32nd of the image width (about 3 degrees of rotation on
KITTI, f = 721 px: twice the errors a hand-measured rig shows), and a move must lower the matching residual by a fifth
to condemn the transform. On the 20 shared KITTI frames, pitch errors of half a degree and mixes of 1-2 degrees find
moves that lower it by 29-80 %, the exact calibration at most 6 %, also at twice the resolution with JPEG compression
(doc/benchmarks/fail_safe_kitti20.txt). */
const int kLidarShiftFraction = 32;
const double kLidarShiftGain = 0.8;
/** checkLidar: where no move condemns the map, turns of up to this many degrees about the image centre are searched too
(each with the move refined around the best one): a roll of the LiDAR about the camera's optical axis moves the points
in opposite directions on the two sides of the image, which no move matches. A turn about the principal point is a
turn about the centre and a move. 3 degrees: the reach of the moves (kLidarShiftFraction) as a rotation. */
const double kLidarMaxTurn = 3.0;
//! checkLidar's search evaluates every k-th point, at least this many (the median of a few thousand is stable).
const int kLidarSearchPoints = 4096;

//! A 3x4, or 4x4 with last row [0 0 0 1], single-channel CV_32F / CV_64F matrix with finite entries, as Matx34d;
//! raises cv::Exception naming `name` otherwise.
Matx34d toMatx34(InputArray m, const char* name);

//! Raises cv::Exception unless T's 3x3 block is a rotation (orthonormal rows, determinant 1).
void checkRigidTransform(const Matx34d& T);

//! Number of points and floats per point of an N x 3 / N x 4 (or N x 1 / 1 x N with 3 or 4 channels) CV_32F array;
//! n = stride = 0 when empty. Raises cv::Exception for any other layout.
void pointLayout(int rows, int cols, int channels, int depth, bool empty, int& n, int& stride);

/** The image and sparse-map checks of compute() and semidensify() (src/stereo_lidar_sgm.cpp), for Mat and GpuMat
alike; needer names the call that needs the sparse map where needSparse. Returns whether the inputs are on the GPU
(then all of them, and out too, must be GpuMats). */
bool checkInputs(InputArray left, InputArray right, InputArray sparse, OutputArray out, bool needSparse,
                 const char* needer);

//! A module message without its "lidarsgm: " in front, to put a file's name there instead.
String withoutModulePrefix(const String& message);
/** What cv::FileStorage's parser said: its exceptions carry "file(line): what" in func and the parser's function in err
(OpenCV 4 and 5 pass the two the other way round); other exceptions their err. */
String parserMessage(const cv::Exception& e);
//! The known name nearest to key (edit distance, case ignored): for "did you mean" in the messages.
String nearestName(const String& key, const std::vector<String>& names);
//! Raises cv::Exception for the first key of the map node that is not in known, naming what holds it and the
//! nearest known key.
void refuseUnknownKeys(const FileNode& node, const std::vector<String>& known, const String& what);

}}} // namespace cv::lidarsgm::detail

#endif
