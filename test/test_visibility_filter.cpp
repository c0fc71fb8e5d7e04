// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

static PipelineParams visibilityParams(int rx, int ry, int tc16)
{
    PipelineParams p = PipelineParams();
    p.visibilityRadiusX = rx;
    p.visibilityRadiusY = ry;
    p.checkThreshold16 = tc16;
    return p;
}

TEST(Lidarsgm_VisibilityFilter, nearer_points_hide_farther_ones_in_the_window)
{
    // A near object (disparity 40 px) whose points surround a background point (10 px) seen past its edge, and a
    // background point outside the window.
    Mat s(20, 20, CV_16SC1, Scalar::all(NO_DISP)), out;
    s.at<short>(10, 10) = 10 * 16;                  // background, among the object's points
    s.at<short>(10, 12) = 40 * 16;                  // 2 px right: inside rx = 2
    s.at<short>(6, 10) = 40 * 16;                   // 4 px up: inside ry = 4
    s.at<short>(10, 16) = 10 * 16;                  // background, 4 px right of the nearest object point: visible
    s.at<short>(3, 3) = 11 * 16;                    // a neighbour nearer by only 1 px (Tc = 2): both stay
    s.at<short>(4, 4) = 12 * 16;
    filterHiddenPoints(s, visibilityParams(2, 4, 32), out, false);
    EXPECT_EQ(NO_DISP, out.at<short>(10, 10));
    EXPECT_EQ(40 * 16, out.at<short>(10, 12));
    EXPECT_EQ(40 * 16, out.at<short>(6, 10));
    EXPECT_EQ(10 * 16, out.at<short>(10, 16));
    EXPECT_EQ(11 * 16, out.at<short>(3, 3));
    EXPECT_EQ(12 * 16, out.at<short>(4, 4));
    EXPECT_EQ(5, countNonZero(out != NO_DISP));
    // Exactly Tc nearer does not hide; 1/16 px more does.
    s.at<short>(4, 4) = 11 * 16 + 32;
    filterHiddenPoints(s, visibilityParams(2, 4, 32), out, false);
    EXPECT_EQ(11 * 16, out.at<short>(3, 3));
    s.at<short>(4, 4) = 11 * 16 + 33;
    filterHiddenPoints(s, visibilityParams(2, 4, 32), out, false);
    EXPECT_EQ(NO_DISP, out.at<short>(3, 3));
    // A smaller window no longer reaches the object's points.
    filterHiddenPoints(s, visibilityParams(1, 3, 32), out, false);
    EXPECT_EQ(10 * 16, out.at<short>(10, 10));
}

TEST(Lidarsgm_VisibilityFilter, window_grows_with_the_disparity_step)
{
    // hiddenBy at parallax 0.25: the window (2 x 4) grows by 1 px per 4 px of disparity step, at most
    // VISIBILITY_MAX_GROWTH.
    PipelineParams p = visibilityParams(2, 4, 32);
    p.visibilityParallax256 = 64;
    EXPECT_TRUE(hiddenBy(14 * 16, 10 * 16, 3, 0, p));        // 3 px right, 4 px nearer: growth 1
    EXPECT_FALSE(hiddenBy(14 * 16 - 1, 10 * 16, 3, 0, p));   // 3.9375 px nearer: growth 0.98
    EXPECT_TRUE(hiddenBy(42 * 16, 10 * 16, 0, -12, p));      // 12 px above, 32 px nearer: growth 8 reaches ry + 8
    EXPECT_FALSE(hiddenBy(42 * 16, 10 * 16, 0, -13, p));
    EXPECT_TRUE(hiddenBy(42 * 16, 10 * 16, -10, 12, p));     // both sides grow by the same 8 px
    EXPECT_FALSE(hiddenBy(10 * 16 + 32, 10 * 16, 0, 0, p)); // nearer by Tc only: never
    EXPECT_FALSE(hiddenBy(NO_DISP, 10 * 16, 0, 0, p));
    const int far = 2 + VISIBILITY_MAX_GROWTH;               // a 200 px step would grow the window by 50 px
    EXPECT_TRUE(hiddenBy(205 * 16, 5 * 16, far, 0, p));
    EXPECT_FALSE(hiddenBy(205 * 16, 5 * 16, far + 1, 0, p));
    p.visibilityParallax256 = 0;                             // without growth only the base window counts
    EXPECT_TRUE(hiddenBy(42 * 16, 10 * 16, -2, 4, p));
    EXPECT_FALSE(hiddenBy(42 * 16, 10 * 16, 3, 0, p));
}

TEST(Lidarsgm_VisibilityFilter, growth_allowed_is_the_largest_growth_its_inequality_admits)
{
    // visibilityGrowthAllowed, which hiddenBy, the CPU stage's dilation test and the CUDA kernel's row reach take,
    // against its definition: the largest k <= VISIBILITY_MAX_GROWTH with k * 4096 <= parallax256 * diff16 (0 where
    // none), at every parallax the matcher accepts (0 to 1) and differences of either sign.
    PipelineParams p = PipelineParams();
    for (int par = 0; par <= 256; par++)
    {
        p.visibilityParallax256 = par;
        for (int diff = -64; diff <= 2 * SHRT_MAX; diff += 5)
        {
            int k = 0;
            while (k < (int)VISIBILITY_MAX_GROWTH && (int64)(k + 1) * 4096 <= (int64)par * diff)
                k++;
            ASSERT_EQ(k, visibilityGrowthAllowed(diff, p)) << "parallax256 " << par << ", diff16 " << diff;
        }
    }
}

/* A synthetic LiDAR scan: rings every 5 rows with a shot every 2 columns, background at 10 px, and a near object at
40 px on the rings of rows 20 and 25 (columns 40 to 60); the background point (30, 50) sits 5 rows below the object,
beyond the 4 x 4 base window but within the growth (30 px step x 0.25). transposed: the same with rows and columns
exchanged, so that the points are closer across the lines than along them. */
static Mat syntheticScan(bool transposed)
{
    Mat s(80, 100, CV_16SC1, Scalar::all(NO_DISP));
    for (int y = 0; y < 80; y += 5)
        for (int x = 0; x < 80; x += 2)
            s.at<short>(y, x) = (short)((y == 20 || y == 25) && x >= 40 && x <= 60 ? 40 * 16 : 10 * 16);
    if (transposed)
    {
        Mat t(100, 80, CV_16SC1, Scalar::all(NO_DISP));
        Mat square = t(Rect(0, 0, 80, 80));
        cv::transpose(s(Rect(0, 0, 80, 80)), square);
        return t;
    }
    return s;
}

TEST(Lidarsgm_VisibilityFilter, growth_applies_to_scans_only)
{
    PipelineParams p = visibilityParams(4, 4, 32);
    p.numDisparities = 64;
    Mat out;
    for (int transposed = 0; transposed < 2; transposed++)
    {
        const Mat s = syntheticScan(transposed != 0);
        const Point target = transposed ? Point(30, 50) : Point(50, 30);
        p.visibilityParallax256 = 0;
        filterHiddenPoints(s, p, out, isLidarScan(s));
        EXPECT_EQ(10 * 16, out.at<short>(target)) << transposed;
        p.visibilityParallax256 = 64;
        filterHiddenPoints(s, p, out, isLidarScan(s));
        // A scan: the window grows and hides the point; a map whose lines run across: no scan, no growth.
        EXPECT_EQ(transposed ? 10 * 16 : (int)NO_DISP, out.at<short>(target)) << transposed;
    }
}

/* The filter against its definition, point by point: hidden where some value of the window grown to the largest
growth hides it (hiddenBy). On both KITTI scans, a random map and a slanted plane with near points on it, with and
without growth (the filter's dilation pre-test must not change the result). */
TEST(Lidarsgm_VisibilityFilter, equals_the_definition)
{
    std::vector<std::pair<std::string, Mat> > maps;
    for (const char* id : { "000002", "000046" })
    {
        Mat l, r, sparse, s16;
        loadKittiTestFrame(id, l, r, sparse);
        convertSparse(sparse, 0, 128, s16);
        maps.push_back(std::make_pair(std::string(id), s16));
    }
    RNG rng(11);
    Mat random(120, 160, CV_16SC1, Scalar::all(NO_DISP)), plane(120, 160, CV_16SC1, Scalar::all(NO_DISP));
    for (int i = 0; i < 3000; i++)
        random.at<short>(rng.uniform(0, 120), rng.uniform(0, 160)) = (short)rng.uniform(16, 127 * 16);
    for (int y = 0; y < 120; y += 3)
        for (int x = 0; x < 160; x += 2)
            plane.at<short>(y, x) = (short)(y * 12 + (rng.uniform(0, 8) == 0 ? rng.uniform(40, 800) : 0));
    maps.push_back(std::make_pair(std::string("random"), random));
    maps.push_back(std::make_pair(std::string("plane"), plane));
    for (const auto& m : maps)
        for (int parallax256 : { 0, 46, 64 })
            for (int rx : { 0, 2 })
            {
                PipelineParams p = visibilityParams(rx, 4, 32);
                p.numDisparities = 128;
                p.visibilityParallax256 = parallax256;
                const Mat& s = m.second;
                Mat out;
                filterHiddenPoints(s, p, out, true);
                const int g = visibilityGrowth(p), wx = rx + g, wy = 4 + g;
                int wrong = 0;
                for (int y = 0; y < s.rows; y++)
                    for (int x = 0; x < s.cols; x++)
                    {
                        const short d = s.at<short>(y, x);
                        bool hidden = false;
                        for (int v = std::max(y - wy, 0); d != NO_DISP && v <= std::min(y + wy, s.rows - 1); v++)
                            for (int u = std::max(x - wx, 0); u <= std::min(x + wx, s.cols - 1); u++)
                                hidden = hidden || hiddenBy(s.at<short>(v, u), d, u - x, v - y, p);
                        wrong += out.at<short>(y, x) != (hidden ? NO_DISP : d);
                    }
                EXPECT_EQ(0, wrong) << m.first << ", parallax256 " << parallax256 << ", rx " << rx;
            }
}

TEST(Lidarsgm_VisibilityFilter, matcher_drops_hidden_points_before_every_stage)
{
    // With the filter on, the matcher behaves as if the hidden points were not in the input.
    RNG rng(3);
    Mat l(60, 90, CV_8UC1), r, s(60, 90, CV_32FC1, Scalar::all(0));
    rng.fill(l, RNG::UNIFORM, 0, 256);
    GaussianBlur(l, l, Size(3, 3), 0);
    r = Mat(l.size(), CV_8UC1, Scalar::all(0));
    l(Rect(8, 0, 82, 60)).copyTo(r(Rect(0, 0, 82, 60)));
    for (int k = 0; k < 200; k++)
        s.at<float>(rng.uniform(0, 60), rng.uniform(0, 90)) = (float)rng.uniform(2.0, 30.0);
    Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(0, 32);
    m->setVisibilityRadiusX(2);
    m->setVisibilityRadiusY(4);
    m->setVisibilityParallax(0.25);
    EXPECT_THROW(m->setVisibilityParallax(1.5), cv::Exception);
    EXPECT_THROW(m->setVisibilityParallax(std::numeric_limits<double>::quiet_NaN()), cv::Exception);
    EXPECT_DOUBLE_EQ(0.25, m->getVisibilityParallax());
    Mat s16, visible16, withFilter, byHand;
    convertSparse(s, 0, 32, s16);
    PipelineParams p = visibilityParams(2, 4, 32);
    p.numDisparities = 32;
    p.visibilityParallax256 = 64;
    filterHiddenPoints(s16, p, visible16, isLidarScan(s16));
    ASSERT_LT(countNonZero(visible16 != NO_DISP), countNonZero(s16 != NO_DISP));
    Mat visible(s.size(), CV_32FC1, Scalar::all(0));
    s.copyTo(visible, visible16 != NO_DISP);
    m->compute(l, r, s, withFilter);
    m->setVisibilityRadiusX(0);
    m->setVisibilityRadiusY(0);
    m->setVisibilityParallax(0);
    m->compute(l, r, visible, byHand);
    EXPECT_EQ(0, cvtest::norm(withFilter, byHand, NORM_INF));
}

//! The scan test's histograms on the device against the CPU's.
static void expectSameScanGaps(const Mat& sparse16, const std::string& name)
{
    Mat cpu(1, 2 * SCAN_GAP_BINS, CV_32SC1);
    scanGapHistograms(sparse16, cpu.ptr<int>(), cpu.ptr<int>() + SCAN_GAP_BINS);
    const Mat gpu = cuda_host::scanGapHistograms(cuda::GpuMat(sparse16));
    EXPECT_EQ(0, cvtest::norm(cpu, gpu, NORM_INF)) << name << "\n" << cpu << "\n" << gpu;
}

// The CUDA twins (src_cuda/visibility_filter.cu): the scan test, and the filter with and without the window's
// parallax growth, on every stage configuration.
TEST(Lidarsgm_CUDA_VisibilityFilter, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        const cuda::GpuMat g(c.converted16);
        EXPECT_EQ(c.scan, cuda_host::isLidarScan(g)) << c.name;
        expectSameScanGaps(c.converted16, c.name);
        for (int parallax256 : { 0, 46 })
        {
            PipelineParams p = c.p;
            p.visibilityRadiusX = 2;
            p.visibilityRadiusY = 4;
            p.visibilityParallax256 = parallax256;
            Mat cpu;
            filterHiddenPoints(c.converted16, p, cpu, c.scan);
            cuda::GpuMat gv;
            cuda_host::filterHiddenPoints(g, p, gv);
            expectSameAsCpu(cpu, gv, c.name + format(", parallax %d/256", parallax256));
        }
    }
}

// The scan test's gaps where they reach the cap, the image's edges and the warps' 32-column edges: random points at
// several densities on a size that is no multiple of 32.
TEST(Lidarsgm_CUDA_VisibilityFilter, scan_gaps_bit_exact)
{
    requireCudaDevice();
    RNG rng(31);
    for (const Size sz : { Size(75, 47), Size(130, 90) })
        for (double density : { 0.004, 0.03, 0.2 })
        {
            Mat s(sz, CV_16SC1, Scalar::all(NO_DISP));
            for (int y = 0; y < sz.height; y++)
                for (int x = 0; x < sz.width; x++)
                    if (rng.uniform(0.0, 1.0) < density || ((x == 0 || x == sz.width - 1) && y % 7 == 0))
                        s.at<short>(y, x) = (short)rng.uniform(0, 1000);
            expectSameScanGaps(s, format("%dx%d, density %.3f", sz.width, sz.height, density));
        }
}

}} // namespace
