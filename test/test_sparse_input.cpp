// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

TEST(Lidarsgm_SparseInput, conversion_rules)
{
    Mat f(1, 8, CV_32FC1);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const float v[8] = { 0.f, -3.f, nan, inf, 10.03f, 10.04f, 200.f, 127.4f };
    for (int i = 0; i < 8; i++)
        f.at<float>(0, i) = v[i];
    Mat s16;
    convertSparse(f, 0, 128, s16);
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 0));
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 1));
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 2));
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 3));
    EXPECT_EQ(160, s16.at<short>(0, 4));   // 10.03 * 16 = 160.48 -> 160
    EXPECT_EQ(161, s16.at<short>(0, 5));   // 160.64 -> 161
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 6));  // out of [0, 128)
    EXPECT_EQ(2038, s16.at<short>(0, 7));  // rounds to 127: in range

    Mat u(1, 3, CV_16UC1);
    u.at<ushort>(0, 0) = 0;
    u.at<ushort>(0, 1) = 2568;             // 10.03125 px -> 160.5 -> 161 (halves up)
    u.at<ushort>(0, 2) = 200 * 256;  // 200 px: outside [0, 128)
    convertSparse(u, 0, 128, s16);
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 0));
    EXPECT_EQ(161, s16.at<short>(0, 1));
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 2));

    // The range ends, minDisparity 10, 16 disparities: [10, 25.5) is kept at 1/16 pixel.
    Mat e = (Mat_<float>(1, 6) << 9.96f, 10.0f, 25.4f, 25.45f, 25.5f, 9.97f);
    convertSparse(e, 10, 16, s16);
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 0));  // 159.4 -> 159 < 160: below minDisparity
    EXPECT_EQ(160, s16.at<short>(0, 1));
    EXPECT_EQ(406, s16.at<short>(0, 2));      // 406.4 -> 406, rounds to 25
    EXPECT_EQ(407, s16.at<short>(0, 3));      // 407.2 -> 407, rounds to 25
    EXPECT_EQ(NO_DISP, s16.at<short>(0, 4));  // 408 rounds to 26: outside the search range
    EXPECT_EQ(160, s16.at<short>(0, 5));      // 159.52 -> 160 (to 1/16 first): exactly minDisparity, kept
}

// The CUDA twin (src_cuda/sparse_input.cu) on every stage configuration, as CV_32F pixels and as KITTI's x256 encoding.
TEST(Lidarsgm_CUDA_SparseInput, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        Mat s16u, cpu16u;
        c.sparse.convertTo(s16u, CV_16U, 256);
        convertSparse(s16u, c.p.minDisparity, c.p.numDisparities, cpu16u);
        cuda::GpuMat g;
        cuda_host::convertSparse(cuda::GpuMat(c.sparse), c.p.minDisparity, c.p.numDisparities, g);
        expectSameAsCpu(c.converted16, g, c.name);
        cuda_host::convertSparse(cuda::GpuMat(s16u), c.p.minDisparity, c.p.numDisparities, g);
        expectSameAsCpu(cpu16u, g, c.name + " (x256)");
    }
}

}} // namespace
