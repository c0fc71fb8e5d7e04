// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// StereoLidarSGM: parameters, input validation, and the order of the pipeline stages (see pipeline.hpp).

#include "precomp.hpp"
#include "pipeline.hpp"
#ifdef HAVE_CUDA
#  include "opencv2/core/cuda_stream_accessor.hpp"
#  include "pipeline_cuda.hpp"
#endif

namespace cv { namespace lidarsgm {

using namespace detail;

namespace {

const char* modeName(int mode)
{
    switch (mode)
    {
    case StereoLidarSGM::MODE_SGM: return "MODE_SGM";
    case StereoLidarSGM::MODE_DSGM: return "MODE_DSGM";
    case StereoLidarSGM::MODE_SDSGM: return "MODE_SDSGM";
    default: return "?";
    }
}

void checkStereoPairInfo(bool emptyL, bool emptyR, int chL, int chR, int typeL, int typeR, Size szL, Size szR)
{
    CV_CheckFalse(emptyL, "lidarsgm: the left image is empty");
    CV_CheckFalse(emptyR, "lidarsgm: the right image is empty");
    if (chL != 1 || chR != 1)
        CV_Error_(Error::BadNumChannels,
                  ("lidarsgm: the images must be single-channel (grey); got %d and %d channels. "
                   "Convert colour images with cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY)", chL, chR));
    if (CV_MAT_DEPTH(typeL) != CV_8U && CV_MAT_DEPTH(typeL) != CV_16U)
        CV_Error_(Error::BadDepth, ("lidarsgm: the images must be CV_8UC1 or CV_16UC1; the left image is %s",
                                    typeToString(typeL).c_str()));
    if (typeL != typeR)
        CV_Error_(Error::StsUnmatchedFormats, ("lidarsgm: left and right images differ in type (%s vs %s)",
                                               typeToString(typeL).c_str(), typeToString(typeR).c_str()));
    if (szL != szR)
        CV_Error_(Error::StsUnmatchedSizes, ("lidarsgm: left and right images differ in size (%dx%d vs %dx%d)",
                                             szL.width, szL.height, szR.width, szR.height));
}

void checkStereoPair(const Mat& left, const Mat& right)
{
    checkStereoPairInfo(left.empty(), right.empty(), left.channels(), right.channels(), left.type(), right.type(),
                        left.size(), right.size());
}

void checkSparseInfo(int type, Size size, Size imageSize)
{
    if (type != CV_16UC1 && type != CV_32FC1)
        CV_Error_(Error::StsUnsupportedFormat,
                  ("lidarsgm: the sparse disparity map must be CV_16UC1 (KITTI, value / 256) or CV_32FC1 (pixels); got %s",
                   typeToString(type).c_str()));
    if (size != imageSize)
        CV_Error_(Error::StsUnmatchedSizes, ("lidarsgm: the sparse disparity map is %dx%d but the images are %dx%d",
                                             size.width, size.height, imageSize.width, imageSize.height));
}

void checkSparse(const Mat& sparse, Size size)
{
    checkSparseInfo(sparse.type(), sparse.size(), size);
}

bool isGpuInput(InputArray a)
{
    return a.kind() == _InputArray::CUDA_GPU_MAT;
}

} // namespace

class StereoLidarSGMImpl CV_FINAL : public StereoLidarSGM
{
public:
    StereoLidarSGMImpl(int minDisparity, int numDisparities, int P1, int P2, int Q1, int Q2, double alpha,
                       int mode, int check)
    {
        setMinDisparity(minDisparity);
        setNumDisparities(numDisparities);
        setP1(P1); setP2(P2); setQ1(Q1); setQ2(Q2);
        setAlpha(alpha);
        setMode(mode);
        setConsistencyCheck(check);
        checkRelations();
    }

#ifdef HAVE_CUDA
    ~StereoLidarSGMImpl()
    {
        if (g_done_)
            cudaEventDestroy(g_done_);
    }
#endif

    void compute(InputArray left, InputArray right, InputArray sparse, OutputArray disparity) CV_OVERRIDE
    {
        CV_INSTRUMENT_REGION();
        if (isGpuInput(left) || isGpuInput(right) || isGpuInput(sparse))
        {
            runCuda(left, right, sparse, disparity, nullptr, false);
            return;
        }
        AutoLock lock(mutex_);  // one call at a time per instance: the work buffers are members
        const Mat L = left.getMat(), R = right.getMat(), Sp = sparse.getMat();
        checkStereoPair(L, R);
        const PipelineParams p = pipelineParams();
        const bool needSparse = p.mode != MODE_SGM || p.check == CHECK_CAMERA_LIDAR || p.check == CHECK_STEREO_LIDAR;
        if (needSparse && Sp.empty())
            CV_Error_(Error::StsBadArg, ("lidarsgm: the sparse disparity map is empty, but %s with consistency check %d needs it",
                                         modeName(p.mode), p.check));
        if (!Sp.empty())
            checkSparse(Sp, L.size());

        censusTransform(L, censusL_);
        censusTransform(R, censusR_);
        if (!Sp.empty())
            convertSparse(Sp, p.minDisparity, p.numDisparities, sparse16_);
        else
            sparse16_.release();

        Mat prior;
        if (p.mode == MODE_SDSGM)
        {
            detail::semidensify(censusL_, censusR_, sparse16_, p, semidense16_);
            prior = semidense16_;
        }
        else if (p.mode == MODE_DSGM)
            prior = sparse16_;

        computeMatchingCost(censusL_, censusR_, prior, p, cost_);
        aggregateCosts(cost_, L.cols, p, sum_);
        winnerTakesAll(sum_, L.cols, p, disp16_, dispInt_, dispRight_);
        if (p.medianSize == 3)
        {
            medianFilter(disp16_, med16_);
            medianFilter(dispInt_, medInt_);
            medianFilter(dispRight_, medRight_);
            consistencyCheck(med16_, medInt_, medRight_, sparse16_, p);
            writeOutput(med16_, disparity);
            return;
        }
        consistencyCheck(disp16_, dispInt_, dispRight_, sparse16_, p);
        writeOutput(disp16_, disparity);
    }

    void compute(InputArray left, InputArray right, InputArray sparse, OutputArray disparity,
                 cuda::Stream& stream) CV_OVERRIDE
    {
        runCuda(left, right, sparse, disparity, &stream, false);
    }

    void semidensify(InputArray left, InputArray right, InputArray sparse, OutputArray semidense) CV_OVERRIDE
    {
        CV_INSTRUMENT_REGION();
        if (isGpuInput(left) || isGpuInput(right) || isGpuInput(sparse))
        {
            runCuda(left, right, sparse, semidense, nullptr, true);
            return;
        }
        AutoLock lock(mutex_);
        const Mat L = left.getMat(), R = right.getMat(), Sp = sparse.getMat();
        checkStereoPair(L, R);
        CV_CheckFalse(Sp.empty(), "lidarsgm: semidensify needs a sparse disparity map; it is empty");
        checkSparse(Sp, L.size());
        const PipelineParams p = pipelineParams();
        censusTransform(L, censusL_);
        censusTransform(R, censusR_);
        convertSparse(Sp, p.minDisparity, p.numDisparities, sparse16_);
        detail::semidensify(censusL_, censusR_, sparse16_, p, semidense16_);
        writeOutput(semidense16_, semidense);
    }

    void semidensify(InputArray left, InputArray right, InputArray sparse, OutputArray semidense,
                     cuda::Stream& stream) CV_OVERRIDE
    {
        runCuda(left, right, sparse, semidense, &stream, true);
    }

    // ---- parameters ------------------------------------------------------------------------------------------
    int getMinDisparity() const CV_OVERRIDE { return minDisparity_; }
    void setMinDisparity(int v) CV_OVERRIDE
    {
        CV_CheckGE(v, -1024, "lidarsgm: minDisparity must be in [-1024, 1024]");
        CV_CheckLE(v, 1024, "lidarsgm: minDisparity must be in [-1024, 1024]");
        minDisparity_ = v;
    }
    int getNumDisparities() const CV_OVERRIDE { return numDisparities_; }
    void setNumDisparities(int v) CV_OVERRIDE
    {
        CV_CheckTrue(v >= 16 && v <= 256 && v % 16 == 0, "lidarsgm: numDisparities must be a multiple of 16 in [16, 256]");
        numDisparities_ = v;
    }
    int getP1() const CV_OVERRIDE { return P1_; }
    void setP1(int v) CV_OVERRIDE { checkRange(v, 0, 1000, "P1"); P1_ = v; }
    int getP2() const CV_OVERRIDE { return P2_; }
    void setP2(int v) CV_OVERRIDE { checkRange(v, 0, 1000, "P2"); P2_ = v; }
    int getQ1() const CV_OVERRIDE { return Q1_; }
    void setQ1(int v) CV_OVERRIDE { checkRange(v, 0, 1000, "Q1"); Q1_ = v; }
    int getQ2() const CV_OVERRIDE { return Q2_; }
    void setQ2(int v) CV_OVERRIDE { checkRange(v, 0, 1000, "Q2"); Q2_ = v; }
    double getAlpha() const CV_OVERRIDE { return alpha_; }
    void setAlpha(double v) CV_OVERRIDE
    {
        CV_CheckTrue(v >= 0.0 && v <= 1.0, "lidarsgm: alpha must be in [0, 1] (and not NaN)");
        alpha_ = v;
    }
    double getUniquenessRatio() const CV_OVERRIDE { return uniquenessRatio_; }
    void setUniquenessRatio(double v) CV_OVERRIDE
    {
        CV_CheckTrue(v > 0.0 && v <= 1.0, "lidarsgm: uniquenessRatio must be in (0, 1] (1 disables the check)");
        uniquenessRatio_ = v;
    }
    int getLRMaxDiff() const CV_OVERRIDE { return lrMaxDiff_; }
    void setLRMaxDiff(int v) CV_OVERRIDE { checkRange(v, 0, 16, "LRMaxDiff"); lrMaxDiff_ = v; }
    int getNumPaths() const CV_OVERRIDE { return numPaths_; }
    void setNumPaths(int v) CV_OVERRIDE
    {
        CV_CheckTrue(v == 4 || v == 8, "lidarsgm: numPaths must be 4 or 8");
        numPaths_ = v;
    }
    bool getSubpixel() const CV_OVERRIDE { return subpixel_; }
    void setSubpixel(bool v) CV_OVERRIDE { subpixel_ = v; }
    int getSemidenseRadius() const CV_OVERRIDE { return rs_; }
    void setSemidenseRadius(int v) CV_OVERRIDE { checkRange(v, 0, 32, "semidenseRadius (rs)"); rs_ = v; }
    int getSemidenseThreshold() const CV_OVERRIDE { return Ts_; }
    void setSemidenseThreshold(int v) CV_OVERRIDE { checkRange(v, 0, 32, "semidenseThreshold (Ts)"); Ts_ = v; }
    int getCheckRadius() const CV_OVERRIDE { return rc_; }
    void setCheckRadius(int v) CV_OVERRIDE { checkRange(v, 0, 64, "checkRadius (rc)"); rc_ = v; }
    double getCheckThreshold() const CV_OVERRIDE { return Tc_; }
    void setCheckThreshold(double v) CV_OVERRIDE
    {
        CV_CheckTrue(v >= 0.0 && v <= 64.0, "lidarsgm: checkThreshold (Tc) must be in [0, 64] pixels (and not NaN)");
        Tc_ = v;
    }
    int getMode() const CV_OVERRIDE { return mode_; }
    void setMode(int v) CV_OVERRIDE
    {
        CV_CheckTrue(v == MODE_SGM || v == MODE_DSGM || v == MODE_SDSGM,
                     "lidarsgm: mode must be MODE_SGM (0), MODE_DSGM (1) or MODE_SDSGM (2)");
        mode_ = v;
    }
    int getConsistencyCheck() const CV_OVERRIDE { return check_; }
    void setConsistencyCheck(int v) CV_OVERRIDE
    {
        CV_CheckTrue(v >= CHECK_NONE && v <= CHECK_STEREO_LIDAR,
                     "lidarsgm: consistency check must be CHECK_NONE (0), CHECK_STEREO (1), CHECK_CAMERA_LIDAR (2) or CHECK_STEREO_LIDAR (3)");
        check_ = v;
    }
    int getMedianSize() const CV_OVERRIDE { return medianSize_; }
    void setMedianSize(int v) CV_OVERRIDE
    {
        CV_CheckTrue(v == 1 || v == 3, "lidarsgm: medianSize must be 1 (off) or 3 (3x3 median)");
        medianSize_ = v;
    }
    int getOutputType() const CV_OVERRIDE { return outputType_; }
    void setOutputType(int v) CV_OVERRIDE
    {
        CV_CheckTrue(v == CV_16S || v == CV_32F, "lidarsgm: outputType must be CV_16S or CV_32F");
        outputType_ = v;
    }

    // ---- persistence -----------------------------------------------------------------------------------------
    // A FileStorage key: letters, digits and '_' only.
    String getDefaultName() const CV_OVERRIDE { return "lidarsgm_StereoLidarSGM"; }

    void write(FileStorage& fs) const CV_OVERRIDE
    {
        writeFormat(fs);
        fs << "name" << getDefaultName()
           << "minDisparity" << minDisparity_ << "numDisparities" << numDisparities_
           << "P1" << P1_ << "P2" << P2_ << "Q1" << Q1_ << "Q2" << Q2_ << "alpha" << alpha_
           << "uniquenessRatio" << uniquenessRatio_ << "lrMaxDiff" << lrMaxDiff_ << "numPaths" << numPaths_
           << "subpixel" << (int)subpixel_ << "semidenseRadius" << rs_ << "semidenseThreshold" << Ts_
           << "checkRadius" << rc_ << "checkThreshold" << Tc_ << "mode" << mode_ << "consistencyCheck" << check_
           << "outputType" << outputType_ << "medianSize" << medianSize_;
    }

    void read(const FileNode& fn) CV_OVERRIDE
    {
        FileNode name = fn["name"];
        CV_CheckTrue(name.empty() || (String)name == getDefaultName(),
                     "lidarsgm: the file node does not hold a lidarsgm_StereoLidarSGM");
        // Through the setters, so a hand-edited file gets the same range checks.
        setMinDisparity(readInt(fn, "minDisparity", minDisparity_));
        setNumDisparities(readInt(fn, "numDisparities", numDisparities_));
        setP1(readInt(fn, "P1", P1_)); setP2(readInt(fn, "P2", P2_));
        setQ1(readInt(fn, "Q1", Q1_)); setQ2(readInt(fn, "Q2", Q2_));
        setAlpha(readDouble(fn, "alpha", alpha_));
        setUniquenessRatio(readDouble(fn, "uniquenessRatio", uniquenessRatio_));
        setLRMaxDiff(readInt(fn, "lrMaxDiff", lrMaxDiff_));
        setNumPaths(readInt(fn, "numPaths", numPaths_));
        setSubpixel(readInt(fn, "subpixel", subpixel_) != 0);
        setSemidenseRadius(readInt(fn, "semidenseRadius", rs_));
        setSemidenseThreshold(readInt(fn, "semidenseThreshold", Ts_));
        setCheckRadius(readInt(fn, "checkRadius", rc_));
        setCheckThreshold(readDouble(fn, "checkThreshold", Tc_));
        setMode(readInt(fn, "mode", mode_));
        setConsistencyCheck(readInt(fn, "consistencyCheck", check_));
        setOutputType(readInt(fn, "outputType", outputType_));
        setMedianSize(readInt(fn, "medianSize", medianSize_));
        checkRelations();
    }

private:
    static void checkRange(int v, int lo, int hi, const char* name)
    {
        if (v < lo || v > hi)
            CV_Error_(Error::StsOutOfRange, ("lidarsgm: %s must be in [%d, %d]; got %d", name, lo, hi, v));
    }
    static int readInt(const FileNode& fn, const char* key, int def)
    {
        FileNode n = fn[key];
        return n.empty() ? def : (int)n;
    }
    static double readDouble(const FileNode& fn, const char* key, double def)
    {
        FileNode n = fn[key];
        return n.empty() ? def : (double)n;
    }

    //! Constraints between parameters, checked when they are used (setters may be called in any order).
    void checkRelations() const
    {
        if (P1_ > P2_)
            CV_Error_(Error::StsOutOfRange, ("lidarsgm: P1 (%d) must not exceed P2 (%d)", P1_, P2_));
        if (Q1_ > Q2_)
            CV_Error_(Error::StsOutOfRange, ("lidarsgm: Q1 (%d) must not exceed Q2 (%d)", Q1_, Q2_));
    }

    PipelineParams pipelineParams() const
    {
        checkRelations();
        PipelineParams p;
        p.minDisparity = minDisparity_;
        p.numDisparities = numDisparities_;
        p.numPaths = numPaths_;
        p.subpixel = subpixel_;
        p.uniqueness1024 = cvRound(uniquenessRatio_ * 1024);
        p.lrMaxDiff = lrMaxDiff_;
        p.semidenseRadius = rs_;
        p.semidenseThreshold = Ts_;
        p.checkRadius = rc_;
        p.checkThreshold16 = cvRound(Tc_ * 16);
        p.medianSize = medianSize_;
        p.mode = mode_;
        p.check = check_;
        p.w = computeCostWeights(P1_, P2_, Q1_, Q2_, alpha_, numPaths_, mode_ != MODE_SGM);
        return p;
    }

    void writeOutput(const Mat& d16, OutputArray out) const
    {
        if (outputType_ == CV_16S)
        {
            out.create(d16.size(), CV_16SC1);
            Mat o = out.getMat();
            const short invalid = (short)((minDisparity_ - 1) * 16);
            for (int y = 0; y < d16.rows; y++)
            {
                const short* s = d16.ptr<short>(y);
                short* dst = o.ptr<short>(y);
                for (int x = 0; x < d16.cols; x++)
                    dst[x] = s[x] == NO_DISP ? invalid : s[x];
            }
        }
        else
        {
            out.create(d16.size(), CV_32FC1);
            Mat o = out.getMat();
            const float invalid = (float)(minDisparity_ - 1);
            for (int y = 0; y < d16.rows; y++)
            {
                const short* s = d16.ptr<short>(y);
                float* dst = o.ptr<float>(y);
                for (int x = 0; x < d16.cols; x++)
                    dst[x] = s[x] == NO_DISP ? invalid : s[x] * (1.f / 16);
            }
        }
    }

#ifdef HAVE_CUDA
    static void cudaCheck(cudaError_t err)
    {
        if (err != cudaSuccess)
            CV_Error_(Error::GpuApiCallError, ("lidarsgm: %s", cudaGetErrorString(err)));
    }

    template <typename T>
    static cuda::PtrStepSz<T> ptr(const cuda::GpuMat& m)
    {
        return m.empty() ? cuda::PtrStepSz<T>() : cuda::PtrStepSz<T>(m);
    }

    /* The CUDA pipeline, in the same order as compute(); semidenseOnly stops after semidensification. streamPtr ==
    nullptr means the default stream (not cuda::Stream::Null() up front: that needs a working driver, and the CPU
    entry points call this only when given GpuMats). Work buffers are members and only (re)allocated when the
    size, disparity count or types change; everything else is enqueued on the stream without synchronising. */
    void runCuda(InputArray left, InputArray right, InputArray sparse, OutputArray out, cuda::Stream* streamPtr,
                 bool semidenseOnly)
    {
        CV_INSTRUMENT_REGION();
        if (left.kind() != _InputArray::CUDA_GPU_MAT || right.kind() != _InputArray::CUDA_GPU_MAT ||
            (!sparse.empty() && sparse.kind() != _InputArray::CUDA_GPU_MAT))
            CV_Error(Error::StsBadArg, "lidarsgm: the CUDA path needs cv::cuda::GpuMat inputs (left, right and sparse)");
        if (out.kind() != _InputArray::CUDA_GPU_MAT)
            CV_Error(Error::StsBadArg, "lidarsgm: the CUDA path writes a cv::cuda::GpuMat; pass one as the output");
        AutoLock lock(mutex_);
        const cuda::GpuMat L = left.getGpuMat(), R = right.getGpuMat();
        const cuda::GpuMat Sp = sparse.empty() ? cuda::GpuMat() : sparse.getGpuMat();
        checkStereoPairInfo(L.empty(), R.empty(), L.channels(), R.channels(), L.type(), R.type(), L.size(), R.size());
        const PipelineParams p = pipelineParams();
        const bool needSparse = semidenseOnly || p.mode != MODE_SGM || p.check == CHECK_CAMERA_LIDAR ||
                                p.check == CHECK_STEREO_LIDAR;
        if (needSparse && Sp.empty())
            CV_Error_(Error::StsBadArg, ("lidarsgm: the sparse disparity map is empty, but %s with consistency check %d needs it",
                                         semidenseOnly ? "semidensify" : modeName(p.mode), p.check));
        if (!Sp.empty())
            checkSparseInfo(Sp.type(), Sp.size(), L.size());

        cudaStream_t st = streamPtr ? cuda::StreamAccessor::getStream(*streamPtr) : 0;
        const bool capturing = orderAfterLastCall(st);
        const Size sz = L.size();
        namespace ci = cuda_impl;
        g_censusL_.create(sz, CV_32SC1);
        g_censusR_.create(sz, CV_32SC1);
        const bool u8 = L.depth() == CV_8U;
        ci::censusTransform(u8 ? ptr<uchar>(L) : cuda::PtrStepSz<uchar>(), u8 ? ptr<uchar>(R) : cuda::PtrStepSz<uchar>(),
                            u8 ? cuda::PtrStepSz<ushort>() : ptr<ushort>(L), u8 ? cuda::PtrStepSz<ushort>() : ptr<ushort>(R),
                            g_censusL_, g_censusR_, st);
        if (!Sp.empty())
        {
            g_sparse16_.create(sz, CV_16SC1);
            ci::convertSparse(Sp.depth() == CV_16U ? ptr<ushort>(Sp) : cuda::PtrStepSz<ushort>(),
                              Sp.depth() == CV_32F ? ptr<float>(Sp) : cuda::PtrStepSz<float>(),
                              p.minDisparity, p.numDisparities, g_sparse16_, st);
        }
        cuda::GpuMat prior;
        if (semidenseOnly || p.mode == MODE_SDSGM)
        {
            g_semidense16_.create(sz, CV_16SC1);
            ci::semidensify(g_censusL_, g_censusR_, g_sparse16_, p, g_semidense16_, st);
            prior = g_semidense16_;
        }
        else if (p.mode == MODE_DSGM)
            prior = g_sparse16_;

        out.create(sz, outputType_ == CV_16S ? CV_16SC1 : CV_32FC1);
        cuda::GpuMat o = out.getGpuMat();
        cuda::PtrStepSz<short> o16 = outputType_ == CV_16S ? ptr<short>(o) : cuda::PtrStepSz<short>();
        cuda::PtrStepSz<float> o32 = outputType_ == CV_32F ? ptr<float>(o) : cuda::PtrStepSz<float>();
        if (semidenseOnly)
        {
            ci::consistencyCheck(g_semidense16_, cuda::PtrStepSz<short>(), cuda::PtrStepSz<short>(),
                                 cuda::PtrStepSz<short>(), p, o16, o32, st);
            markCallEnd(st, capturing);
            return;
        }

        g_sum_.create(sz.height, sz.width * p.numDisparities, CV_16UC1);
        ci::aggregateCosts(g_censusL_, g_censusR_, ptr<short>(prior), p, g_sum_, st);
        g_disp16_.create(sz, CV_16SC1);
        g_dispInt_.create(sz, CV_16SC1);
        g_rightKey_.create(sz, CV_32SC1);
        g_dispRight_.create(sz, CV_16SC1);
        ci::winnerTakesAll(g_sum_, sz.width, p, g_disp16_, g_dispInt_, g_rightKey_, g_dispRight_, st);
        if (p.medianSize == 3)
        {
            g_med16_.create(sz, CV_16SC1);
            g_medInt_.create(sz, CV_16SC1);
            g_medRight_.create(sz, CV_16SC1);
            ci::MedianMaps maps = { { g_disp16_, g_dispInt_, g_dispRight_ }, { g_med16_, g_medInt_, g_medRight_ } };
            ci::medianFilter(maps, 3, st);
            ci::consistencyCheck(g_med16_, g_medInt_, g_medRight_, ptr<short>(g_sparse16_), p, o16, o32, st);
        }
        else
            ci::consistencyCheck(g_disp16_, g_dispInt_, g_dispRight_, ptr<short>(g_sparse16_), p, o16, o32, st);
        markCallEnd(st, capturing);
    }

    /* The work buffers are members, so a call must not start on the GPU before the previous call of this instance
    has finished with them. On the same stream that holds by stream order; on another stream the new stream first
    waits (on the GPU, not the host) for an event recorded at the end of the previous call. Inside a CUDA graph
    capture there is no event to wait for or record: a captured call must follow calls on the stream it captures
    (see the class documentation). Returns whether st is capturing. */
    bool orderAfterLastCall(cudaStream_t st)
    {
        cudaStreamCaptureStatus capture = cudaStreamCaptureStatusNone;
        cudaCheck(cudaStreamIsCapturing(st, &capture));
        const bool capturing = capture != cudaStreamCaptureStatusNone;
        if (g_done_ && st != g_lastStream_)
        {
            if (capturing)
                CV_Error(Error::StsBadArg, "lidarsgm: a call captured into a CUDA graph must follow this instance's "
                                           "previous call on the same stream (the work buffers are shared)");
            cudaCheck(cudaStreamWaitEvent(st, g_done_, 0));
        }
        return capturing;
    }

    void markCallEnd(cudaStream_t st, bool capturing)
    {
        g_lastStream_ = st;
        if (capturing)
            return;
        if (!g_done_)
            cudaCheck(cudaEventCreateWithFlags(&g_done_, cudaEventDisableTiming));
        cudaCheck(cudaEventRecord(g_done_, st));
    }
#else
    void runCuda(InputArray, InputArray, InputArray, OutputArray, cuda::Stream*, bool)
    {
        CV_Error(Error::GpuNotSupported, "lidarsgm: GpuMat input needs the CUDA path, but lidarsgm was built without CUDA");
    }
#endif

    int minDisparity_ = 0, numDisparities_ = 128, P1_ = 10, P2_ = 120, Q1_ = 5, Q2_ = 160;
    double alpha_ = 0.7, uniquenessRatio_ = 0.95;
    int lrMaxDiff_ = 1, numPaths_ = 8;
    bool subpixel_ = true;
    int rs_ = 6, Ts_ = 2, rc_ = 20;
    double Tc_ = 2.0;
    int mode_ = MODE_SDSGM, check_ = CHECK_STEREO_LIDAR, outputType_ = CV_16S, medianSize_ = 3;

    Mutex mutex_;
    Mat censusL_, censusR_, sparse16_, semidense16_, cost_, sum_, disp16_, dispInt_, dispRight_, med16_, medInt_, medRight_;
#ifdef HAVE_CUDA
    cuda::GpuMat g_censusL_, g_censusR_, g_sparse16_, g_semidense16_, g_sum_, g_disp16_, g_dispInt_, g_rightKey_,
                 g_dispRight_, g_med16_, g_medInt_, g_medRight_;
    cudaEvent_t g_done_ = nullptr;     //!< recorded at the end of the last call
    cudaStream_t g_lastStream_ = 0;    //!< the stream of the last call
#endif
};

Ptr<StereoLidarSGM> StereoLidarSGM::create(int minDisparity, int numDisparities, int P1, int P2, int Q1, int Q2,
                                           double alpha, int mode, int check)
{
    return makePtr<StereoLidarSGMImpl>(minDisparity, numDisparities, P1, P2, Q1, Q2, alpha, mode, check);
}

Ptr<StereoLidarSGM> StereoLidarSGM::load(const String& filename, const String& objname)
{
    return Algorithm::load<StereoLidarSGM>(filename, objname);
}

}} // namespace cv::lidarsgm

namespace cv { namespace cuda {

void computeStereoLidarSGM(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left, InputArray right,
                           InputArray sparseDisparity, OutputArray disparity, Stream& stream)
{
    CV_CheckFalse(matcher.empty(), "lidarsgm: the matcher is empty");
    matcher->compute(left, right, sparseDisparity, disparity, stream);
}

void semidensifyStereoLidarSGM(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left, InputArray right,
                               InputArray sparseDisparity, OutputArray semidense, Stream& stream)
{
    CV_CheckFalse(matcher.empty(), "lidarsgm: the matcher is empty");
    matcher->semidensify(left, right, sparseDisparity, semidense, stream);
}

}} // namespace cv::cuda
