// This file is part of the lidarsgm module (an OpenCV extra module).
#include "perf_precomp.hpp"

CV_PERF_TEST_MAIN(lidarsgm)
