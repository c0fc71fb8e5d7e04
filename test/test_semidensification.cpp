// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

// Left census all zero; right census zero at columns 5 and 7, three bits elsewhere, so H(p, d) = 0 exactly when
// x - d is 5 or 7, else 3. Two sparse points on row 2: d = 5 at x = 10 and d = 7 at x = 12.
class Lidarsgm_Semidensification : public testing::Test
{
protected:
    void SetUp() CV_OVERRIDE
    {
        W = 40; H = 5;
        cl = Mat(H, W, CV_32SC1, Scalar::all(0));
        cr = Mat(H, W, CV_32SC1, Scalar::all(7));
        cr.col(5).setTo(Scalar::all(0));
        cr.col(7).setTo(Scalar::all(0));
        sparse = Mat(H, W, CV_16SC1, Scalar::all(NO_DISP));
        sparse.at<short>(2, 10) = 5 * 16;
        sparse.at<short>(2, 12) = 7 * 16 + 2;  // 7.125 px: the value is carried at 1/16 px
        p = PipelineParams();
        p.minDisparity = 0;
        p.numDisparities = 16;
        p.semidenseRadius = 6;
        p.semidenseThreshold = 2;
    }
    int W, H;
    Mat cl, cr, sparse;
    PipelineParams p;
};

TEST_F(Lidarsgm_Semidensification, choice)
{
    Mat out;
    semidensify(cl, cr, sparse, p, out);
    EXPECT_EQ(5 * 16, out.at<short>(2, 10));       // d = 5 matches (cost 0), d = 7 does not (cost 3)
    EXPECT_EQ(7 * 16 + 2, out.at<short>(2, 12));   // both cost 0: the nearer point (itself) wins
    EXPECT_EQ(7 * 16 + 2, out.at<short>(2, 14));   // propagated: d = 7 matches at x = 14 (x - d = 7)
    EXPECT_EQ(5 * 16, out.at<short>(0, 10));       // propagated vertically within rs
    EXPECT_EQ(NO_DISP, out.at<short>(2, 11));      // both candidates cost 3 >= Ts and no own value
    EXPECT_EQ(NO_DISP, out.at<short>(2, 19));      // x - 7 = 12: cost 3; outside d = 5's window anyway
    EXPECT_EQ(NO_DISP, out.at<short>(2, 25));      // no sparse point within rs
}

TEST_F(Lidarsgm_Semidensification, threshold_and_radius)
{
    Mat out;
    p.semidenseThreshold = 0;  // no cost is below 0: only the own values remain
    semidensify(cl, cr, sparse, p, out);
    Mat expected = sparse.clone();
    EXPECT_EQ(0, cvtest::norm(out, expected, NORM_INF));

    p.semidenseThreshold = 4;  // now cost 3 qualifies: at x = 11 the candidates tie at 3, the first in raster order
    semidensify(cl, cr, sparse, p, out);  // of the two equally near points (x = 10 and x = 12 are both 1 away) wins
    EXPECT_EQ(5 * 16, out.at<short>(2, 11));

    p.semidenseThreshold = 2;
    p.semidenseRadius = 1;     // x = 14 is 2 away from x = 12
    semidensify(cl, cr, sparse, p, out);
    EXPECT_EQ(NO_DISP, out.at<short>(2, 14));
}

TEST_F(Lidarsgm_Semidensification, own_value_kept_when_nothing_matches)
{
    cr.setTo(Scalar::all(0x7FFF));  // every candidate costs 15
    Mat out;
    semidensify(cl, cr, sparse, p, out);
    EXPECT_EQ(0, cvtest::norm(out, sparse, NORM_INF));
}

}} // namespace

namespace opencv_test { namespace {

// semidenseKey orders the candidates of one pixel exactly as (cost, squared distance, row, column) lexicographically.
TEST_F(Lidarsgm_Semidensification, key_order_is_the_lexicographic_order)
{
    using namespace cv::lidarsgm::detail;
    RNG rng(11);
    for (int rs : { 0, 1, 6, 32 })
        for (int t = 0; t < 20000; t++)
        {
            const int c1 = rng.uniform(0, 32), c2 = rng.uniform(0, 32);
            const int dx1 = rng.uniform(-rs, rs + 1), dy1 = rng.uniform(-rs, rs + 1);
            const int dx2 = rng.uniform(-rs, rs + 1), dy2 = rng.uniform(-rs, rs + 1);
            const int d1 = dx1 * dx1 + dy1 * dy1, d2 = dx2 * dx2 + dy2 * dy2;
            const bool lex = c1 != c2 ? c1 < c2 : d1 != d2 ? d1 < d2 : dy1 != dy2 ? dy1 < dy2 : dx1 < dx2;
            ASSERT_EQ(lex, semidenseKey(c1, dx1, dy1, rs) < semidenseKey(c2, dx2, dy2, rs));
            ASSERT_EQ(c1, semidenseKeyCost(semidenseKey(c1, dx1, dy1, rs)));
        }
}

// The CUDA twin (src_cuda/semidensification.cu) on every stage configuration, from the CUDA census strings.
TEST(Lidarsgm_CUDA_Semidensification, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        cuda::GpuMat gl, gr, gs;
        cuda_host::censusTransform(cuda::GpuMat(c.left), cuda::GpuMat(c.right), c.p, gl, gr);
        cuda_host::semidensify(gl, gr, cuda::GpuMat(c.sparse16), c.p, gs);
        expectSameAsCpu(c.semidense0, gs, c.name);
    }
}

}} // namespace
