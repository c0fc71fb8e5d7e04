// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#include "files.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include <fstream>

namespace lidarsgm_fuse {

cv::Mat readImage(const std::string& path, const std::string& what)
{
    // Tested first: imread would log its own warning before this message.
    if (!std::ifstream(path).good())
        CV_Error(cv::Error::StsObjectNotFound, "cannot read " + what + " " + path + ": no such file, or not readable");
    cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (img.empty())
        CV_Error(cv::Error::StsObjectNotFound, "cannot read " + what + " " + path + ": not an image format OpenCV "
                                               "decodes");
    return img;
}

cv::Mat toGrey(const cv::Mat& img)
{
    cv::Mat g;
    if (img.channels() == 3)
        cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
    else if (img.channels() == 4)
        cv::cvtColor(img, g, cv::COLOR_BGRA2GRAY);
    else
        g = img;
    return g;
}

FramePaths kittiFramePaths(const std::string& dir, const std::string& id)
{
    return { dir + "/image_2/" + id + "_10.png", dir + "/image_3/" + id + "_10.png", dir + "/velodyne/" + id + ".bin" };
}

FramePaths kittiRawFramePaths(const std::string& drive, const std::string& name)
{
    return { drive + "/image_02/data/" + name + ".png", drive + "/image_03/data/" + name + ".png",
             drive + "/velodyne_points/data/" + name + ".bin" };
}

cv::Mat disparityToFloat(const cv::Mat& disp16, int minDisparity)
{
    cv::Mat d;
    disp16.convertTo(d, CV_32F, 1.0 / 16);
    d.setTo(-1.f, disp16 <= (minDisparity - 1) * 16);
    return d;
}

bool writeRawS16(const std::string& path, const cv::Mat& disp16)
{
    CV_Assert(disp16.type() == CV_16SC1);
    std::ofstream out(path.c_str(), std::ios::binary);
    for (int y = 0; y < disp16.rows && out; y++)
        out.write(disp16.ptr<char>(y), (std::streamsize)disp16.cols * 2);
    return (bool)out;
}

} // namespace lidarsgm_fuse
