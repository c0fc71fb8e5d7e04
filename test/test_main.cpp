// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"

#if defined(HAVE_HPX)
    #include <hpx/hpx_main.hpp>
#endif

CV_TEST_MAIN("")
