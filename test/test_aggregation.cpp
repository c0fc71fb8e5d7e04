// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

/* Straightforward reference of paper Eq. 2, one path at a time, in int arithmetic. With an image and a threshold, a
jump from q to p costs P2edge instead of P2 where |I(p) - I(q)| > thr. With windows (CV_16SC2 per WINDOW_TILE tile,
[lo, hi)), a pixel has path costs in its window only: outside it they are infinite, its sums there SENTINEL (0xFFFF). */
static void referenceAggregation(const Mat& cost, int W, int D, int numPaths, int P1, int P2, Mat& sum,
                                 const Mat& image = Mat(), int thr = 0, int P2edge = 0, const Mat& windows = Mat())
{
    const int H = cost.rows, INF = 1 << 20;   // above every path cost (< 2^16); 8 of them still fit in an int
    const auto lowOf = [&](int x, int y) { return windows.empty() ? 0 : (int)windows.at<Vec2s>(y / 32, x / 32)[0]; };
    const auto highOf = [&](int x, int y) { return windows.empty() ? D : (int)windows.at<Vec2s>(y / 32, x / 32)[1]; };
    ASSERT_EQ(32, (int)WINDOW_TILE);
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
                const int lo = lowOf(x, y), hi = highOf(x, y);
                for (int d = 0; d < D; d++)
                    Lp[d] = INF;
                if (px < 0 || px >= W || py < 0 || py >= H)
                {
                    for (int d = lo; d < hi; d++)
                        Lp[d] = C[d];
                    continue;
                }
                const int* Lq = &L[((size_t)py * W + px) * D];
                int mq = INT_MAX;
                for (int d = 0; d < D; d++)
                    mq = std::min(mq, Lq[d]);
                const bool edge = thr > 0 && std::abs(image.at<uchar>(y, x) - image.at<uchar>(py, px)) > thr;
                for (int d = lo; d < hi; d++)
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
            const int d = k % D, x = k / D;
            if (d < lowOf(x, y) || d >= highOf(x, y))
            {
                sum.at<ushort>(y, k) = 0xFFFF;
                continue;
            }
            ASSERT_LE(S[(size_t)y * W * D + k], 65535);
            sum.at<ushort>(y, k) = (ushort)S[(size_t)y * W * D + k];
        }
}

/* Straightforward winner-takes-all over each pixel's window of a reference volume (SENTINEL outside): the first
lowest cost, the uniqueness check against the lowest cost more than one disparity away, the parabola where both
neighbours are in the window, the right view from the candidates in the windows (the lowest cost, then the smallest
disparity). */
static void referenceWinners(const Mat& sum, const Mat& windows, int W, const PipelineParams& p, Mat& d16, Mat& di,
                             Mat& dr, Mat& nu)
{
    const int H = sum.rows, D = p.numDisparities, minD = p.minDisparity;
    d16.create(H, W, CV_16SC1);
    di.create(H, W, CV_16SC1);
    dr.create(H, W, CV_16SC1);
    nu.create(H, W, CV_16SC1);
    for (int y = 0; y < H; y++)
    {
        std::vector<int> rightCost(W, INT_MAX), rightD(W, -1);
        for (int x = 0; x < W; x++)
        {
            const Vec2s w = windows.at<Vec2s>(y / 32, x / 32);
            const ushort* s = sum.ptr<ushort>(y) + (size_t)x * D;
            int best = w[0];
            for (int d = w[0]; d < w[1]; d++)
            {
                if (s[d] < s[best])
                    best = d;
                const int xr = x - minD - d;
                if (xr >= 0 && xr < W && (s[d] < rightCost[xr] || (s[d] == rightCost[xr] && d < rightD[xr])))
                {
                    rightCost[xr] = s[d];
                    rightD[xr] = d;
                }
            }
            int second = INT_MAX;
            for (int d = w[0]; d < w[1]; d++)
                if (std::abs(d - best) > 1)
                    second = std::min(second, (int)s[d]);
            int v16 = (best + minD) * 16;
            if (p.subpixel && best - 1 >= w[0] && best + 1 < w[1])
                v16 += subpixelOffset16(s[best - 1], s[best], s[best + 1]);
            const bool unique = p.uniqueness1024 >= 1024 || uniqueWinner(s[best], second, p.uniqueness1024);
            d16.at<short>(y, x) = unique ? (short)v16 : NO_DISP;
            di.at<short>(y, x) = unique ? (short)(best + minD) : NO_DISP;
            nu.at<short>(y, x) = unique ? NO_DISP : (short)v16;
        }
        for (int xr = 0; xr < W; xr++)
            dr.at<short>(y, xr) = rightD[xr] < 0 ? NO_DISP : (short)(rightD[xr] + minD);
    }
}

// One step of the recursion by hand: previous L = [0, 5, 40, 40], C = [1, 1, 1, 1], P1 = 3, P2 = 20:
// L(0) = 1 + min(0, 5+3, 0+20) - 0 = 1; L(1) = 1 + min(5, 0+3, 40+3, 20) = 4; L(2) = 1 + min(40, 5+3, 40+3, 20) = 9;
// L(3) = 1 + min(40, 40+3, 20) = 21. Two pixels in a row; the costs come from census strings with plain SGM
// weights (census256 = 256: C = H), so pixel 0 has H = [0, 5, 40->31 ...] and pixel 1 H = 1 everywhere.
TEST(Lidarsgm_Aggregation, one_step_by_hand)
{
    const int W = 2, D = 16;
    // Right census strings 0; left: pixel 0 sees popcount(L ^ R(x - d)) with R clamped to column 0 -> the same
    // string at every d. Use distinct right strings per column instead: x - d < 0 clamps to column 0.
    Mat cl(1, W, CV_32SC1), cr(1, W, CV_32SC1);
    cl.at<int>(0, 0) = 0x1F;            // pixel 0: H(d) = popcount(0x1F ^ R(clamp(-d))) = popcount(0x1F ^ R(0))
    cr.at<int>(0, 0) = 0x1F;            //   = 0 at every d
    cl.at<int>(0, 1) = 0x1E;            // pixel 1: d = 0 sees R(1), d >= 1 sees R(0)
    cr.at<int>(0, 1) = 0x1F;            //   H = 1 at every d
    PipelineParams p = PipelineParams();
    p.numDisparities = D;
    p.numPaths = 4;
    p.uniqueness1024 = 1024;
    p.w.census256 = 256;
    p.w.p1 = 3;
    p.w.p2 = 20;
    WinnerMaps w;
    Mat sum;
    aggregateCosts(aggregationInputs(cl, cr), p, w, sum);
    // Pixel 1: left-to-right = C(1) + L(0) step with L(0) = C(0) = 0 everywhere: 1 + min(0, 3, 3, 20) - 0 = 1;
    // right-to-left starts at pixel 1 (= C = 1); vertical paths = C = 1. Sum = 4 at every d.
    for (int d = 0; d < D; d++)
        EXPECT_EQ(4, (int)sum.at<ushort>(0, D + d)) << "d=" << d;
    // Pixel 0: left-to-right starts (0), right-to-left: 0 + min(1, ...) - 1 = 0, vertical 0 + 0: sum 0.
    for (int d = 0; d < D; d++)
        EXPECT_EQ(0, (int)sum.at<ushort>(0, d)) << "d=" << d;
}

/* Random census strings, priors and images: the fused aggregation's sums equal the reference recursion on the cost
 volume of computeMatchingCost, and its disparities the winner-takes-all of those sums. Edge threshold 0 (off) or 60,
 where P2 falls to 90 across the image's steps. */
typedef testing::TestWithParam<tuple<int, int, Size, int> > Lidarsgm_AggregationRandom;
TEST_P(Lidarsgm_AggregationRandom, matches_reference)
{
    const int numPaths = get<0>(GetParam()), D = get<1>(GetParam()), thr = get<3>(GetParam());
    const Size sz = get<2>(GetParam());
    RNG rng(numPaths * 1000 + D + sz.width + thr);
    Mat cl(sz, CV_32SC1), cr(sz, CV_32SC1), image(sz, CV_8UC1), prior(sz, CV_16SC1, Scalar::all(NO_DISP));
    rng.fill(cl, RNG::UNIFORM, 0, 1 << 30);
    rng.fill(cr, RNG::UNIFORM, 0, 1 << 30);
    rng.fill(image, RNG::UNIFORM, 0, 256);
    for (int k = 0; k < sz.area() / 5; k++)
        prior.at<short>(rng.uniform(0, sz.height), rng.uniform(0, sz.width)) = (short)rng.uniform(0, D * 16 - 8);
    PipelineParams p = PipelineParams();
    p.numDisparities = D;
    p.minDisparity = (int)rng.uniform(-3, 3);
    p.numPaths = numPaths;
    p.subpixel = true;
    p.uniqueness1024 = 970;
    p.edgeThreshold = thr;
    p.w = computeCostWeights(10, 120, 5, 160, 0.7, numPaths, true, 0.75);
    // With the ring check on, the winner-takes-all also keeps the non-unique winners.
    p.ringGapFactor16 = 32;
    p.semidense = p.lidarCheck = true;
    Mat cost, ref, sum, e16, ei, er, enu;
    computeMatchingCost(cl, cr, prior, p, cost);
    referenceAggregation(cost, sz.width, D, numPaths, p.w.p1, p.w.p2, ref, image, thr, p.w.p2Edge);
    WinnerMaps w;
    aggregateCosts(aggregationInputs(cl, cr, prior, image), p, w, sum);
    EXPECT_EQ(0, cvtest::norm(sum, ref, NORM_INF));
    winnerTakesAll(ref, sz.width, p, e16, ei, er, enu);
    EXPECT_EQ(0, cvtest::norm(w.disp16, e16, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(w.dispInt, ei, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(w.dispRight, er, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(w.nonUnique16, enu, NORM_INF));
}
INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_AggregationRandom,
    testing::Combine(testing::Values(4, 8), testing::Values(16, 48),
                     testing::Values(Size(1, 1), Size(7, 1), Size(1, 9), Size(13, 11), Size(70, 33), Size(300, 17)),
                     testing::Values(0, 60)));
// The largest search the CPU path takes (MAX_DISPARITIES); minDisparity is drawn from [-3, 2].
INSTANTIATE_TEST_CASE_P(D512, Lidarsgm_AggregationRandom,
    testing::Combine(testing::Values(4, 8), testing::Values(512),
                     testing::Values(Size(1, 1), Size(13, 11), Size(70, 33)), testing::Values(0, 60)));

//! Random census strings of both views and a prior on a fifth of the pixels (1/16-pixel values in the range).
static void randomCensusAndPrior(RNG& rng, Size sz, int D, Mat& cl, Mat& cr, Mat& prior)
{
    cl.create(sz, CV_32SC1);
    cr.create(sz, CV_32SC1);
    prior.create(sz, CV_16SC1);
    prior.setTo(Scalar::all(NO_DISP));
    rng.fill(cl, RNG::UNIFORM, 0, 1 << 30);
    rng.fill(cr, RNG::UNIFORM, 0, 1 << 30);
    for (int k = 0; k < sz.area() / 5; k++)
        prior.at<short>(rng.uniform(0, sz.height), rng.uniform(0, sz.width)) = (short)rng.uniform(0, D * 16 - 8);
}

//! The tests' aggregation: D disparities from 0, subpixel, uniqueness 0.95 (970 / 1024), the paper's weights.
static PipelineParams aggregationParams(int D, int numPaths)
{
    PipelineParams p = PipelineParams();
    p.numDisparities = D;
    p.numPaths = numPaths;
    p.subpixel = true;
    p.uniqueness1024 = 970;
    p.w = computeCostWeights(10, 120, 5, 160, 0.7, numPaths, true);
    return p;
}

/* Copied priors (copiedPrior): with the filtered sparse map given, a pixel whose prior differs from its own value
takes wCopy, every other pixel w. The reference builds the cost volume per pixel from the two weightings; half of
the priors are the pixel's own values, the rest copies, and some own values were replaced by a copy. */
TEST(Lidarsgm_Aggregation, copied_priors_take_their_weights)
{
    const int D = 32;
    const Size sz(97, 23);
    RNG rng(77);
    Mat cl, cr, prior;
    randomCensusAndPrior(rng, sz, D, cl, cr, prior);
    Mat own(sz, CV_16SC1, Scalar::all(NO_DISP));
    for (int y = 0; y < sz.height; y++)
        for (int x = 0; x < sz.width; x++)
        {
            const short v = prior.at<short>(y, x);
            if (v != NO_DISP && (x + y) % 2 == 0)
                own.at<short>(y, x) = v;                          // the pixel's own value
            else if (v != NO_DISP && (x + 2 * y) % 5 == 0)
                own.at<short>(y, x) = (short)(v < 64 ? v + 48 : v - 48);   // its own value, replaced by a copy
        }
    PipelineParams p = aggregationParams(D, 8);
    p.wCopy = scaleDdcWeights(p.w, 0.7, 5, 160, 0.5);
    p.weighCopies = p.semidense = true;
    ASSERT_LT(p.wCopy.q2, p.w.q2);
    PipelineParams pc = p;
    pc.w = p.wCopy;
    Mat costOwn, costCopy;
    computeMatchingCost(cl, cr, prior, p, costOwn);
    computeMatchingCost(cl, cr, prior, pc, costCopy);
    Mat cost = costOwn.clone();
    int copies = 0;
    for (int y = 0; y < sz.height; y++)
        for (int x = 0; x < sz.width; x++)
            if (copiedPrior(true, prior.at<short>(y, x), own.at<short>(y, x)))
            {
                copies++;
                costCopy.row(y).colRange(x * D, (x + 1) * D).copyTo(cost.row(y).colRange(x * D, (x + 1) * D));
            }
    ASSERT_GT(copies, 0);
    ASSERT_GT(cvtest::norm(cost, costOwn, NORM_INF), 0);
    Mat ref, e16, ei, er, enu, sum;
    referenceAggregation(cost, sz.width, D, 8, p.w.p1, p.w.p2, ref);
    winnerTakesAll(ref, sz.width, p, e16, ei, er, enu);
    AggregationInputs in = aggregationInputs(cl, cr, prior, Mat(), own);
    WinnerMaps w;
    aggregateCosts(in, p, w, sum);
    EXPECT_EQ(0, cvtest::norm(sum, ref, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(w.disp16, e16, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(w.dispRight, er, NORM_INF));
    // Without the sparse map every prior takes w.
    Mat refOwn;
    referenceAggregation(costOwn, sz.width, D, 8, p.w.p1, p.w.p2, refOwn);
    in.own16.release();
    aggregateCosts(in, p, w, sum);
    EXPECT_EQ(0, cvtest::norm(sum, refOwn, NORM_INF));
}

/* The sweeps' scheduling (wavefront.hpp) over 1 to 16 threads, with fewer strips than threads (narrow images) and
 more: every thread count gives the reference sums and the same disparities, whatever order the items ran in. */
typedef testing::TestWithParam<tuple<int, int, Size> > Lidarsgm_AggregationThreads;
TEST_P(Lidarsgm_AggregationThreads, same_as_reference)
{
    const int numPaths = get<0>(GetParam()), threads = get<1>(GetParam()), D = 32;
    const Size sz = get<2>(GetParam());
    RNG rng(numPaths * 100 + threads + sz.width);
    Mat cl, cr, prior;
    randomCensusAndPrior(rng, sz, D, cl, cr, prior);
    PipelineParams p = aggregationParams(D, numPaths);
    p.ringGapFactor16 = 32;
    p.semidense = p.lidarCheck = true;
    Mat cost, ref, e16, ei, er, enu;
    computeMatchingCost(cl, cr, prior, p, cost);
    referenceAggregation(cost, sz.width, D, numPaths, p.w.p1, p.w.p2, ref);
    winnerTakesAll(ref, sz.width, p, e16, ei, er, enu);
    const int saved = getNumThreads();
    setNumThreads(threads);
    const AggregationInputs in = aggregationInputs(cl, cr, prior);
    WinnerMaps w;
    Mat sum;
    // Twice: the second call reuses the buffers the first one left.
    Ptr<AggregationState> kept;
    for (int call = 0; call < 2; call++)
    {
        aggregateCosts(in, p, w, sum, &kept);
        EXPECT_EQ(0, cvtest::norm(sum, ref, NORM_INF)) << "call " << call;
        EXPECT_EQ(0, cvtest::norm(w.nonUnique16, enu, NORM_INF)) << "call " << call;
        EXPECT_EQ(0, cvtest::norm(w.disp16, e16, NORM_INF)) << "call " << call;
        EXPECT_EQ(0, cvtest::norm(w.dispInt, ei, NORM_INF)) << "call " << call;
        EXPECT_EQ(0, cvtest::norm(w.dispRight, er, NORM_INF)) << "call " << call;
    }
    setNumThreads(saved);
}
INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_AggregationThreads,
    testing::Combine(testing::Values(4, 8), testing::Values(1, 2, 3, 7, 16),
                     testing::Values(Size(100, 13), Size(1030, 21))));

/* Where the calling thread's stack starts differs in every process (address-space randomisation) and once set the
speed of the whole process (aggregation.simd.hpp keeps its scratch rows off the stack). Calls at several stack
offsets, with 1 and 2 threads, give the reference sums and disparities: the placement may change the time only. */
template <int N, typename F>
static void withStackShift(const F& f)
{
    volatile char pad[N];
    pad[0] = pad[N - 1] = 1;
    f();
    EXPECT_EQ(2, pad[0] + pad[N - 1]);
}

TEST(Lidarsgm_Aggregation, stack_placement_does_not_change_results)
{
    const int D = 48;
    const Size sz(211, 19);
    RNG rng(2024);
    Mat cl, cr, prior;
    randomCensusAndPrior(rng, sz, D, cl, cr, prior);
    PipelineParams p = aggregationParams(D, 8);
    Mat cost, ref, e16, ei, er, enu;
    computeMatchingCost(cl, cr, prior, p, cost);
    referenceAggregation(cost, sz.width, D, 8, p.w.p1, p.w.p2, ref);
    winnerTakesAll(ref, sz.width, p, e16, ei, er, enu);
    const int saved = getNumThreads();
    for (int threads = 1; threads <= 2; threads++)
    {
        setNumThreads(threads);
        int shift = 0;
        const auto check = [&]() {
            SCOPED_TRACE(cv::format("%d threads, stack shift %d", threads, shift));
            WinnerMaps w;
            Mat sum;
            aggregateCosts(aggregationInputs(cl, cr, prior), p, w, sum);
            EXPECT_EQ(0, cvtest::norm(sum, ref, NORM_INF));
            EXPECT_EQ(0, cvtest::norm(w.disp16, e16, NORM_INF));
            EXPECT_EQ(0, cvtest::norm(w.dispInt, ei, NORM_INF));
            EXPECT_EQ(0, cvtest::norm(w.dispRight, er, NORM_INF));
        };
        shift = 16;   withStackShift<16>(check);
        shift = 48;   withStackShift<48>(check);
        shift = 272;  withStackShift<272>(check);
        shift = 2064; withStackShift<2064>(check);
        shift = 4080; withStackShift<4080>(check);
    }
    setNumThreads(saved);
}

/* Disparity windows (searchWindows): random windows per tile, so that paths cross windows that overlap, nest, touch
and lie apart; the sums, winners and right view equal the reference over the windows, with 1, 2 and 7 threads,
4 and 8 paths, the edge rule on and off. */
typedef testing::TestWithParam<tuple<int, int, Size, int> > Lidarsgm_AggregationWindows;
TEST_P(Lidarsgm_AggregationWindows, match_reference)
{
    const int numPaths = get<0>(GetParam()), D = get<1>(GetParam()), thr = get<3>(GetParam());
    const Size sz = get<2>(GetParam());
    RNG rng(numPaths * 1000 + D + sz.width * 7 + sz.height + thr);
    Mat cl, cr, prior, image(sz, CV_8UC1);
    randomCensusAndPrior(rng, sz, D, cl, cr, prior);
    rng.fill(image, RNG::UNIFORM, 0, 256);
    PipelineParams p = aggregationParams(D, numPaths);
    p.minDisparity = (int)rng.uniform(-3, 3);
    p.edgeThreshold = thr;
    p.w = computeCostWeights(10, 120, 5, 160, 0.7, numPaths, true, 0.75);
    p.ringGapFactor16 = 32;
    p.semidense = p.lidarCheck = true;
    Mat windows((sz.height + 31) / 32, (sz.width + 31) / 32, CV_16SC2);
    for (int ty = 0; ty < windows.rows; ty++)
        for (int tx = 0; tx < windows.cols; tx++)
        {
            const int lo = 16 * rng.uniform(0, D / 16), hi = lo + 16 * rng.uniform(1, (D - lo) / 16 + 1);
            windows.at<Vec2s>(ty, tx) = Vec2s((short)lo, (short)hi);
        }
    Mat cost, ref, e16, ei, er, enu;
    computeMatchingCost(cl, cr, prior, p, cost);
    referenceAggregation(cost, sz.width, D, numPaths, p.w.p1, p.w.p2, ref, image, thr, p.w.p2Edge, windows);
    referenceWinners(ref, windows, sz.width, p, e16, ei, er, enu);
    const int saved = getNumThreads();
    AggregationInputs in = aggregationInputs(cl, cr, prior, image, Mat(), windows);
    Ptr<AggregationState> kept;
    for (int threads : { 1, 2, 7 })
    {
        SCOPED_TRACE(cv::format("%d threads", threads));
        setNumThreads(threads);
        WinnerMaps w;
        Mat sum;
        aggregateCosts(in, p, w, sum, &kept);
        EXPECT_EQ(0, cvtest::norm(sum, ref, NORM_INF));
        EXPECT_EQ(0, cvtest::norm(w.disp16, e16, NORM_INF));
        EXPECT_EQ(0, cvtest::norm(w.dispInt, ei, NORM_INF));
        EXPECT_EQ(0, cvtest::norm(w.dispRight, er, NORM_INF));
        EXPECT_EQ(0, cvtest::norm(w.nonUnique16, enu, NORM_INF));
    }
    setNumThreads(saved);
    // The full range as windows is the aggregation without them, and the reference winners agree with the
    // winner-takes-all on the full volume.
    Mat full((sz.height + 31) / 32, (sz.width + 31) / 32, CV_16SC2, Scalar(0, D));
    Mat sumW, sumF;
    WinnerMaps wW, wF;
    in.windows = full;
    aggregateCosts(in, p, wW, sumW);
    in.windows.release();
    aggregateCosts(in, p, wF, sumF);
    EXPECT_EQ(0, cvtest::norm(sumW, sumF, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(wW.disp16, wF.disp16, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(wW.dispRight, wF.dispRight, NORM_INF));
    referenceWinners(sumF, full, sz.width, p, e16, ei, er, enu);
    EXPECT_EQ(0, cvtest::norm(wF.disp16, e16, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(wF.dispRight, er, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(wF.nonUnique16, enu, NORM_INF));
}
INSTANTIATE_TEST_CASE_P(/**/, Lidarsgm_AggregationWindows,
    testing::Combine(testing::Values(4, 8), testing::Values(48, 128),
                     testing::Values(Size(1, 1), Size(40, 3), Size(70, 33), Size(97, 70), Size(300, 17)),
                     testing::Values(0, 60)));

/* The window rule (tileWindow): the priors of a tile and the eight around it, widened by the margin, rounded out to
multiples of 16 and clamped; tiles with no prior around them take the coarse pass's range; a margin of the whole
range gives the whole range everywhere. */
TEST(Lidarsgm_SearchWindows, rule_by_hand)
{
    int lo = -1, hi = -1;
    tileWindow(20, 33, 4, 128, lo, hi);
    EXPECT_EQ(16, lo); EXPECT_EQ(48, hi);     // [16, 38) rounded out
    tileWindow(2, 5, 4, 128, lo, hi);
    EXPECT_EQ(0, lo); EXPECT_EQ(16, hi);
    tileWindow(120, 127, 4, 128, lo, hi);
    EXPECT_EQ(112, lo); EXPECT_EQ(128, hi);
    tileWindow(50, 50, 0, 64, lo, hi);
    EXPECT_EQ(48, lo); EXPECT_EQ(64, hi);
    tileWindow(0, 127, 200, 128, lo, hi);
    EXPECT_EQ(0, lo); EXPECT_EQ(128, hi);

    // 5 x 3 tiles of 32 pixels; priors at 40.5 px in tile (0, 0), 70 px in tile (4, 2); none elsewhere.
    const Size sz(150, 90);
    Mat left(sz, CV_8UC1), right;
    RNG rng(5);
    rng.fill(left, RNG::UNIFORM, 0, 256);
    right = left.clone();   // the coarse pass sees disparity 0 everywhere
    Mat prior(sz, CV_16SC1, Scalar::all(NO_DISP));
    prior.at<short>(3, 4) = 40 * 16 + 8;   // rounds to 41
    prior.at<short>(80, 140) = 70 * 16;
    PipelineParams p = PipelineParams();
    p.numDisparities = 128;
    p.minDisparity = 0;
    p.searchWindow = 4;
    Mat windows, coarse;
    Ptr<AggregationState> work;
    searchWindows(prior, left, right, p, windows, &work, &coarse);
    ASSERT_EQ(Size(5, 3), windows.size());
    ASSERT_FALSE(coarse.empty());
    EXPECT_EQ(Size(150 / 4, 90 / 4), coarse.size());
    const Vec2s nearFirst(32, 48), nearSecond(64, 80), coarseOnly(0, 16);
    for (int ty = 0; ty < 3; ty++)
        for (int tx = 0; tx < 5; tx++)
        {
            const bool a = tx <= 1 && ty <= 1, b = tx >= 3 && ty >= 1;
            const Vec2s expect = a ? nearFirst : b ? nearSecond : coarseOnly;
            EXPECT_EQ(expect, windows.at<Vec2s>(ty, tx)) << "tile " << tx << "," << ty;
        }
    EXPECT_EQ((int64)sz.area() * 16, windowCells(windows, sz));
    // A margin of the whole range: the whole range everywhere.
    p.searchWindow = 128;
    searchWindows(prior, left, right, p, windows);
    for (int ty = 0; ty < 3; ty++)
        for (int tx = 0; tx < 5; tx++)
            EXPECT_EQ(Vec2s(0, 128), windows.at<Vec2s>(ty, tx));
    // No prior at all: the coarse pass alone; with minDisparity -8 its disparity 0 is index 8.
    p.searchWindow = 4;
    p.minDisparity = -8;
    searchWindows(Mat(), left, right, p, windows);
    for (int ty = 0; ty < 3; ty++)
        for (int tx = 0; tx < 5; tx++)
            EXPECT_EQ(Vec2s(0, 32), windows.at<Vec2s>(ty, tx));
    // The coarse pass covers the range in whole coarse disparities, their count rounded up to a multiple of 16 (the
    // GPU's unit): minDisparity 5, 128 disparities: coarse 1 .. 33, 48 of them.
    p.minDisparity = 5;
    const PipelineParams q = coarseParams(p);
    EXPECT_EQ(1, q.minDisparity);
    EXPECT_EQ(48, q.numDisparities);
}

// The CUDA twin (src_cuda/aggregation.cu): the aggregated costs of every stage configuration (4 and 8 paths, with
// and without a prior, the edge rule, the copied priors' weight) against the CPU's, before any winner is taken.
TEST(Lidarsgm_CUDA_Aggregation, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        cuda::GpuMat gl, gr, sum;
        cuda_host::censusTransform(cuda::GpuMat(c.left), cuda::GpuMat(c.right), c.p, gl, gr);
        const cuda::GpuMat prior = c.prior.empty() ? cuda::GpuMat() : cuda::GpuMat(c.prior);
        const cuda::GpuMat own = c.own16.empty() ? cuda::GpuMat() : cuda::GpuMat(c.own16);
        cuda_host::aggregateCosts(gl, gr, prior, cuda::GpuMat(c.left), c.p, own, c.scan, sum);
        expectSameAsCpu(c.sum, sum, c.name);
    }
}

//! The GPU's sums within the windows against the CPU's finalSum (whose sentinel fills the rest; the GPU's is 0 there).
void expectSameWindowSums(const Mat& cpu, const cuda::GpuMat& gpu, const Mat& windows, int D, const std::string& what)
{
    Mat s;
    gpu.download(s);
    for (int y = 0; y < s.rows; y++)
        for (int x = 0; x < s.cols / D; x++)
        {
            const Vec2s w = windows.at<Vec2s>(y / WINDOW_TILE, x / WINDOW_TILE);
            for (int k = 0; k < D; k++)
                if (k < w[0] || k >= w[1])
                    s.at<ushort>(y, x * D + k) = 0xFFFF;
        }
    ASSERT_EQ(0, cvtest::norm(cpu, s, NORM_INF)) << what << " (sums within the windows)";
}

// The path kernel's two layouts (several lines a warp where each multiprocessor has many lines, as on a small GPU;
// one line a warp otherwise) against the CPU, at every range the packed layout takes: its lanes' last group full
// (128, 256) or partly used (112, 208, 240), 4 and 8 paths, SDSGM with the edge rule.
TEST(Lidarsgm_CUDA_Aggregation, packed_layout_bit_exact)
{
    requireCudaDevice();
    RNG rng(99);
    Mat l, r, s;
    randomInputs(Size(271, 71), rng, l, r, s);   // 9 x 3 tiles of windows
    for (int D : { 112, 128, 208, 240, 256 })
        for (int paths : { 4, 8 })
        {
            Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(0, D);
            m->setNumPaths(paths);
            m->setEdgeThreshold(24);
            const StageCase c = runCpuStages(format("random 271x71, %d disparities, %d paths", D, paths), l, r, s, m);
            cuda::GpuMat gl, gr;
            cuda_host::censusTransform(cuda::GpuMat(c.left), cuda::GpuMat(c.right), c.p, gl, gr);
            // 1 multiprocessor: the packed layout (271 x 71 has 684 lines with 4 paths); 10^6: one line a warp.
            for (int sms : { 1, 1000000 })
            {
                cuda::GpuMat sum;
                cuda_host::aggregateCosts(gl, gr, cuda::GpuMat(c.prior), cuda::GpuMat(c.left), c.p, cuda::GpuMat(),
                                          false, sum, cuda::GpuMat(), sms);
                expectSameAsCpu(c.sum, sum, c.name + format(", as on %d SMs", sms));
            }
            // The same over the disparity windows (margin 4): up to 128 disparities the packed layout walks the
            // union of a warp's windows on any number of SMs (on 1 SM with the windows' costs stored, on 10^6
            // computed as it goes); above, on 1 SM, it masks the full range to them.
            PipelineParams p = c.p;
            p.searchWindow = 4;
            Mat windows, wsum;
            searchWindows(c.prior, c.left, c.right, p, windows);
            WinnerMaps winners;
            aggregateCosts(aggregationInputs(c.censusL, c.censusR, c.prior, c.left, Mat(), windows), p, winners, wsum);
            for (int sms : { 1, 1000000 })
            {
                cuda::GpuMat sum;
                cuda_host::aggregateCosts(gl, gr, cuda::GpuMat(c.prior), cuda::GpuMat(c.left), p, cuda::GpuMat(),
                                          false, sum, cuda::GpuMat(windows), sms);
                expectSameWindowSums(wsum, sum, windows, D, c.name + format(", windows, as on %d SMs", sms));
            }
        }
}

// The disparity windows on the GPU (src_cuda/search_window.cu and the windowed path and winner-takes-all kernels)
// against the CPU's, stage by stage: the windows and the coarse map, the sums within the windows, the winners.
TEST(Lidarsgm_CUDA_Aggregation, windows_bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
        for (int margin : { 1, 4, 24 })
        {
            const std::string what = c.name + format(", margin %d", margin);
            PipelineParams p = c.p;
            p.searchWindow = margin;
            const Mat windowPrior = p.semidense ? c.semidense16 : c.sparse16;
            Mat windows, coarse;
            Ptr<AggregationState> work;
            searchWindows(windowPrior, c.left, c.right, p, windows, &work, &coarse);
            if (coarse.empty())
                coarseDisparities(c.left, c.right, p, coarse);   // the GPU computes it on every call
            cuda::GpuMat gw, gcoarse;
            cuda_host::searchWindows(windowPrior.empty() ? cuda::GpuMat() : cuda::GpuMat(windowPrior),
                                     cuda::GpuMat(c.left), cuda::GpuMat(c.right), p, gw, &gcoarse);
            expectSameAsCpu(coarse, gcoarse, what + " (coarse)");
            expectSameAsCpu(windows, gw, what + " (windows)");

            WinnerMaps winners;
            Mat sum;
            aggregateCosts(aggregationInputs(c.censusL, c.censusR, c.prior, c.left, c.own16, windows), p, winners, sum);
            cuda::GpuMat gl, gr, gsum;
            cuda_host::censusTransform(cuda::GpuMat(c.left), cuda::GpuMat(c.right), p, gl, gr);
            // Both layouts: one line a warp (the device's multiprocessors) and the packed layout (as on 1 SM, where
            // the range allows it; up to 128 disparities the packed windows' layout on both, with the costs stored
            // on 1 SM).
            for (int sms : { 1, 0 })
            {
                cuda_host::aggregateCosts(gl, gr, c.prior.empty() ? cuda::GpuMat() : cuda::GpuMat(c.prior),
                                          cuda::GpuMat(c.left), p,
                                          c.own16.empty() ? cuda::GpuMat() : cuda::GpuMat(c.own16), c.scan, gsum, gw,
                                          sms);
                expectSameWindowSums(sum, gsum, windows, p.numDisparities, what + format(", as on %d SMs", sms));
            }
            cuda::GpuMat g16, gInt, gRight, gNonUnique;
            cuda_host::winnerTakesAll(gsum, c.left.cols, p, g16, gInt, gRight, gNonUnique, gw);
            expectSameAsCpu(winners.disp16, g16, what + " (disp16)");
            expectSameAsCpu(winners.dispInt, gInt, what + " (dispInt)");
            expectSameAsCpu(winners.dispRight, gRight, what + " (dispRight)");
            if (!winners.nonUnique16.empty())
                expectSameAsCpu(winners.nonUnique16, gNonUnique, what + " (nonUnique16)");
        }
}

}} // namespace
