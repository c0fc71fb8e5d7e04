// This file is part of the lidarsgm module (an OpenCV extra module).
#ifndef OPENCV_LIDARSGM_PRECOMP_HPP
#define OPENCV_LIDARSGM_PRECOMP_HPP
#include "opencv2/lidarsgm.hpp"
#include "opencv2/core/utility.hpp"
#include "opencv2/core/hal/intrin.hpp"
#include "opencv2/core/private.hpp"
#include "opencv2/core/utils/logger.hpp"

/* What the module raises is read by people: Python and the tool print the text as it is. So the message says what
was wrong and what to do, and the exception carries no function name (cv::Exception appends "in function '...'" only
when it has one). Internal invariants that no input can break stay CV_Assert. */
#define LIDARSGM_Error(code, msg) cv::error(code, msg, "", __FILE__, __LINE__)
#define LIDARSGM_Error_(code, args) cv::error(code, cv::format args, "", __FILE__, __LINE__)
//! Refuses an argument: `cond` must hold, else cv::Error::StsBadArg with `msg`.
#define LIDARSGM_Check(cond, msg) do { if (!(cond)) LIDARSGM_Error(cv::Error::StsBadArg, msg); } while (0)

//! A warning for people, in OpenCV's log at its WARNING level, likewise without the source location.
inline void lidarsgmWarning(const cv::String& msg)
{
    using namespace cv::utils::logging;
    if (getLogLevel() >= LOG_LEVEL_WARNING)
        internal::writeLogMessageEx(LOG_LEVEL_WARNING, nullptr, nullptr, 0, nullptr, msg.c_str());
}
#endif
