// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

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

}} // namespace
