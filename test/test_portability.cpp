// This file is part of the lidarsgm module (an OpenCV extra module).
// The same bytes on every instruction set. The CPU kernels have per-instruction-set branches (AVX2, SSE4, NEON and
// OpenCV's universal intrinsics elsewhere); the maps of the shipped KITTI frames are compared with checksums recorded
// in testdata/kitti/map_checksums.txt, so that a build for another architecture (the aarch64 build run under qemu,
// a Jetson, a Raspberry Pi) is checked against the x86-64 bytes without an x86-64 build beside it. The CUDA path is
// held to the CPU's bytes by its own tests. Recording (after a change of the arithmetic, on x86-64):
// LIDARSGM_RECORD_CHECKSUMS=<file> opencv_test_lidarsgm --gtest_filter=Lidarsgm_Portability.*
#include "test_common.hpp"
#include <fstream>
#include <map>

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;

//! 64-bit FNV-1a of a map's bytes, row by row (the padding of a strided map left out).
static uint64_t fnv1a(const Mat& m)
{
    uint64_t h = 14695981039346656037ull;
    const size_t rowBytes = m.cols * m.elemSize();
    for (int y = 0; y < m.rows; y++)
    {
        const uchar* p = m.ptr(y);
        for (size_t i = 0; i < rowBytes; i++)
            h = (h ^ p[i]) * 1099511628211ull;
    }
    return h;
}

struct MapCase
{
    std::string name;
    Ptr<StereoLidarSGM> matcher;
    bool confidence;
};

/** Every mode, check and path count at 128 disparities; kitti_best.yml's steps with and without its LiDAR-derived
windows; 16, 64 and 256 disparities, and 512 from -32; the confidence map of the defaults and of kitti_best.yml. */
static std::vector<MapCase> mapCases()
{
    std::vector<MapCase> cases;
    const char* modes[] = { "sgm", "dsgm", "sdsgm" };
    const char* checks[] = { "none", "stereo", "camera_lidar", "stereo_lidar" };
    for (int mode = 0; mode < 3; mode++)
        for (int check = 0; check < 4; check++)
            for (int paths : { 4, 8 })
            {
                Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
                m->setNumPaths(paths);
                cases.push_back({ format("%s_%s_%dpaths", modes[mode], checks[check], paths), m, false });
            }
    for (int windows : { 4, 0 })
    {
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
        setKittiBestSteps(*m);
        m->setSearchWindow(windows);
        cases.push_back({ format("kitti_best_steps_window%d", windows), m, windows != 0 });
    }
    for (int d : { 16, 64, 256 })
        cases.push_back({ format("sdsgm_%d_disparities", d), StereoLidarSGM::create(0, d), false });
    cases.push_back({ "sdsgm_512_from_minus_32", StereoLidarSGM::create(-32, 512), false });
    cases.push_back({ "defaults", StereoLidarSGM::create(), true });
    return cases;
}

static std::map<std::string, std::string> readChecksums(const std::string& path)
{
    std::map<std::string, std::string> sums;
    std::ifstream in(path);
    std::string key, value;
    while (in >> key >> value)
        if (key[0] != '#')
            sums[key] = value;
        else
            std::getline(in, value);
    return sums;
}

TEST(Lidarsgm_Portability, kitti_maps_match_the_recorded_checksums)
{
    const char* record = getenv("LIDARSGM_RECORD_CHECKSUMS");
    std::map<std::string, std::string> expected;
    if (!record)
        expected = readChecksums(cvtest::findDataFile("kitti/map_checksums.txt"));
    std::ostringstream written;
    written << "# FNV-1a 64 of the maps of test/test_portability.cpp (frame/case/map), recorded on x86-64\n";
    int equal = 0, different = 0;
    for (const char* id : { "000002", "000046" })
    {
        Mat l, r, s;
        loadKittiTestFrame(id, l, r, s);
        for (const MapCase& c : mapCases())
        {
            Mat disp, conf;
            if (c.confidence)
                c.matcher->compute(l, r, s, disp, conf);
            else
                c.matcher->compute(l, r, s, disp);
            std::vector<std::pair<std::string, Mat> > maps = { { "disparity", disp } };
            if (c.confidence)
                maps.push_back({ "confidence", conf });
            for (const auto& m : maps)
            {
                const std::string key = format("%s/%s/%s", id, c.name.c_str(), m.first.c_str());
                const std::string sum = format("%016llx", (unsigned long long)fnv1a(m.second));
                written << key << " " << sum << "\n";
                if (record)
                    continue;
                const auto it = expected.find(key);
                if (it != expected.end() && it->second == sum)
                    equal++;
                else
                {
                    different++;
                    ADD_FAILURE() << key << ": " << sum << ", recorded "
                                  << (it == expected.end() ? std::string("none") : it->second);
                }
            }
        }
    }
    if (record)
    {
        std::ofstream(record) << written.str();
        std::cout << "recorded the checksums in " << record << std::endl;
        return;
    }
    std::cout << equal << " maps byte for byte equal, " << different << " different (built for " << cv::getCPUFeaturesLine()
              << "; at run time AVX2 " << checkHardwareSupport(CV_CPU_AVX2) << ", SSE4.1 "
              << checkHardwareSupport(CV_CPU_SSE4_1) << ", NEON " << checkHardwareSupport(CV_CPU_NEON) << ")"
              << std::endl;
    EXPECT_EQ(0, different);
    EXPECT_EQ(expected.size(), (size_t)equal);   // nothing recorded goes unchecked
}

}} // namespace
