// This file is part of the lidarsgm module (an OpenCV extra module).
#ifndef OPENCV_LIDARSGM_TEST_PRECOMP_HPP
#define OPENCV_LIDARSGM_TEST_PRECOMP_HPP

#include "opencv2/ts.hpp"
#include "opencv2/lidarsgm.hpp"
#include "opencv2/lidarsgm/calibration.hpp"
#include "opencv2/lidarsgm/datasets.hpp"
#include "opencv2/lidarsgm/evaluation.hpp"
#include "opencv2/lidarsgm/rig.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include <thread>

#endif
