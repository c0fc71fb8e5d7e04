// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Speed against OpenCV's own matchers, in one process: on the CPU every cv::StereoSGBM mode, runs alternating; on the
// GPU cv::cuda::StereoSGM, CUDA-event medians, and the device memory one instance holds.

#include "tool.hpp"
#if CV_VERSION_MAJOR >= 5
#include "opencv2/stereo.hpp"     // cv::StereoSGBM moved from calib3d to stereo in OpenCV 5
#else
#include "opencv2/calib3d.hpp"
#endif
#include "opencv2/core/cuda.hpp"
#ifdef LIDARSGM_HAVE_CUDASTEREO
#include "opencv2/cudastereo.hpp"
#endif
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <vector>

using namespace cv;

namespace lidarsgm_fuse {

namespace {

//! A field of /proc/self/status in MB (Linux: VmRSS, VmHWM); -1 where there is none.
double procStatusMB(const char* field)
{
    std::ifstream status("/proc/self/status");
    std::string line;
    const std::string key = std::string(field) + ":";
    while (std::getline(status, line))
        if (line.compare(0, key.size(), key) == 0)
            return std::atof(line.c_str() + key.size()) * 1024.0 / 1e6;   // kB (1024 bytes) to MB
    return -1;
}

} // namespace

int runCpuTiming(const Options& o, const Frame& f, int reps)
{
    Ptr<Matcher> m = makeMatcher(o, modeFromName(o.list("modes", "sdsgm").front()), checkFromName(o.str("check", "stereo-lidar")));
    const int numD = m->getNumDisparities(), minD = m->getMinDisparity();
    // OpenCV's recommended penalties for blockSize 3 (8 and 32 x 3 x 3), uniqueness 10, left-right 1, speckles 100/2.
    const struct { int mode; const char* name; } sgbmModes[] = {
        { StereoSGBM::MODE_HH, "MODE_HH (8 paths)" }, { StereoSGBM::MODE_HH4, "MODE_HH4 (4 paths)" },
        { StereoSGBM::MODE_SGBM, "MODE_SGBM (5 paths)" }, { StereoSGBM::MODE_SGBM_3WAY, "MODE_SGBM_3WAY" } };
    std::vector<Ptr<StereoSGBM> > sgbm;
    for (const auto& s : sgbmModes)
        sgbm.push_back(StereoSGBM::create(minD, numD, 3, 72, 288, 1, 0, 10, 100, 2, s.mode));
    Mat disp;
    // The first call (buffers made): the growth of the process's peak resident memory is what one instance needs.
    // (Writing 5 to clear_refs resets the peak to the current resident size, Linux 4.0 and later.)
    std::ofstream("/proc/self/clear_refs") << "5";
    const double rssBefore = procStatusMB("VmRSS");
    m->compute(f.left, f.right, f.sparse, disp);
    const double peakAfter = procStatusMB("VmHWM");
    for (const Ptr<StereoSGBM>& s : sgbm)
        s->compute(f.left, f.right, disp);
    std::vector<std::vector<double> > t(1 + sgbm.size());
    std::vector<double> withConfidence;
    Mat confidence;
    for (int r = 0; r < reps; r++)
    {
        TickMeter a, c;
        a.start(); m->compute(f.left, f.right, f.sparse, disp); a.stop();
        t[0].push_back(a.getTimeMilli());
        c.start(); m->compute(f.left, f.right, f.sparse, disp, confidence); c.stop();
        withConfidence.push_back(c.getTimeMilli());
        for (size_t k = 0; k < sgbm.size(); k++)
        {
            TickMeter b;
            b.start(); sgbm[k]->compute(f.left, f.right, disp); b.stop();
            t[k + 1].push_back(b.getTimeMilli());
        }
    }
    const double ours = medianMs(t[0]);
    printf("timing (%d runs alternating in one process, %d threads, %dx%d, %d disparities, %d paths), medians:\n", reps,
           getNumThreads(), f.left.cols, f.left.rows, numD, m->getNumPaths());
    printf("| lidarsgm %-22s | %8.1f ms |                   |\n", modeLabel(m->getMode()), ours);
    printf("| lidarsgm %-22s | %8.1f ms | %+.1f %%           |\n",
           format("%s + confidence", modeLabel(m->getMode())).c_str(), medianMs(withConfidence),
           100.0 * (medianMs(withConfidence) / ours - 1));
    printf("cells searched: %.1f %% of width x height x disparities%s\n", 100.0 * m->getSearchedFraction(),
           m->getSearchWindow() > 0 ? format(" (disparity windows, margin %d)", m->getSearchWindow()).c_str()
                                    : " (full range)");
    if (rssBefore >= 0 && peakAfter >= 0)
        printf("working memory of one lidarsgm instance (peak resident growth over its first call): %.1f MB\n",
               peakAfter - rssBefore);
    for (size_t k = 0; k < sgbm.size(); k++)
        printf("| cv::StereoSGBM %-16s | %8.1f ms | lidarsgm / it %.2f |\n", sgbmModes[k].name, medianMs(t[k + 1]),
               ours / medianMs(t[k + 1]));
    return 0;
}

namespace {

//! CUDA-event median of fn on one stream, after a warm-up.
double eventMedian(const std::function<void(cuda::Stream&)>& fn, int reps)
{
    cuda::Stream st;
    cuda::Event e0, e1;
    for (int i = 0; i < 3; i++)
        fn(st);
    st.waitForCompletion();
    std::vector<double> t;
    for (int i = 0; i < reps; i++)
    {
        e0.record(st);
        fn(st);
        e1.record(st);
        e1.waitForCompletion();
        t.push_back(cuda::Event::elapsedTime(e0, e1));
    }
    return medianMs(t);
}

//! Device memory a freshly made matcher holds after its first call.
template <class M, class Call>
double heldMB(const M& matcher, const Call& firstCall)
{
    cuda::DeviceInfo info;
    const size_t before = info.freeMemory();
    firstCall(matcher);
    cuda::Stream::Null().waitForCompletion();
    const size_t after = info.freeMemory();
    return before > after ? (before - after) / 1048576.0 : 0.0;
}

} // namespace

int runCudaTiming(const Options& o, const Frame& f, int reps)
{
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    cuda::GpuMat gl(f.left), gr(f.right), gs(f.sparse), gd;
    const Ptr<Matcher> probe = makeMatcher(o, Matcher::MODE_SDSGM, check);
    const int numD = probe->getNumDisparities(), paths = probe->getNumPaths();
    printf("device: %s, %dx%d, %d disparities, %d paths, median of %d CUDA-event timings (ms)\n",
           cuda::DeviceInfo().name(), f.left.cols, f.left.rows, numD, paths, reps);
    const int modes[3] = { Matcher::MODE_SDSGM, Matcher::MODE_DSGM, Matcher::MODE_SGM };
    for (int k = 0; k < 3 * o.i("rounds", 1); k++)
    {
        Ptr<Matcher> m = makeMatcher(o, modes[k % 3], check);
        const double mb = heldMB(m, [&](const Ptr<Matcher>& x) { x->compute(gl, gr, gs, gd); });
        const double ms = eventMedian([&](cuda::Stream& st) { m->compute(gl, gr, gs, gd, st); }, reps);
        printf("| lidarsgm %-5s | %8.3f ms | device memory held %.1f MB |\n", modeLabel(modes[k % 3]), ms, mb);
        if (k == 0)
        {
            // The same call with the confidence map.
            cuda::GpuMat gc;
            const double msc = eventMedian([&](cuda::Stream& st) { m->compute(gl, gr, gs, gd, gc, st); }, reps);
            printf("| lidarsgm %-5s + confidence | %8.3f ms | %+.1f %% |\n", modeLabel(modes[k % 3]), msc,
                   100.0 * (msc / ms - 1));
            if (m->getSearchWindow() > 0)
                printf("cells searched: %.1f %% of width x height x disparities (disparity windows, margin %d)\n",
                       100.0 * m->getSearchedFraction(), m->getSearchWindow());
        }
    }
    // Throughput: k instances, each on its own stream, frames handed round-robin; page-locked input and output, so
    // one instance's uploads and downloads overlap the others' kernels. Frames per second over 200 frames.
    double oneFps = 0;
    for (int k : { 1, 2, 4 })
    {
        std::vector<Ptr<Matcher> > ms;
        std::vector<cuda::Stream> st(k);
        std::vector<cuda::GpuMat> dl(k), dr(k), ds(k), dd(k);
        std::vector<cuda::HostMem> out(k);
        cuda::HostMem hl(f.left), hr(f.right), hs(f.sparse);
        for (int j = 0; j < k; j++)
        {
            ms.push_back(makeMatcher(o, Matcher::MODE_SDSGM, check));
            ms[j]->compute(gl, gr, gs, dd[j], st[j]);   // buffers made
        }
        cuda::Stream::Null().waitForCompletion();
        const int frames = 200;
        TickMeter tm;
        tm.start();
        for (int i = 0; i < frames; i++)
        {
            const int j = i % k;
            st[j].waitForCompletion();   // this instance's previous frame is back
            dl[j].upload(hl, st[j]);
            dr[j].upload(hr, st[j]);
            ds[j].upload(hs, st[j]);
            ms[j]->compute(dl[j], dr[j], ds[j], dd[j], st[j]);
            dd[j].download(out[j], st[j]);
        }
        for (cuda::Stream& s : st)
            s.waitForCompletion();
        tm.stop();
        const double fps = frames / tm.getTimeSec();
        if (k == 1)
            oneFps = fps;
        printf("| %d SDSGM instance(s), own streams, upload + compute + download | %7.1f frames/s | %.2f x one |\n", k,
               fps, fps / oneFps);
    }
#ifdef LIDARSGM_HAVE_CUDASTEREO
    for (int p = 8; p >= 4; p -= 4)
    {
        try
        {
            Ptr<cuda::StereoSGM> sgm = cuda::createStereoSGM(0, numD, 10, 120, 5,
                                                              p == 8 ? cuda::StereoSGM::MODE_HH : cuda::StereoSGM::MODE_HH4);
            const double mb = heldMB(sgm, [&](const Ptr<cuda::StereoSGM>& x) { x->compute(gl, gr, gd); });
            const double ms = eventMedian([&](cuda::Stream& st) { sgm->compute(gl, gr, gd, st); }, reps);
            printf("| cv::cuda::StereoSGM %d paths | %8.3f ms | device memory held %.1f MB |\n", p, ms, mb);
        }
        catch (const cv::Exception& e)
        {
            printf("| cv::cuda::StereoSGM %d paths | failed: %s |\n", p, e.what());
        }
    }
#endif
    return 0;
}

} // namespace lidarsgm_fuse
