// This file is part of the lidarsgm module (an OpenCV extra module).
// Inputs shared by several test files.
#ifndef OPENCV_LIDARSGM_TEST_COMMON_HPP
#define OPENCV_LIDARSGM_TEST_COMMON_HPP

#include "test_precomp.hpp"

namespace opencv_test {

//! A shipped KITTI frame (testdata/kitti): grey pair and the raw scan projected to a CV_32F sparse map.
inline void loadKittiTestFrame(const std::string& id, Mat& l, Mat& r, Mat& s)
{
    const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(cvtest::findDataDirectory("kitti"), id);
    l = f.left;
    r = f.right;
    s = f.sparse;
}

//! Uncorrelated 8-bit images and a sparse map with about 4 % of the pixels set to disparities in [1, 60).
inline void randomInputs(Size sz, RNG& rng, Mat& l, Mat& r, Mat& s)
{
    l.create(sz, CV_8UC1);
    r.create(sz, CV_8UC1);
    s = Mat(sz, CV_32FC1, Scalar::all(0));
    rng.fill(l, RNG::UNIFORM, 0, 256);
    rng.fill(r, RNG::UNIFORM, 0, 256);
    for (int k = 0; k < sz.area() / 25 + 1; k++)
        s.at<float>(rng.uniform(0, sz.height), rng.uniform(0, sz.width)) = (float)rng.uniform(1.0, 60.0);
}

} // namespace

#endif
