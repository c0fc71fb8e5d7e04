// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Speed against OpenCV's own matchers, in one process: on the CPU every cv::StereoSGBM mode, runs alternating; on the
// GPU cv::cuda::StereoSGM, CUDA-event medians, and the device memory one instance holds.

#include "tool.hpp"
#if CV_VERSION_MAJOR >= 5
#include "opencv2/stereo.hpp"     // cv::StereoSGBM is in stereo in OpenCV 5, calib3d in 4
#else
#include "opencv2/calib3d.hpp"
#endif
#include "opencv2/core/cuda.hpp"
#ifdef LIDARSGM_HAVE_CUDASTEREO
#include "opencv2/cudastereo.hpp"
#endif
#ifdef LIDARSGM_HAVE_CUDA_DRIVER_API
#include "opencv2/core/cuda_stream_accessor.hpp"
#include <cuda.h>
#include <cudaProfiler.h>
#include <dlfcn.h>
#endif
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
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

#ifdef LIDARSGM_HAVE_CUDA_DRIVER_API
/* A stream whose kernels run on N of the device's SMs: a CUDA green context (driver API, CUDA 12.4 and later), for a
small GPU's parallelism on a big one (the whole card's L2 and memory bandwidth stay). The driver is opened at run time,
so that the tool also runs where there is none. The runtime's kernels and memory of the primary context work on such
a stream; its timings use the driver's events, which any copy of the runtime can use on it. */
class GreenStream
{
public:
    //! Empty why() when the stream is made; else why it cannot be (no driver, no green contexts, too few SMs).
    explicit GreenStream(int smCount)
    {
        lib_ = dlopen("libcuda.so.1", RTLD_NOW | RTLD_LOCAL);
        if (!lib_)
        {
            why_ = "the CUDA driver (libcuda.so.1) cannot be opened";
            return;
        }
#define LIDARSGM_STRING2(x) #x
#define LIDARSGM_STRING(x) LIDARSGM_STRING2(x)   // the name cuda.h maps it to (cuEventElapsedTime_v2, ...)
#define LIDARSGM_LOAD(fn) fn##_ = (decltype(&fn))dlsym(lib_, LIDARSGM_STRING(fn))
        LIDARSGM_LOAD(cuInit); LIDARSGM_LOAD(cuDeviceGet); LIDARSGM_LOAD(cuDeviceGetDevResource);
        LIDARSGM_LOAD(cuDevSmResourceSplitByCount); LIDARSGM_LOAD(cuDevResourceGenerateDesc);
        LIDARSGM_LOAD(cuGreenCtxCreate); LIDARSGM_LOAD(cuGreenCtxStreamCreate); LIDARSGM_LOAD(cuGreenCtxDestroy);
        LIDARSGM_LOAD(cuStreamDestroy); LIDARSGM_LOAD(cuEventCreate); LIDARSGM_LOAD(cuEventRecord);
        LIDARSGM_LOAD(cuEventSynchronize); LIDARSGM_LOAD(cuEventElapsedTime); LIDARSGM_LOAD(cuEventDestroy);
        LIDARSGM_LOAD(cuProfilerStart); LIDARSGM_LOAD(cuProfilerStop);
#undef LIDARSGM_LOAD
        if (!cuGreenCtxCreate_ || !cuGreenCtxStreamCreate_ || !cuDevSmResourceSplitByCount_ || !cuEventElapsedTime_)
        {
            why_ = "this CUDA driver has no green contexts (they need driver 550 / CUDA 12.4 or later)";
            return;
        }
        CUdevice dev;
        CUdevResource all, part, rest;
        CUdevResourceDesc desc;
        unsigned groups = 1;
        if (cuInit_(0) != CUDA_SUCCESS || cuDeviceGet_(&dev, cuda::getDevice()) != CUDA_SUCCESS ||
            cuDeviceGetDevResource_(dev, &all, CU_DEV_RESOURCE_TYPE_SM) != CUDA_SUCCESS)
        {
            why_ = "the device's SMs cannot be queried (cuDeviceGetDevResource)";
            return;
        }
        total_ = (int)all.sm.smCount;
        if (smCount > total_ ||
            cuDevSmResourceSplitByCount_(&part, &groups, &all, &rest, 0, (unsigned)smCount) != CUDA_SUCCESS ||
            groups != 1 || cuDevResourceGenerateDesc_(&desc, &part, 1) != CUDA_SUCCESS ||
            cuGreenCtxCreate_(&ctx_, desc, dev, CU_GREEN_CTX_DEFAULT_STREAM) != CUDA_SUCCESS ||
            cuGreenCtxStreamCreate_(&stream_, ctx_, CU_STREAM_NON_BLOCKING, 0) != CUDA_SUCCESS)
        {
            why_ = format("the device's %d SMs give no green context of %d", total_, smCount);
            return;
        }
        sms_ = (int)part.sm.smCount;
    }
    ~GreenStream()
    {
        if (stream_)
            cuStreamDestroy_(stream_);
        if (ctx_)
            cuGreenCtxDestroy_(ctx_);
        if (lib_)
            dlclose(lib_);
    }
    /* Marks the calls a profiler sees when it starts with profiling off (ncu --profile-from-start off): the
    partition's SDSGM calls, per kernel (tools/device_check.sh, SM_PROFILE). No-ops without a profiler. */
    void profile(bool on) const
    {
        if (on && cuProfilerStart_)
            cuProfilerStart_();
        if (!on && cuProfilerStop_)
            cuProfilerStop_();
    }
    const std::string& why() const { return why_; }
    int sms() const { return sms_; }
    int totalSms() const { return total_; }
    cuda::Stream stream() const { return cuda::StreamAccessor::wrapStream((cudaStream_t)stream_); }

    //! Driver-event median of fn on the green stream, after a warm-up.
    double median(const std::function<void(cuda::Stream&)>& fn, int reps) const
    {
        cuda::Stream st = stream();
        CUevent e0, e1;
        cuEventCreate_(&e0, CU_EVENT_DEFAULT);
        cuEventCreate_(&e1, CU_EVENT_DEFAULT);
        for (int i = 0; i < 3; i++)
            fn(st);
        std::vector<double> t;
        for (int i = 0; i < reps; i++)
        {
            cuEventRecord_(e0, stream_);
            fn(st);
            cuEventRecord_(e1, stream_);
            cuEventSynchronize_(e1);
            float ms = 0;
            cuEventElapsedTime_(&ms, e0, e1);
            t.push_back(ms);
        }
        cuEventDestroy_(e0);
        cuEventDestroy_(e1);
        return medianMs(t);
    }

private:
    void* lib_ = nullptr;
    CUgreenCtx ctx_ = nullptr;
    CUstream stream_ = nullptr;
    int sms_ = 0, total_ = 0;
    std::string why_;
#define LIDARSGM_POINTER(fn) decltype(&fn) fn##_ = nullptr;
    LIDARSGM_POINTER(cuInit) LIDARSGM_POINTER(cuDeviceGet) LIDARSGM_POINTER(cuDeviceGetDevResource)
    LIDARSGM_POINTER(cuDevSmResourceSplitByCount) LIDARSGM_POINTER(cuDevResourceGenerateDesc)
    LIDARSGM_POINTER(cuGreenCtxCreate) LIDARSGM_POINTER(cuGreenCtxStreamCreate) LIDARSGM_POINTER(cuGreenCtxDestroy)
    LIDARSGM_POINTER(cuStreamDestroy) LIDARSGM_POINTER(cuEventCreate) LIDARSGM_POINTER(cuEventRecord)
    LIDARSGM_POINTER(cuEventSynchronize) LIDARSGM_POINTER(cuEventElapsedTime) LIDARSGM_POINTER(cuEventDestroy)
    LIDARSGM_POINTER(cuProfilerStart) LIDARSGM_POINTER(cuProfilerStop)
#undef LIDARSGM_POINTER
};
#endif

/* The SDSGM call and cv::cuda::StereoSGM (8 and 4 paths) on N SMs, as the whole card's table times them: the
partition's figures beside the whole card's. Returns 2 where no such partition can be made. */
int runSmCountTiming(const Options& o, const cuda::GpuMat& gl, const cuda::GpuMat& gr, const cuda::GpuMat& gs,
                     int check, int numD, int reps)
{
#ifdef LIDARSGM_HAVE_CUDA_DRIVER_API
    const int n = o.i("sm-count", 0);
    GreenStream green(n);
    if (!green.why().empty())
    {
        fprintf(stderr, "lidarsgm_fuse: --sm-count %d: %s\n", n, green.why().c_str());
        return 2;
    }
    printf("on %d of the device's %d SMs (a CUDA green context), median of %d driver-event timings (ms)\n",
           green.sms(), green.totalSms(), reps);
    cuda::GpuMat gd;
    const int modes[3] = { Matcher::MODE_SDSGM, Matcher::MODE_DSGM, Matcher::MODE_SGM };
    for (int mode : modes)
    {
        Ptr<Matcher> m = makeMatcher(o, mode, check);
        green.profile(mode == Matcher::MODE_SDSGM);
        const double ms = green.median([&](cuda::Stream& st) { m->compute(gl, gr, gs, gd, st); }, reps);
        green.profile(false);
        printf("| %d SMs: lidarsgm %-5s | %8.3f ms |\n", green.sms(), modeLabel(mode), ms);
    }
#ifdef LIDARSGM_HAVE_CUDASTEREO
    for (int p = 8; p >= 4; p -= 4)
    {
        // As on the whole card: where StereoSGM rejects the call (it asserts at 256 disparities), its row says so.
        try
        {
            Ptr<cuda::StereoSGM> sgm = cuda::createStereoSGM(0, numD, 10, 120, 5,
                                                              p == 8 ? cuda::StereoSGM::MODE_HH : cuda::StereoSGM::MODE_HH4);
            const double ms = green.median([&](cuda::Stream& st) { sgm->compute(gl, gr, gd, st); }, reps);
            printf("| %d SMs: cv::cuda::StereoSGM %d paths | %8.3f ms |\n", green.sms(), p, ms);
        }
        catch (const cv::Exception& e)
        {
            printf("| %d SMs: cv::cuda::StereoSGM %d paths | failed: %s |\n", green.sms(), p, e.what());
        }
    }
#endif
    return 0;
#else
    CV_UNUSED(gl); CV_UNUSED(gr); CV_UNUSED(gs); CV_UNUSED(check); CV_UNUSED(numD); CV_UNUSED(reps);
    fprintf(stderr, "lidarsgm_fuse: --sm-count %s: this tool was built without the CUDA driver's header (cuda.h)\n",
            o.str("sm-count").c_str());
    return 2;
#endif
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
    if (o.has("sm-count"))
        return runSmCountTiming(o, gl, gr, gs, check, numD, reps);
    return 0;
}

} // namespace lidarsgm_fuse
