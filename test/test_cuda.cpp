// This file is part of the lidarsgm module (an OpenCV extra module).
// The CUDA path against the CPU path: bit for bit. These tests run where a CUDA device exists and skip otherwise.
#include "test_common.hpp"
#include "opencv2/core/cuda.hpp"
#ifdef HAVE_CUDA
#include "opencv2/core/cuda_stream_accessor.hpp"
#include <cuda_runtime.h>
#endif

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;

static void compareCpuGpu(const Ptr<StereoLidarSGM>& m, const Mat& l, const Mat& r, const Mat& s, const std::string& what)
{
    Mat cpu, gpuOut;
    m->compute(l, r, s, cpu);
    cuda::GpuMat gl(l), gr(r), gs, gd;
    if (!s.empty())
        gs.upload(s);
    m->compute(gl, gr, gs, gd);
    gd.download(gpuOut);
    ASSERT_EQ(cpu.type(), gpuOut.type()) << what;
    ASSERT_EQ(cpu.size(), gpuOut.size()) << what;
    EXPECT_EQ(0, cvtest::norm(cpu, gpuOut, NORM_INF)) << what;
    // The confidence map, and the disparity beside it.
    Mat confCpu, confGpu, cpu2, gpu2;
    cuda::GpuMat gd2, gconf;
    m->compute(l, r, s, cpu2, confCpu);
    m->compute(gl, gr, gs, gd2, gconf);
    gd2.download(gpu2);
    gconf.download(confGpu);
    EXPECT_EQ(0, cvtest::norm(cpu, cpu2, NORM_INF)) << what << " (with confidence, CPU)";
    EXPECT_EQ(0, cvtest::norm(cpu, gpu2, NORM_INF)) << what << " (with confidence, CUDA)";
    ASSERT_EQ(CV_32FC1, confGpu.type()) << what;
    EXPECT_EQ(0, cvtest::norm(confCpu, confGpu, NORM_INF)) << what << " (confidence)";
    if (!s.empty())
    {
        Mat semiCpu, semiGpu;
        m->semidensify(l, r, s, semiCpu);
        cuda::GpuMat gsemi;
        m->semidensify(gl, gr, gs, gsemi);
        gsemi.download(semiGpu);
        EXPECT_EQ(0, cvtest::norm(semiCpu, semiGpu, NORM_INF)) << what << " (semidense)";
    }
}

// Both shipped frames x every mode x every check x 4/8 paths; one test per combination, named for it, so a
// sanitizer run can pick a few (racecheck takes about half a minute per KITTI-size combination).
typedef testing::TestWithParam<tuple<int, int, int, int> > Lidarsgm_CUDA_Kitti;
TEST_P(Lidarsgm_CUDA_Kitti, bit_exact)
{
    requireCudaDevice();
    const char* ids[] = { "000002", "000046" };
    const int frame = get<0>(GetParam()), mode = get<1>(GetParam()), check = get<2>(GetParam()), paths = get<3>(GetParam());
    Mat l, r, s;
    loadKittiTestFrame(ids[frame], l, r, s);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
    m->setNumPaths(paths);
    compareCpuGpu(m, l, r, s, format("frame %s mode %d check %d paths %d", ids[frame], mode, check, paths));
}
static std::string kittiName(const testing::TestParamInfo<tuple<int, int, int, int> >& info)
{
    const char* modes[] = { "SGM", "DSGM", "SDSGM" };
    const char* checks[] = { "none", "stereo", "camera_lidar", "stereo_lidar" };
    return format("f%s_%s_%s_p%d", get<0>(info.param) ? "000046" : "000002", modes[get<1>(info.param)],
                  checks[get<2>(info.param)], get<3>(info.param));
}
INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_CUDA_Kitti,
    testing::Combine(testing::Values(0, 1), testing::Values(0, 1, 2), testing::Values(0, 1, 2, 3), testing::Values(4, 8)),
    kittiName);

// The median filter off (the parameterised test above runs the default, on): both frames, every mode, the checks
// that read the filtered maps.
TEST(Lidarsgm_CUDA, kitti_median_off_bit_exact)
{
    requireCudaDevice();
    for (const char* id : { "000002", "000046" })
    {
        Mat l, r, s;
        loadKittiTestFrame(id, l, r, s);
        for (int mode = 0; mode < 3; mode++)
            for (int check : { (int)StereoLidarSGM::CHECK_STEREO, (int)StereoLidarSGM::CHECK_STEREO_LIDAR })
            {
                Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
                m->setMedianSize(1);
                compareCpuGpu(m, l, r, s, format("frame %s mode %d check %d median off", id, mode, check));
            }
    }
}

// The units check on the device counts what the CPU counts: the same refusal (the same message), the same warning once,
// and a map whose values only partly miss the range runs, on the same bits as the CPU.
TEST(Lidarsgm_CUDA, units_check_as_the_cpu)
{
    requireCudaDevice();
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    Mat png = cv::lidarsgm::encodeKittiDisparity(s), asFloat;
    png.convertTo(asFloat, CV_32F);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    cv::cuda::GpuMat gl(l), gr(r), gs(asFloat), gd;
    std::string cpu, gpu;
    Mat d;
    try { m->compute(l, r, asFloat, d); } catch (const cv::Exception& e) { cpu = e.err; }
    try { m->compute(gl, gr, gs, gd); } catch (const cv::Exception& e) { gpu = e.err; }
    EXPECT_NE(std::string::npos, cpu.find("divide it by 256")) << cpu;
    EXPECT_EQ(cpu, gpu);
    cv::cuda::Stream stream;
    try { m->compute(gl, gr, gs, gd, stream); gpu.clear(); } catch (const cv::Exception& e) { gpu = e.err; }
    EXPECT_EQ(cpu, gpu) << "on a stream";
    // The 16-bit map as it is runs, bit for bit as on the CPU.
    compareCpuGpu(m, l, r, png, "KITTI x256 map as CV_16U");
    {
        CapturedLog log;
        const Mat nan(s.size(), CV_32F, Scalar::all(std::numeric_limits<float>::quiet_NaN()));
        Ptr<StereoLidarSGM> n = StereoLidarSGM::create();
        cv::cuda::GpuMat gnan(nan);
        n->compute(gl, gr, gnan, gd);
        n->compute(gl, gr, gnan, gd);
        const std::string said = log.str();
        EXPECT_NE(std::string::npos, said.find("has no value in the search range")) << said;
        EXPECT_EQ(said.find("no value in"), said.rfind("no value in")) << "twice: " << said;
    }
}

// The steps beyond the paper that doc/params/kitti_best.yml switches on (visibility filter, edge-aware P2, ring
// interpolation, the copied priors' weight), both frames, every mode, 4 and 8 paths.
TEST(Lidarsgm_CUDA, kitti_best_configuration_bit_exact)
{
    requireCudaDevice();
    for (const char* id : { "000002", "000046" })
    {
        Mat l, r, s;
        loadKittiTestFrame(id, l, r, s);
        for (int mode = 0; mode < 3; mode++)
            for (int paths : { 4, 8 })
            {
                Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode);
                setKittiBestSteps(*m);
                m->setNumPaths(paths);
                compareCpuGpu(m, l, r, s, format("frame %s mode %d paths %d, kitti_best steps", id, mode, paths));
            }
    }
}

// The disparity windows: both shipped frames, every mode and check, 4 and 8 paths, with kitti_best.yml's steps; the
// share of the cells searched is the CPU's; a margin of the whole range gives the full range's output.
TEST(Lidarsgm_CUDA, search_windows_bit_exact)
{
    requireCudaDevice();
    for (const char* id : { "000002", "000046" })
    {
        Mat l, r, s;
        loadKittiTestFrame(id, l, r, s);
        for (int mode = 0; mode < 3; mode++)
            for (int check = 0; check < 4; check++)
                for (int paths : { 4, 8 })
                {
                    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
                    if (check == 3)
                        setKittiBestSteps(*m);
                    m->setNumPaths(paths);
                    m->setSearchWindow(4);
                    const std::string what = format("frame %s mode %d check %d paths %d, windows", id, mode, check, paths);
                    compareCpuGpu(m, l, r, s, what);
                    Mat d;
                    m->compute(l, r, s, d);
                    const double cpuFraction = m->getSearchedFraction();
                    cuda::GpuMat gl(l), gr(r), gs(s), gd;
                    m->compute(gl, gr, gs, gd);
                    EXPECT_EQ(cpuFraction, m->getSearchedFraction()) << what;
                    EXPECT_LT(cpuFraction, 0.6) << what;
                }
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
        cuda::GpuMat gl(l), gr(r), gs(s), full, wide;
        m->compute(gl, gr, gs, full);
        m->setSearchWindow(128);
        m->compute(gl, gr, gs, wide);
        EXPECT_EQ(1.0, m->getSearchedFraction());
        Mat a, b;
        full.download(a);
        wide.download(b);
        EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF)) << id << ": margin 128 against the full range";
    }
}

// The windows' sums are stored compactly: a windowed instance holds less device memory than a full-range one, by at
// least the cells it does not search less the layout's slack (tiles padded at the image's edges, an eighth of headroom).
TEST(Lidarsgm_CUDA, search_windows_shrink_device_memory)
{
    requireCudaDevice();
#ifdef HAVE_CUDA
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    cuda::GpuMat gl(l), gr(r), gs(s), gd;
    const auto held = [&](int margin, double& fraction) {
        size_t before = 0, after = 0, total = 0;
        EXPECT_EQ(cudaSuccess, cudaDeviceSynchronize());
        EXPECT_EQ(cudaSuccess, cudaMemGetInfo(&before, &total));
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
        m->setSearchWindow(margin);
        m->compute(gl, gr, gs, gd);
        EXPECT_EQ(cudaSuccess, cudaDeviceSynchronize());
        EXPECT_EQ(cudaSuccess, cudaMemGetInfo(&after, &total));
        fraction = m->getSearchedFraction();
        return (double)before - (double)after;   // m still holds its buffers here
    };
    double fullFraction = 0, fraction = 0;
    const double full = held(0, fullFraction), windowed = held(4, fraction);
    const double volume = (double)l.total() * 128 * sizeof(ushort);
    ASSERT_EQ(1.0, fullFraction);
    ASSERT_LT(fraction, 0.5);
    EXPECT_LE(windowed, full - (1 - 1.3 * fraction) * volume)
        << "full range " << full / 1048576 << " MB, windows (" << fraction << " of the cells) " << windowed / 1048576
        << " MB";
#endif
}

// A uniform pair (every cost 0: no unique winner anywhere) and a pair uniform in its left half.
TEST(Lidarsgm_CUDA, flat_images_bit_exact)
{
    requireCudaDevice();
    Mat l(40, 130, CV_8UC1, Scalar::all(128)), r = l.clone(), s(l.size(), CV_32FC1, Scalar::all(0));
    s.at<float>(20, 60) = 12.f;
    for (int mode = 0; mode < 3; mode++)
        compareCpuGpu(StereoLidarSGM::create(0, 64, 10, 120, 5, 160, 0.7, mode), l, r, s, format("flat, mode %d", mode));
    RNG rng(3);
    rng.fill(l.colRange(65, 130), RNG::UNIFORM, 0, 256);
    l.copyTo(r);
    for (int mode = 0; mode < 3; mode++)
        compareCpuGpu(StereoLidarSGM::create(0, 64, 10, 120, 5, 160, 0.7, mode), l, r, s, format("half flat, mode %d", mode));
}

typedef testing::TestWithParam<tuple<Size, int, int> > Lidarsgm_CUDA_Random;
TEST_P(Lidarsgm_CUDA_Random, bit_exact)
{
    requireCudaDevice();
    const Size sz = get<0>(GetParam());
    const int numD = get<1>(GetParam()), minD = get<2>(GetParam());
    RNG rng((uint64)(sz.area() * 131 + numD * 7 + minD + 1000));
    for (int depth = 0; depth < 2; depth++)
    {
        Mat l(sz, depth ? CV_16UC1 : CV_8UC1), r(sz, l.type());
        rng.fill(l, RNG::UNIFORM, 0, depth ? 65536 : 256);
        rng.fill(r, RNG::UNIFORM, 0, depth ? 65536 : 256);
        GaussianBlur(l, l, Size(3, 3), 0);
        GaussianBlur(r, r, Size(3, 3), 0);
        Mat s32(sz, CV_32FC1, Scalar::all(0));
        for (int i = 0; i < sz.area() / 20 + 1; i++)
            s32.at<float>(rng.uniform(0, sz.height), rng.uniform(0, sz.width)) = (float)rng.uniform(minD - 2.0, minD + numD + 2.0);
        Mat s16;
        s32.convertTo(s16, CV_16U, 256);
        Mat full(sz, CV_32FC1);
        rng.fill(full, RNG::UNIFORM, std::max(minD, 1), minD + numD);
        // Rings: every 5th row, every 2nd pixel (a LiDAR scan by the scan test: the copied priors' weight applies).
        Mat rings(sz, CV_32FC1, Scalar::all(0));
        for (int y = 0; y < sz.height; y += 5)
            for (int x = y % 2; x < sz.width; x += 2)
                rings.at<float>(y, x) = (float)rng.uniform(minD - 1.0, minD + numD + 1.0);
        const Mat sparses[] = { s32, s16, Mat(sz, CV_32FC1, Scalar::all(0)), full, rings };
        for (int k = 0; k < 5; k++)
            for (int mode = 0; mode < 3; mode++)
            {
                Ptr<StereoLidarSGM> m = StereoLidarSGM::create(minD, numD, 10, 120, 5, 160, 0.7, mode, (mode + k) % 4);
                m->setNumPaths(k % 2 ? 4 : 8);
                m->setSubpixel(mode != 1);
                m->setOutputType(k == 3 ? CV_32F : CV_16S);
                m->setMedianSize((k + mode) % 2 ? 1 : 3);
                m->setVisibilityRadiusX(k == 1 ? mode : 0);   // mode 0: a vertical window only
                m->setVisibilityRadiusY(k == 1 ? 3 : 0);
                m->setVisibilityParallax(k == 1 || k == 3 ? 0.125 * (mode + 1) : 0.0);   // k 3: growth alone
                m->setEdgeThreshold(k == 2 || mode == 2 ? (depth ? 4000 : 16) : 0);
                m->setRingGapFactor(k == 0 || k == 1 || k == 4 ? 1.5 * (k % 3 + 1) : 0.0);
                m->setSemidenseWeight(k == 0 || k == 4 ? 0.25 + 0.25 * mode : 1.0);
                m->setSearchWindow((k + mode) % 3 == 1 ? 1 + 2 * k : 0);   // a third of the cases with windows
                compareCpuGpu(m, l, r, sparses[k], format("size %dx%d depth %d sparse %d mode %d", sz.width, sz.height, depth, k, mode));
            }
    }
}
INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_CUDA_Random,
    testing::Values(make_tuple(Size(1, 1), 16, 0), make_tuple(Size(7, 3), 16, 0), make_tuple(Size(1, 37), 64, -5),
                    make_tuple(Size(53, 1), 64, 3), make_tuple(Size(97, 61), 64, 0), make_tuple(Size(333, 111), 128, -7),
                    make_tuple(Size(257, 190), 256, 0), make_tuple(Size(130, 77), 48, 2),
                    // 160 and 176: a warp lane's run of 6 disparities passes the last one
                    make_tuple(Size(75, 40), 160, 0), make_tuple(Size(64, 33), 176, -3),
                    // 224: lanes in groups of 4 disparities, the second group held by only some lanes
                    make_tuple(Size(90, 50), 224, -2),
                    // 320 to 512: five to eight pairs per lane (in groups of 2 where even), a negative minDisparity
                    make_tuple(Size(610, 21), 512, -9), make_tuple(Size(400, 17), 464, 0),
                    make_tuple(Size(350, 13), 336, -1)));

// Every shared KITTI frame and Middlebury scene (LIDARSGM_SHARED_DATA, set by the README's test command to
// ../shared/data): CPU and CUDA outputs equal. KITTI frames use sparse16/<id>.png when present (pre-projected raw
// scans, for machines the scans cannot travel to), else project velodyne/<id>.bin.
TEST(Lidarsgm_CUDA, shared_data_bit_exact)
{
    requireCudaDevice();
    const char* env = getenv("LIDARSGM_SHARED_DATA");
    if (!env || !std::ifstream((std::string(env) + "/kitti2015_lidar/frames.txt").c_str()).good())
        throw SkipTestException("LIDARSGM_SHARED_DATA does not point at the shared data");
    const std::string kitti = std::string(env) + "/kitti2015_lidar";
    std::ifstream list((kitti + "/frames.txt").c_str());
    std::string id;
    int frames = 0;
    while (list >> id)
    {
        // Packed for the GPU machine (tools/make_device_data.py): grey images and the projected scans as PNGs.
        const Mat s16 = imread(kitti + "/sparse16/" + id + ".png", IMREAD_UNCHANGED);
        Mat l, r, s = s16;
        if (s16.empty())
        {
            const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(kitti, id);
            l = f.left;
            r = f.right;
            s = f.sparse;
        }
        else
        {
            l = imread(kitti + "/image_2/" + id + "_10.png", IMREAD_UNCHANGED);   // stored grey
            r = imread(kitti + "/image_3/" + id + "_10.png", IMREAD_UNCHANGED);
        }
        ASSERT_FALSE(l.empty() || r.empty() || s.empty()) << id;
        for (int mode = 0; mode < 3; mode++)
            compareCpuGpu(StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode), l, r, s, "KITTI " + id + format(" mode %d", mode));
        frames++;
    }
    EXPECT_EQ(20, frames);
    const char* scenes[] = { "Aloe", "Cloth3", "Motorcycle_quarter", "Reindeer", "Wood2", "cone" };
    for (int i = 0; i < 6; i++)
    {
        Mat l, r, gt;
        ASSERT_NO_THROW(cv::lidarsgm::loadMiddleburyScene(std::string(env) + "/middlebury/" + scenes[i], l, r, gt)) << scenes[i];
        Mat s = cv::lidarsgm::sampleGroundTruth(gt, 0.01, 1);
        for (int mode = 0; mode < 3; mode++)
            compareCpuGpu(StereoLidarSGM::create(0, 256, 10, 120, 5, 160, 0.7, mode), l, r, s, format("%s mode %d", scenes[i], mode));
    }
}

TEST(Lidarsgm_CUDA, projection_bit_exact)
{
    requireCudaDevice();
    const std::string dir = cvtest::findDataDirectory("kitti");
    cv::lidarsgm::KittiCalibration c = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    const char* ids[] = { "000002", "000046" };
    for (int i = 0; i < 2; i++)
    {
        Mat pts4 = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/" + ids[i] + ".bin");
        Mat pts3 = pts4.colRange(0, 3).clone();
        for (int dtype = 0; dtype < 2; dtype++)
        {
            const int t = dtype ? CV_16U : CV_32F;
            Mat cpu, gpuOut;
            cv::lidarsgm::projectPointsToDisparity(pts4, c.projection, c.lidarToCamera, c.focalBaseline, Size(1242, 375), cpu, t);
            cuda::GpuMat g4(pts4), g3(pts3), gd;
            cv::lidarsgm::projectPointsToDisparity(g4, c.projection, c.lidarToCamera, c.focalBaseline, Size(1242, 375), gd, t);
            gd.download(gpuOut);
            EXPECT_EQ(0, cvtest::norm(cpu, gpuOut, NORM_INF)) << ids[i] << " dtype " << t;
            cuda::Stream stream;
            cv::cuda::projectPointsToDisparity(g3, c.projection, c.lidarToCamera, c.focalBaseline, Size(1242, 375), gd, t, stream);
            stream.waitForCompletion();
            gd.download(gpuOut);
            EXPECT_EQ(0, cvtest::norm(cpu, gpuOut, NORM_INF)) << ids[i] << " N x 3, dtype " << t;
        }
    }
}

TEST(Lidarsgm_CUDA, roi_input)
{
    requireCudaDevice();
    RNG rng(11);
    Mat bigL(200, 300, CV_8UC1), bigR(200, 300, CV_8UC1), bigS(200, 300, CV_32FC1, Scalar::all(0));
    rng.fill(bigL, RNG::UNIFORM, 0, 256);
    rng.fill(bigR, RNG::UNIFORM, 0, 256);
    for (int i = 0; i < 2000; i++)
        bigS.at<float>(rng.uniform(0, 200), rng.uniform(0, 300)) = (float)rng.uniform(1.0, 60.0);
    const Rect roi(13, 7, 211, 123);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 64);
    Mat cpu, gpuOut;
    m->compute(bigL(roi), bigR(roi), bigS(roi), cpu);
    cuda::GpuMat gl(bigL), gr(bigR), gs(bigS), gd;
    m->compute(gl(roi), gr(roi), gs(roi), gd);  // non-contiguous GpuMat views
    gd.download(gpuOut);
    EXPECT_EQ(0, cvtest::norm(cpu, gpuOut, NORM_INF));
}

// One instance, calls on two streams without synchronising in between: the instance orders them on the GPU, so each
// output equals the CPU result (without that ordering the second call overwrites buffers the first still reads).
TEST(Lidarsgm_CUDA, one_instance_two_streams)
{
    requireCudaDevice();
    Mat l[2], r[2], s[2], cpu[2];
    loadKittiTestFrame("000002", l[0], r[0], s[0]);
    loadKittiTestFrame("000046", l[1], r[1], s[1]);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    for (int i = 0; i < 2; i++)
        m->compute(l[i], r[i], s[i], cpu[i]);
    cuda::GpuMat gl[2], gr[2], gs[2], gd[6];
    for (int i = 0; i < 2; i++)
    {
        gl[i].upload(l[i]); gr[i].upload(r[i]); gs[i].upload(s[i]);
    }
    cuda::Stream st[2];
    for (int round = 0; round < 3; round++)
        for (int i = 0; i < 2; i++)
            m->compute(gl[i], gr[i], gs[i], gd[2 * round + i], st[(i + round) % 2]);
    st[0].waitForCompletion();
    st[1].waitForCompletion();
    for (int k = 0; k < 6; k++)
    {
        Mat out;
        gd[k].download(out);
        EXPECT_EQ(0, cvtest::norm(cpu[k % 2], out, NORM_INF)) << "call " << k;
    }
#ifdef HAVE_CUDA
    // A graph capture on another stream than the previous call's is refused with a message, not left to luck.
    cudaStream_t cs = cuda::StreamAccessor::getStream(st[1]);
    m->compute(gl[0], gr[0], gs[0], gd[0], st[0]);
    ASSERT_EQ(cudaSuccess, cudaStreamBeginCapture(cs, cudaStreamCaptureModeThreadLocal));
    std::string msg;
    try { m->compute(gl[0], gr[0], gs[0], gd[0], st[1]); }
    catch (const cv::Exception& e) { msg = e.what(); }
    cudaGraph_t graph = nullptr;
    EXPECT_EQ(cudaSuccess, cudaStreamEndCapture(cs, &graph));
    if (graph)
        cudaGraphDestroy(graph);
    EXPECT_NE(std::string::npos, msg.find("same stream")) << msg;
    st[0].waitForCompletion();
#endif
}

// Several instances on several threads, each on its own stream, at once: the same outputs as alone.
TEST(Lidarsgm_CUDA, instances_on_threads)
{
    requireCudaDevice();
    Mat l[2], r[2], s[2];
    loadKittiTestFrame("000002", l[0], r[0], s[0]);
    loadKittiTestFrame("000046", l[1], r[1], s[1]);
    const int T = 6;
    std::vector<Mat> expected(T);
    for (int t = 0; t < T; t++)
        StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, t % 3)->compute(l[t % 2], r[t % 2], s[t % 2], expected[t]);
    std::vector<double> err(T, -1);
    std::vector<std::string> failure(T);
    std::vector<std::thread> threads;
    for (int t = 0; t < T; t++)
        threads.emplace_back([&, t] {
            try
            {
                Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, t % 3);
                cuda::Stream stream;
                cuda::GpuMat gl(l[t % 2]), gr(r[t % 2]), gs(s[t % 2]), gd;
                double worst = 0;
                for (int k = 0; k < 10; k++)
                {
                    m->compute(gl, gr, gs, gd, stream);
                    Mat out;
                    gd.download(out, stream);
                    stream.waitForCompletion();
                    worst = std::max(worst, cvtest::norm(expected[t], out, NORM_INF));
                }
                err[t] = worst;
            }
            catch (const std::exception& e) { failure[t] = e.what(); }
        });
    for (auto& th : threads)
        th.join();
    for (int t = 0; t < T; t++)
        EXPECT_EQ(0, err[t]) << "thread " << t << " " << failure[t];
}

// Sizes, disparity ranges and output types change between calls of one instance: each result equals a fresh
// instance's CPU result.
TEST(Lidarsgm_CUDA, size_change_between_calls)
{
    requireCudaDevice();
    const Size sizes[] = { Size(320, 240), Size(1242, 375), Size(7, 5), Size(320, 240), Size(97, 300) };
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 64);
    RNG rng(5);
    for (int i = 0; i < 5; i++)
    {
        Mat l, r, s;
        randomInputs(sizes[i], rng, l, r, s);
        m->setNumDisparities(i % 2 ? 128 : 64);
        m->setOutputType(i % 2 ? CV_32F : CV_16S);
        compareCpuGpu(m, l, r, s, format("call %d", i));
    }
}

// 3840x2160 with 256 disparities: runs, and equals the CPU.
TEST(Lidarsgm_CUDA, size_3840x2160)
{
    requireCudaDevice();
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    resize(l, l, Size(3840, 2160), 0, 0, INTER_LINEAR);
    resize(r, r, Size(3840, 2160), 0, 0, INTER_LINEAR);
    Mat s4k(Size(3840, 2160), CV_32FC1, Scalar::all(0));
    for (int y = 0; y < s.rows; y++)
        for (int x = 0; x < s.cols; x++)
            if (s.at<float>(y, x) > 0)
                s4k.at<float>(y * 2160 / 375, x * 3840 / 1242) = s.at<float>(y, x) * 3840.f / 1242.f;
    compareCpuGpu(StereoLidarSGM::create(0, 256), l, r, s4k, "3840x2160");
}

// Device memory does not grow over 1000 calls with changing sizes, disparity ranges, modes, compute/semidensify and
// a new instance every 100 calls: measured at calls 299 and 899, where the live instance is in the same state
// (same mode, same last size), it is the same.
TEST(Lidarsgm_CUDA, memory_does_not_grow)
{
    requireCudaDevice();
#ifdef HAVE_CUDA
    const Size sizes[] = { Size(1242, 375), Size(640, 480), Size(97, 61), Size(1, 1), Size(333, 111), Size(1920, 1080) };
    const int numDs[] = { 128, 64, 256, 16, 128, 256 };
    std::vector<cuda::GpuMat> gl(6), gr(6), gs(6);
    RNG rng(9);
    for (int i = 0; i < 6; i++)
    {
        Mat l, r, s;
        randomInputs(sizes[i], rng, l, r, s);
        gl[i].upload(l); gr[i].upload(r); gs[i].upload(s);
    }
    Ptr<StereoLidarSGM> m;
    cuda::Stream stream;
    cuda::GpuMat out;
    size_t freeAfterWarmUp = 0, freeNow = 0, total = 0;
    for (int call = 0; call < 1000; call++)
    {
        if (call % 100 == 0)
            m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, (call / 100) % 3);
        const int i = call % 6;
        m->setNumDisparities(numDs[i]);
        m->setSearchWindow((call / 6) % 2 ? 4 : 0);   // the compact volume of the windows, and the full one
        if ((call / 6) % 5 == 2)
            m->semidensify(gl[i], gr[i], gs[i], out, stream);
        else
            m->compute(gl[i], gr[i], gs[i], out, stream);
        if (call == 299 || call == 899)
        {
            stream.waitForCompletion();
            ASSERT_EQ(cudaSuccess, cudaMemGetInfo(call == 299 ? &freeAfterWarmUp : &freeNow, &total));
        }
    }
    stream.waitForCompletion();
    EXPECT_GE(freeNow, freeAfterWarmUp) << "device memory grew by " << (freeAfterWarmUp - freeNow) << " bytes";
#endif
}

// compute(..., stream) must be truly asynchronous once buffers exist: capture it into a CUDA graph (capture fails on
// a synchronisation or an allocation) and replay it. With disparity windows the captured call cannot wait for the
// windows' total: its graph allocates a full-size volume; replayed on other LiDAR input, the windows change with it.
TEST(Lidarsgm_CUDA, stream_call_is_graph_capturable)
{
    requireCudaDevice();
#ifdef HAVE_CUDA
    const std::string dir = cvtest::findDataDirectory("kitti");
    Mat l = imread(dir + "/image_2/000002_10.png", IMREAD_GRAYSCALE), r = imread(dir + "/image_3/000002_10.png", IMREAD_GRAYSCALE);
    Mat s(l.size(), CV_32F, Scalar::all(0)), s2;
    RNG rng(3);
    for (int i = 0; i < 20000; i++)
        s.at<float>(rng.uniform(0, l.rows), rng.uniform(0, l.cols)) = (float)rng.uniform(1.0, 100.0);
    s.copyTo(s2);
    s2.rowRange(0, l.rows / 2).setTo(Scalar::all(0));   // the top half's windows from the coarse pass
    for (int margin : { 0, 4 })
    {
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
        m->setSearchWindow(margin);
        cuda::GpuMat gl(l), gr(r), gs(s), gd;
        cuda::Stream stream;
        m->compute(gl, gr, gs, gd, stream);  // allocates the buffers
        stream.waitForCompletion();
        gd.setTo(Scalar::all(12345));
        cudaStream_t st = cuda::StreamAccessor::getStream(stream);
        ASSERT_EQ(cudaSuccess, cudaStreamBeginCapture(st, cudaStreamCaptureModeThreadLocal));
        m->compute(gl, gr, gs, gd, stream);
        cudaGraph_t graph = nullptr;
        ASSERT_EQ(cudaSuccess, cudaStreamEndCapture(st, &graph)) << "margin " << margin;
        cudaGraphExec_t exec = nullptr;
        ASSERT_EQ(cudaSuccess, cudaGraphInstantiate(&exec, graph, 0));
        for (const Mat& sparse : { s, s2 })
        {
            gs.upload(sparse, stream);   // same size: the captured memory
            ASSERT_EQ(cudaSuccess, cudaGraphLaunch(exec, st));
            stream.waitForCompletion();
            Mat cpu, gpuOut;
            m->compute(l, r, sparse, cpu);
            gd.download(gpuOut);
            EXPECT_EQ(0, cvtest::norm(cpu, gpuOut, NORM_INF)) << "margin " << margin;
        }
        cudaGraphExecDestroy(exec);
        cudaGraphDestroy(graph);
    }
#endif
}

}} // namespace
