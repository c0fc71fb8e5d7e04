// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

/* Straightforward reference of paper Eq. 2, one path at a time, in int arithmetic. With an image and a threshold, a
jump from q to p costs P2edge instead of P2 where |I(p) - I(q)| > thr. */
static void referenceAggregation(const Mat& cost, int W, int D, int numPaths, int P1, int P2, Mat& sum,
                                 const Mat& image = Mat(), int thr = 0, int P2edge = 0)
{
    const int H = cost.rows;
    std::vector<int> S((size_t)W * H * D, 0);
    const int dirs[8][2] = { {1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1} };
    std::vector<int> L((size_t)W * H * D);
    for (int r = 0; r < numPaths; r++)
    {
        const int dx = dirs[r][0], dy = dirs[r][1];
        // Visit pixels so that p - r comes before p.
        for (int i = 0; i < H; i++)
            for (int j = 0; j < W; j++)
            {
                const int y = dy >= 0 ? i : H - 1 - i;
                const int x = dx >= 0 ? j : W - 1 - j;
                const int px = x - dx, py = y - dy;
                const ushort* C = cost.ptr<ushort>(y) + (size_t)x * D;
                int* Lp = &L[((size_t)y * W + x) * D];
                if (px < 0 || px >= W || py < 0 || py >= H)
                {
                    for (int d = 0; d < D; d++)
                        Lp[d] = C[d];
                    continue;
                }
                const int* Lq = &L[((size_t)py * W + px) * D];
                int mq = INT_MAX;
                for (int d = 0; d < D; d++)
                    mq = std::min(mq, Lq[d]);
                const bool edge = thr > 0 && std::abs(image.at<uchar>(y, x) - image.at<uchar>(py, px)) > thr;
                for (int d = 0; d < D; d++)
                {
                    int best = std::min(Lq[d], mq + (edge ? P2edge : P2));
                    if (d > 0) best = std::min(best, Lq[d - 1] + P1);
                    if (d < D - 1) best = std::min(best, Lq[d + 1] + P1);
                    Lp[d] = C[d] + best - mq;
                }
            }
        for (size_t k = 0; k < S.size(); k++)
            S[k] += L[k];
    }
    sum.create(H, W * D, CV_16UC1);
    for (int y = 0; y < H; y++)
        for (int k = 0; k < W * D; k++)
        {
            ASSERT_LE(S[(size_t)y * W * D + k], 65535);
            sum.at<ushort>(y, k) = (ushort)S[(size_t)y * W * D + k];
        }
}

// One step of the recursion by hand: previous L = [0, 5, 40, 40], C = [1, 1, 1, 1], P1 = 3, P2 = 20:
// L(0) = 1 + min(0, 5+3, 0+20) - 0 = 1; L(1) = 1 + min(5, 0+3, 40+3, 20) = 4; L(2) = 1 + min(40, 5+3, 40+3, 20) = 9;
// L(3) = 1 + min(40, 40+3, 20) = 21. Two pixels in a row, left-to-right path, summed with the other paths.
TEST(Lidarsgm_Aggregation, one_step_by_hand)
{
    const int W = 2, D = 16;
    Mat cost(1, W * D, CV_16UC1, Scalar::all(60));
    const ushort c0[4] = { 0, 5, 40, 40 };
    for (int d = 0; d < 4; d++)
    {
        cost.at<ushort>(0, d) = c0[d];
        cost.at<ushort>(0, D + d) = 1;
    }
    PipelineParams p = PipelineParams();
    p.numDisparities = D;
    p.numPaths = 4;
    p.w.p1 = 3;
    p.w.p2 = 20;
    Mat sum;
    aggregateCosts(cost, Mat(1, W, CV_8UC1, Scalar::all(0)), p, sum);
    // Pixel 1: left-to-right path = hand values; right-to-left path starts at pixel 1 (= C); vertical paths = C.
    const int lr[4] = { 1, 4, 9, 21 };
    for (int d = 0; d < 4; d++)
        EXPECT_EQ(lr[d] + 3 * 1, (int)sum.at<ushort>(0, D + d)) << "d=" << d;
}

// Random costs and images; edge threshold 0 (off) or 60, where P2 falls to 90 across the image's steps.
typedef testing::TestWithParam<tuple<int, int, Size, int> > Lidarsgm_AggregationRandom;
TEST_P(Lidarsgm_AggregationRandom, matches_reference)
{
    const int numPaths = get<0>(GetParam()), D = get<1>(GetParam()), thr = get<3>(GetParam());
    const Size sz = get<2>(GetParam());
    RNG rng(numPaths * 1000 + D + sz.width + thr);
    Mat cost(sz.height, sz.width * D, CV_16UC1), image(sz, CV_8UC1);
    rng.fill(cost, RNG::UNIFORM, 0, 400);
    rng.fill(image, RNG::UNIFORM, 0, 256);
    PipelineParams p = PipelineParams();
    p.numDisparities = D;
    p.numPaths = numPaths;
    p.edgeThreshold = thr;
    p.w.p1 = 37;
    p.w.p2 = 250;
    p.w.p2Edge = 90;
    Mat sum, ref;
    aggregateCosts(cost, image, p, sum);
    referenceAggregation(cost, sz.width, D, numPaths, p.w.p1, p.w.p2, ref, image, thr, p.w.p2Edge);
    EXPECT_EQ(0, cvtest::norm(sum, ref, NORM_INF));
}
INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_AggregationRandom,
    testing::Combine(testing::Values(4, 8), testing::Values(16, 48),
                     testing::Values(Size(1, 1), Size(7, 1), Size(1, 9), Size(13, 11), Size(70, 33)),
                     testing::Values(0, 60)));

}} // namespace
