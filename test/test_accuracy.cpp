// This file is part of the lidarsgm module (an OpenCV extra module).
// Accuracy on the curated frames in testdata/ (KITTI 000002 + 000046 with their raw scans, Middlebury Cones with 1 %
// of the ground truth). Thresholds were set from measured values (doc/accuracy.md) with a small margin, so that the
// tests fail when DDC, semidensification or the LiDAR consistency check is switched off or broken.
#include "test_precomp.hpp"

// Thresholds. Measured 2026-11-23 with the create() defaults (3x3 median on), the frames read as the tool reads them
// (cv::lidarsgm::loadKittiFrame), sums over the 2 shipped frames: SDSGM coverage 99.86 %, covered D1 1.39 %, total
// D1 1.40 % (median off: 99.02 / 1.57 / 1.69); DSGM total 1.54 %; SGM total 7.07 %; SDSGM with the stereo check
// alone coverage 96.63 %, total 1.81 %. Cones (1 % of GT, seed 1): SDSGM total bad-2 10.28 %, SGM 12.45 %. Switching
// off the median, DDC (SGM), semidensification (DSGM) or the LiDAR check (stereo) breaks at least one of these.
#define LIDARSGM_T_SDSGM_COV 99.6
#define LIDARSGM_T_SDSGM_COVERED 1.50
#define LIDARSGM_T_SDSGM_TOTAL 1.50
#define LIDARSGM_T_DSGM_TOTAL 1.65
#define LIDARSGM_T_SEMI_GAIN 0.08
#define LIDARSGM_T_CHECK_COV_GAIN 2.5
#define LIDARSGM_T_CONES_SDSGM_TOTAL 10.5
#define LIDARSGM_T_CONES_GAIN 1.5
// The 20 frames of ../shared/data/kitti2015_lidar (LIDARSGM_SHARED_DATA): the bars of the reference-faithful defaults
// (measured 2026-11-23: SDSGM 99.51 / 1.87 / 2.01 %, DSGM total 2.53 %, as the tool prints; the paper's public code: SDSGM 99.38 / 2.14 /
// 2.41 %, DSGM total 2.84 %).
#define LIDARSGM_T_SHARED_SDSGM_COV 99.4
#define LIDARSGM_T_SHARED_SDSGM_TOTAL 2.10
#define LIDARSGM_T_SHARED_DSGM_TOTAL 2.65
#define LIDARSGM_T_SHARED_SEMI_GAIN 0.3
// doc/params/kitti_best.yml (LIDARSGM_PARAMS) on the same 20 frames, SDSGM: the bar (measured 2026-11-25:
// 99.56 / 1.48 / 1.65 %, DSGM 1.82 %; 1.68 and 1.85 % without the visibility window's parallax growth).
#define LIDARSGM_T_SHARED_BEST_SDSGM_TOTAL 1.71
#define LIDARSGM_T_SHARED_BEST_DSGM_TOTAL 1.88

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;
using cv::lidarsgm::DisparityErrors;
using cv::lidarsgm::evaluateDisparity;

static const std::vector<cv::lidarsgm::StereoLidarFrame>& kittiFrames()
{
    static std::vector<cv::lidarsgm::StereoLidarFrame> frames;
    if (frames.empty())
        for (const char* id : { "000002", "000046" })
            frames.push_back(cv::lidarsgm::loadKittiFrame(cvtest::findDataDirectory("kitti"), id));
    return frames;
}

static void print(const std::string& what, const DisparityErrors& e)
{
    std::cout << what << ": coverage " << e.coverage() << " %, covered " << e.coveredError() << " %, total "
              << e.totalError() << " %" << std::endl;
}

static DisparityErrors runKitti(int mode, int check)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
    DisparityErrors total;
    for (const cv::lidarsgm::StereoLidarFrame& f : kittiFrames())
    {
        Mat disp;
        m->compute(f.left, f.right, f.sparse, disp);
        total.add(evaluateDisparity(disp, f.groundTruth));
    }
    print(format("mode %d check %d", mode, check), total);
    return total;
}

TEST(Lidarsgm_Accuracy, kitti_sdsgm)
{
    DisparityErrors s = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    EXPECT_GE(s.coverage(), LIDARSGM_T_SDSGM_COV);
    EXPECT_LE(s.coveredError(), LIDARSGM_T_SDSGM_COVERED);
    EXPECT_LE(s.totalError(), LIDARSGM_T_SDSGM_TOTAL);
}

/* 512 disparities from -32 on the shipped frames (the CPU path's largest search, a negative start): the same
devkit figures as 128 from 0 within a tenth of a point, since the frames' true disparities lie below 230 and a wider
range only adds candidates that lose. */
TEST(Lidarsgm_Accuracy, kitti_sdsgm_512_disparities)
{
    Ptr<StereoLidarSGM> wide = StereoLidarSGM::create(-32, 512), base = StereoLidarSGM::create(0, 128);
    DisparityErrors w, b;
    for (const cv::lidarsgm::StereoLidarFrame& f : kittiFrames())
    {
        Mat dw, db;
        wide->compute(f.left, f.right, f.sparse, dw);
        base->compute(f.left, f.right, f.sparse, db);
        ASSERT_EQ(CV_16SC1, dw.type());
        EXPECT_GE((int)*std::min_element(dw.begin<short>(), dw.end<short>()), (-32 - 1) * 16);   // invalid: minD - 1
        w.add(evaluateDisparity(dw, f.groundTruth, lidarsgm::METRIC_KITTI_D1, 2.0, -32));
        b.add(evaluateDisparity(db, f.groundTruth));
    }
    print("512 from -32", w);
    EXPECT_NEAR(w.coverage(), b.coverage(), 0.1);
    EXPECT_NEAR(w.totalError(), b.totalError(), 0.1);
}

TEST(Lidarsgm_Accuracy, kitti_ordering_sdsgm_dsgm_sgm)
{
    DisparityErrors sd = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    DisparityErrors d = runKitti(StereoLidarSGM::MODE_DSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    DisparityErrors s = runKitti(StereoLidarSGM::MODE_SGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    EXPECT_LE(d.totalError(), LIDARSGM_T_DSGM_TOTAL);
    // Semidensification must pay (SDSGM clearly better than DSGM), and DDC must pay (DSGM far better than SGM).
    EXPECT_LT(sd.totalError() + LIDARSGM_T_SEMI_GAIN, d.totalError());
    EXPECT_LT(2 * d.totalError(), s.totalError());
}

TEST(Lidarsgm_Accuracy, kitti_lidar_check_keeps_coverage)
{
    DisparityErrors sl = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    DisparityErrors st = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO);
    // The LiDAR view rescues what the left-right check drops, and the total error falls with it (paper Table V).
    EXPECT_GT(sl.coverage(), st.coverage() + LIDARSGM_T_CHECK_COV_GAIN);
    EXPECT_LT(sl.totalError(), st.totalError());
}

TEST(Lidarsgm_Accuracy, middlebury_cones_1_percent)
{
    Mat l, r, gt;
    ASSERT_NO_THROW(cv::lidarsgm::loadMiddleburyScene(cvtest::findDataDirectory("middlebury/cone"), l, r, gt));
    // The tool's default seed: the same sampling as `lidarsgm_fuse --middlebury`.
    Mat sparse = cv::lidarsgm::sampleGroundTruth(gt, 0.01, 1);
    DisparityErrors res[2];
    const int modes[2] = { StereoLidarSGM::MODE_SGM, StereoLidarSGM::MODE_SDSGM };
    for (int i = 0; i < 2; i++)
    {
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 64, 10, 120, 5, 160, 0.7, modes[i]);
        Mat disp;
        m->compute(l, r, sparse, disp);
        res[i] = evaluateDisparity(disp, gt, cv::lidarsgm::METRIC_BAD, 2.0);
        print(format("cones mode %d (bad-2)", modes[i]), res[i]);
    }
    EXPECT_LE(res[1].totalError(), LIDARSGM_T_CONES_SDSGM_TOTAL);
    EXPECT_LT(res[1].totalError() + LIDARSGM_T_CONES_GAIN, res[0].totalError());
}

//! The shipped configuration doc/params/kitti_best.yml (LIDARSGM_PARAMS: that folder, set by ctest).
static Ptr<StereoLidarSGM> kittiBest()
{
    const char* env = getenv("LIDARSGM_PARAMS");
    if (!env)
        throw SkipTestException("LIDARSGM_PARAMS does not name the folder of kitti_best.yml");
    Ptr<StereoLidarSGM> m = StereoLidarSGM::load(std::string(env) + "/kitti_best.yml");
    CV_Assert(!m.empty());
    return m;
}

// The 20 KITTI frames of the shared development data, each raw scan projected by the module: the create() defaults
// (the public code's pipeline) and kitti_best.yml.
TEST(Lidarsgm_Accuracy, kitti_shared_frames_defaults_and_best)
{
    const char* env = getenv("LIDARSGM_SHARED_DATA");
    const std::string dir = env ? std::string(env) + "/kitti2015_lidar" : std::string();
    if (dir.empty() || !std::ifstream((dir + "/frames.txt").c_str()).good())
        throw SkipTestException("LIDARSGM_SHARED_DATA does not point at the shared data");
    DisparityErrors sd, d, bestSd, bestD;
    Ptr<StereoLidarSGM> msd = StereoLidarSGM::create(), md = StereoLidarSGM::create(), best = kittiBest(),
                        bestDsgm = kittiBest();
    md->setMode(StereoLidarSGM::MODE_DSGM);
    bestDsgm->setMode(StereoLidarSGM::MODE_DSGM);
    const std::vector<std::string> ids = cv::lidarsgm::readKittiFrameIds(dir);
    for (const std::string& id : ids)
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(dir, id);
        Mat disp;
        msd->compute(f.left, f.right, f.sparse, disp);
        sd.add(evaluateDisparity(disp, f.groundTruth));
        md->compute(f.left, f.right, f.sparse, disp);
        d.add(evaluateDisparity(disp, f.groundTruth));
        best->compute(f.left, f.right, f.sparse, disp);
        bestSd.add(evaluateDisparity(disp, f.groundTruth));
        bestDsgm->compute(f.left, f.right, f.sparse, disp);
        bestD.add(evaluateDisparity(disp, f.groundTruth));
    }
    print(format("%d shared frames, SDSGM", (int)ids.size()), sd);
    print("DSGM", d);
    print("kitti_best.yml, SDSGM", bestSd);
    print("kitti_best.yml, DSGM", bestD);
    EXPECT_EQ(20u, ids.size());
    EXPECT_GE(sd.coverage(), LIDARSGM_T_SHARED_SDSGM_COV);
    EXPECT_LE(sd.totalError(), LIDARSGM_T_SHARED_SDSGM_TOTAL);
    EXPECT_LE(d.totalError(), LIDARSGM_T_SHARED_DSGM_TOTAL);
    EXPECT_LT(sd.totalError() + LIDARSGM_T_SHARED_SEMI_GAIN, d.totalError());
    EXPECT_LE(bestSd.totalError(), LIDARSGM_T_SHARED_BEST_SDSGM_TOTAL);
    EXPECT_LE(bestD.totalError(), LIDARSGM_T_SHARED_BEST_DSGM_TOTAL);
}

// kitti_best.yml on the shipped frames and Cones: better than the defaults on both datasets.
TEST(Lidarsgm_Accuracy, kitti_best_beats_defaults)
{
    DisparityErrors def, best;
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(), b = kittiBest();
    for (const cv::lidarsgm::StereoLidarFrame& f : kittiFrames())
    {
        Mat disp;
        m->compute(f.left, f.right, f.sparse, disp);
        def.add(evaluateDisparity(disp, f.groundTruth));
        b->compute(f.left, f.right, f.sparse, disp);
        best.add(evaluateDisparity(disp, f.groundTruth));
    }
    print("defaults", def);
    print("kitti_best.yml", best);
    EXPECT_LT(best.totalError(), def.totalError());
    Mat l, r, gt, disp;
    ASSERT_NO_THROW(cv::lidarsgm::loadMiddleburyScene(cvtest::findDataDirectory("middlebury/cone"), l, r, gt));
    const Mat sparse = cv::lidarsgm::sampleGroundTruth(gt, 0.01, 1);
    m->setNumDisparities(64);
    b->setNumDisparities(64);
    m->compute(l, r, sparse, disp);
    const DisparityErrors coneDef = evaluateDisparity(disp, gt, cv::lidarsgm::METRIC_BAD, 2.0);
    b->compute(l, r, sparse, disp);
    const DisparityErrors coneBest = evaluateDisparity(disp, gt, cv::lidarsgm::METRIC_BAD, 2.0);
    print("cones, defaults", coneDef);
    print("cones, kitti_best.yml", coneBest);
    EXPECT_LT(coneBest.totalError(), coneDef.totalError());
}

}} // namespace
