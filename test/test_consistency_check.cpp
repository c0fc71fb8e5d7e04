// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "cpu_stages.hpp"

namespace opencv_test { namespace {

using namespace cv::lidarsgm::detail;
typedef cv::lidarsgm::StereoLidarSGM SLS;

// One row of 60 pixels. Pixel 30 has disparity 10 (x16 = 160) but its right-view partner (x = 20) says 14: the
// left-right check fails. A sparse value of 11.5 px (184) sits at x = 30 + dx.
static Mat runCheck(int check, int dx, int sparseValue16, int rc = 20, int tc16 = 32)
{
    const int W = 60;
    Mat d16(1, W, CV_16SC1, Scalar::all(NO_DISP)), di(1, W, CV_16SC1, Scalar::all(NO_DISP));
    Mat dr(1, W, CV_16SC1, Scalar::all(NO_DISP)), sparse(1, W, CV_16SC1, Scalar::all(NO_DISP));
    d16.at<short>(0, 30) = 160;
    di.at<short>(0, 30) = 10;
    dr.at<short>(0, 20) = 14;
    // Pixel 40: disparity 5, consistent with the right view (x = 35 says 6, within lrMaxDiff 1).
    d16.at<short>(0, 40) = 80;
    di.at<short>(0, 40) = 5;
    dr.at<short>(0, 35) = 6;
    if (30 + dx >= 0 && 30 + dx < W)
        sparse.at<short>(0, 30 + dx) = (short)sparseValue16;
    PipelineParams p = PipelineParams();
    p.stereoCheck = check == SLS::CHECK_STEREO || check == SLS::CHECK_STEREO_LIDAR;
    p.lidarCheck = check == SLS::CHECK_CAMERA_LIDAR || check == SLS::CHECK_STEREO_LIDAR;
    p.lrMaxDiff = 1;
    p.checkRadius = rc;
    p.checkThreshold16 = tc16;
    // Output in CV_16S x16 with minDisparity 0: "none" is written as -16.
    Mat out;
    consistencyCheck(d16, di, dr, sparse, Mat(), RingMaps(), p, out);
    out.setTo(NO_DISP, out == encodeOutput16(NO_DISP, 0));
    return out;
}

TEST(Lidarsgm_ConsistencyCheck, lidar_rescues_left_right_failure)
{
    // |160 - 184| = 24 <= 32: the LiDAR view confirms pixel 30.
    EXPECT_EQ(160, runCheck(SLS::CHECK_STEREO_LIDAR, 15, 184).at<short>(0, 30));
    EXPECT_EQ(NO_DISP, runCheck(SLS::CHECK_STEREO, 15, 184).at<short>(0, 30));
    EXPECT_EQ(160, runCheck(SLS::CHECK_CAMERA_LIDAR, 15, 184).at<short>(0, 30));
    EXPECT_EQ(160, runCheck(SLS::CHECK_NONE, 15, 184).at<short>(0, 30));
}

TEST(Lidarsgm_ConsistencyCheck, window_and_threshold_edges)
{
    EXPECT_EQ(160, runCheck(SLS::CHECK_STEREO_LIDAR, 20, 184).at<short>(0, 30));      // at the window's edge
    EXPECT_EQ(NO_DISP, runCheck(SLS::CHECK_STEREO_LIDAR, 21, 184).at<short>(0, 30));  // just outside
    EXPECT_EQ(160, runCheck(SLS::CHECK_STEREO_LIDAR, -3, 192).at<short>(0, 30));      // |160 - 192| = 32 = Tc
    EXPECT_EQ(NO_DISP, runCheck(SLS::CHECK_STEREO_LIDAR, -3, 193).at<short>(0, 30));  // 1/16 px over
}

TEST(Lidarsgm_ConsistencyCheck, left_right_pass_and_camera_lidar_rejection)
{
    // Pixel 40 passes left-right; with no sparse value near 5 px the camera-LiDAR check drops it.
    EXPECT_EQ(80, runCheck(SLS::CHECK_STEREO, 15, 184).at<short>(0, 40));
    EXPECT_EQ(80, runCheck(SLS::CHECK_STEREO_LIDAR, 15, 184).at<short>(0, 40));
    EXPECT_EQ(NO_DISP, runCheck(SLS::CHECK_CAMERA_LIDAR, 15, 184).at<short>(0, 40));
}


/* The confidence (outputConfidence): one row of isolated pixels, so that each one's 3x3 neighbourhood holds only
itself (range 0) unless a neighbour is set. Pixel 10: left-right and LiDAR confirm it (1); 20: the LiDAR only (3/4);
30: the left-right test only (1/2); 40: both, with a neighbour 2 px away (a range of 32/16 px halves it); 50:
neither, dropped by the check (0) and, with the check off, kept at 1/4. */
TEST(Lidarsgm_ConsistencyCheck, confidence_rule)
{
    const int W = 60;
    Mat d16(1, W, CV_16SC1, Scalar::all(NO_DISP)), di(1, W, CV_16SC1, Scalar::all(NO_DISP));
    Mat dr(1, W, CV_16SC1, Scalar::all(NO_DISP)), sparse(1, W, CV_16SC1, Scalar::all(NO_DISP));
    const auto setPixel = [&](int x, int d, bool lr, bool lidar) {
        d16.at<short>(0, x) = (short)(16 * d);
        di.at<short>(0, x) = (short)d;
        dr.at<short>(0, x - d) = (short)(lr ? d : d + 5);
        if (lidar)
            sparse.at<short>(0, x) = (short)(16 * d + 8);
    };
    setPixel(10, 4, true, true);
    setPixel(20, 3, false, true);
    setPixel(30, 6, true, false);
    setPixel(40, 2, true, true);
    d16.at<short>(0, 41) = 16 * 4;   // a neighbour 2 px away, itself unverified
    setPixel(50, 7, false, false);
    PipelineParams p = PipelineParams();
    p.lrMaxDiff = 1;
    p.checkRadius = 1;
    p.checkThreshold16 = 16;
    p.confidence = true;
    for (int check : { (int)SLS::CHECK_STEREO_LIDAR, (int)SLS::CHECK_NONE })
    {
        p.stereoCheck = check == SLS::CHECK_STEREO_LIDAR;
        p.lidarCheck = check == SLS::CHECK_STEREO_LIDAR;
        Mat out, conf, outPlain;
        consistencyCheck(d16, di, dr, sparse, Mat(), RingMaps(), p, out, conf);
        ASSERT_EQ(CV_32FC1, conf.type());
        EXPECT_EQ(1.f, conf.at<float>(0, 10)) << check;
        EXPECT_EQ(0.75f, conf.at<float>(0, 20)) << check;
        EXPECT_EQ(0.5f, conf.at<float>(0, 30)) << check;
        EXPECT_EQ(confidenceValue(4 * 16383 * 32 / 64), conf.at<float>(0, 40)) << check;
        EXPECT_NEAR(0.5, conf.at<float>(0, 40), 1e-4) << check;
        EXPECT_EQ(check == SLS::CHECK_NONE ? 0.25f : 0.f, conf.at<float>(0, 50)) << check;
        EXPECT_EQ(0.f, conf.at<float>(0, 0)) << check;   // no disparity
        // The disparity map does not change when the confidence is asked for.
        PipelineParams q = p;
        q.confidence = false;
        consistencyCheck(d16, di, dr, sparse, Mat(), RingMaps(), q, outPlain);
        EXPECT_EQ(0, cvtest::norm(out, outPlain, NORM_INF)) << check;
    }
}

// The CUDA twin (src_cuda/consistency_check.cu) on the CPU's filtered maps of every stage configuration, under
// every check and both output types.
TEST(Lidarsgm_CUDA_ConsistencyCheck, bit_exact)
{
    requireCudaDevice();
    for (const StageCase& c : stageCases())
        for (int check = 0; check < 4; check++)
            for (bool floatOutput : { false, true })
            {
                PipelineParams p = c.p;
                p.stereoCheck = check == 1 || check == 3;
                p.lidarCheck = check >= 2;
                p.floatOutput = floatOutput;
                p.confidence = floatOutput;   // with and without the confidence map
                Mat cpu, cpuConf;
                consistencyCheck(c.med16, c.medInt, c.medRight, c.sparse16, c.nonUnique16, c.rings, p, cpu, cpuConf);
                const bool rings = c.rings.valid && ringCheckOn(p);
                cuda::GpuMat g, gConf;
                cuda_host::consistencyCheck(cuda::GpuMat(c.med16), cuda::GpuMat(c.medInt), cuda::GpuMat(c.medRight),
                                            cuda::GpuMat(c.sparse16),
                                            rings ? cuda::GpuMat(c.nonUnique16) : cuda::GpuMat(),
                                            rings ? cuda::GpuMat(c.rings.above16) : cuda::GpuMat(),
                                            rings ? cuda::GpuMat(c.rings.below16) : cuda::GpuMat(),
                                            c.rings.gap, p, g, gConf);
                expectSameAsCpu(cpu, g, c.name + format(", check %d, %s", check, floatOutput ? "CV_32F" : "CV_16S"));
                if (p.confidence)
                    expectSameAsCpu(cpuConf, gConf, c.name + format(", check %d, confidence", check));
            }
}

}} // namespace
