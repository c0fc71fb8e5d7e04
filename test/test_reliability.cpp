// This file is part of the lidarsgm module (an OpenCV extra module).
// Reliability on the CPU path: hostile sizes, size changes, threads, determinism, and a seeded random ("fuzz") test
// with a time budget. The CUDA twins are in test_cuda.cpp.
#include "test_common.hpp"

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;

// Every output value is invalid ((minD - 1) in the output's unit) or a disparity in [minD, minD + numD).
static void expectValidOutput(const Mat& out, Size sz, int outputType, int minD, int numD, const std::string& what)
{
    ASSERT_EQ(sz, out.size()) << what;
    ASSERT_EQ(outputType == CV_16S ? CV_16SC1 : CV_32FC1, out.type()) << what;
    for (int y = 0; y < out.rows; y++)
        for (int x = 0; x < out.cols; x++)
        {
            const double v = outputType == CV_16S ? out.at<short>(y, x) / 16.0 : (double)out.at<float>(y, x);
            if (v == minD - 1)
                continue;
            ASSERT_TRUE(v >= minD && v < minD + numD) << what << ": value " << v << " at (" << x << ", " << y << ")";
        }
}

static void texturedPair(Size sz, int depth, int shift, RNG& rng, Mat& l, Mat& r)
{
    Mat big(sz.height, sz.width + shift, depth);
    rng.fill(big, RNG::UNIFORM, 0, depth == CV_8U ? 256 : 65536);
    if (big.cols >= 3 && big.rows >= 3)
        GaussianBlur(big, big, Size(3, 3), 0);
    // Left pixel x matches right pixel x - shift.
    l = big(Rect(0, 0, sz.width, sz.height)).clone();
    r = big(Rect(shift, 0, sz.width, sz.height)).clone();
}

static Mat randomSparse(Size sz, int type, double density, double lo, double hi, RNG& rng, bool hostileValues)
{
    Mat s(sz, type, Scalar::all(0));
    const int n = cvRound(sz.area() * density);
    for (int i = 0; i < n; i++)
    {
        const int y = rng.uniform(0, sz.height), x = rng.uniform(0, sz.width);
        double v = rng.uniform(lo, hi);
        if (type == CV_32F)
        {
            float f = (float)v;
            if (hostileValues)
            {
                const int k = rng.uniform(0, 8);
                if (k == 0) f = std::numeric_limits<float>::quiet_NaN();
                else if (k == 1) f = std::numeric_limits<float>::infinity();
                else if (k == 2) f = -std::numeric_limits<float>::infinity();
                else if (k == 3) f = -(float)rng.uniform(0.0, 50.0);
                else if (k == 4) f = 1e30f;
            }
            s.at<float>(y, x) = f;
        }
        else
            s.at<ushort>(y, x) = saturate_cast<ushort>(hostileValues && rng.uniform(0, 4) == 0 ? rng.uniform(0, 65536) : v * 256);
    }
    return s;
}

// Sizes down to 1x1, strips, images smaller than the census window or narrower than the disparity range, odd sizes:
// every mode and check runs, and the output follows the documented format.
TEST(Lidarsgm_Reliability, hostile_sizes)
{
    const Size sizes[] = { Size(1, 1), Size(1, 57), Size(83, 1), Size(2, 2), Size(5, 3), Size(8, 6), Size(20, 40),
                           Size(63, 17), Size(17, 33), Size(129, 65) };
    RNG rng(21);
    for (const Size& sz : sizes)
        for (int mode = 0; mode < 3; mode++)
            for (int check = 0; check < 4; check++)
            {
                const int numD = check % 2 ? 64 : 16, minD = check == 2 ? -3 : 0;
                Mat l, r;
                texturedPair(sz, mode == 1 ? CV_16U : CV_8U, 2, rng, l, r);
                Mat s = randomSparse(sz, CV_32F, 0.1, minD, minD + numD, rng, false);
                Ptr<StereoLidarSGM> m = StereoLidarSGM::create(minD, numD, 10, 120, 5, 160, 0.7, mode, check);
                m->setNumPaths(check < 2 ? 8 : 4);
                Mat d;
                const std::string what = format("%dx%d mode %d check %d", sz.width, sz.height, mode, check);
                ASSERT_NO_THROW(m->compute(l, r, s, d)) << what;
                expectValidOutput(d, sz, CV_16S, minD, numD, what);
                Mat semi;
                ASSERT_NO_THROW(m->semidensify(l, r, s, semi)) << what;
                expectValidOutput(semi, sz, CV_16S, minD, numD, what + " (semidense)");
            }
}

// The documented border rule: a right pixel x - d left of the image is taken from column 0 (census strings and
// image coordinates are clamped), so the leftmost columns still get a disparity; the left-right check then rejects
// what has no right-view partner. On a pair shifted by 5 the interior is exact and the border is defined.
TEST(Lidarsgm_Reliability, border_rule)
{
    RNG rng(4);
    Mat l, r;
    texturedPair(Size(96, 40), CV_8U, 5, rng, l, r);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16, 10, 120, 5, 160, 0.7, StereoLidarSGM::MODE_SGM,
                                                   StereoLidarSGM::CHECK_NONE);
    m->setSubpixel(false);
    Mat d;
    m->compute(l, r, noArray(), d);
    int exact = 0, interior = 0;
    for (int y = 4; y < 36; y++)
        for (int x = 10; x < 86; x++, interior++)
            exact += d.at<short>(y, x) == 5 * 16;
    EXPECT_GE(exact, interior * 99 / 100);
    // Column 0: every disparity compares with right column 0; the output is still valid or invalid, never garbage.
    expectValidOutput(d, l.size(), CV_16S, 0, 16, "border");
    m->setConsistencyCheck(StereoLidarSGM::CHECK_STEREO);
    Mat checked;
    m->compute(l, r, noArray(), checked);
    // Pixels whose match falls left of the right image cannot have a right-view partner there: x < d fails the check.
    for (int y = 0; y < 40; y++)
        for (int x = 0; x < 5; x++)
        {
            const short v = checked.at<short>(y, x);
            EXPECT_TRUE(v == -16 || v / 16 <= x) << "x " << x << " y " << y << " d " << v / 16.0;
        }
}

TEST(Lidarsgm_Reliability, size_3840x2160)
{
    RNG rng(8);
    Mat l, r;
    texturedPair(Size(3840, 2160), CV_8U, 9, rng, l, r);
    Mat s = randomSparse(l.size(), CV_32F, 0.05, 9, 10, rng, false);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 64);
    Mat d;
    m->compute(l, r, s, d);
    expectValidOutput(d, l.size(), CV_16S, 0, 64, "3840x2160");
    Mat inner = d(Rect(100, 10, 3640, 2140));
    EXPECT_GE(countNonZero(abs(inner - 9 * 16) <= 8), (int)(inner.total() * 0.99));
}

// One instance, sizes and disparity ranges changing from call to call: each result equals a fresh instance's.
TEST(Lidarsgm_Reliability, size_change_between_calls)
{
    const Size sizes[] = { Size(320, 240), Size(64, 64), Size(7, 5), Size(320, 240), Size(97, 300), Size(1, 1) };
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 64);
    RNG rng(5);
    for (int i = 0; i < 6; i++)
    {
        Mat l, r;
        texturedPair(sizes[i], CV_8U, 3, rng, l, r);
        Mat s = randomSparse(sizes[i], CV_32F, 0.04, 1, 60, rng, false);
        const int numD = i % 2 ? 128 : 64;
        m->setNumDisparities(numD);
        m->setOutputType(i % 3 == 1 ? CV_32F : CV_16S);
        Mat reused, fresh;
        m->compute(l, r, s, reused);
        Ptr<StereoLidarSGM> f = StereoLidarSGM::create(0, numD);
        f->setOutputType(m->getOutputType());
        f->compute(l, r, s, fresh);
        EXPECT_EQ(0, cvtest::norm(reused, fresh, NORM_INF)) << "call " << i;
    }
}

// A shipped KITTI frame and its projected scan, cropped to its middle 600 columns (keeps the tests quick under the
// sanitizers while every stage still runs on real data).
static void loadShippedFrame(const std::string& id, Mat& l, Mat& r, Mat& s)
{
    loadKittiTestFrame(id, l, r, s);
    const Rect crop(320, 0, 600, l.rows);
    l = l(crop).clone();
    r = r(crop).clone();
    s = s(crop).clone();
}

// The same input gives the same output, run after run and for 1, 2, 3 and 8 worker threads.
TEST(Lidarsgm_Reliability, deterministic_over_runs_and_thread_counts)
{
    Mat l, r, s;
    loadShippedFrame("000046", l, r, s);
    const int saved = getNumThreads();
    for (int mode = 0; mode < 3; mode++)
    {
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode);
        Mat ref, semiRef;
        setNumThreads(1);
        m->compute(l, r, s, ref);
        m->semidensify(l, r, s, semiRef);
        const int threads[] = { 2, 3, 8, 8 };  // the last one twice: run after run
        for (int t : threads)
        {
            setNumThreads(t);
            Mat d, semi;
            m->compute(l, r, s, d);
            m->semidensify(l, r, s, semi);
            EXPECT_EQ(0, cvtest::norm(ref, d, NORM_INF)) << "mode " << mode << " threads " << t;
            EXPECT_EQ(0, cvtest::norm(semiRef, semi, NORM_INF)) << "mode " << mode << " threads " << t;
        }
    }
    setNumThreads(saved);
}

// Several instances on several threads at once, and one instance shared by several threads (its calls serialise):
// every result equals the result computed alone.
TEST(Lidarsgm_Reliability, threads)
{
    Mat l[2], r[2], s[2];
    loadShippedFrame("000002", l[0], r[0], s[0]);
    loadShippedFrame("000046", l[1], r[1], s[1]);
    const int T = 4;
    std::vector<Mat> alone(T);
    for (int t = 0; t < T; t++)
        StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, t % 3)->compute(l[t % 2], r[t % 2], s[t % 2], alone[t]);
    Ptr<StereoLidarSGM> shared = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, StereoLidarSGM::MODE_SDSGM);
    Mat sharedRef[2];
    for (int i = 0; i < 2; i++)
        shared->compute(l[i], r[i], s[i], sharedRef[i]);

    std::vector<double> errOwn(T, -1), errShared(T, -1);
    std::vector<std::string> failure(T);
    std::vector<std::thread> pool;
    for (int t = 0; t < T; t++)
        pool.emplace_back([&, t] {
            try
            {
                Ptr<StereoLidarSGM> own = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, t % 3);
                double e1 = 0, e2 = 0;
                for (int k = 0; k < 2; k++)
                {
                    Mat d1, d2;
                    own->compute(l[t % 2], r[t % 2], s[t % 2], d1);
                    e1 = std::max(e1, cvtest::norm(alone[t], d1, NORM_INF));
                    shared->compute(l[(t + k) % 2], r[(t + k) % 2], s[(t + k) % 2], d2);
                    e2 = std::max(e2, cvtest::norm(sharedRef[(t + k) % 2], d2, NORM_INF));
                }
                errOwn[t] = e1;
                errShared[t] = e2;
            }
            catch (const std::exception& e) { failure[t] = e.what(); }
        });
    for (auto& th : pool)
        th.join();
    for (int t = 0; t < T; t++)
    {
        EXPECT_EQ(0, errOwn[t]) << "thread " << t << " " << failure[t];
        EXPECT_EQ(0, errShared[t]) << "thread " << t << " (shared instance) " << failure[t];
    }
}

/* The documented units rule, counted here on its own: of at least 64 measurements (nonzero CV_16U, positive finite
 CV_32F), more than half lie outside the range once taken to 1/16 pixel (below minD, or at or above minD + numD - 1/2)
 and at or beyond the image's width. */
static bool mostlyOutOfRange(const Mat& s, int minD, int numD)
{
    int measured = 0, beyond = 0;
    for (int y = 0; y < s.rows; y++)
        for (int x = 0; x < s.cols; x++)
        {
            const double v = s.type() == CV_32F ? (double)s.at<float>(y, x) : s.at<ushort>(y, x) / 256.0;
            if (!(v > 0) || std::isinf(v))
                continue;
            measured++;
            const double d16 = std::floor(v * 16 + 0.5);
            const bool inside = v < 1536 && d16 >= 16.0 * minD && d16 < 16.0 * (minD + numD) - 8;
            beyond += !inside && v >= s.cols;
        }
    return measured >= 64 && 2 * beyond > measured;
}

/* Seeded random test with a time budget (LIDARSGM_FUZZ_SECONDS, default 20; LIDARSGM_FUZZ_SEED, default 1): random
 sizes (1x1 .. 300x200, strips), 8/16-bit images, random valid parameters, modes, checks, paths, output types, sparse
 maps of both types with NaN, infinities, negative, huge and out-of-range values, ROI views; sometimes a broken input
 (size or type mismatch, colour) that must raise cv::Exception, and maps mostly out of range that the units check
 must refuse. compute() and semidensify() must not crash and must
 give outputs of the right size and type whose values are invalid or within [minD, minD + numD). The projection gets
 random point clouds with non-finite coordinates. Prints how many cases ran. */
TEST(Lidarsgm_Reliability, fuzz)
{
    const char* secEnv = getenv("LIDARSGM_FUZZ_SECONDS");
    const char* seedEnv = getenv("LIDARSGM_FUZZ_SEED");
    const double budget = secEnv ? atof(secEnv) : 20.0;
    const uint64 seed = seedEnv ? (uint64)atoll(seedEnv) : 1;
    RNG rng(seed);
    const int64 t0 = getTickCount();
    int cases = 0, refused = 0, projections = 0, maxArea = 0;
    while ((getTickCount() - t0) / getTickFrequency() < budget || cases < 20)
    {
        const int shape = rng.uniform(0, 10);
        Size sz(rng.uniform(1, 301), rng.uniform(1, 201));
        if (shape == 0) sz.width = 1;
        if (shape == 1) sz.height = 1;
        if (shape == 2) sz = Size(rng.uniform(1, 12), rng.uniform(1, 10));
        maxArea = std::max(maxArea, sz.area());
        const int depth = rng.uniform(0, 2) ? CV_16U : CV_8U;
        const int numD = 16 * rng.uniform(1, 17), minD = rng.uniform(-40, 41);
        Mat l, r;
        texturedPair(sz, depth, rng.uniform(0, 20), rng, l, r);
        const int stype = rng.uniform(0, 2) ? CV_32F : CV_16U;
        Mat s = randomSparse(sz, stype, rng.uniform(0.0, 0.3), minD - 5, minD + numD + 5, rng, true);
        if (rng.uniform(0, 4) == 0 && sz.width > 2 && sz.height > 2)  // views into larger buffers
        {
            Mat L2(sz.height + 2, sz.width + 3, l.type()), R2(L2.size(), r.type()), S2(L2.size(), s.type());
            l.copyTo(L2(Rect(1, 1, sz.width, sz.height)));
            r.copyTo(R2(Rect(2, 1, sz.width, sz.height)));
            s.copyTo(S2(Rect(3, 2, sz.width, sz.height)));
            l = L2(Rect(1, 1, sz.width, sz.height));
            r = R2(Rect(2, 1, sz.width, sz.height));
            s = S2(Rect(3, 2, sz.width, sz.height));
        }
        const int P1 = rng.uniform(0, 200), P2 = rng.uniform(P1, 1001), Q1 = rng.uniform(0, 200), Q2 = rng.uniform(Q1, 1001);
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(minD, numD, P1, P2, Q1, Q2, rng.uniform(0.0, 1.0),
                                                       rng.uniform(0, 3), rng.uniform(0, 4));
        m->setNumPaths(rng.uniform(0, 2) ? 8 : 4);
        m->setSubpixel(rng.uniform(0, 2) == 1);
        m->setOutputType(rng.uniform(0, 2) ? CV_32F : CV_16S);
        m->setUniquenessRatio(rng.uniform(0.5, 1.0));
        m->setSemidenseRadius(rng.uniform(0, 33));
        m->setSemidenseThreshold(rng.uniform(0, 33));
        m->setCheckRadius(rng.uniform(0, 65));
        m->setCheckThreshold(rng.uniform(0.0, 64.0));
        m->setLRMaxDiff(rng.uniform(0, 4));
        if (rng.uniform(0, 3) == 0)
        {
            m->setVisibilityRadiusX(rng.uniform(0, 17));
            m->setVisibilityRadiusY(rng.uniform(0, 17));
            m->setVisibilityParallax(rng.uniform(0.0, 1.0));
        }
        const std::string what = format("case %d: %dx%d depth %d minD %d numD %d mode %d check %d", cases,
                                        sz.width, sz.height, depth, minD, numD, m->getMode(), m->getConsistencyCheck());
        const int broken = rng.uniform(0, 12);
        if (broken == 0 || broken == 1 || broken == 2)
        {
            Mat badR = broken == 0 ? Mat(sz.height + 1, sz.width, r.type(), Scalar::all(0))
                     : broken == 1 ? Mat(sz, depth == CV_8U ? CV_16UC1 : CV_8UC1, Scalar::all(0))
                                   : Mat(sz, CV_MAKETYPE(depth, 3), Scalar::all(0));
            Mat d;
            EXPECT_THROW(m->compute(l, badR, s, d), cv::Exception) << what << " broken " << broken;
            refused++;
        }
        else if (mostlyOutOfRange(s, minD, numD))
        {
            // The units check: a map whose measurements mostly miss the range is refused, not fused.
            Mat d, semi;
            EXPECT_THROW(m->compute(l, r, s, d), cv::Exception) << what << " (units)";
            EXPECT_THROW(m->semidensify(l, r, s, semi), cv::Exception) << what << " (units)";
            refused++;
        }
        else
        {
            Mat d, semi;
            ASSERT_NO_THROW(m->compute(l, r, s, d)) << what;
            expectValidOutput(d, sz, m->getOutputType(), minD, numD, what);
            ASSERT_NO_THROW(m->semidensify(l, r, s, semi)) << what;
            expectValidOutput(semi, sz, m->getOutputType(), minD, numD, what + " (semidense)");
        }
        // Projection: random clouds, some coordinates NaN/inf, a random (valid) camera.
        {
            const int n = rng.uniform(0, 2000);
            Mat pts(std::max(n, 1), rng.uniform(0, 2) ? 4 : 3, CV_32F);
            rng.fill(pts, RNG::UNIFORM, -50, 50);
            for (int i = 0; i < n / 20; i++)
                pts.at<float>(rng.uniform(0, pts.rows), rng.uniform(0, pts.cols)) =
                    rng.uniform(0, 2) ? std::numeric_limits<float>::quiet_NaN() : std::numeric_limits<float>::infinity();
            const double f = rng.uniform(50.0, 2000.0);
            Matx34d P(f, 0, sz.width / 2.0, rng.uniform(-100.0, 100.0), 0, f, sz.height / 2.0, 0, 0, 0, 1, 0);
            const double a = rng.uniform(-3.0, 3.0);
            Matx34d T(cos(a), -sin(a), 0, rng.uniform(-1.0, 1.0), sin(a), cos(a), 0, 0, 0, 0, 1, rng.uniform(-5.0, 5.0));
            const int dtype = rng.uniform(0, 2) ? CV_32F : CV_16U;
            Mat disp;
            ASSERT_NO_THROW(cv::lidarsgm::projectPointsToDisparity(pts, P, T, rng.uniform(1.0, 500.0), sz, disp, dtype)) << what;
            ASSERT_EQ(sz, disp.size());
            ASSERT_EQ(dtype == CV_32F ? CV_32FC1 : CV_16UC1, disp.type());
            if (dtype == CV_32F)
            {
                EXPECT_TRUE(checkRange(disp, true, nullptr, 0.0, DBL_MAX)) << what << " projection";
            }
            projections++;
        }
        cases++;
    }
    std::cout << "fuzz: seed " << seed << ", " << cases << " cases (" << refused << " broken inputs refused), "
              << projections << " projections, largest image " << maxArea << " pixels, "
              << format("%.1f s", (getTickCount() - t0) / getTickFrequency()) << std::endl;
}

}} // namespace
