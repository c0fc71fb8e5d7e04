// This file is part of the lidarsgm module (an OpenCV extra module).
#ifndef OPENCV_LIDARSGM_PERF_PRECOMP_HPP
#define OPENCV_LIDARSGM_PERF_PRECOMP_HPP

#include "opencv2/ts.hpp"
#include "opencv2/lidarsgm.hpp"
#include "opencv2/lidarsgm/datasets.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#if CV_VERSION_MAJOR >= 5
#include "opencv2/stereo.hpp"     // cv::StereoSGBM moved from calib3d to stereo in OpenCV 5
#else
#include "opencv2/calib3d.hpp"
#endif

#endif
