// This file is part of the lidarsgm module (an OpenCV extra module).
#ifndef OPENCV_LIDARSGM_PRECOMP_HPP
#define OPENCV_LIDARSGM_PRECOMP_HPP
#include "opencv2/lidarsgm.hpp"
#include "opencv2/core/utility.hpp"
#include "opencv2/core/hal/intrin.hpp"
#include "opencv2/core/private.hpp"
#endif
