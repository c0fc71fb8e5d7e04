// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// One frame of a KITTI folder run, by one worker (FrameWorker): each mode, Table V's checks and the semidense map,
// scored with the devkit's rules, the files written. A worker keeps its matchers between frames (their buffers stay);
// with --cuda it also keeps its own stream and page-locked host buffers, so that the workers' uploads, kernels and
// downloads overlap each other and the other workers' reading and writing on the CPU.

#include "tool.hpp"
#include "opencv2/core/cuda.hpp"
#include <algorithm>
#include <limits>

using namespace cv;

namespace lidarsgm_fuse {

namespace {

lidarsgm::DisparityErrors score(const Mat& disp, const Mat& gt, int minD)
{
    return lidarsgm::evaluateDisparity(disp, gt, lidarsgm::METRIC_KITTI_D1, 0, minD);
}

//! One matcher call of a frame: its matcher, whether it is semidensify(), and its output.
struct Job
{
    Ptr<Matcher> m;
    int check;
    bool semidense;
    Mat out;
    double ms;
    Mat confidence;   //!< where --format confidence asks for it (the modes' jobs)
};

//! The modes (3 at most), Table V's checks (4), the semidense map.
const int kMaxJobs = 8;

} // namespace

struct FrameWorker::Gpu
{
    cuda::Stream stream;
    cuda::HostMem in[3], out[kMaxJobs], conf[kMaxJobs];   // page-locked: left, right, sparse; outputs per job
    cuda::GpuMat gin[3], gout[kMaxJobs], gconf[kMaxJobs];
    cuda::Event start[kMaxJobs], stop[kMaxJobs];

    //! src in page-locked memory, then uploaded on the stream (returns at once).
    void upload(int i, const Mat& src)
    {
        in[i].create(src.size(), src.type());
        Mat h = in[i].createMatHeader();
        src.copyTo(h);
        gin[i].upload(in[i], stream);
    }
};

FrameWorker::FrameWorker(const Options& o) : o_(o), gpu_(o.has("cuda") ? new Gpu : nullptr) {}

FrameWorker::~FrameWorker()
{
    delete gpu_;
}

Ptr<Matcher> FrameWorker::matcher(int mode, int check)
{
    Ptr<Matcher>& m = matchers_[mode * 4 + check];
    if (m.empty())
        m = makeMatcher(o_, mode, check);
    return m;
}

Ptr<Matcher> FrameWorker::stereoAlone(const Ptr<Matcher>& m)
{
    Ptr<Matcher>& a = alone_[m.get()];
    if (a.empty())
        a = lidarsgm::LidarFailSafe::stereoAloneMatcher(m);
    return a;
}

Mat checkFrameLidar(const Options& o, const Frame& f, PassRows& fr)
{
    if (f.sparse.empty())
        return f.sparse;
    const lidarsgm::LidarCheck c = lidarsgm::LidarFailSafe::create(o.has("trust-lidar"))->check(f.left, f.right, f.sparse);
    fr.residual = c.residual;
    fr.shiftedResidual = c.shiftedResidual;
    fr.shift = c.shift;
    fr.turn = c.turn;
    fr.misplaced = !c.trusted;
    fr.stereoAlone = c.stereoAlone || o.has(kLidarLeftOut);
    if (cvIsNaN(c.residual))
        fr.residualFailure = format("fewer than 200 LiDAR pixels can be compared with the images");
    // A map without values, as LidarFailSafe::compute passes its stereo-alone matcher.
    return fr.stereoAlone ? Mat::zeros(f.sparse.size(), f.sparse.type()) : f.sparse;
}

void printResiduals(const std::vector<std::pair<std::string, const PassRows*> >& frames)
{
    std::vector<double> r;
    std::string worst, above, failed, misplaced;
    double largest = -1;
    bool alone = false;
    for (const auto& f : frames)
    {
        const double v = f.second->residual;
        if (f.second->misplaced)
        {
            const std::string turn = f.second->turn != 0 ? format("turned %.2f degrees and ", f.second->turn) : "";
            misplaced += format("%s%s (%.2f px, %.2f %smoved by (%d, %d))", misplaced.empty() ? "" : ", ",
                                f.first.c_str(), v, f.second->shiftedResidual, turn.c_str(), f.second->shift.x,
                                f.second->shift.y);
            alone = alone || f.second->stereoAlone;
        }
        if (v != v)
            failed += (failed.empty() ? "" : ", ") + f.first;
        if (!(v >= 0))
            continue;
        r.push_back(v);
        if (v > largest)
        {
            largest = v;
            worst = f.first;
        }
        if (v > lidarsgm::LidarFailSafe::maxResidual())
            above += (above.empty() ? "" : ", ") + f.first;
    }
    if (r.size() == 1)
        printf("matching residual (the LiDAR against the images, cv::lidarsgm::matchingResidual): %.2f px (%s)\n",
               largest, worst.c_str());
    else if (!r.empty())
    {
        std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
        printf("matching residual (the LiDAR against the images, cv::lidarsgm::matchingResidual): median %.2f px over "
               "%zu frame(s), largest %.2f px (%s)\n", r[r.size() / 2], r.size(), largest, worst.c_str());
    }
    if (!above.empty())
        printf("  above %.0f px, where the LiDAR pulls the fusion off the images (check that the sparse input holds "
               "disparities of the left view in pixels, x 256 in a 16-bit PNG, not depth; then the calibration: "
               "--check-calibration, and with --kitti or --kitti-raw --refine-calibration): %s\n",
               lidarsgm::LidarFailSafe::maxResidual(), above.c_str());
    if (!misplaced.empty())
        printf("  the LiDAR misplaced on the images (cv::lidarsgm::LidarFailSafe: moving the points lowers the residual by "
               "a fifth or more; check the calibration: --refine-calibration), %s: %s\n",
               alone ? "fused as stereo alone" : "fused anyway (--trust-lidar)", misplaced.c_str());
    if (!failed.empty())
        printf("  not measured (the images cannot tell): %s\n", failed.c_str());
}

void FrameWorker::compute(const Frame& f, const std::string& frameOut, PassRows& fr)
{
    const std::vector<std::string> modes = o_.list("modes", "sgm,dsgm,sdsgm");
    const int check = checkFromName(o_.str("check", "stereo-lidar"));
    const bool wantConfidence = writesConfidence(o_, frameOut);
    std::vector<Job> jobs;
    for (const std::string& name : modes)
        jobs.push_back({ matcher(modeFromName(name), check), check, false, Mat(), 0.0, Mat() });
    for (size_t c = 0; c < fr.table5.size(); c++)
        jobs.push_back({ matcher(Matcher::MODE_SDSGM, (int)c), (int)c, false, Mat(), 0.0, Mat() });
    jobs.push_back({ matcher(Matcher::MODE_SDSGM, check), check, true, Mat(), 0.0, Mat() });
    const auto fuseAlone = [&]() {
        for (Job& j : jobs)
            if (!j.semidense)
                j.m = stereoAlone(j.m);
    };
    const auto withConfidence = [&](size_t j) { return wantConfidence && j < modes.size(); };
    CV_Assert(jobs.size() <= (size_t)kMaxJobs);
    // The semidense map is the LiDAR's own (scored as such); the fusions take `fused`: the LiDAR, or none (and plain
    // SGM) where it lands misplaced on the images (the fail-safe, checkFrameLidar).
    if (gpu_)
    {
        // Everything enqueued on this worker's stream, one wait at the end; the check runs on the CPU meanwhile, and
        // a frame it condemns (rare) has its fusions enqueued again without the LiDAR.
        Gpu& g = *gpu_;
        g.upload(0, f.left);
        g.upload(1, f.right);
        const auto enqueue = [&](const Mat& sparse, bool fusionsOnly) {
            g.upload(2, sparse);
            for (size_t j = 0; j < jobs.size(); j++)
            {
                if (fusionsOnly && jobs[j].semidense)
                    continue;
                g.start[j].record(g.stream);
                if (jobs[j].semidense)
                    jobs[j].m->semidensify(g.gin[0], g.gin[1], g.gin[2], g.gout[j], g.stream);
                else if (withConfidence(j))
                    jobs[j].m->compute(g.gin[0], g.gin[1], g.gin[2], g.gout[j], g.gconf[j], g.stream);
                else
                    jobs[j].m->compute(g.gin[0], g.gin[1], g.gin[2], g.gout[j], g.stream);
                g.stop[j].record(g.stream);
                g.out[j].create(g.gout[j].size(), g.gout[j].type());
                g.gout[j].download(g.out[j], g.stream);
                if (withConfidence(j))
                {
                    g.conf[j].create(g.gconf[j].size(), g.gconf[j].type());
                    g.gconf[j].download(g.conf[j], g.stream);
                }
            }
        };
        enqueue(f.sparse, false);
        const Mat fused = checkFrameLidar(o_, f, fr);
        if (fr.stereoAlone)
        {
            g.stream.waitForCompletion();   // the upload buffer of the sparse map is reused
            fuseAlone();
            enqueue(fused, true);
        }
        g.stream.waitForCompletion();
        for (size_t j = 0; j < jobs.size(); j++)
        {
            jobs[j].out = g.out[j].createMatHeader();
            jobs[j].ms = cuda::Event::elapsedTime(g.start[j], g.stop[j]);
            if (withConfidence(j))
                jobs[j].confidence = g.conf[j].createMatHeader();
        }
    }
    else
    {
        const Mat fused = checkFrameLidar(o_, f, fr);
        if (fr.stereoAlone)
            fuseAlone();
        for (size_t k = 0; k < jobs.size(); k++)
        {
            Job& j = jobs[k];
            TickMeter tm;
            tm.start();
            if (j.semidense)
                j.m->semidensify(f.left, f.right, f.sparse, j.out);
            else if (withConfidence(k))
                j.m->compute(f.left, f.right, fused, j.out, j.confidence);
            else
                j.m->compute(f.left, f.right, fused, j.out);
            tm.stop();
            j.ms = tm.getTimeMilli();
        }
    }
    const bool scored = !f.groundTruth.empty();   // raw drives may have no ground truth: times and files only
    for (size_t k = 0; k < modes.size(); k++)
    {
        const Job& j = jobs[k];
        if (scored)
            fr.modes[k].stats = score(j.out, f.groundTruth, j.m->getMinDisparity());
        if (scored && !j.confidence.empty())
            fr.modes[k].confidence = lidarsgm::evaluateConfidence(j.out, j.confidence, f.groundTruth,
                                                                  lidarsgm::METRIC_KITTI_D1, 2.0, j.m->getMinDisparity());
        fr.modes[k].ms.push_back(j.ms);
        if (!frameOut.empty())
            writeDisparity(o_, frameOut, "_" + modes[k], j.out, j.m->getMinDisparity(), j.m->getNumDisparities(), f,
                           j.confidence);
    }
    const Job& semi = jobs.back();
    if (scored)
    {
        for (size_t c = 0; c < fr.table5.size(); c++)
            fr.table5[c].stats = score(jobs[modes.size() + c].out, f.groundTruth, jobs[modes.size() + c].m->getMinDisparity());
        Mat sp = f.sparse.clone();
        sp.setTo(-1.f, f.sparse <= 0);
        fr.lidar.stats = score(sp, f.groundTruth, 0);
        fr.semi.stats = score(semi.out, f.groundTruth, semi.m->getMinDisparity());
    }
    if (!frameOut.empty())
        writeInputs(frameOut, f, semi.m->getMinDisparity(), semi.m->getNumDisparities(), semi.out);
}

} // namespace lidarsgm_fuse
