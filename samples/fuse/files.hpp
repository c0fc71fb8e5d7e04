// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// What only the tool reads and writes beyond the module's datasets API (opencv2/lidarsgm/datasets.hpp): images given
// one by one, where a frame's files lie (for the calibration pass), and its raw CV_16S output format.

#ifndef LIDARSGM_FUSE_FILES_HPP
#define LIDARSGM_FUSE_FILES_HPP

#include "opencv2/lidarsgm.hpp"
#include <string>

namespace lidarsgm_fuse {

//! An image as stored (grey or colour); raises cv::Exception "cannot read <what> <path>: why".
cv::Mat readImage(const std::string& path, const std::string& what = "image");
//! An image as one grey channel (colour converted with cv::cvtColor, as the datasets API does).
cv::Mat toGrey(const cv::Mat& img);
inline cv::Mat readGrey(const std::string& path) { return toGrey(readImage(path)); }

//! Where one frame's files lie: the left and right images and the raw Velodyne scan.
struct FramePaths
{
    std::string left, right, scan;
};
//! Frame `id` of a KITTI-layout folder: image_2/ID_10.png, image_3/ID_10.png, velodyne/ID.bin.
FramePaths kittiFramePaths(const std::string& dir, const std::string& id);
//! Frame `name` of a KITTI raw drive: image_02/data/NAME.png, image_03/data/NAME.png, velodyne_points/data/NAME.bin.
FramePaths kittiRawFramePaths(const std::string& drive, const std::string& name);

//! A matcher's CV_16S (x16) output as float pixels with -1 for "invalid".
cv::Mat disparityToFloat(const cv::Mat& disp16, int minDisparity);
//! A CV_16S matcher output as raw little-endian int16, rows top to bottom, no header (numpy.fromfile(p, '<i2')).
bool writeRawS16(const std::string& path, const cv::Mat& disp16);

} // namespace lidarsgm_fuse

#endif
