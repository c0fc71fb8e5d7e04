// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The KITTI devkit's error scale, written once for colorizeDisparityError (src/addons/evaluation.cpp) and the legend that
// explains it (src/addons/legend.cpp).

#ifndef OPENCV_LIDARSGM_ERROR_BANDS_HPP
#define OPENCV_LIDARSGM_ERROR_BANDS_HPP

namespace cv { namespace lidarsgm { namespace detail {

//! A band of the error over the D1 threshold, [lo, hi), and its colour.
struct ErrorBand
{
    float lo, hi;
    unsigned char r, g, b;
};

//! Doublings from 1/16 to 16 of the threshold; 1 and above are D1 outliers.
static const ErrorBand ERROR_BANDS[10] = {
    { 0.f, 0.0625f, 49, 54, 149 }, { 0.0625f, 0.125f, 69, 117, 180 }, { 0.125f, 0.25f, 116, 173, 209 },
    { 0.25f, 0.5f, 171, 217, 233 }, { 0.5f, 1.f, 224, 243, 248 }, { 1.f, 2.f, 254, 224, 144 },
    { 2.f, 4.f, 253, 174, 97 }, { 4.f, 8.f, 244, 109, 67 }, { 8.f, 16.f, 215, 48, 39 }, { 16.f, 1e30f, 165, 0, 38 } };

}}} // namespace cv::lidarsgm::detail

#endif
