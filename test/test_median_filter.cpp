// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

// The rule written out: the fifth of the nine clamped window values, "no disparity" sorted last.
static short referenceMedian(const Mat& m, int x, int y)
{
    std::vector<int> v;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
        {
            const short s = m.at<short>(std::min(std::max(y + dy, 0), m.rows - 1),
                                        std::min(std::max(x + dx, 0), m.cols - 1));
            v.push_back(s == NO_DISP ? INT_MAX : s);
        }
    std::sort(v.begin(), v.end());
    return v[4] == INT_MAX ? NO_DISP : (short)v[4];
}

TEST(Lidarsgm_MedianFilter, matches_the_rule_on_random_maps)
{
    RNG rng(7);
    const Size sizes[] = { Size(1, 1), Size(1, 9), Size(9, 1), Size(2, 2), Size(7, 5), Size(33, 17), Size(130, 41) };
    for (const Size& sz : sizes)
        for (int invalidPercent : { 0, 30, 60, 100 })
        {
            Mat src(sz, CV_16SC1), dst;
            for (int y = 0; y < sz.height; y++)
                for (int x = 0; x < sz.width; x++)
                    src.at<short>(y, x) = rng.uniform(0, 100) < invalidPercent ? NO_DISP
                                                                               : (short)rng.uniform(-200, 4000);
            medianFilter(src, dst);
            ASSERT_EQ(CV_16SC1, dst.type());
            ASSERT_EQ(sz, dst.size());
            for (int y = 0; y < sz.height; y++)
                for (int x = 0; x < sz.width; x++)
                    ASSERT_EQ(referenceMedian(src, x, y), dst.at<short>(y, x)) << sz << " at " << x << "," << y;
        }
}

TEST(Lidarsgm_MedianFilter, holes_and_outliers)
{
    // A hole with 4 invalid pixels in its window is filled; with 5 it stays; a lone outlier is removed.
    Mat src(5, 24, CV_16SC1, Scalar::all(160)), dst;
    src.at<short>(2, 3) = NO_DISP;                                   // lone hole
    src.at<short>(2, 10) = 900;                                      // lone outlier
    for (int x = 15; x <= 16; x++)
        for (int y = 1; y <= 2; y++)
            src.at<short>(y, x) = NO_DISP;                           // 2x2 hole: each pixel sees 4 invalid
    for (int k = 0; k < 5; k++)
        src.at<short>(1 + k / 3, 20 + k % 3) = NO_DISP;              // 5 invalid around (21, 2)
    medianFilter(src, dst);
    EXPECT_EQ(160, dst.at<short>(2, 3));
    EXPECT_EQ(160, dst.at<short>(2, 10));
    EXPECT_EQ(160, dst.at<short>(1, 15));
    EXPECT_EQ(NO_DISP, dst.at<short>(2, 21));
}

// The CUDA twin (src_cuda/median_filter.cu) on the three maps of every stage configuration (holes included).
TEST(Lidarsgm_CUDA_MedianFilter, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        const Mat* in[] = { &c.disp16, &c.dispInt, &c.dispRight };
        const Mat* cpu[] = { &c.med16, &c.medInt, &c.medRight };
        for (int k = 0; k < 3; k++)
        {
            cuda::GpuMat g;
            cuda_host::medianFilter(cuda::GpuMat(*in[k]), g);
            expectSameAsCpu(*cpu[k], g, c.name + format(" (map %d)", k));
        }
    }
}

}} // namespace
