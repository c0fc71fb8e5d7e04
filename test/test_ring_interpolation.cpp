// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;
using cv::lidarsgm::StereoLidarSGM;

/* Two rings 20 rows apart (rows 5 and 25, a point in every second column of 10..30) on a plane whose disparity is
 4 + y / 4 px (64 + 4 y in 1/16 px), 50 rows. The left census strings equal the right ones at each row's true integer
 disparity, so the plane's pixels match at cost 0. */
class Lidarsgm_RingInterpolation : public testing::Test
{
protected:
    void SetUp() CV_OVERRIDE
    {
        W = 48; H = 50;
        RNG rng(5);
        cr.create(H, W, CV_32SC1);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                cr.at<int>(y, x) = (int)rng.next();
        cl.create(H, W, CV_32SC1);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                cl.at<int>(y, x) = cr.at<int>(y, std::min(std::max(x - roundDisp16(plane16(y)), 0), W - 1));
        sparse = Mat(H, W, CV_16SC1, Scalar::all(NO_DISP));
        for (int x = 10; x <= 30; x += 2)
        {
            sparse.at<short>(5, x) = (short)plane16(5);
            sparse.at<short>(25, x) = (short)plane16(25);
        }
        p = PipelineParams();
        p.minDisparity = 0;
        p.numDisparities = 32;
        p.semidenseThreshold = 2;
    }
    static int plane16(int y) { return 64 + 4 * y; }
    Mat run(double factor, const Mat& left)
    {
        p.ringGapFactor16 = cvRound(factor * 16);
        Mat out = sparse.clone();
        interpolateRings(left, cr, sparse, p, out, rings);
        return out;
    }
    int W, H;
    Mat cl, cr, sparse;
    PipelineParams p;
    RingMaps rings;
};

TEST_F(Lidarsgm_RingInterpolation, fills_the_plane_between_and_beyond_rings)
{
    // Spacing: each upper point's next point below is 20 rows away (the lower ring has none): median 20, limit 20.
    // Between the rings the line through them; above the upper ring and up to 20 rows below the lower one the same
    // line, extrapolated.
    const Mat out = run(1.0, cl);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
        {
            const short v = out.at<short>(y, x);
            if (sparse.at<short>(y, x) != NO_DISP)
                EXPECT_EQ(sparse.at<short>(y, x), v) << x << "," << y;   // a pixel with a value keeps it
            else if (y != 5 && y != 25 && y <= 45 && x >= 8 && x <= 32)
                EXPECT_EQ(plane16(y), v) << x << "," << y;               // a ring point within 2 columns
            else   // too far below, no ring in the columns, or on a ring's row (its points are neither above nor below)
                EXPECT_EQ(NO_DISP, v) << x << "," << y;
        }
}

TEST_F(Lidarsgm_RingInterpolation, gap_limit_off_and_census_test)
{
    // 0.95 x 20 = 19 rows: the rings are 20 apart, nothing bridged; factor 0: off.
    EXPECT_EQ(0, cvtest::norm(run(0.95, cl), sparse, NORM_INF));
    EXPECT_EQ(0, cvtest::norm(run(0.0, cl), sparse, NORM_INF));
    // Left strings that match nothing: the census test rejects every interpolation.
    Mat other(H, W, CV_32SC1);
    RNG rng(6);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            other.at<int>(y, x) = (int)rng.next();
    EXPECT_EQ(0, cvtest::norm(run(1.0, other), sparse, NORM_INF));
}

/* The ring check on the same plane: a pixel between the rings whose left-right test fails and whose check window
 (rc = 2) holds no sparse value survives when it is within Tc of the line through the rings; a non-unique winner is
 kept on the same test where the median left the pixel empty. */
TEST_F(Lidarsgm_RingInterpolation, ring_check)
{
    run(1.0, cl);
    ASSERT_TRUE(rings.valid);
    p.semidense = p.stereoCheck = p.lidarCheck = true;
    p.lrMaxDiff = 1;
    p.checkRadius = 2;
    p.checkThreshold16 = 32;
    enum { y = 15 };
    const auto check = [&](int v16, int nonUnique16, const RingMaps& r, int x = 20, int yy = y) {
        Mat d16(H, W, CV_16SC1, Scalar::all(NO_DISP)), di(H, W, CV_16SC1, Scalar::all(NO_DISP));
        Mat dr(H, W, CV_16SC1, Scalar::all(NO_DISP)), nu(H, W, CV_16SC1, Scalar::all(NO_DISP)), out;
        d16.at<short>(yy, x) = (short)v16;
        di.at<short>(yy, x) = v16 == NO_DISP ? NO_DISP : (short)(v16 / 16);   // no right view: left-right fails
        nu.at<short>(yy, x) = (short)nonUnique16;
        consistencyCheck(d16, di, dr, sparse, nu, r, p, out);
        const short o = out.at<short>(yy, x);
        return o == encodeOutput16(NO_DISP, 0) ? (int)NO_DISP : (int)o;
    };
    EXPECT_EQ(plane16(y) + 32, check(plane16(y) + 32, NO_DISP, rings));           // |d - line| = Tc: kept
    EXPECT_EQ(NO_DISP, check(plane16(y) + 33, NO_DISP, rings));                   // 1/16 px over
    EXPECT_EQ(NO_DISP, check(plane16(y) + 32, NO_DISP, RingMaps()));              // no ring maps: the paper's check
    EXPECT_EQ(plane16(y) - 20, check(NO_DISP, plane16(y) - 20, rings));           // a non-unique winner on the line
    EXPECT_EQ(NO_DISP, check(NO_DISP, plane16(y) - 40, rings));                   // off the line
    EXPECT_EQ(NO_DISP, check(NO_DISP, plane16(47), rings, 20, 47));               // 22 rows below the last ring
    EXPECT_EQ(NO_DISP, check(NO_DISP, plane16(y), rings, 40));                    // no ring within 2 columns
    p.semidense = false;                                                          // not SDSGM: off
    EXPECT_EQ(NO_DISP, check(plane16(y), NO_DISP, rings));
    EXPECT_EQ(NO_DISP, check(NO_DISP, plane16(y), rings));
    p.semidense = true;
    p.stereoCheck = p.lidarCheck = false;                                         // no check: nothing rescued
    EXPECT_EQ(NO_DISP, check(NO_DISP, plane16(y), rings));
}

/* The maps of each pixel's nearest ring points (ringNearestMaps: vectors of pixels at a time, 16-bit keys; rows past
4094 by the rule itself) equal nearestRingPoints on the above / below maps, on random maps of several densities and
sizes: ties between columns, the image's side columns, widths that are not a multiple of the vector width. */
TEST(Lidarsgm_RingInterpolationRules, nearest_maps_match_the_rule)
{
    RNG rng(11);
    const Size sizes[] = { Size(1, 7), Size(5, 40), Size(37, 23), Size(100, 61), Size(3, 4200) };
    for (const Size& sz : sizes)
        for (double density : { 0.01, 0.05, 0.3 })
        {
            Mat sparse(sz, CV_16SC1, Scalar::all(NO_DISP));
            for (int y = 0; y < sz.height; y++)
                for (int x = 0; x < sz.width; x++)
                    if (rng.uniform(0.0, 1.0) < density)
                        sparse.at<short>(y, x) = (short)rng.uniform(0, 2000);
            RingMaps rings;
            ringNearestMaps(sparse, rings);
            for (int y = 0; y < sz.height; y++)
                for (int x = 0; x < sz.width; x++)
                {
                    // above / below as their definition gives them
                    int xa, ya, xb, yb;
                    nearestRingPoints(rings.above16.ptr<short>(y), rings.below16.ptr<short>(y), x, sz.width, xa, ya,
                                      xb, yb);
                    const Vec4s v = rings.nearest.at<Vec4s>(y, x);
                    ASSERT_EQ(Vec4s((short)xa, (short)ya, (short)xb, (short)yb), v) << sz << " " << x << "," << y;
                }
            for (int x = 0; x < sz.width; x++)
                for (int y = 0; y < sz.height; y++)
                {
                    int a = -1, b = -1;
                    for (int v = y - 1; v >= 0 && a < 0; v--)
                        a = sparse.at<short>(v, x) != NO_DISP ? v : -1;
                    for (int v = y + 1; v < sz.height && b < 0; v++)
                        b = sparse.at<short>(v, x) != NO_DISP ? v : -1;
                    ASSERT_EQ(a, rings.above16.at<short>(y, x));
                    ASSERT_EQ(b, rings.below16.at<short>(y, x));
                }
        }
}

TEST(Lidarsgm_RingInterpolationRules, arithmetic)
{
    // Rounded to nearest, halves up, for rising and falling values.
    EXPECT_EQ(100, ringLine16(100, 0, 200, 10, 0));
    EXPECT_EQ(150, ringLine16(100, 0, 200, 10, 5));
    EXPECT_EQ(101, ringLine16(100, 0, 103, 4, 1));   // 100.75
    EXPECT_EQ(102, ringLine16(100, 0, 103, 6, 3));   // 101.5 -> 102
    EXPECT_EQ(102, ringLine16(103, 0, 100, 6, 3));   // 101.5 -> 102
    EXPECT_EQ(101, ringLine16(103, 0, 100, 4, 3));   // 100.75
    EXPECT_EQ(106, ringLine16(100, 0, 103, 4, 8));   // beyond the points
    EXPECT_EQ(99, ringLine16(100, 4, 103, 8, 3));    // 99.25
    // Lower median of a histogram; the gap limit from 16 x the factor.
    const int hist[5] = { 0, 2, 0, 3, 0 };
    EXPECT_EQ(3, histogramLowerMedian(hist, 5));
    const int even[4] = { 0, 1, 1, 0 };
    EXPECT_EQ(1, histogramLowerMedian(even, 4));
    const int none[3] = { 0, 0, 0 };
    EXPECT_EQ(0, histogramLowerMedian(none, 3));
    EXPECT_EQ(40, ringGapLimit(32, 20));
    EXPECT_EQ(11, ringGapLimit(24, 7));    // 10.5 -> 11
    // Nearest points: the closer row wins, on equal rows the nearer column (0, -1, 1, -2, 2).
    const short above[5] = { 3, 4, -1, 4, 2 }, below[5] = { 9, -1, 12, 9, 9 };
    int xa, ya, xb, yb;
    nearestRingPoints(above, below, 2, 5, xa, ya, xb, yb);
    EXPECT_EQ(4, ya); EXPECT_EQ(1, xa);
    EXPECT_EQ(9, yb); EXPECT_EQ(3, xb);
    nearestRingPoints(above, below, 0, 5, xa, ya, xb, yb);   // columns 0..2 only
    EXPECT_EQ(4, ya); EXPECT_EQ(1, xa);
    EXPECT_EQ(9, yb); EXPECT_EQ(0, xb);
}

// Through the API: ringGapFactor reaches the pipeline (semidensify() fills more pixels) and is range-checked.
TEST(Lidarsgm_RingInterpolationApi, parameter)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    EXPECT_EQ(0.0, m->getRingGapFactor());
    EXPECT_THROW(m->setRingGapFactor(-1), cv::Exception);
    EXPECT_THROW(m->setRingGapFactor(std::numeric_limits<double>::quiet_NaN()), cv::Exception);
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    Mat off, on;
    m->semidensify(l, r, s, off);
    m->setRingGapFactor(2);
    m->semidensify(l, r, s, on);
    // Invalid pixels are minDisparity - 1 (-16 here): count the valid ones (64 lines: few gaps to bridge).
    EXPECT_GT(countNonZero(on >= 0), countNonZero(off >= 0) + 500);   // 62000 + 879 measured
}

// The CUDA twin (src_cuda/ring_interpolation.cu): the filled semidense map, the maps the ring check reads and the
// gap limit, on the configurations with ring interpolation on.
TEST(Lidarsgm_CUDA_RingInterpolation, bit_exact)
{
    requireCudaDevice();
    int tested = 0;
    for (const StageCase& c : stageCases())
    {
        if (c.p.ringGapFactor16 <= 0)
            continue;
        cuda::GpuMat gl, gr, above, below;
        cuda_host::censusTransform(cuda::GpuMat(c.left), cuda::GpuMat(c.right), c.p, gl, gr);
        cuda::GpuMat gs(c.semidense0);
        int gap = -1;
        cuda_host::interpolateRings(gl, gr, cuda::GpuMat(c.sparse16), c.p, gs, above, below, gap);
        Mat semidense = c.semidense0.clone();
        RingMaps rings;
        interpolateRings(c.censusL, c.censusR, c.sparse16, c.p, semidense, rings);
        expectSameAsCpu(semidense, gs, c.name);
        expectSameAsCpu(rings.above16, above, c.name + " (above)");
        expectSameAsCpu(rings.below16, below, c.name + " (below)");
        EXPECT_EQ(rings.gap, gap) << c.name;
        tested++;
    }
    EXPECT_EQ(2, tested);
}

}} // namespace
