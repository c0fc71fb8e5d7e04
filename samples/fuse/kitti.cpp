// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// A KITTI-layout folder: every frame of frames.txt with each mode, sums of the devkit's counts over the frames, one
// summary table per LiDAR line count (the paper's Tables III-VI).

#include "tool.hpp"
#include <cstdio>

using namespace cv;
using namespace lidarsgm_data;

namespace lidarsgm_fuse {

namespace {

lidarsgm::DisparityErrors score(const Mat& disp, const Mat& gt, int minD)
{
    return lidarsgm::evaluateDisparity(disp, gt, lidarsgm::METRIC_KITTI_D1, 0, minD);
}

void kittiPass(const Options& o, const std::vector<std::string>& ids, int lines, bool lineTitle)
{
    const std::string dir = o.str("kitti"), out = o.str("out");
    const std::vector<std::string> modes = o.list("modes", "sgm,dsgm,sdsgm");
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const bool table5 = o.has("table5");
    std::vector<Row> rows(modes.size()), t5(4);
    for (size_t k = 0; k < modes.size(); k++)
        rows[k].label = std::string(modeLabel(modeFromName(modes[k]))) + " (" + checkLabel(check) + ")";
    for (int c = 0; c < 4; c++)
        t5[c].label = std::string("SDSGM (") + checkLabel(c) + ")";
    Row lidar, semi;
    lidar.label = "LiDAR points alone";
    semi.label = "semidense map (SDSGM input)";

    TickMeter total;
    total.start();
    for (size_t n = 0; n < ids.size(); n++)
    {
        Frame f = loadKittiFrame(dir, ids[n], 64 / lines);
        if (f.gt.empty())
            CV_Error(Error::StsObjectNotFound, "no ground truth for frame " + ids[n] + " in " + dir + "/disp_occ_0");
        std::string frameOut = out.empty() ? "" : out + "/" + ids[n] + (lineTitle ? format("_%dlines", lines) : "");
        if (!frameOut.empty())
            makeDir(frameOut);
        for (size_t k = 0; k < modes.size(); k++)
        {
            Ptr<Matcher> m = makeMatcher(o, modeFromName(modes[k]), check);
            Mat disp;
            TickMeter tm;
            tm.start();
            m->compute(f.left, f.right, f.sparse, disp);
            tm.stop();
            rows[k].stats.add(score(disp, f.gt, m->getMinDisparity()));
            rows[k].ms.push_back(tm.getTimeMilli());
            if (!frameOut.empty())
                writeDisparity(o, frameOut, "_" + modes[k], disp, m->getMinDisparity(), m->getNumDisparities(), f.gt);
        }
        for (int c = 0; table5 && c < 4; c++)
        {
            Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, c);
            Mat disp;
            m->compute(f.left, f.right, f.sparse, disp);
            t5[c].stats.add(score(disp, f.gt, m->getMinDisparity()));
        }
        Mat sp = f.sparse.clone();
        sp.setTo(-1.f, f.sparse <= 0);
        lidar.stats.add(score(sp, f.gt, 0));
        Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, check);
        Mat sd;
        m->semidensify(f.left, f.right, f.sparse, sd);
        semi.stats.add(score(sd, f.gt, m->getMinDisparity()));
        if (!frameOut.empty())
            writeInputs(frameOut, f, m, true);
        total.stop();
        progress(o, n + 1, ids.size(), total.getTimeSec());
        total.start();
    }
    const std::string title = format("KITTI %s: %zu frames%s, D1 (KITTI devkit rules), sums over frames, %d threads",
                                     dir.c_str(), ids.size(), lineTitle ? format(", %d LiDAR lines", lines).c_str() : "",
                                     getNumThreads());
    rows.push_back(lidar);
    printTable(title, "D1", rows);
    printf("| %-28s | %6.2f %% | %11.2f %% | %11s | %8s |\n", semi.label.c_str(), semi.stats.coverage(),
           semi.stats.coveredError(), "-", "-");
    if (table5)
        printTable("Consistency checks on SDSGM (the paper's Table V)", "D1", t5);
}

} // namespace

int runKittiFolder(const Options& o)
{
    const std::vector<std::string> ids = kittiFrameIds(o.str("kitti"));
    if (ids.empty())
        CV_Error(Error::StsObjectNotFound, o.str("kitti") + "/frames.txt lists no frame");
    const std::vector<int> lines = lidarLineCounts(o);
    for (int n : lines)
        kittiPass(o, ids, n, lines.size() > 1 || n != 64);
    return 0;
}

} // namespace lidarsgm_fuse
