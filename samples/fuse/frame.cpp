// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// One frame: fuse it with each mode, print the time and (with ground truth) the KITTI devkit's figures, write the
// outputs, then the timing run if asked for.

#include "tool.hpp"
#include "opencv2/core/cuda.hpp"
#include <algorithm>
#include <cstdio>

using namespace cv;

namespace lidarsgm_fuse {

int runFrame(const Options& o, Frame& f)
{
    const std::vector<std::string> modes = o.list("modes", "sdsgm");
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const std::string out = o.str("out");
    if (!out.empty())
        makeDir(out);
    const bool wantConfidence = writesConfidence(o, out);
    PassRows lidarCheck;
    const Mat fused = checkFrameLidar(o, f, lidarCheck);
    printResiduals({ std::make_pair(f.name, (const PassRows*)&lidarCheck) });
    for (const std::string& name : modes)
    {
        Ptr<Matcher> m = makeMatcher(o, modeFromName(name), check);
        if (lidarCheck.stereoAlone)   // the LiDAR misplaced on the images
            m = lidarsgm::LidarFailSafe::stereoAloneMatcher(m);
        const int mode = m->getMode();
        const int minD = m->getMinDisparity();
        Mat disp, confidence;
        TickMeter tm;
        if (o.has("cuda"))
        {
            cuda::GpuMat gl(f.left), gr(f.right), gs, gd, gc;
            if (!fused.empty())
                gs.upload(fused);
            tm.start();
            if (wantConfidence)
                m->compute(gl, gr, gs, gd, gc);
            else
                m->compute(gl, gr, gs, gd);
            gd.download(disp);
            if (wantConfidence)
                gc.download(confidence);
            tm.stop();
        }
        else
        {
            tm.start();
            if (wantConfidence)
                m->compute(f.left, f.right, fused, disp, confidence);
            else
                m->compute(f.left, f.right, fused, disp);
            tm.stop();
        }
        printf("%s %-6s check %-12s %s %8.1f ms", f.name.c_str(), modeLabel(mode), checkLabel(check),
               o.has("cuda") ? "CUDA" : "CPU ", tm.getTimeMilli());
        if (!f.groundTruth.empty())
        {
            const lidarsgm::DisparityErrors s = lidarsgm::evaluateDisparity(disp, f.groundTruth, lidarsgm::METRIC_KITTI_D1, 0, minD);
            printf("  coverage %6.2f %%  covered D1 %5.2f %%  total D1 %5.2f %%", s.coverage(), s.coveredError(),
                   s.totalError());
        }
        printf("\n");
        if (wantConfidence && !f.groundTruth.empty())
        {
            Row row;
            row.label = std::string(modeLabel(mode)) + " (" + checkLabel(check) + ")";
            row.confidence = lidarsgm::evaluateConfidence(disp, confidence, f.groundTruth, lidarsgm::METRIC_KITTI_D1,
                                                          2.0, minD);
            printConfidence(row, "D1", "frame " + f.name);
        }
        if (!out.empty())
            writeDisparity(o, out, modes.size() > 1 ? "_" + name : "", disp, minD, m->getNumDisparities(), f,
                           confidence);
    }
    if (!out.empty())
    {
        const Ptr<Matcher> sdsgm = makeMatcher(o, Matcher::MODE_SDSGM, check);
        Mat semi;
        if (std::find(modes.begin(), modes.end(), "sdsgm") != modes.end())
            sdsgm->semidensify(f.left, f.right, f.sparse, semi);
        writeInputs(out, f, sdsgm->getMinDisparity(), sdsgm->getNumDisparities(), semi);
        printf("wrote %s/: disparity (%s), colour and error pictures, LiDAR points\n", out.c_str(),
               o.str("format", "kitti").c_str());
    }
    const int reps = o.i("timing", 0);
    if (reps > 0)
        return o.has("cuda") ? runCudaTiming(o, f, reps) : runCpuTiming(o, f, reps);
    return 0;
}

} // namespace lidarsgm_fuse
