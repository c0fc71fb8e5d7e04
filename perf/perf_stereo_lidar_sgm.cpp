// This file is part of the lidarsgm module (an OpenCV extra module).
#include "perf_precomp.hpp"

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;

struct KittiInput
{
    Mat left, right, sparse;
};

static const KittiInput& kittiFrame()
{
    static KittiInput in;
    if (in.left.empty())
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(cvtest::findDataDirectory("kitti"), "000002");
        in.left = f.left;
        in.right = f.right;
        in.sparse = f.sparse;
    }
    return in;
}

//! The frame scaled to `size` (its LiDAR disparities scaled with the width).
static KittiInput kittiFrameAt(Size size)
{
    KittiInput in = kittiFrame();
    if (size != in.left.size())
    {
        const double sx = (double)size.width / in.left.cols;
        resize(in.left, in.left, size, 0, 0, INTER_LINEAR);
        resize(in.right, in.right, size, 0, 0, INTER_LINEAR);
        resize(in.sparse, in.sparse, size, 0, 0, INTER_NEAREST);
        in.sparse *= sx;
    }
    return in;
}

CV_ENUM(FusionMode, StereoLidarSGM::MODE_SGM, StereoLidarSGM::MODE_DSGM, StereoLidarSGM::MODE_SDSGM)

typedef tuple<Size, FusionMode, int, int> SizeModePathsDisp;
typedef perf::TestBaseWithParam<SizeModePathsDisp> Lidarsgm_KITTI;

// KITTI frame 000002 (1242x375) and the same frame scaled to 1080p, CPU path.
PERF_TEST_P(Lidarsgm_KITTI, compute,
            testing::Combine(testing::Values(Size(1242, 375), Size(1920, 1080)), FusionMode::all(),
                             testing::Values(4, 8), testing::Values(128, 256)))
{
    const Size size = get<0>(GetParam());
    const KittiInput in = kittiFrameAt(size);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, get<3>(GetParam()), 10, 120, 5, 160, 0.7, get<1>(GetParam()));
    m->setNumPaths(get<2>(GetParam()));
    Mat disp;
    m->compute(in.left, in.right, in.sparse, disp);  // allocate buffers outside the timed loop
    TEST_CYCLE() m->compute(in.left, in.right, in.sparse, disp);
    SANITY_CHECK_NOTHING();
}

typedef perf::TestBaseWithParam<tuple<Size, int> > Lidarsgm_KITTI_Windows;

// SDSGM with the disparity windows (searchWindow margin; 0: the full range), KITTI size with 128 disparities and 1080p
// with 256, 8 paths, CPU path.
PERF_TEST_P(Lidarsgm_KITTI_Windows, compute, testing::Combine(testing::Values(Size(1242, 375), Size(1920, 1080)),
                                                               testing::Values(0, 4)))
{
    const Size size = get<0>(GetParam());
    const KittiInput in = kittiFrameAt(size);
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, size.width > 1242 ? 256 : 128);
    m->setSearchWindow(get<1>(GetParam()));
    Mat disp;
    m->compute(in.left, in.right, in.sparse, disp);
    TEST_CYCLE() m->compute(in.left, in.right, in.sparse, disp);
    SANITY_CHECK_NOTHING();
}

PERF_TEST(Lidarsgm_KITTI, semidensify)
{
    const KittiInput& in = kittiFrame();
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    Mat semi;
    TEST_CYCLE() m->semidensify(in.left, in.right, in.sparse, semi);
    SANITY_CHECK_NOTHING();
}

// The bars: OpenCV's own CPU matchers, every mode, on the same frame (anchors: blockSize 3, P1 72, P2 288); compare
// with Lidarsgm_KITTI.compute at 1242x375, 128 disparities (the tool's --timing prints the ratios of alternating runs).
CV_ENUM(SgbmMode, StereoSGBM::MODE_HH, StereoSGBM::MODE_HH4, StereoSGBM::MODE_SGBM, StereoSGBM::MODE_SGBM_3WAY)
typedef perf::TestBaseWithParam<SgbmMode> Lidarsgm_KITTI_StereoSGBM;
PERF_TEST_P(Lidarsgm_KITTI_StereoSGBM, opencv_StereoSGBM_128, SgbmMode::all())
{
    const KittiInput& in = kittiFrame();
    Ptr<StereoSGBM> sgbm = StereoSGBM::create(0, 128, 3, 72, 288, 1, 0, 10, 100, 2, (int)GetParam());
    Mat disp;
    sgbm->compute(in.left, in.right, disp);
    TEST_CYCLE() sgbm->compute(in.left, in.right, disp);
    SANITY_CHECK_NOTHING();
}

// The per-frame calibration check; compare with Lidarsgm_KITTI.compute at 1242x375 (the fusion call it rides along).
PERF_TEST(Lidarsgm_KITTI, matchingResidual)
{
    const KittiInput& in = kittiFrame();
    double r = 0;
    TEST_CYCLE() r = cv::lidarsgm::matchingResidual(in.left, in.right, in.sparse);
    EXPECT_GT(r, 0.0);
    SANITY_CHECK_NOTHING();
}

PERF_TEST(Lidarsgm_KITTI, projectPointsToDisparity)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    cv::lidarsgm::KittiCalibration c = cv::lidarsgm::readKittiCalibration(dir + "/calib.txt");
    Mat pts = cv::lidarsgm::readVelodyneScan(dir + "/velodyne/000002.bin"), sparse;
    TEST_CYCLE() cv::lidarsgm::projectPointsToDisparity(pts, c.projection, c.lidarToCamera, c.focalBaseline, Size(1242, 375), sparse);
    SANITY_CHECK_NOTHING();
}

}} // namespace
