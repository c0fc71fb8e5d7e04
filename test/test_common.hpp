// This file is part of the lidarsgm module (an OpenCV extra module).
// Inputs shared by several test files.
#ifndef OPENCV_LIDARSGM_TEST_COMMON_HPP
#define OPENCV_LIDARSGM_TEST_COMMON_HPP

#include "test_precomp.hpp"
#include "lidarsgm_eval.hpp"

namespace opencv_test {

//! A shipped KITTI frame (testdata/kitti): grey pair and the raw scan projected to a CV_32F sparse map.
inline void loadKittiTestFrame(const std::string& id, Mat& l, Mat& r, Mat& s)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    lidarsgm_eval::KittiCalib c = lidarsgm_eval::readKittiCalib(dir + "/calib.txt");
    l = imread(dir + "/image_2/" + id + "_10.png", IMREAD_GRAYSCALE);
    r = imread(dir + "/image_3/" + id + "_10.png", IMREAD_GRAYSCALE);
    ASSERT_FALSE(l.empty() || r.empty()) << id;
    cv::lidarsgm::projectPointsToDisparity(lidarsgm_eval::readVelodyne(dir + "/velodyne/" + id + ".bin"),
                                           c.P2, c.lidarToCamera, c.focalBaseline, l.size(), s);
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
