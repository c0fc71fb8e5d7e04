// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

static PipelineParams wtaParams(int minD, int D, bool subpixel, double uniq)
{
    PipelineParams p = PipelineParams();
    p.minDisparity = minD;
    p.numDisparities = D;
    p.subpixel = subpixel;
    p.uniqueness1024 = cvRound(uniq * 1024);
    return p;
}

TEST(Lidarsgm_WinnerTakesAll, subpixel_parabola_and_uniqueness)
{
    const int W = 1, D = 16;
    Mat sum(1, W * D, CV_16UC1, Scalar::all(100));
    sum.at<ushort>(0, 4) = 30;
    sum.at<ushort>(0, 5) = 10;   // best
    sum.at<ushort>(0, 6) = 20;
    Mat d16, di, dr, nu;
    // offset = round(8 * (30 - 20) / (30 + 20 - 20)) = round(80 / 30) = 3 (2.67)
    winnerTakesAll(sum, W, wtaParams(3, D, true, 0.95), d16, di, dr, nu);
    EXPECT_EQ((5 + 3) * 16 + 3, d16.at<short>(0, 0));
    EXPECT_EQ(8, di.at<short>(0, 0));
    winnerTakesAll(sum, W, wtaParams(3, D, false, 0.95), d16, di, dr, nu);
    EXPECT_EQ(8 * 16, d16.at<short>(0, 0));

    // Uniqueness: the best must be at most ratio x the lowest cost more than one disparity away.
    sum.at<ushort>(0, 12) = 11;  // 10 <= 0.95 * 11 = 10.45: unique
    winnerTakesAll(sum, W, wtaParams(0, D, true, 0.95), d16, di, dr, nu);
    EXPECT_NE(NO_DISP, d16.at<short>(0, 0));
    EXPECT_EQ(NO_DISP, nu.at<short>(0, 0));
    sum.at<ushort>(0, 12) = 10;  // tie with a far disparity: the best is the first (d = 5), not unique
    winnerTakesAll(sum, W, wtaParams(0, D, true, 0.95), d16, di, dr, nu);
    EXPECT_EQ(NO_DISP, d16.at<short>(0, 0));
    EXPECT_EQ(NO_DISP, di.at<short>(0, 0));
    EXPECT_EQ(5 * 16 + 3, nu.at<short>(0, 0));   // the rejected winner, for the ring check
    winnerTakesAll(sum, W, wtaParams(0, D, true, 1.0), d16, di, dr, nu);  // 1 disables the check
    EXPECT_EQ(5 * 16 + 3, d16.at<short>(0, 0));
}

/* A cost curve flat at zero (a textureless patch: every disparity costs 0) has no unique winner, though 0 <= ratio x 0;
a zero best with a positive second is unique. The same on a whole flat image pair through the matcher. */
TEST(Lidarsgm_WinnerTakesAll, flat_zero_costs_are_not_unique)
{
    const int D = 16;
    Mat sum(1, D, CV_16UC1, Scalar::all(0));
    Mat d16, di, dr, nu;
    winnerTakesAll(sum, 1, wtaParams(0, D, true, 0.95), d16, di, dr, nu);
    EXPECT_EQ(NO_DISP, d16.at<short>(0, 0));
    winnerTakesAll(sum, 1, wtaParams(0, D, true, 1.0), d16, di, dr, nu);   // the check off: the first disparity
    EXPECT_EQ(0, di.at<short>(0, 0));
    sum.setTo(Scalar::all(5));
    sum.at<ushort>(0, 7) = 0;
    winnerTakesAll(sum, 1, wtaParams(0, D, true, 0.95), d16, di, dr, nu);
    EXPECT_EQ(7, di.at<short>(0, 0));

    // A uniform pair: every census string is 0, every cost 0. Plain SGM with the left-right check leaves no disparity
    // (it used to report 0 at every pixel).
    Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(
        0, 64, 10, 120, 5, 160, 0.7, cv::lidarsgm::StereoLidarSGM::MODE_SGM, cv::lidarsgm::StereoLidarSGM::CHECK_STEREO);
    Mat l(40, 90, CV_8UC1, Scalar::all(128)), out;
    m->compute(l, l, Mat(), out);
    EXPECT_EQ(0, countNonZero(out != -16));
}

TEST(Lidarsgm_WinnerTakesAll, right_view_disparity)
{
    // Three left pixels, D = 16, minD = 0: pixel x at index k sees right pixel x - k.
    const int W = 3, D = 16;
    Mat sum(1, W * D, CV_16UC1, Scalar::all(50));
    // Right pixel 0 is seen by (x=0,k=0), (x=1,k=1), (x=2,k=2): make k=1 the cheapest.
    sum.at<ushort>(0, 0 * D + 0) = 40;
    sum.at<ushort>(0, 1 * D + 1) = 5;
    sum.at<ushort>(0, 2 * D + 2) = 30;
    Mat d16, di, dr, nu;
    winnerTakesAll(sum, W, wtaParams(0, D, false, 1.0), d16, di, dr, nu);
    EXPECT_EQ(1, dr.at<short>(0, 0));
    // Right pixel 2 is seen only by (x=2,k=0).
    EXPECT_EQ(0, dr.at<short>(0, 2));
}

// The CUDA twin (src_cuda/winner_takes_all.cu) on the CPU's aggregated costs of every stage configuration: the left
// and right disparities and the non-unique winners the ring check reads.
TEST(Lidarsgm_CUDA_WinnerTakesAll, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        cuda::GpuMat d16, dInt, dRight, nonUnique;
        cuda_host::winnerTakesAll(cuda::GpuMat(c.sum), c.left.cols, c.p, d16, dInt, dRight, nonUnique);
        expectSameAsCpu(c.disp16, d16, c.name + " (disp16)");
        expectSameAsCpu(c.dispInt, dInt, c.name + " (dispInt)");
        expectSameAsCpu(c.dispRight, dRight, c.name + " (dispRight)");
        if (!c.nonUnique16.empty())
            expectSameAsCpu(c.nonUnique16, nonUnique, c.name + " (nonUnique16)");
    }
}

}} // namespace
