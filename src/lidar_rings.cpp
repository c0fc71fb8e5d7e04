// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// A Velodyne scan's laser rings, from its points in the driver's order: counted, and thinned to every n-th ring to
// stand for a sparser LiDAR (the paper's Table VI).

#include "precomp.hpp"
#include <algorithm>
#include <cmath>

namespace cv { namespace lidarsgm {

namespace {

//! The start of each ring of a scan in the driver's order, and the end: ring r is rows [start[r], start[r + 1]).
std::vector<int> ringStarts(const Mat& points)
{
    LIDARSGM_Check(points.type() == CV_32FC1, "lidarsgm: the scan must be CV_32FC1");
    LIDARSGM_Check(points.cols >= 3, "lidarsgm: the scan needs x, y, z columns");
    std::vector<int> start(1, 0);
    double prev = 0;
    for (int i = 0; i < points.rows; i++)
    {
        const float* p = points.ptr<float>(i);
        double az = std::atan2((double)p[1], (double)p[0]) * 180.0 / CV_PI;
        if (az < 0)
            az += 360.0;
        if (i > 0 && az < prev - 90.0)
            start.push_back(i);
        prev = az;
    }
    start.push_back(points.rows);
    return start;
}

} // namespace

int countLidarRings(InputArray points_)
{
    return (int)ringStarts(points_.getMat()).size() - 1;
}

Mat selectLidarRings(InputArray points_, int keepEvery, int firstRing)
{
    const Mat points = points_.getMat();
    LIDARSGM_Check(keepEvery >= 1, "lidarsgm: keepEvery must be at least 1");
    LIDARSGM_Check(firstRing >= 0, "lidarsgm: firstRing must be in [0, keepEvery)");
    LIDARSGM_Check(firstRing < keepEvery, "lidarsgm: firstRing must be in [0, keepEvery)");
    const std::vector<int> start = ringStarts(points);
    const int rings = (int)start.size() - 1;
    if (keepEvery == 1)
        return points.clone();
    std::vector<std::pair<double, int> > order;   // (-median elevation, ring): top ring first
    for (int r = 0; r < rings; r++)
    {
        std::vector<double> el;
        for (int i = start[r]; i < start[r + 1]; i++)
        {
            const float* p = points.ptr<float>(i);
            el.push_back(std::atan2((double)p[2], std::hypot((double)p[0], (double)p[1])));
        }
        std::nth_element(el.begin(), el.begin() + el.size() / 2, el.end());
        order.push_back(std::make_pair(-el[el.size() / 2], r));
    }
    std::sort(order.begin(), order.end());
    Mat out;
    for (int k = firstRing; k < rings; k += keepEvery)
        out.push_back(points.rowRange(start[order[k].second], start[order[k].second + 1]));
    return out.empty() ? Mat(0, points.cols, CV_32FC1) : out;
}

}} // namespace cv::lidarsgm
