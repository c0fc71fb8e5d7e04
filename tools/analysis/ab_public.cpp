// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// One process of tools/analysis/ab_public.sh: create() calls on KITTI 000002 of testdata through the public API only
// (so that a library built before an API change can be preloaded in its place); prints the median time of RUNS calls
// after one warm-up, in ms.
//   ab_public TESTDATA_KITTI_DIR RUNS THREADS

#include "opencv2/lidarsgm.hpp"
#include "opencv2/lidarsgm/datasets.hpp"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

int main(int argc, char** argv)
{
    if (argc < 4)
        return 2;
    cv::setNumThreads(std::atoi(argv[3]));
    const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(argv[1], "000002");
    cv::Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create();
    cv::Mat d;
    m->compute(f.left, f.right, f.sparse, d);
    std::vector<double> t;
    for (int i = 0; i < std::atoi(argv[2]); i++)
    {
        cv::TickMeter tm;
        tm.start();
        m->compute(f.left, f.right, f.sparse, d);
        tm.stop();
        t.push_back(tm.getTimeMilli());
    }
    std::sort(t.begin(), t.end());
    std::printf("%.1f\n", t.empty() ? 0.0 : t[t.size() / 2]);
    return 0;
}
