// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// A Middlebury folder: every scene folder in it, 1 % of the ground truth as the sparse input (the paper's indoor
// protocol), bad-N per scene and summed over the scenes.

#include "tool.hpp"
#include <cmath>
#include <cstdio>
#include <set>

using namespace cv;

namespace lidarsgm_fuse {

namespace {

//! The scenes of dir: its sub-folders (cv::glob lists files; the scenes are the folders that hold them) that hold a
//! known layout, in name order.
std::vector<Frame> findScenes(const std::string& dir)
{
    std::vector<String> files;
    glob(dir + "/*", files, true);
    std::set<std::string> folders;
    for (const String& file : files)
    {
        const std::string rel = file.substr(dir.size() + 1);
        const size_t slash = rel.find('/');
        if (slash != std::string::npos && rel.find('/', slash + 1) == std::string::npos)
            folders.insert(rel.substr(0, slash));
    }
    std::vector<Frame> scenes;
    for (const std::string& name : folders)
    {
        Frame f;
        f.name = name;
        try
        {
            lidarsgm::loadMiddleburyScene(dir + "/" + name, f.left, f.right, f.groundTruth);
            scenes.push_back(f);
        }
        catch (const cv::Exception&)
        {
            // not a scene (or not a readable one): the folder is skipped
        }
    }
    return scenes;
}

} // namespace

int runMiddlebury(const Options& o)
{
    const std::string dir = o.str("middlebury"), out = o.str("out");
    std::vector<Frame> scenes = findScenes(dir);
    const std::vector<std::string> modes = o.list("modes", "sgm,dsgm,sdsgm");
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const int seed = o.i("seed", 1);
    const double badN = o.d("bad", 2.0);
    printf("Middlebury %s: 1 %% of the ground truth as sparse input (seed %d), bad-%.0f errors, check %s\n",
           dir.c_str(), seed, badN, checkLabel(check));
    if (scenes.empty())
        CV_Error(Error::StsObjectNotFound, "no Middlebury scene (im0/im1/disp0.pfm, im2/im6/disp2.png, "
                                           "view1/view5/disp1.png) in the folders of " + dir);
    printf("| %-20s | ndisp | %-6s | coverage | covered bad | total bad |       ms |\n", "scene", "mode");
    printf("|----------------------|-------|--------|----------|-------------|-----------|----------|\n");
    std::vector<Row> rows(modes.size());
    for (size_t k = 0; k < modes.size(); k++)
        rows[k].label = std::string(modeLabel(modeFromName(modes[k]))) + " (" + checkLabel(check) + ")";
    TickMeter total;
    total.start();
    for (size_t s = 0; s < scenes.size(); s++)
    {
        Frame& f = scenes[s];
        const std::string frameOut = out.empty() ? "" : out + "/" + f.name;
        if (!frameOut.empty())
            makeDir(frameOut);
        // The scene's range: its largest ground-truth disparity, rounded up to a multiple of 16 (at least 64);
        // --num-disparities overrides it.
        double maxGt = 0;
        minMaxLoc(f.groundTruth, nullptr, &maxGt);
        const int ndisp = std::min(256, std::max(64, ((int)std::ceil(maxGt) + 1 + 15) / 16 * 16));
        f.sparse = lidarsgm::sampleGroundTruth(f.groundTruth, 0.01, seed);
        for (size_t k = 0; k < modes.size(); k++)
        {
            Ptr<Matcher> m = makeMatcher(o, modeFromName(modes[k]), check, ndisp);
            Mat disp;
            TickMeter tm;
            tm.start();
            m->compute(f.left, f.right, f.sparse, disp);
            tm.stop();
            rows[k].ms.push_back(tm.getTimeMilli());
            const lidarsgm::DisparityErrors st = lidarsgm::evaluateDisparity(disp, f.groundTruth, lidarsgm::METRIC_BAD, badN,
                                                                              m->getMinDisparity());
            rows[k].stats.add(st);
            printf("| %-20s | %5d | %-6s | %6.2f %% | %9.2f %% | %7.2f %% | %8.1f |\n", f.name.c_str(),
                   m->getNumDisparities(), modeLabel(modeFromName(modes[k])), st.coverage(), st.coveredError(),
                   st.totalError(), tm.getTimeMilli());
            fflush(stdout);
            if (!frameOut.empty())
            {
                Frame noErrorPicture = f;   // KITTI's error colours do not fit bad-N: no error picture here
                noErrorPicture.groundTruth.release();
                writeDisparity(o, frameOut, "_" + modes[k], disp, m->getMinDisparity(), m->getNumDisparities(),
                               noErrorPicture);
                if (k == 0)
                {
                    const Ptr<Matcher> sdsgm = makeMatcher(o, Matcher::MODE_SDSGM, check, ndisp);
                    Mat semi;
                    sdsgm->semidensify(f.left, f.right, f.sparse, semi);
                    writeInputs(frameOut, f, sdsgm->getMinDisparity(), sdsgm->getNumDisparities(), semi);
                }
            }
        }
        total.stop();
        progress(o, s + 1, s + 1, scenes.size(), total.getTimeSec());
        total.start();
    }
    printTable(format("Middlebury %s: %zu scenes, bad-%g (sums over scenes), %d threads", dir.c_str(), scenes.size(),
                      badN, getNumThreads()), format("bad-%g", badN), rows);
    return 0;
}

} // namespace lidarsgm_fuse
