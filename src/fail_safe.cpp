// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The fail-safe: the bound on the matching residual and the stereo-alone fallback, defined here once for every front
// end (the tool, the ROS 2 node and bag command, the samples).

#include "precomp.hpp"
#include "pipeline.hpp"

namespace cv { namespace lidarsgm {

namespace {

/* The DDC's Q1 band (pixels): a LiDAR whose matching residual exceeds it pulls the fusion off the images by more than
a disparity (doc/accuracy.md, "Calibration"). */
const double kMaxResidual = 1.0;

//! `from`'s settings in MODE_SGM on `to`: the LiDAR's part of the check has no map to keep anything with.
void stereoAloneSettings(const StereoLidarSGM& from, StereoLidarSGM& to)
{
    detail::copySettings(from, to);
    to.setMode(StereoLidarSGM::MODE_SGM);
    const int check = from.getConsistencyCheck();
    if (check == StereoLidarSGM::CHECK_STEREO_LIDAR || check == StereoLidarSGM::CHECK_CAMERA_LIDAR)
        to.setConsistencyCheck(StereoLidarSGM::CHECK_STEREO);
}

class LidarFailSafeImpl CV_FINAL : public LidarFailSafe
{
public:
    explicit LidarFailSafeImpl(bool trustLidar) : trust_(trustLidar) {}

    bool getTrustLidar() const CV_OVERRIDE { return trust_; }
    void setTrustLidar(bool trust) CV_OVERRIDE { trust_ = trust; }

    LidarCheck check(InputArray left, InputArray right, InputArray sparseDisparity) const CV_OVERRIDE
    {
        LidarCheck c = checkLidar(left, right, sparseDisparity, kMaxResidual);
        c.stereoAlone = !c.trusted && !trust_;
        return c;
    }

    LidarCheck compute(const Ptr<StereoLidarSGM>& matcher, InputArray left, InputArray right,
                       InputArray sparseDisparity, OutputArray disparity) CV_OVERRIDE
    {
        LIDARSGM_Check(!matcher.empty(), "lidarsgm: LidarFailSafe::compute: the matcher is empty");
        if (disparity.kind() == _InputArray::CUDA_GPU_MAT)
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: LidarFailSafe::compute runs the check on the CPU: pass cv::Mat "
                                             "inputs and output, or call check() on the host images and compute with "
                                             "the matcher it names (stereoAloneMatcher() where stereoAlone)");
        const LidarCheck c = check(left, right, sparseDisparity);
        if (!c.stereoAlone)
        {
            matcher->compute(left, right, sparseDisparity, disparity);
            return c;
        }
        // The settings again on every call: the matcher may have changed; its buffers stay (no reallocation).
        if (alone_.empty())
            alone_ = StereoLidarSGM::create();
        stereoAloneSettings(*matcher, *alone_);
        // A map without values rather than none: every stage runs as for a LiDAR that saw nothing (the confidence's
        // LiDAR evidence says so), and the search windows come from the coarse pass.
        none_.create(sparseDisparity.size(), sparseDisparity.type());
        none_.setTo(Scalar::all(0));
        alone_->compute(left, right, none_, disparity);
        return c;
    }

private:
    bool trust_;
    Ptr<StereoLidarSGM> alone_;
    Mat none_;
};

} // namespace

Ptr<LidarFailSafe> LidarFailSafe::create(bool trustLidar)
{
    return makePtr<LidarFailSafeImpl>(trustLidar);
}

double LidarFailSafe::maxResidual()
{
    return kMaxResidual;
}

Ptr<StereoLidarSGM> LidarFailSafe::stereoAloneMatcher(const Ptr<StereoLidarSGM>& matcher)
{
    LIDARSGM_Check(!matcher.empty(), "lidarsgm: LidarFailSafe::stereoAloneMatcher: the matcher is empty");
    Ptr<StereoLidarSGM> m = StereoLidarSGM::create();
    stereoAloneSettings(*matcher, *m);
    return m;
}

}} // namespace cv::lidarsgm
