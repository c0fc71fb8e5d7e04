// This file is part of the lidarsgm module (an OpenCV extra module).
// Inputs shared by several test files.
#ifndef OPENCV_LIDARSGM_TEST_COMMON_HPP
#define OPENCV_LIDARSGM_TEST_COMMON_HPP

#include "test_precomp.hpp"
#include "opencv2/core/cuda.hpp"
#include "opencv2/core/utils/logger.hpp"
#include "cpu_stages.hpp"
#include "cuda_stages_host.hpp"

namespace opencv_test {

//! A shipped KITTI frame (testdata/kitti): grey pair and the raw scan projected to a CV_32F sparse map.
inline void loadKittiTestFrame(const std::string& id, Mat& l, Mat& r, Mat& s)
{
    const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(cvtest::findDataDirectory("kitti"), id);
    l = f.left;
    r = f.right;
    s = f.sparse;
}

//! A row vector of floats.
inline Mat floatRow(std::initializer_list<float> v)
{
    return Mat(std::vector<float>(v), true).reshape(1, 1);
}

//! Float maps equal element by element (infinities included).
inline void expectSameFloats(const Mat& expected, const Mat& actual)
{
    ASSERT_EQ(expected.size(), actual.size());
    for (int y = 0; y < expected.rows; y++)
        for (int x = 0; x < expected.cols; x++)
            EXPECT_EQ(expected.at<float>(y, x), actual.at<float>(y, x)) << "at (" << x << ", " << y << ")";
}

//! The steps beyond the paper that doc/params/kitti_best.yml switches on (its values), on a matcher.
inline void setKittiBestSteps(cv::lidarsgm::StereoLidarSGM& m)
{
    m.setVisibilityRadiusX(2);
    m.setVisibilityRadiusY(4);
    m.setVisibilityParallax(0.18);
    m.setEdgeThreshold(32);
    m.setRingGapFactor(2);
    m.setSemidenseWeight(0.5);
}

//! Uncorrelated 8-bit images and a sparse map with about 4 % of the pixels set to disparities in [1, 60).
inline void randomInputs(Size sz, RNG& rng, Mat& l, Mat& r, Mat& s)
{
    l.create(sz, CV_8UC1);
    r.create(sz, CV_8UC1);
    s = Mat(sz, CV_32FC1, Scalar::all(0));
    rng.fill(l, RNG::UNIFORM, 0, 256);
    rng.fill(r, RNG::UNIFORM, 0, 256);
    for (int k = 0; k < sz.area() / 25 + 1; k++)
        s.at<float>(rng.uniform(0, sz.height), rng.uniform(0, sz.width)) = (float)rng.uniform(1.0, 60.0);
}

// ---- The stages one at a time: CPU intermediate maps, and the CUDA twins checked against them ----------------------

//! Skips a CUDA test where the build has no CUDA or the machine no device.
inline void requireCudaDevice()
{
#ifndef HAVE_CUDA
    throw SkipTestException("lidarsgm was built without CUDA");
#else
    if (cv::cuda::getCudaEnabledDeviceCount() <= 0)
        throw SkipTestException("no CUDA device");
#endif
}

//! A CUDA stage's output equal to its CPU twin's, bit for bit.
inline void expectSameAsCpu(const Mat& cpu, const cuda::GpuMat& gpu, const std::string& what)
{
    Mat g;
    gpu.download(g);
    ASSERT_EQ(cpu.type(), g.type()) << what;
    ASSERT_EQ(cpu.size(), g.size()) << what;
    EXPECT_EQ(0, cvtest::norm(cpu, g, NORM_INF)) << what;
}

/** One configuration and every intermediate map of the CPU pipeline on it (src/cpu_pipeline.cpp's calls in order):
the inputs each stage gets and the outputs it gives, for the per-stage CUDA tests. */
struct StageCase
{
    std::string name;
    Mat left, right, sparse;
    Ptr<cv::lidarsgm::StereoLidarSGM> matcher;
    cv::lidarsgm::detail::PipelineParams p;
    bool scan = false;                    //!< the scan test on the converted map
    Mat converted16;                      //!< convertSparse's output
    Mat sparse16;                         //!< after the visibility filter (where it is on)
    Mat censusL, censusR;
    Mat semidense0;                       //!< semidensify's output, before ring interpolation
    Mat semidense16;                      //!< after ring interpolation
    cv::lidarsgm::detail::RingMaps rings;
    Mat prior, own16;                     //!< the aggregation's prior and copied-prior map
    Mat sum, disp16, dispInt, dispRight, nonUnique16;
    Mat med16, medInt, medRight;          //!< the median filter's outputs (medianSize 3)
    Mat out;                              //!< the consistency check's output
};

/** The aggregation stage's inputs (aggregateCosts): both views' census strings, and where given the prior, the
image of the edge rule, the copied-prior map and the disparity windows (an empty Mat: that input off). */
inline cv::lidarsgm::detail::AggregationInputs aggregationInputs(const Mat& censusL, const Mat& censusR,
                                                                 const Mat& prior16 = Mat(), const Mat& left = Mat(),
                                                                 const Mat& own16 = Mat(), const Mat& windows = Mat())
{
    cv::lidarsgm::detail::AggregationInputs in;
    in.censusL = censusL;
    in.censusR = censusR;
    in.prior16 = prior16;
    in.left = left;
    in.own16 = own16;
    in.windows = windows;
    return in;
}

inline StageCase runCpuStages(const std::string& name, const Mat& l, const Mat& r, const Mat& s,
                              const Ptr<cv::lidarsgm::StereoLidarSGM>& m)
{
    using namespace cv::lidarsgm::detail;
    StageCase c;
    c.name = name;
    c.left = l;
    c.right = r;
    c.sparse = s;
    c.matcher = m;
    const PipelineParams& p = c.p = pipelineParamsOf(*m);
    censusTransform(l, c.censusL);
    censusTransform(r, c.censusR);
    convertSparse(s, p.minDisparity, p.numDisparities, c.converted16);
    c.scan = isLidarScan(c.converted16);
    if (visibilityFilterOn(p))
        filterHiddenPoints(c.converted16, p, c.sparse16, p.visibilityParallax256 > 0 && c.scan);
    else
        c.sparse16 = c.converted16;
    semidensify(c.censusL, c.censusR, c.sparse16, p, c.semidense0);
    c.semidense16 = c.semidense0.clone();
    interpolateRings(c.censusL, c.censusR, c.sparse16, p, c.semidense16, c.rings);
    if (!p.semidense)
        c.rings.valid = false;
    c.prior = p.semidense ? c.semidense16 : p.ddc ? c.sparse16 : Mat();
    c.own16 = p.weighCopies && c.scan ? c.sparse16 : Mat();
    cv::lidarsgm::detail::WinnerMaps w;
    aggregateCosts(aggregationInputs(c.censusL, c.censusR, c.prior, l, c.own16), p, w, c.sum);
    c.disp16 = w.disp16;
    c.dispInt = w.dispInt;
    c.dispRight = w.dispRight;
    c.nonUnique16 = w.nonUnique16;
    medianFilter(c.disp16, c.med16);
    medianFilter(c.dispInt, c.medInt);
    medianFilter(c.dispRight, c.medRight);
    consistencyCheck(c.med16, c.medInt, c.medRight, c.sparse16, c.nonUnique16, c.rings, p, c.out);
    return c;
}

/** The configurations of the per-stage CUDA tests: both shipped KITTI frames (the paper's defaults at 64 lines;
kitti_best.yml's steps at 16 lines with 4 paths), a 16-bit random pair with a negative minDisparity and a LiDAR-like
ring pattern (the scan test passes, so the copied priors' weight applies), and a pair smaller than the census window
and a warp's disparities. Computed once. */
inline const std::vector<StageCase>& stageCases()
{
    static std::vector<StageCase> cases;
    if (!cases.empty())
        return cases;
    using cv::lidarsgm::StereoLidarSGM;
    const std::string kitti = cvtest::findDataDirectory("kitti");
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(kitti, "000002");
        cases.push_back(runCpuStages("KITTI 000002, defaults", f.left, f.right, f.sparse, StereoLidarSGM::create()));
    }
    {
        const cv::lidarsgm::StereoLidarFrame f = cv::lidarsgm::loadKittiFrame(kitti, "000046", 4);
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
        setKittiBestSteps(*m);
        m->setNumPaths(4);
        cases.push_back(runCpuStages("KITTI 000046, kitti_best steps, 16 lines, 4 paths", f.left, f.right, f.sparse, m));
    }
    {
        RNG rng(4242);
        const Size sz(97, 61);
        Mat l(sz, CV_16UC1), r(sz, CV_16UC1), s(sz, CV_32FC1, Scalar::all(0));
        rng.fill(l, RNG::UNIFORM, 0, 65536);
        rng.fill(r, RNG::UNIFORM, 0, 65536);
        GaussianBlur(l, l, Size(3, 3), 0);
        GaussianBlur(r, r, Size(3, 3), 0);
        for (int y = 0; y < sz.height; y += 5)   // rings: every 5th row, every 2nd pixel
            for (int x = y % 2; x < sz.width; x += 2)
                s.at<float>(y, x) = (float)rng.uniform(-6.0, 60.0);
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(-5, 64);
        m->setVisibilityRadiusX(1);
        m->setVisibilityRadiusY(3);
        m->setVisibilityParallax(0.25);
        m->setEdgeThreshold(4000);
        m->setRingGapFactor(3);
        m->setSemidenseWeight(0.25);
        m->setOutputType(CV_32F);
        cases.push_back(runCpuStages("random 16-bit 97x61, rings, minDisparity -5", l, r, s, m));
    }
    {
        RNG rng(7);
        Mat l, r, s;
        randomInputs(Size(7, 3), rng, l, r, s);
        Ptr<StereoLidarSGM> m = StereoLidarSGM::create(0, 16, 10, 120, 5, 160, 0.7, StereoLidarSGM::MODE_DSGM,
                                                       StereoLidarSGM::CHECK_CAMERA_LIDAR);
        cases.push_back(runCpuStages("random 8-bit 7x3, 16 disparities, DSGM", l, r, s, m));
    }
    return cases;
}

/* What the module writes to OpenCV's log while it lives (warnings and notices for people), for the tests that check
what a user is told. One at a time. */
class CapturedLog
{
public:
    CapturedLog() { text().clear(); cv::utils::logging::internal::replaceWriteLogMessage(&CapturedLog::write); }
    ~CapturedLog() { cv::utils::logging::internal::replaceWriteLogMessage(nullptr); }
    std::string str() const { return text(); }
private:
    static std::string& text() { static std::string t; return t; }
    static void write(cv::utils::logging::LogLevel, const char* message) { text() += std::string(message) + "\n"; }
};

} // namespace opencv_test

#endif
