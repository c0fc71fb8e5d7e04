// This file is part of the lidarsgm module (an OpenCV extra module).
#include "test_precomp.hpp"
#include "test_common.hpp"
#include <fstream>
#include <iterator>

namespace opencv_test { namespace {

using cv::lidarsgm::StereoLidarSGM;
typedef cv::lidarsgm::StereoLidarSGM SLS;

static void randomPair(Size sz, Mat& l, Mat& r, Mat& sparse, int seed = 1)
{
    RNG rng(seed);
    l.create(sz, CV_8UC1);
    rng.fill(l, RNG::UNIFORM, 0, 256);
    GaussianBlur(l, l, Size(3, 3), 0);
    r = Mat(sz, CV_8UC1, Scalar::all(0));
    l(Rect(7, 0, sz.width - 7, sz.height)).copyTo(r(Rect(0, 0, sz.width - 7, sz.height)));  // disparity 7
    sparse = Mat(sz, CV_32FC1, Scalar::all(0));
    for (int i = 0; i < sz.area() / 30; i++)
        sparse.at<float>(rng.uniform(0, sz.height), rng.uniform(0, sz.width)) = 7.f;
}

static std::string messageOf(const std::function<void()>& f)
{
    try { f(); }
    catch (const cv::Exception& e) { return e.what(); }
    return "";
}

TEST(Lidarsgm_API, defaults_are_the_papers)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    EXPECT_EQ(0, m->getMinDisparity());
    EXPECT_EQ(128, m->getNumDisparities());
    EXPECT_EQ(10, m->getP1());
    EXPECT_EQ(120, m->getP2());
    EXPECT_EQ(5, m->getQ1());
    EXPECT_EQ(160, m->getQ2());
    EXPECT_DOUBLE_EQ(0.7, m->getAlpha());
    EXPECT_EQ(6, m->getSemidenseRadius());
    EXPECT_EQ(2, m->getSemidenseThreshold());
    EXPECT_EQ(20, m->getCheckRadius());
    EXPECT_DOUBLE_EQ(2.0, m->getCheckThreshold());
    EXPECT_EQ(8, m->getNumPaths());
    EXPECT_TRUE(m->getSubpixel());
    EXPECT_EQ((int)StereoLidarSGM::MODE_SDSGM, m->getMode());
    EXPECT_EQ((int)StereoLidarSGM::CHECK_STEREO_LIDAR, m->getConsistencyCheck());
    EXPECT_EQ(CV_16S, m->getOutputType());
}

TEST(Lidarsgm_API, parameter_validation)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    EXPECT_THROW(m->setNumDisparities(0), cv::Exception);
    EXPECT_THROW(m->setNumDisparities(100), cv::Exception);
    EXPECT_THROW(m->setNumDisparities(520), cv::Exception);
    EXPECT_THROW(m->setNumDisparities(528), cv::Exception);
    EXPECT_NO_THROW(m->setNumDisparities(64));
    EXPECT_NO_THROW(m->setNumDisparities(256));
    EXPECT_NO_THROW(m->setNumDisparities(272));
    EXPECT_NO_THROW(m->setNumDisparities(512));
    EXPECT_THROW(m->setMinDisparity(5000), cv::Exception);
    EXPECT_THROW(m->setP1(-1), cv::Exception);
    EXPECT_THROW(m->setP2(1001), cv::Exception);
    EXPECT_THROW(m->setQ1(-1), cv::Exception);
    EXPECT_THROW(m->setAlpha(-0.1), cv::Exception);
    EXPECT_THROW(m->setAlpha(1.5), cv::Exception);
    EXPECT_THROW(m->setAlpha(std::numeric_limits<double>::quiet_NaN()), cv::Exception);
    EXPECT_THROW(m->setUniquenessRatio(0), cv::Exception);
    EXPECT_THROW(m->setNumPaths(6), cv::Exception);
    EXPECT_THROW(m->setSemidenseRadius(-1), cv::Exception);
    EXPECT_THROW(m->setCheckRadius(-2), cv::Exception);
    EXPECT_THROW(m->setCheckThreshold(-1), cv::Exception);
    EXPECT_THROW(m->setMode(3), cv::Exception);
    EXPECT_THROW(m->setConsistencyCheck(4), cv::Exception);
    EXPECT_THROW(m->setOutputType(CV_8U), cv::Exception);
    EXPECT_THROW(m->setSearchWindow(-1), cv::Exception);
    EXPECT_THROW(m->setSearchWindow(513), cv::Exception);
    EXPECT_NE(std::string::npos, messageOf([&] { m->setSearchWindow(100000); }).find("searchWindow"));
    EXPECT_THROW(StereoLidarSGM::create(0, 128, 200, 120), cv::Exception);          // P1 > P2
    EXPECT_THROW(StereoLidarSGM::create(0, 128, 10, 120, 170, 160), cv::Exception); // Q1 > Q2
    EXPECT_NE(std::string::npos, messageOf([&] { m->setNumDisparities(100); }).find("numDisparities"));
    EXPECT_NE(std::string::npos, messageOf([&] { m->setAlpha(2); }).find("alpha"));

    // A relation broken through the setters is reported when the matcher is used.
    Mat l, r, s, d;
    randomPair(Size(64, 32), l, r, s);
    m->setNumDisparities(16);
    m->setP1(500);
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(l, r, s, d); }).find("P1"));
}

TEST(Lidarsgm_API, bad_input_messages)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16);
    Mat l, r, s, d;
    randomPair(Size(64, 32), l, r, s);
    Mat colour;
    cvtColor(l, colour, COLOR_GRAY2BGR);
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(colour, colour, s, d); }).find("COLOR_BGR2GRAY"));
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(Mat(), r, s, d); }).find("empty"));
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(l, r(Rect(0, 0, 60, 32)), s, d); }).find("size"));
    Mat r16;
    r.convertTo(r16, CV_16U);
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(l, r16, s, d); }).find("type"));
    Mat lf;
    l.convertTo(lf, CV_32F);
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(lf, lf, s, d); }).find("CV_8UC1 or CV_16UC1"));
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(l, r, s(Rect(0, 0, 10, 10)), d); }).find("sparse"));
    Mat s8;
    s.convertTo(s8, CV_8U);
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(l, r, s8, d); }).find("CV_16UC1"));
    EXPECT_NE(std::string::npos, messageOf([&] { m->compute(l, r, Mat(), d); }).find("sparse"));
    // Plain SGM with the stereo check needs no sparse map.
    m->setMode(StereoLidarSGM::MODE_SGM);
    m->setConsistencyCheck(StereoLidarSGM::CHECK_STEREO);
    EXPECT_NO_THROW(m->compute(l, r, noArray(), d));
}

TEST(Lidarsgm_API, non_finite_sparse_values_are_no_measurement)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16);
    Mat l, r, s;
    randomPair(Size(80, 40), l, r, s);
    Mat withNan = s.clone();
    withNan.at<float>(5, 5) = std::numeric_limits<float>::quiet_NaN();
    withNan.at<float>(6, 6) = std::numeric_limits<float>::infinity();
    withNan.at<float>(7, 7) = -4.f;
    withNan.at<float>(8, 8) = 1000.f;  // outside [0, 16)
    Mat clean = s.clone();
    clean.at<float>(5, 5) = clean.at<float>(6, 6) = clean.at<float>(7, 7) = clean.at<float>(8, 8) = 0.f;
    Mat a, b;
    m->compute(l, r, withNan, a);
    m->compute(l, r, clean, b);
    EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF));
}

TEST(Lidarsgm_API, output_formats)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16);
    Mat l, r, s, d16, d32;
    randomPair(Size(96, 48), l, r, s);
    m->compute(l, r, s, d16);
    ASSERT_EQ(CV_16SC1, d16.type());
    m->setOutputType(CV_32F);
    m->compute(l, r, s, d32);
    ASSERT_EQ(CV_32FC1, d32.type());
    Mat conv;
    d16.convertTo(conv, CV_32F, 1.0 / 16);
    EXPECT_EQ(0, cvtest::norm(conv, d32, NORM_INF));
    // The shifted pair has disparity 7 wherever the right image is defined.
    EXPECT_NEAR(7 * 16, d16.at<short>(24, 50), 8);
    // Invalid = (minDisparity - 1) * 16, as cv::StereoSGBM.
    double mn;
    minMaxLoc(d16, &mn);
    EXPECT_GE(mn, -16);
    m->setMinDisparity(-8);
    m->setOutputType(CV_16S);
    m->compute(l, r, s, d16);
    minMaxLoc(d16, &mn);
    EXPECT_GE(mn, -9 * 16);
    EXPECT_NEAR(7 * 16, d16.at<short>(24, 50), 8);
}

TEST(Lidarsgm_API, sixteen_bit_input_and_kitti_sparse)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16);
    Mat l, r, s;
    randomPair(Size(96, 48), l, r, s);
    Mat l16, r16, s16u, a, b;
    l.convertTo(l16, CV_16U, 257);
    r.convertTo(r16, CV_16U, 257);
    s.convertTo(s16u, CV_16U, 256);
    m->compute(l, r, s, a);
    m->compute(l16, r16, s16u, b);
    EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF));
}

TEST(Lidarsgm_API, filestorage_round_trip)
{
    // create() takes every parameter (the paper's nine first, then the header's order); all survive save() and load().
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(-4, 64, 12, 150, 7, 140, 0.55, StereoLidarSGM::MODE_DSGM,
                                                   StereoLidarSGM::CHECK_CAMERA_LIDAR, 0.9, 2, 4, false, 3, 5, 11, 1.5,
                                                   1, 1, 3, 0.3, 20, 0.25, 1.5, 0.5, 6, CV_32F);
    const std::string file = cv::tempfile(".yml");
    m->save(file);
    Ptr<StereoLidarSGM> n = StereoLidarSGM::load(file);
    ASSERT_FALSE(n.empty());
    EXPECT_EQ(-4, n->getMinDisparity());
    EXPECT_EQ(64, n->getNumDisparities());
    EXPECT_EQ(12, n->getP1());
    EXPECT_EQ(150, n->getP2());
    EXPECT_EQ(7, n->getQ1());
    EXPECT_EQ(140, n->getQ2());
    EXPECT_DOUBLE_EQ(0.55, n->getAlpha());
    EXPECT_DOUBLE_EQ(0.9, n->getUniquenessRatio());
    EXPECT_EQ(2, n->getLRMaxDiff());
    EXPECT_EQ(4, n->getNumPaths());
    EXPECT_FALSE(n->getSubpixel());
    EXPECT_EQ(3, n->getSemidenseRadius());
    EXPECT_EQ(5, n->getSemidenseThreshold());
    EXPECT_EQ(11, n->getCheckRadius());
    EXPECT_DOUBLE_EQ(1.5, n->getCheckThreshold());
    EXPECT_EQ(1, n->getMedianSize());
    EXPECT_EQ(1, n->getVisibilityRadiusX());
    EXPECT_EQ(3, n->getVisibilityRadiusY());
    EXPECT_DOUBLE_EQ(0.3, n->getVisibilityParallax());
    EXPECT_EQ(20, n->getEdgeThreshold());
    EXPECT_DOUBLE_EQ(0.25, n->getEdgeP2Ratio());
    EXPECT_DOUBLE_EQ(1.5, n->getRingGapFactor());
    EXPECT_DOUBLE_EQ(0.5, n->getSemidenseWeight());
    EXPECT_EQ(6, n->getSearchWindow());
    EXPECT_EQ((int)StereoLidarSGM::MODE_DSGM, n->getMode());
    EXPECT_EQ((int)StereoLidarSGM::CHECK_CAMERA_LIDAR, n->getConsistencyCheck());
    EXPECT_EQ(CV_32F, n->getOutputType());
    Mat l, r, s, a, b;
    randomPair(Size(96, 48), l, r, s);
    m->compute(l, r, s, a);
    n->compute(l, r, s, b);
    EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF));
    remove(file.c_str());

    EXPECT_THROW(StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, 2, 3, 0.95, 1, 6), cv::Exception);   // 6 paths
    // A hand-edited file gets the setters' range checks.
    FileStorage fs("{\"name\": \"lidarsgm_StereoLidarSGM\", \"numDisparities\": 100}",
                   FileStorage::READ | FileStorage::MEMORY | FileStorage::FORMAT_JSON);
    EXPECT_THROW(n->read(fs.root()), cv::Exception);
}

/* The newcomer's mistakes, each refused or told, with a message that says what was wrong and what to do (the table
of doc/tutorial.md, "Mistakes and their messages"). No message carries the function that noticed it. */
static void expectSentence(const std::string& msg, const char* what)
{
    EXPECT_FALSE(msg.empty()) << what << ": nothing was raised";
    EXPECT_EQ(std::string::npos, msg.find("in function")) << what << ": " << msg;
    EXPECT_EQ(std::string::npos, msg.find("cv::lidarsgm::")) << what << ": " << msg;
}

TEST(Lidarsgm_API, kitti_png_given_as_float_pixels_is_refused)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(dir, "000002");
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    Mat png = cv::lidarsgm::encodeKittiDisparity(f.sparse), asFloat, d;   // uint16, disparity x 256
    png.convertTo(asFloat, CV_32F);                                           // the mistake: x256 as pixels
    const std::string msg = messageOf([&] { m->compute(f.left, f.right, asFloat, d); });
    expectSentence(msg, "x256 as float");
    EXPECT_NE(std::string::npos, msg.find(" % of the ")) << msg;
    EXPECT_NE(std::string::npos, msg.find("beyond the image's width")) << msg;
    EXPECT_NE(std::string::npos, msg.find("x 256")) << msg;
    EXPECT_NE(std::string::npos, msg.find("divide it by 256")) << msg;
    EXPECT_EQ((int)cv::Error::StsOutOfRange, [&]() -> int {
        try { m->compute(f.left, f.right, asFloat, d); }
        catch (const cv::Exception& e) { return e.code; }
        return 0;
    }());
    // Both fixes run and agree: the CV_16U map as it is, or divided by 256.
    Mat a, b;
    m->compute(f.left, f.right, png, a);
    m->compute(f.left, f.right, Mat(asFloat / 256.0), b);
    EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF));
    // A range too small for the scene is no unit mistake: 16 disparities on KITTI leave most points beyond it.
    EXPECT_NO_THROW(StereoLidarSGM::create(0, 16)->compute(f.left, f.right, f.sparse, d));
    // Nor are a few near points beyond the range: a map with a third of its values beyond it runs.
    Mat some = f.sparse.clone();
    int n = 0;
    for (float* p = some.ptr<float>(); p != some.ptr<float>() + some.total(); p++)
        if (*p > 0 && n++ % 3 == 0)
            *p += 200.f;
    EXPECT_NO_THROW(m->compute(f.left, f.right, some, d));
}

TEST(Lidarsgm_API, a_map_without_values_runs_and_warns)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16);
    Mat l, r, s, a, b;
    randomPair(Size(80, 40), l, r, s);
    const Mat nan(s.size(), CV_32F, Scalar::all(std::numeric_limits<float>::quiet_NaN()));
    // Runs as the fusion with no LiDAR value at all, and says so in OpenCV's log once per matcher.
    {
        CapturedLog log;
        EXPECT_NO_THROW(m->compute(l, r, nan, a));
        EXPECT_NO_THROW(m->compute(l, r, nan, a));
        const std::string said = log.str();
        EXPECT_NE(std::string::npos, said.find("has no value in the search range [0, 16) px")) << said;
        EXPECT_EQ(said.find("no value in"), said.rfind("no value in")) << "twice: " << said;
        EXPECT_EQ(std::string::npos, said.find("sparse_input.cpp")) << said;
    }
    m->compute(l, r, Mat::zeros(s.size(), CV_32F), b);
    EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF));
}

TEST(Lidarsgm_API, messages_name_no_function)
{
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16);
    Mat l, r, s, d;
    randomPair(Size(64, 32), l, r, s);
    expectSentence(messageOf([&] { m->compute(Mat(), r, s, d); }), "empty image");
    expectSentence(messageOf([&] { m->setP1(-1); }), "bad parameter");
    expectSentence(messageOf([&] { m->compute(l, r, Mat(), d); }), "no sparse map");
    const std::string none = messageOf([&] { m->compute(l, r, Mat(), d); });
    EXPECT_NE(std::string::npos, none.find("MODE_SDSGM with CHECK_STEREO_LIDAR needs")) << none;
    EXPECT_NE(std::string::npos, none.find("MODE_SGM with CHECK_STEREO")) << none;
    expectSentence(messageOf([&] { cv::lidarsgm::projectPointsToDisparity(Mat(4, 3, CV_32F, Scalar::all(1)),
                                   Matx34d::eye(), Matx34d::eye(), -1, Size(8, 8), d); }), "projection");
    expectSentence(messageOf([&] { cv::lidarsgm::readKittiCalibration("/nonexistent/calib.txt"); }), "calibration");
    expectSentence(messageOf([&] { cv::lidarsgm::selectLidarRings(Mat(4, 4, CV_32F), 0); }), "rings");
}

TEST(Lidarsgm_API, parameter_files_refuse_mistakes)
{
    const char* env = getenv("LIDARSGM_PARAMS");   // doc/params, set by ctest
    if (!env)
        throw SkipTestException("LIDARSGM_PARAMS does not name the folder of kitti_best.yml");
    const std::string best = std::string(env) + "/kitti_best.yml";
    std::string text;
    {
        std::ifstream in(best.c_str());
        ASSERT_TRUE(in.good()) << best;
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string file = cv::tempfile(".yml");
    const auto write = [&](const std::string& t) { std::ofstream(file.c_str()) << t; };
    // A misspelt key: the key, the file and the nearest known name.
    std::string typo = text;
    typo.replace(typo.find("edgeThreshold:"), 14, "edgeTreshold:");
    write(typo);
    std::string msg = messageOf([&] { StereoLidarSGM::load(file); });
    expectSentence(msg, "misspelt key");
    EXPECT_NE(std::string::npos, msg.find("'edgeTreshold'")) << msg;
    EXPECT_NE(std::string::npos, msg.find(file)) << msg;
    EXPECT_NE(std::string::npos, msg.find("did you mean 'edgeThreshold'")) << msg;
    typo = text;
    typo.replace(typo.find("searchWindow:"), 13, "serchWindow:");
    write(typo);
    msg = messageOf([&] { StereoLidarSGM::load(file); });
    EXPECT_NE(std::string::npos, msg.find("did you mean 'searchWindow'")) << msg;
    // A value out of range: the file and the parameter.
    std::string bad = text;
    bad.replace(bad.find("numPaths: 8"), 11, "numPaths: 6");
    write(bad);
    msg = messageOf([&] { StereoLidarSGM::load(file); });
    expectSentence(msg, "bad value");
    EXPECT_NE(std::string::npos, msg.find(file + ": numPaths")) << msg;
    // A missing file: its path.
    msg = messageOf([&] { StereoLidarSGM::load(file + ".missing"); });
    expectSentence(msg, "missing file");
    EXPECT_NE(std::string::npos, msg.find(file + ".missing does not exist")) << msg;
    // A malformed file: its path and the parser's line.
    write("%YAML:1.0\n---\nlidarsgm_StereoLidarSGM:\n   P1: 10\n   P2: [120\n   Q1: 5\n");
    msg = messageOf([&] { StereoLidarSGM::load(file); });
    expectSentence(msg, "malformed file");
    EXPECT_NE(std::string::npos, msg.find(file + " cannot be parsed")) << msg;
    EXPECT_NE(std::string::npos, msg.find(file + "(")) << msg;   // the parser's "file(line)"
    // read() itself, on a node (the tool's and a user's own FileStorage).
    FileStorage fs("{\"name\": \"lidarsgm_StereoLidarSGM\", \"P3\": 100}",
                   FileStorage::READ | FileStorage::MEMORY | FileStorage::FORMAT_JSON);
    msg = messageOf([&] { StereoLidarSGM::create()->read(fs.root()); });
    EXPECT_NE(std::string::npos, msg.find("unknown key 'P3'")) << msg;
    remove(file.c_str());
}

/* Disparity windows on a shipped KITTI frame in every mode, with kitti_best.yml's steps: a margin of the whole range
gives the full-range output bit for bit; a margin of 8 searches well under half of the cells and leaves the
disparity within 1 px of the full range's where both have one nearly everywhere; without a sparse map plain SGM
takes its windows from the coarse pass alone. (The CUDA path's windows: test_cuda.cpp, search_windows_bit_exact.) */
TEST(Lidarsgm_API, search_windows)
{
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    for (int mode : { StereoLidarSGM::MODE_SGM, StereoLidarSGM::MODE_DSGM, StereoLidarSGM::MODE_SDSGM })
    {
        SCOPED_TRACE(cv::format("mode %d", mode));
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, mode);
        setKittiBestSteps(*m);
        EXPECT_EQ(0.0, m->getSearchedFraction());
        Mat full, same, narrow;
        m->compute(l, r, s, full);
        EXPECT_EQ(1.0, m->getSearchedFraction());
        m->setSearchWindow(128);
        m->compute(l, r, s, same);
        EXPECT_EQ(1.0, m->getSearchedFraction());
        EXPECT_EQ(0, cvtest::norm(full, same, NORM_INF));
        m->setSearchWindow(8);
        m->compute(l, r, s, narrow);
        EXPECT_LT(m->getSearchedFraction(), 0.5);
        EXPECT_GT(m->getSearchedFraction(), 0.1);
        int both = 0, agree = 0;
        for (int y = 0; y < l.rows; y++)
            for (int x = 0; x < l.cols; x++)
            {
                const short a = full.at<short>(y, x), b = narrow.at<short>(y, x);
                if (a == -16 || b == -16)   // invalid: (minDisparity - 1) * 16
                    continue;
                both++;
                agree += std::abs(a - b) <= 16;
            }
        ASSERT_GT(both, l.total() / 3);
        EXPECT_GT((double)agree / both, 0.97) << agree << " of " << both;
    }
    Ptr<StereoLidarSGM> sgm = StereoLidarSGM::create(0, 128, 10, 120, 5, 160, 0.7, StereoLidarSGM::MODE_SGM,
                                                     StereoLidarSGM::CHECK_STEREO);
    sgm->setSearchWindow(8);
    Mat d;
    sgm->compute(l, r, noArray(), d);
    EXPECT_LT(sgm->getSearchedFraction(), 1.0);
}

// The stage calls of the per-stage CUDA tests (test_common.hpp, runCpuStages) give the matcher's own output on every
// configuration: they feed each CUDA stage what the pipeline feeds it.
TEST(Lidarsgm_Api, stage_by_stage_gives_the_output)
{
    for (const StageCase& c : stageCases())
    {
        Mat out;
        c.matcher->compute(c.left, c.right, c.sparse, out);
        ASSERT_EQ(out.type(), c.out.type()) << c.name;
        EXPECT_EQ(0, cvtest::norm(out, c.out, NORM_INF)) << c.name;
    }
}

// The confidence overload: the disparity map bit for bit compute()'s in every mode and check; the confidence in
// [0, 1], 0 exactly where there is no disparity; the 10 % least confident pixels hold the outliers' larger share.
TEST(Lidarsgm_Api, confidence_leaves_the_disparity_unchanged)
{
    Mat l, r, s;
    loadKittiTestFrame("000002", l, r, s);
    const Mat gt = cv::lidarsgm::loadKittiFrame(cvtest::findDataDirectory("kitti"), "000002").groundTruth;
    for (int mode = 0; mode < 3; mode++)
        for (int check = 0; check < 4; check++)
        {
            Ptr<SLS> m = SLS::create(0, 128, 10, 120, 5, 160, 0.7, mode, check);
            Mat d, d2, conf;
            m->compute(l, r, s, d);
            m->compute(l, r, s, d2, conf);
            const std::string what = format("mode %d check %d", mode, check);
            ASSERT_EQ(0, cvtest::norm(d, d2, NORM_INF)) << what;
            ASSERT_EQ(CV_32FC1, conf.type()) << what;
            double lo = 0, hi = 0;
            minMaxLoc(conf, &lo, &hi);
            EXPECT_GE(lo, 0.0) << what;
            EXPECT_LE(hi, 1.0) << what;
            EXPECT_EQ(0, countNonZero((d == -16) != (conf == 0))) << what;
            if (mode != 2 || check != 3)
                continue;
            // The errors concentrate in the least confident pixels (SDSGM, the default check).
            std::vector<std::pair<float, bool> > px;
            for (int y = 0; y < d.rows; y++)
                for (int x = 0; x < d.cols; x++)
                    if (d.at<short>(y, x) > -16 && gt.at<float>(y, x) > 0)
                    {
                        const float e = std::abs(d.at<short>(y, x) / 16.f - gt.at<float>(y, x));
                        px.push_back(std::make_pair(conf.at<float>(y, x), e > 3 && e > 0.05f * gt.at<float>(y, x)));
                    }
            std::stable_sort(px.begin(), px.end(),
                             [](const std::pair<float, bool>& a, const std::pair<float, bool>& b) { return a.first < b.first; });
            size_t all = 0, low = 0;
            for (size_t i = 0; i < px.size(); i++)
            {
                all += px[i].second;
                low += px[i].second && i < px.size() / 10;
            }
            ASSERT_GT(all, 0u);
            EXPECT_GT((double)low / all, 0.4) << low << " of " << all << " outliers in the least confident 10 %";
        }
    // The confidence's container follows the inputs'.
    Ptr<SLS> m = SLS::create();
    Mat d;
    cuda::GpuMat gconf;
    EXPECT_THROW(m->compute(l, r, s, d, gconf), cv::Exception);
}

}} // namespace
