// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;

// A ramp increasing to the right: of the 31 pairs (p + o, p - o), exactly those with o pointing right (dx > 0,
// only in the three rows above the centre) have I(p + o) > I(p - o). In raster order of o, rows dy = -3..-1 give
// dx = -4..4 -> 0 0 0 0 0 1 1 1 1, and the centre row dx = -4..-1 gives 0 0 0 0.
TEST(Lidarsgm_Census, ramp_bits)
{
    Mat img(20, 30, CV_8UC1);
    for (int y = 0; y < img.rows; y++)
        for (int x = 0; x < img.cols; x++)
            img.at<uchar>(y, x) = (uchar)(5 * x);
    Mat census;
    censusTransform(img, census);
    ASSERT_EQ(CV_32SC1, census.type());
    const unsigned rowBits = 0x0F;  // 000001111
    const unsigned expected = (((rowBits << 9) | rowBits) << 9 | rowBits) << 4;
    EXPECT_EQ(31, (int)CENSUS_BITS);
    EXPECT_EQ(expected, (unsigned)census.at<int>(10, 15));
    // Clamped borders keep the ramp's order: the border pixels get the same code.
    EXPECT_EQ(expected, (unsigned)census.at<int>(10, 0));
    EXPECT_EQ(expected, (unsigned)census.at<int>(0, 29));
}

TEST(Lidarsgm_Census, vertical_ramp_bits)
{
    // Increasing downwards: I(p + o) > I(p - o) never holds for the upper-half offsets (p + o is above p - o),
    // and the centre-row pairs are equal.
    Mat img(20, 30, CV_8UC1);
    for (int y = 0; y < img.rows; y++)
        img.row(y).setTo(Scalar::all(10 * y));
    Mat census;
    censusTransform(img, census);
    EXPECT_EQ(0u, (unsigned)census.at<int>(10, 15));
    // Decreasing downwards: every pair of the three upper rows is 1; the centre row pairs are equal (0).
    Mat flipped;
    flip(img, flipped, 0);
    censusTransform(flipped, census);
    EXPECT_EQ(((1u << 27) - 1) << 4, (unsigned)census.at<int>(10, 15));
}

TEST(Lidarsgm_Census, constant_image_is_zero)
{
    Mat img(9, 11, CV_8UC1, Scalar::all(77)), census;
    censusTransform(img, census);
    EXPECT_EQ(0, countNonZero(census));
}

TEST(Lidarsgm_Census, sixteen_bit_matches_eight_bit_order)
{
    RNG rng(7);
    Mat img8(40, 50, CV_8UC1);
    rng.fill(img8, RNG::UNIFORM, 0, 256);
    Mat img16;
    img8.convertTo(img16, CV_16U, 257);  // order-preserving
    Mat c8, c16;
    censusTransform(img8, c8);
    censusTransform(img16, c16);
    EXPECT_EQ(0, cvtest::norm(c8, c16, NORM_INF));
}

// Every pixel against censusString read through clamped coordinates: the vector kernels (a byte lane per pixel for
// 8-bit images, 16-bit lanes otherwise), their scalar tails and the padded borders. Few grey levels, so that equal
// pairs (bit 0) are common, and both sides of 128, where signed and unsigned byte order differ.
TEST(Lidarsgm_Census, every_pixel_matches_the_rule)
{
    RNG rng(11);
    for (const Size size : { Size(101, 37), Size(64, 9), Size(7, 5), Size(200, 3) })
        for (const int depth : { CV_8U, CV_16U })
        {
            Mat levels(size, CV_8UC1), img;
            rng.fill(levels, RNG::UNIFORM, 0, 6);
            // Levels around 128 (8-bit) or around 32768 and above 255 (16-bit).
            levels.convertTo(img, depth, depth == CV_8U ? 1.0 : 300.0, depth == CV_8U ? 125.0 : 32000.0);
            Mat census;
            censusTransform(img, census);
            ASSERT_EQ(size, census.size());
            int wrong = 0;
            for (int y = 0; y < img.rows; y++)
                for (int x = 0; x < img.cols; x++)
                {
                    const auto at = [&](int dx, int dy) {
                        const int u = std::min(std::max(x + dx, 0), img.cols - 1);
                        const int v = std::min(std::max(y + dy, 0), img.rows - 1);
                        return depth == CV_8U ? (int)img.at<uchar>(v, u) : (int)img.at<ushort>(v, u);
                    };
                    wrong += (unsigned)census.at<int>(y, x) != censusString(at);
                }
            EXPECT_EQ(0, wrong) << size << " depth " << depth;
        }
}

TEST(Lidarsgm_Census, tiny_images)
{
    for (int h = 1; h <= 3; h++)
        for (int w = 1; w <= 3; w++)
        {
            Mat img(h, w, CV_8UC1);
            randu(img, 0, 256);
            Mat census;
            ASSERT_NO_THROW(censusTransform(img, census));
            EXPECT_EQ(img.size(), census.size());
        }
}

// The CUDA twin (src_cuda/census.cu): both images of every stage configuration, 8 and 16 bits.
TEST(Lidarsgm_CUDA_Census, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
    {
        cuda::GpuMat gl, gr;
        cuda_host::censusTransform(cuda::GpuMat(c.left), cuda::GpuMat(c.right), c.p, gl, gr);
        expectSameAsCpu(c.censusL, gl, c.name + " (left)");
        expectSameAsCpu(c.censusR, gr, c.name + " (right)");
    }
}

}} // namespace
