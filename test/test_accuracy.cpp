// This file is part of the lidarsgm module (an OpenCV extra module).
// Accuracy on the curated frames in testdata/ (KITTI 000002 + 000046 with their raw scans, Middlebury Cones with 1 %
// of the ground truth). Thresholds were set from measured values (doc/notes.md) with a small margin, so that the
// tests fail when DDC, semidensification or the LiDAR consistency check is switched off or broken.
#include "test_precomp.hpp"
#include "lidarsgm_eval.hpp"

// Thresholds. Measured 2026-11-23 with the create() defaults (3x3 median on), tool and test on the 2 shipped frames,
// sums over both: SDSGM coverage 99.85 %, covered D1 1.40 %, total D1 1.42 % (median off: 98.96 / 1.58 / 1.72);
// DSGM total 1.53 %; SGM total 7.00 %; SDSGM with the stereo check alone coverage 96.64 %, total 1.80 %. Cones (1 % of
// GT, seed 1): SDSGM total bad-2 10.28 %, SGM 12.45 %. Switching off the median, DDC (SGM), semidensification (DSGM)
// or the LiDAR check (stereo) breaks at least one of these.
#define LIDARSGM_T_SDSGM_COV 99.6
#define LIDARSGM_T_SDSGM_COVERED 1.50
#define LIDARSGM_T_SDSGM_TOTAL 1.50
#define LIDARSGM_T_DSGM_TOTAL 1.65
#define LIDARSGM_T_SEMI_GAIN 0.08
#define LIDARSGM_T_CHECK_COV_GAIN 2.5
#define LIDARSGM_T_CONES_SDSGM_TOTAL 10.5
#define LIDARSGM_T_CONES_GAIN 1.5
// The 20 frames of ../shared/data/kitti2015_lidar (LIDARSGM_SHARED_DATA): the bars of the reference-faithful defaults
// (measured 2026-11-23: SDSGM 99.51 / 1.87 / 2.01 %, DSGM total 2.53 %; the paper's public code: SDSGM 99.38 / 2.14 /
// 2.41 %, DSGM total 2.84 %).
#define LIDARSGM_T_SHARED_SDSGM_COV 99.4
#define LIDARSGM_T_SHARED_SDSGM_TOTAL 2.10
#define LIDARSGM_T_SHARED_DSGM_TOTAL 2.65
#define LIDARSGM_T_SHARED_SEMI_GAIN 0.3

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;
using namespace lidarsgm_eval;

struct KittiFrames
{
    std::vector<Mat> left, right, sparse, gt;
};

static const KittiFrames& kittiFrames()
{
    static KittiFrames f;
    if (f.left.empty())
    {
        const std::string dir = cvtest::findDataDirectory("kitti");
        KittiCalib c = readKittiCalib(dir + "/calib.txt");
        const char* ids[] = { "000002", "000046" };
        for (int i = 0; i < 2; i++)
        {
            f.left.push_back(imread(dir + "/image_2/" + ids[i] + "_10.png", IMREAD_GRAYSCALE));
            f.right.push_back(imread(dir + "/image_3/" + ids[i] + "_10.png", IMREAD_GRAYSCALE));
            Mat s;
            cv::lidarsgm::projectPointsToDisparity(readVelodyne(dir + "/velodyne/" + ids[i] + ".bin"), c.P2,
                                                   c.lidarToCamera, c.focalBaseline, f.left.back().size(), s);
            f.sparse.push_back(s);
            f.gt.push_back(readKittiDisparity(dir + "/disp_occ_0/" + ids[i] + "_10.png"));
        }
    }
    return f;
}

static ErrorStats runKitti(int mode, int check)
{
    const KittiFrames& f = kittiFrames();
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
    ErrorStats total;
    for (size_t i = 0; i < f.left.size(); i++)
    {
        Mat disp;
        m->compute(f.left[i], f.right[i], f.sparse[i], disp);
        total.add(evaluate(disparityToFloat(disp, 0), f.gt[i], isD1Outlier));
    }
    std::cout << "mode " << mode << " check " << check << ": coverage " << total.coverage() << " %, covered D1 "
              << total.coveredError() << " %, total D1 " << total.totalError() << " %" << std::endl;
    return total;
}

TEST(Lidarsgm_Accuracy, kitti_sdsgm)
{
    ErrorStats s = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    EXPECT_GE(s.coverage(), LIDARSGM_T_SDSGM_COV);
    EXPECT_LE(s.coveredError(), LIDARSGM_T_SDSGM_COVERED);
    EXPECT_LE(s.totalError(), LIDARSGM_T_SDSGM_TOTAL);
}

TEST(Lidarsgm_Accuracy, kitti_ordering_sdsgm_dsgm_sgm)
{
    ErrorStats sd = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    ErrorStats d = runKitti(StereoLidarSGM::MODE_DSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    ErrorStats s = runKitti(StereoLidarSGM::MODE_SGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    EXPECT_LE(d.totalError(), LIDARSGM_T_DSGM_TOTAL);
    // Semidensification must pay (SDSGM clearly better than DSGM), and DDC must pay (DSGM far better than SGM).
    EXPECT_LT(sd.totalError() + LIDARSGM_T_SEMI_GAIN, d.totalError());
    EXPECT_LT(2 * d.totalError(), s.totalError());
}

TEST(Lidarsgm_Accuracy, kitti_lidar_check_keeps_coverage)
{
    ErrorStats sl = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO_LIDAR);
    ErrorStats st = runKitti(StereoLidarSGM::MODE_SDSGM, StereoLidarSGM::CHECK_STEREO);
    // The LiDAR view rescues what the left-right check drops, and the total error falls with it (paper Table V).
    EXPECT_GT(sl.coverage(), st.coverage() + LIDARSGM_T_CHECK_COV_GAIN);
    EXPECT_LT(sl.totalError(), st.totalError());
}

TEST(Lidarsgm_Accuracy, middlebury_cones_1_percent)
{
    const std::string dir = cvtest::findDataDirectory("middlebury/cone");
    Mat l = imread(dir + "/im2.png", IMREAD_GRAYSCALE), r = imread(dir + "/im6.png", IMREAD_GRAYSCALE);
    Mat raw = imread(dir + "/disp2.png", IMREAD_UNCHANGED);
    ASSERT_FALSE(l.empty() || r.empty() || raw.empty());
    Mat gt;
    raw.convertTo(gt, CV_32F, 0.25);
    gt.setTo(-1.f, raw == 0);
    // The tool's default seed: the same sampling as `lidarsgm_fuse --middlebury`.
    Mat sparse = sampleGroundTruth(gt, 0.01, 1);
    BadN bad2 = { 2.f };
    ErrorStats res[2];
    const int modes[2] = { StereoLidarSGM::MODE_SGM, StereoLidarSGM::MODE_SDSGM };
    for (int i = 0; i < 2; i++)
    {
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 64, 10, 120, 5, 160, 0.7, modes[i]);
        Mat disp;
        m->compute(l, r, sparse, disp);
        res[i] = evaluate(disparityToFloat(disp, 0), gt, bad2);
        std::cout << "cones mode " << modes[i] << ": coverage " << res[i].coverage() << " %, covered bad-2 "
                  << res[i].coveredError() << " %, total bad-2 " << res[i].totalError() << " %" << std::endl;
    }
    EXPECT_LE(res[1].totalError(), LIDARSGM_T_CONES_SDSGM_TOTAL);
    EXPECT_LT(res[1].totalError() + LIDARSGM_T_CONES_GAIN, res[0].totalError());
}

}} // namespace

namespace opencv_test { namespace {

// The 20 KITTI frames of the shared development data, each raw scan projected by the module; create() defaults.
TEST(Lidarsgm_Accuracy, kitti_shared_frames_defaults)
{
    const char* env = getenv("LIDARSGM_SHARED_DATA");
    const std::string dir = env ? std::string(env) + "/kitti2015_lidar" : std::string();
    if (dir.empty() || !std::ifstream((dir + "/frames.txt").c_str()).good())
        throw SkipTestException("LIDARSGM_SHARED_DATA does not point at the shared data");
    KittiCalib c = readKittiCalib(dir + "/calib.txt");
    std::ifstream list((dir + "/frames.txt").c_str());
    std::string id;
    ErrorStats sd, d;
    Ptr<StereoLidarSGM> msd = StereoLidarSGM::create();
    Ptr<StereoLidarSGM> md = StereoLidarSGM::create();
    md->setMode(StereoLidarSGM::MODE_DSGM);
    int frames = 0;
    while (list >> id)
    {
        Mat l = imread(dir + "/image_2/" + id + "_10.png", IMREAD_GRAYSCALE);
        Mat r = imread(dir + "/image_3/" + id + "_10.png", IMREAD_GRAYSCALE);
        ASSERT_FALSE(l.empty() || r.empty()) << id;
        Mat s, disp;
        cv::lidarsgm::projectPointsToDisparity(readVelodyne(dir + "/velodyne/" + id + ".bin"), c.P2, c.lidarToCamera,
                                               c.focalBaseline, l.size(), s);
        const Mat gt = readKittiDisparity(dir + "/disp_occ_0/" + id + "_10.png");
        msd->compute(l, r, s, disp);
        sd.add(evaluate(disparityToFloat(disp, 0), gt, isD1Outlier));
        md->compute(l, r, s, disp);
        d.add(evaluate(disparityToFloat(disp, 0), gt, isD1Outlier));
        frames++;
    }
    std::cout << frames << " frames: SDSGM coverage " << sd.coverage() << " %, covered D1 " << sd.coveredError()
              << " %, total D1 " << sd.totalError() << " %; DSGM total D1 " << d.totalError() << " %" << std::endl;
    EXPECT_EQ(20, frames);
    EXPECT_GE(sd.coverage(), LIDARSGM_T_SHARED_SDSGM_COV);
    EXPECT_LE(sd.totalError(), LIDARSGM_T_SHARED_SDSGM_TOTAL);
    EXPECT_LE(d.totalError(), LIDARSGM_T_SHARED_DSGM_TOTAL);
    EXPECT_LT(sd.totalError() + LIDARSGM_T_SHARED_SEMI_GAIN, d.totalError());
}

}} // namespace
