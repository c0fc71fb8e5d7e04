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
                Mat cpu;
                consistencyCheck(c.med16, c.medInt, c.medRight, c.sparse16, c.nonUnique16, c.rings, p, cpu);
                const bool rings = c.rings.valid && ringCheckOn(p);
                cuda::GpuMat g;
                cuda_host::consistencyCheck(cuda::GpuMat(c.med16), cuda::GpuMat(c.medInt), cuda::GpuMat(c.medRight),
                                            cuda::GpuMat(c.sparse16),
                                            rings ? cuda::GpuMat(c.nonUnique16) : cuda::GpuMat(),
                                            rings ? cuda::GpuMat(c.rings.above16) : cuda::GpuMat(),
                                            rings ? cuda::GpuMat(c.rings.below16) : cuda::GpuMat(),
                                            c.rings.gap, p, g);
                expectSameAsCpu(cpu, g, c.name + format(", check %d, %s", check, floatOutput ? "CV_32F" : "CV_16S"));
            }
}

}} // namespace
