// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;
using cv::lidarsgm::StereoLidarSGM;

static PipelineParams smallParams(int minD, int numD, bool ddc)
{
    PipelineParams p = PipelineParams();
    p.minDisparity = minD;
    p.numDisparities = numD;
    p.numPaths = 8;
    p.subpixel = true;
    p.uniqueness1024 = 1024;
    p.lrMaxDiff = 1;
    p.semidenseRadius = 6;
    p.semidenseThreshold = 2;
    p.checkRadius = 20;
    p.checkThreshold16 = 32;
    p.ddc = ddc;
    p.w = computeCostWeights(10, 120, 5, 160, 0.7, 8, ddc);
    return p;
}

TEST(Lidarsgm_CostWeights, paper_defaults_honour_alpha)
{
    CostWeights w = computeCostWeights(10, 120, 5, 160, 0.7, 8, true);
    const double K = w.scale;
    // Each weight within 0.3 % of K times its real value; in particular (1 - alpha) stays 0.3, not 0.375.
    EXPECT_NEAR(0.3, w.census256 / 256.0 / K, 0.3 * 0.003);
    EXPECT_NEAR(0.7 * 5, w.q1 / K, 0.7 * 5 * 0.003);
    EXPECT_NEAR(0.7 * 160, w.q2 / K, 0.7 * 160 * 0.003);
    EXPECT_NEAR(10.0, w.p1 / K, 10 * 0.003);
    EXPECT_NEAR(120.0, w.p2 / K, 120 * 0.003);
    // The worst-case sum of 8 path costs fits in 16 bits.
    EXPECT_LE(maxPathSum(w, 8), 65535);
    EXPECT_GT(maxPathSum(w, 8), 65535 * 0.99);  // K is as large as fits: the best precision
    // Plain SGM: census weight K.
    CostWeights s = computeCostWeights(10, 120, 5, 160, 0.7, 8, false);
    EXPECT_NEAR(10.0, s.p1 / (s.census256 / 256.0), 10 * 0.003);
    EXPECT_EQ(0, s.q2);
}

TEST(Lidarsgm_CostWeights, extreme_parameters_fit_16_bits)
{
    const int P[][4] = { {0, 0, 0, 0}, {1000, 1000, 1000, 1000}, {0, 1000, 0, 1000}, {10, 120, 5, 160} };
    const double alphas[] = { 0.0, 0.001, 0.5, 0.999, 1.0 };
    for (int paths = 4; paths <= 8; paths += 4)
        for (size_t i = 0; i < sizeof(P) / sizeof(P[0]); i++)
            for (size_t a = 0; a < sizeof(alphas) / sizeof(alphas[0]); a++)
            {
                CostWeights w = computeCostWeights(P[i][0], P[i][1], P[i][2], P[i][3], alphas[a], paths, true);
                EXPECT_LE(maxPathSum(w, paths), 65535);
                if (alphas[a] == 1.0)
                {
                    EXPECT_EQ(0, w.census256);  // pure DDC
                }
                else
                {
                    // The census weight keeps its ratio to the other weights to within 1/256 of a cost unit.
                    EXPECT_NEAR((1.0 - alphas[a]) * w.scale, w.census256 / 256.0, 0.5 / 256 + 1e-9);
                }
            }
}

// DDC values on hand-made census strings: H(p, d) = popcount(L(x) ^ R(x - minD - d)).
TEST(Lidarsgm_MatchingCost, ddc_values)
{
    const int W = 40, D = 16, minD = 2;
    Mat cl(1, W, CV_32SC1, Scalar::all(0)), cr(1, W, CV_32SC1);
    for (int x = 0; x < W; x++)
        cr.at<int>(0, x) = (1 << (x % 5)) - 1;  // popcount = x % 5
    Mat prior(1, W, CV_16SC1, Scalar::all(NO_DISP));
    const int x0 = 30, k = 7;                   // prior disparity minD + k at x0
    prior.at<short>(0, x0) = (short)((minD + k) * 16 + 3);  // 1/16 px: rounds to minD + k
    PipelineParams p = smallParams(minD, D, true);
    Mat cost;
    computeMatchingCost(cl, cr, prior, p, cost);
    ASSERT_EQ(W * D, cost.cols);
    for (int d = 0; d < D; d++)
    {
        const int h = (x0 - minD - d) % 5;
        const int ddc = d == k ? 0 : std::abs(d - k) == 1 ? p.w.q1 : p.w.q2;
        EXPECT_EQ(censusTerm(p.w.census256, h) + ddc, (int)cost.at<ushort>(0, x0 * D + d)) << "d=" << d;
        // A pixel without a prior has the plain census cost.
        const int h1 = (x0 - 1 - minD - d) % 5;
        EXPECT_EQ(censusTerm(p.w.census256, h1), (int)cost.at<ushort>(0, (x0 - 1) * D + d)) << "d=" << d;
    }
    // Right pixels left of the image are clamped to column 0.
    for (int d = 0; d < D; d++)
        EXPECT_EQ(0, (int)cost.at<ushort>(0, 1 * D + d));
}

TEST(Lidarsgm_MatchingCost, plain_sgm_ignores_prior)
{
    RNG rng(3);
    Mat cl(5, 37, CV_32SC1), cr(5, 37, CV_32SC1);
    rng.fill(cl, RNG::UNIFORM, 0, 1 << 30);
    rng.fill(cr, RNG::UNIFORM, 0, 1 << 30);
    PipelineParams p = smallParams(0, 32, false);
    Mat cost;
    computeMatchingCost(cl, cr, Mat(), p, cost);
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 37; x++)
            for (int d = 0; d < 32; d++)
            {
                const int xr = std::max(x - d, 0);
                const int h = popcount32((unsigned)cl.at<int>(y, x) ^ (unsigned)cr.at<int>(y, xr));
                ASSERT_EQ(censusTerm(p.w.census256, h), (int)cost.at<ushort>(y, x * 32 + d));
            }
}

/* The vector cost against the scalar rule (matchingCost) on full 32-bit census strings (Hamming distances 0-32), for
 census weights on both sides of 2^15 (the vector path takes a different multiply there) and a prior at every third
 pixel. */
TEST(Lidarsgm_MatchingCost, vector_equals_scalar_rule)
{
    RNG rng(11);
    const int W = 53, H = 3, D = 48, minD = -2;
    Mat cl(H, W, CV_32SC1), cr(H, W, CV_32SC1), prior(H, W, CV_16SC1, Scalar::all(NO_DISP));
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
        {
            // A third of the strings are complements, so that every distance up to 32 occurs.
            const unsigned r = (unsigned)rng.next();
            cl.at<int>(y, x) = (int)r;
            cr.at<int>(y, x) = (int)(x % 3 == 0 ? ~r : (unsigned)rng.next());
            if (x % 3 == 1)
                prior.at<short>(y, x) = (short)rng.uniform(minD * 16, (minD + D) * 16 - 8);
        }
    struct { int P1, P2, Q1, Q2; double alpha; int paths; bool ddc; } cases[] = {
        { 10, 120, 5, 160, 0.7, 8, true }, { 10, 120, 5, 160, 0.7, 4, true }, { 10, 120, 5, 160, 0.7, 4, false },
        { 0, 0, 0, 0, 0.0, 4, true }, { 1, 2, 0, 0, 0.3, 4, false } };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++)
    {
        PipelineParams p = smallParams(minD, D, cases[i].ddc);
        p.w = computeCostWeights(cases[i].P1, cases[i].P2, cases[i].Q1, cases[i].Q2, cases[i].alpha, cases[i].paths,
                                 cases[i].ddc);
        Mat cost;
        computeMatchingCost(cl, cr, cases[i].ddc ? prior : Mat(), p, cost);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
            {
                const short pr = prior.at<short>(y, x);
                const int k = cases[i].ddc && pr != NO_DISP ? roundDisp16(pr) - minD : -1;
                for (int d = 0; d < D; d++)
                {
                    const int xr = std::min(std::max(x - minD - d, 0), W - 1);
                    const int h = popcount32((unsigned)cl.at<int>(y, x) ^ (unsigned)cr.at<int>(y, xr));
                    ASSERT_EQ(matchingCost(h, d, k, p.w), (int)cost.at<ushort>(y, x * D + d))
                        << "case " << i << " census256 " << p.w.census256 << " x " << x << " d " << d;
                }
            }
    }
}

/* Through the API: semidenseWeight is range-checked and reaches the pipeline on LiDAR scans only. On the KITTI frame
(a scan) SDSGM's output changes with it and DSGM's (no copies) does not; on a sample scattered over the image (the
Middlebury protocol's kind, no scan) nothing changes. */
TEST(Lidarsgm_MatchingCost, semidense_weight_through_the_api)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    EXPECT_EQ(1.0, m->getSemidenseWeight());
    EXPECT_THROW(m->setSemidenseWeight(0), cv::Exception);
    EXPECT_THROW(m->setSemidenseWeight(1.5), cv::Exception);
    EXPECT_THROW(m->setSemidenseWeight(std::numeric_limits<double>::quiet_NaN()), cv::Exception);
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    RNG rng(5);
    Mat scattered(s.size(), CV_32FC1, Scalar::all(0));
    for (int i = 0; i < s.size().area() / 100; i++)
        scattered.at<float>(rng.uniform(0, s.rows), rng.uniform(0, s.cols)) = (float)rng.uniform(5.0, 60.0);
    for (int mode : { StereoLidarSGM::MODE_DSGM, StereoLidarSGM::MODE_SDSGM })
        for (int k = 0; k < 2; k++)
        {
            const Mat& sparse = k ? scattered : s;
            SCOPED_TRACE(cv::format("mode %d, %s", mode, k ? "scattered sample" : "LiDAR scan"));
            m->setMode(mode);
            Mat full, half;
            m->setSemidenseWeight(1.0);
            m->compute(l, r, sparse, full);
            m->setSemidenseWeight(0.5);
            m->compute(l, r, sparse, half);
            const int changed = countNonZero(full != half);
            if (mode == StereoLidarSGM::MODE_SDSGM && k == 0)
                EXPECT_GT(changed, 1000);   // 161486 measured
            else
                EXPECT_EQ(0, changed);
        }
}

}} // namespace
