// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// StereoLidarSGM: the parameters (one table), the input checks (once, for Mat and GpuMat alike), and the dispatch to
// the CPU pipeline (src/cpu_pipeline.cpp) or the CUDA pipeline (src_cuda/cuda_pipeline.cpp).

#include "precomp.hpp"
#include "pipeline.hpp"
#include "projection.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <algorithm>
#include <cctype>
#include <fstream>

namespace cv { namespace lidarsgm {

using namespace detail;

/* The parameters: C++ type, the name in getX/setX, the key in write()/read() and the member (key_), the default (the
paper's), the test a value must pass, the range as the error message states it, and what the parameter is. This
table makes the members, getters, setters, write() and read(); the public header documents each one. */
#define LIDARSGM_PARAMETERS(X) \
    X(int, MinDisparity, minDisparity, 0, v >= -1024 && v <= 1024, "in [-1024, 1024]", "the smallest disparity") \
    X(int, NumDisparities, numDisparities, 128, v >= 16 && v <= MAX_DISPARITIES && v % 16 == 0, \
      "a multiple of 16 in [16, 512]", \
      "the number of disparities") \
    X(int, P1, P1, 10, v >= 0 && v <= 1000, "in [0, 1000]", "the penalty of a disparity step of 1") \
    X(int, P2, P2, 120, v >= 0 && v <= 1000, "in [0, 1000]", "the penalty of larger steps") \
    X(int, Q1, Q1, 5, v >= 0 && v <= 1000, "in [0, 1000]", "the DDC penalty for |d - sparse| = 1") \
    X(int, Q2, Q2, 160, v >= 0 && v <= 1000, "in [0, 1000]", "the DDC penalty for |d - sparse| > 1") \
    X(double, Alpha, alpha, 0.7, v >= 0.0 && v <= 1.0, "in [0, 1] (and not NaN)", "the weight of DDC") \
    X(double, UniquenessRatio, uniquenessRatio, 0.95, v > 0.0 && v <= 1.0, "in (0, 1] (1 disables the check)", \
      "the uniqueness ratio") \
    X(int, LRMaxDiff, lrMaxDiff, 1, v >= 0 && v <= 16, "in [0, 16]", "the left-right tolerance") \
    X(int, NumPaths, numPaths, 8, v == 4 || v == 8, "4 or 8", "the number of aggregation paths") \
    X(bool, Subpixel, subpixel, true, true, "", "the parabola fit") \
    X(int, SemidenseRadius, semidenseRadius, 6, v >= 0 && v <= 32, "in [0, 32]", "rs, the semidensification radius") \
    X(int, SemidenseThreshold, semidenseThreshold, 2, v >= 0 && v <= 32, "in [0, 32]", \
      "Ts, the semidensification threshold") \
    X(int, CheckRadius, checkRadius, 20, v >= 0 && v <= 64, "in [0, 64]", "rc, the consistency-check radius") \
    X(double, CheckThreshold, checkThreshold, 2.0, v >= 0.0 && v <= 64.0, "in [0, 64] pixels (and not NaN)", \
      "Tc, the consistency-check threshold") \
    X(int, MedianSize, medianSize, 3, v == 1 || v == 3, "1 (off) or 3 (3x3 median)", "the median filter") \
    X(int, VisibilityRadiusX, visibilityRadiusX, 0, v >= 0 && v <= 16, "in [0, 16]", \
      "the visibility filter's half width") \
    X(int, VisibilityRadiusY, visibilityRadiusY, 0, v >= 0 && v <= 16, "in [0, 16]", \
      "the visibility filter's half height") \
    X(double, VisibilityParallax, visibilityParallax, 0.0, v >= 0.0 && v <= 1.0, "in [0, 1] (and not NaN)", \
      "the visibility window's growth per pixel of disparity step") \
    X(int, EdgeThreshold, edgeThreshold, 0, v >= 0 && v <= 65535, "in [0, 65535] (0: off)", \
      "the left-image step that makes a disparity jump cheaper") \
    X(double, EdgeP2Ratio, edgeP2Ratio, 0.5, v > 0.0 && v <= 1.0, "in (0, 1]", "P2's factor across an image edge") \
    X(double, RingGapFactor, ringGapFactor, 0.0, v >= 0.0 && v <= 16.0, "in [0, 16] (0: off; and not NaN)", \
      "the ring interpolation's longest gap in ring spacings") \
    X(double, SemidenseWeight, semidenseWeight, 1.0, v > 0.0 && v <= 1.0, "in (0, 1]", \
      "the DDC weight of copied priors on LiDAR scans") \
    X(int, SearchWindow, searchWindow, 0, v >= 0 && v <= MAX_DISPARITIES, "in [0, 512] (0: off)", \
      "the disparity windows' margin") \
    X(int, Mode, mode, MODE_SDSGM, v == MODE_SGM || v == MODE_DSGM || v == MODE_SDSGM, \
      "MODE_SGM (0), MODE_DSGM (1) or MODE_SDSGM (2)", "the fusion mode") \
    X(int, ConsistencyCheck, consistencyCheck, CHECK_STEREO_LIDAR, v >= CHECK_NONE && v <= CHECK_STEREO_LIDAR, \
      "CHECK_NONE (0), CHECK_STEREO (1), CHECK_CAMERA_LIDAR (2) or CHECK_STEREO_LIDAR (3)", "the consistency check") \
    X(int, OutputType, outputType, CV_16S, v == CV_16S || v == CV_32F, "CV_16S or CV_32F", "the output type")

namespace {

void rejectValue(const char* key, const char* what, const char* range, double v)
{
    LIDARSGM_Error_(Error::StsOutOfRange, ("lidarsgm: %s (%s) must be %s; got %g", key, what, range, v));
}

void writeValue(FileStorage& fs, const char* key, int v) { fs << key << v; }
void writeValue(FileStorage& fs, const char* key, double v) { fs << key << v; }
void writeValue(FileStorage& fs, const char* key, bool v) { fs << key << (int)v; }
int readValue(const FileNode& fn, const char* key, int def) { return fn[key].empty() ? def : (int)fn[key]; }
double readValue(const FileNode& fn, const char* key, double def) { return fn[key].empty() ? def : (double)fn[key]; }
bool readValue(const FileNode& fn, const char* key, bool def) { return fn[key].empty() ? def : (int)fn[key] != 0; }

const char* modeName(int mode)
{
    return mode == StereoLidarSGM::MODE_SGM ? "MODE_SGM" : mode == StereoLidarSGM::MODE_DSGM ? "MODE_DSGM" : "MODE_SDSGM";
}

const char* checkName(int check)
{
    static const char* names[] = { "CHECK_NONE", "CHECK_STEREO", "CHECK_CAMERA_LIDAR", "CHECK_STEREO_LIDAR" };
    return names[check];
}

//! The keys write() writes: read() refuses any other (a misspelt key would leave its parameter silently as it was).
const std::vector<String>& knownKeys()
{
    static const std::vector<String> keys = {
        "format", "name",
#define LIDARSGM_KEY(type, Name, key, def, valid, range, what) #key,
        LIDARSGM_PARAMETERS(LIDARSGM_KEY)
#undef LIDARSGM_KEY
    };
    return keys;
}

} // namespace

namespace detail {

static int editDistance(const String& a, const String& b)
{
    std::vector<int> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); j++)
        row[j] = (int)j;
    for (size_t i = 1; i <= a.size(); i++)
    {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= b.size(); j++)
        {
            const int up = row[j];
            const bool same = std::tolower((unsigned char)a[i - 1]) == std::tolower((unsigned char)b[j - 1]);
            row[j] = std::min(std::min(row[j] + 1, row[j - 1] + 1), diag + (same ? 0 : 1));
            diag = up;
        }
    }
    return row[b.size()];
}

//! Letters that a and b share from their start, case ignored.
static size_t commonPrefix(const String& a, const String& b)
{
    size_t i = 0;
    while (i < a.size() && i < b.size() && std::tolower((unsigned char)a[i]) == std::tolower((unsigned char)b[i]))
        i++;
    return i;
}

String nearestName(const String& key, const std::vector<String>& names)
{
    // Between names as near, the one that starts as key does: a misspelling seldom begins at the first letter
    // (numDisparity is 3 edits from both minDisparity and numDisparities).
    String best;
    int bestDistance = INT_MAX;
    size_t bestPrefix = 0;
    for (const String& n : names)
    {
        const int d = editDistance(key, n);
        const size_t prefix = commonPrefix(key, n);
        if (d < bestDistance || (d == bestDistance && prefix > bestPrefix))
        {
            bestDistance = d;
            bestPrefix = prefix;
            best = n;
        }
    }
    return best;
}

String withoutModulePrefix(const String& message)
{
    static const String prefix = "lidarsgm: ";
    return message.compare(0, prefix.size(), prefix) == 0 ? message.substr(prefix.size()) : message;
}

String parserMessage(const cv::Exception& e)
{
    return e.code == Error::StsParseError && e.func.find("): ") != String::npos ? e.func : e.err;
}

void refuseUnknownKeys(const FileNode& node, const std::vector<String>& known, const String& what)
{
    for (const String& key : node.keys())
        if (std::find(known.begin(), known.end(), key) == known.end())
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: unknown key '" + key + "' in " + what + " (did you mean '" +
                                                 nearestName(key, known) + "'?)");
}


bool checkInputs(InputArray left, InputArray right, InputArray sparse, OutputArray out, bool needSparse,
                 const char* needer)
{
    const bool gpu = left.kind() == _InputArray::CUDA_GPU_MAT || right.kind() == _InputArray::CUDA_GPU_MAT ||
                     sparse.kind() == _InputArray::CUDA_GPU_MAT;
    if (gpu && (left.kind() != _InputArray::CUDA_GPU_MAT || right.kind() != _InputArray::CUDA_GPU_MAT ||
                (!sparse.empty() && sparse.kind() != _InputArray::CUDA_GPU_MAT)))
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm: the CUDA path needs cv::cuda::GpuMat inputs (left, right and sparse)");
    if (gpu && out.kind() != _InputArray::CUDA_GPU_MAT)
        LIDARSGM_Error(Error::StsBadArg, "lidarsgm: the CUDA path writes a cv::cuda::GpuMat; pass one as the output");
    LIDARSGM_Check(!left.empty(), "lidarsgm: the left image is empty");
    LIDARSGM_Check(!right.empty(), "lidarsgm: the right image is empty");
    const int typeL = left.type(), typeR = right.type();
    if (CV_MAT_CN(typeL) != 1 || CV_MAT_CN(typeR) != 1)
        LIDARSGM_Error_(Error::BadNumChannels,
                        ("lidarsgm: the images must be single-channel (grey); got %d and %d channels. "
                         "Convert colour images with cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY)", CV_MAT_CN(typeL),
                         CV_MAT_CN(typeR)));
    if (CV_MAT_DEPTH(typeL) != CV_8U && CV_MAT_DEPTH(typeL) != CV_16U)
        LIDARSGM_Error_(Error::BadDepth, ("lidarsgm: the images must be CV_8UC1 or CV_16UC1; the left image is %s",
                                          typeToString(typeL).c_str()));
    if (typeL != typeR)
        LIDARSGM_Error_(Error::StsUnmatchedFormats, ("lidarsgm: left and right images differ in type (%s vs %s)",
                                                     typeToString(typeL).c_str(), typeToString(typeR).c_str()));
    const Size sz = left.size();
    if (sz != right.size())
        LIDARSGM_Error_(Error::StsUnmatchedSizes, ("lidarsgm: left and right images differ in size (%dx%d vs %dx%d)",
                                                   sz.width, sz.height, right.size().width, right.size().height));
    if (needSparse && sparse.empty())
        LIDARSGM_Error_(Error::StsBadArg, ("lidarsgm: %s needs the LiDAR's sparse disparity map, but it is empty: pass "
                                           "the LiDAR's disparities (projectPointsToDisparity), or for stereo alone "
                                           "use MODE_SGM with CHECK_STEREO", needer));
    if (!sparse.empty())
    {
        const int type = sparse.type();
        if (type != CV_16UC1 && type != CV_32FC1)
            LIDARSGM_Error_(Error::StsUnsupportedFormat,
                            ("lidarsgm: the sparse disparity map must be CV_16UC1 (KITTI, value / 256) or CV_32FC1 (pixels); "
                             "got %s: convert it first (C++: sparse.convertTo(sparse32f, CV_32F); numpy: "
                             "sparse.astype(numpy.float32))", typeToString(type).c_str()));
        if (sparse.size() != sz)
            LIDARSGM_Error_(Error::StsUnmatchedSizes, ("lidarsgm: the sparse disparity map is %dx%d but the images are %dx%d",
                                                       sparse.size().width, sparse.size().height, sz.width, sz.height));
    }
    return gpu;
}

} // namespace detail

class StereoLidarSGMImpl CV_FINAL : public StereoLidarSGM
{
public:
    //! Every parameter, in the table's order: what create() takes.
    StereoLidarSGMImpl(
#define LIDARSGM_ARG(type, Name, key, def, valid, range, what) type key,
        LIDARSGM_PARAMETERS(LIDARSGM_ARG)
#undef LIDARSGM_ARG
        bool /*end of the list*/)
    {
#define LIDARSGM_SET(type, Name, key, def, valid, range, what) set##Name(key);
        LIDARSGM_PARAMETERS(LIDARSGM_SET)
#undef LIDARSGM_SET
        checkRelations();
    }

    void compute(InputArray left, InputArray right, InputArray sparse, OutputArray disparity) CV_OVERRIDE
    {
        run(left, right, sparse, disparity, nullptr, false);
    }
    void compute(InputArray left, InputArray right, InputArray sparse, OutputArray disparity,
                 cuda::Stream& stream) CV_OVERRIDE
    {
        run(left, right, sparse, disparity, &stream, false);
    }
    void compute(InputArray left, InputArray right, InputArray sparse, OutputArray disparity,
                 OutputArray confidence) CV_OVERRIDE
    {
        run(left, right, sparse, disparity, nullptr, false, confidence);
    }
    void compute(InputArray left, InputArray right, InputArray sparse, OutputArray disparity, OutputArray confidence,
                 cuda::Stream& stream) CV_OVERRIDE
    {
        run(left, right, sparse, disparity, &stream, false, confidence);
    }
    void semidensify(InputArray left, InputArray right, InputArray sparse, OutputArray semidense) CV_OVERRIDE
    {
        run(left, right, sparse, semidense, nullptr, true);
    }
    void semidensify(InputArray left, InputArray right, InputArray sparse, OutputArray semidense,
                     cuda::Stream& stream) CV_OVERRIDE
    {
        run(left, right, sparse, semidense, &stream, true);
    }

#define LIDARSGM_ACCESSORS(type, Name, key, def, valid, range, what) \
    type get##Name() const CV_OVERRIDE { return key##_; } \
    void set##Name(type v) CV_OVERRIDE \
    { \
        if (!(valid)) \
            rejectValue(#key, what, range, (double)v); \
        key##_ = v; \
    }
    LIDARSGM_PARAMETERS(LIDARSGM_ACCESSORS)
#undef LIDARSGM_ACCESSORS

    double getSearchedFraction() const CV_OVERRIDE
    {
        AutoLock lock(mutex_);
        return lastGpu_ ? gpu_.searchedFraction() : cpu_.searchedFraction();
    }

    // A FileStorage key: letters, digits and '_' only.
    String getDefaultName() const CV_OVERRIDE { return "lidarsgm_StereoLidarSGM"; }

    void write(FileStorage& fs) const CV_OVERRIDE
    {
        writeFormat(fs);
        fs << "name" << getDefaultName();
#define LIDARSGM_WRITE(type, Name, key, def, valid, range, what) writeValue(fs, #key, key##_);
        LIDARSGM_PARAMETERS(LIDARSGM_WRITE)
#undef LIDARSGM_WRITE
    }

    /** Keys missing from the node keep their values; every value read goes through its setter's check; a key that
    write() does not write is refused, naming the nearest known one. */
    void read(const FileNode& fn) CV_OVERRIDE
    {
        if (!fn.isMap())
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: the parameters must be a map of keys and values (as save() "
                                             "writes them)");
        detail::refuseUnknownKeys(fn, knownKeys(), "the matcher's parameters");
        FileNode name = fn["name"];
        LIDARSGM_Check(name.empty() || (String)name == getDefaultName(),
                       "lidarsgm: the file node does not hold a lidarsgm_StereoLidarSGM");
#define LIDARSGM_READ(type, Name, key, def, valid, range, what) set##Name(readValue(fn, #key, key##_));
        LIDARSGM_PARAMETERS(LIDARSGM_READ)
#undef LIDARSGM_READ
        checkRelations();
    }

    /** The parameters as the stages take them (validated and converted to integers); also for the per-stage tests
    (pipelineParamsOf). */
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
        p.semidenseRadius = semidenseRadius_;
        p.semidenseThreshold = semidenseThreshold_;
        p.checkRadius = checkRadius_;
        p.checkThreshold16 = cvRound(checkThreshold_ * 16);
        p.medianSize = medianSize_;
        p.visibilityRadiusX = visibilityRadiusX_;
        p.visibilityRadiusY = visibilityRadiusY_;
        p.visibilityParallax256 = cvRound(visibilityParallax_ * 256);
        p.semidense = mode_ == MODE_SDSGM;
        p.ddc = mode_ != MODE_SGM;
        p.stereoCheck = consistencyCheck_ == CHECK_STEREO || consistencyCheck_ == CHECK_STEREO_LIDAR;
        p.lidarCheck = consistencyCheck_ == CHECK_CAMERA_LIDAR || consistencyCheck_ == CHECK_STEREO_LIDAR;
        p.floatOutput = outputType_ == CV_32F;
        p.edgeThreshold = edgeThreshold_;
        p.ringGapFactor16 = cvRound(ringGapFactor_ * 16);
        p.w = computeCostWeights(P1_, P2_, Q1_, Q2_, alpha_, numPaths_, p.ddc, edgeP2Ratio_);
        p.weighCopies = p.semidense && semidenseWeight_ < 1.0;
        p.wCopy = scaleDdcWeights(p.w, alpha_, Q1_, Q2_, semidenseWeight_);
        p.confidence = false;
        p.searchWindow = searchWindow_;
        return p;
    }

private:
    //! Constraints between parameters, checked when they are used (setters may be called in any order).
    void checkRelations() const
    {
        if (P1_ > P2_)
            LIDARSGM_Error_(Error::StsOutOfRange, ("lidarsgm: P1 (%d) must not exceed P2 (%d)", P1_, P2_));
        if (Q1_ > Q2_)
            LIDARSGM_Error_(Error::StsOutOfRange, ("lidarsgm: Q1 (%d) must not exceed Q2 (%d)", Q1_, Q2_));
    }

    /* Every entry point: checks, then one backend. One call at a time per instance (the backends' work buffers are
    members). stream == nullptr: the caller gave none (the default stream on the GPU). */
    void run(InputArray left, InputArray right, InputArray sparse, OutputArray out, cuda::Stream* stream,
             bool semidenseOnly, OutputArray confidence = noArray())
    {
        CV_INSTRUMENT_REGION();
        PipelineParams p = pipelineParams();
        p.confidence = confidence.needed();
        const bool needSparse = semidenseOnly || p.ddc || p.lidarCheck;
        const String needer = semidenseOnly ? String("semidensify")
                                            : format("%s with %s", modeName(mode_), checkName(consistencyCheck_));
        const bool gpu = detail::checkInputs(left, right, sparse, out, needSparse, needer.c_str());
        if (p.confidence && gpu != (confidence.kind() == _InputArray::CUDA_GPU_MAT))
            LIDARSGM_Error(Error::StsBadArg, gpu ? "lidarsgm: the CUDA path writes the confidence to a cv::cuda::GpuMat; "
                                                   "pass one"
                                                 : "lidarsgm: cv::Mat inputs give the confidence in a cv::Mat; pass one");
        if (!gpu && stream)
            LIDARSGM_Error(Error::StsBadArg, "lidarsgm: the Stream overloads take cv::cuda::GpuMat inputs");
        AutoLock lock(mutex_);
        if (!semidenseOnly)
            lastGpu_ = gpu;
        if (gpu)
            gpu_.run(left.getGpuMat(), right.getGpuMat(), sparse.empty() ? cuda::GpuMat() : sparse.getGpuMat(), p,
                     semidenseOnly, out, stream, unitsWarned_, confidence);
        else
            cpu_.run(left.getMat(), right.getMat(), sparse.getMat(), p, semidenseOnly, out, unitsWarned_, confidence);
    }

#define LIDARSGM_MEMBER(type, Name, key, def, valid, range, what) type key##_ = def;
    LIDARSGM_PARAMETERS(LIDARSGM_MEMBER)
#undef LIDARSGM_MEMBER

    mutable Mutex mutex_;
    bool lastGpu_ = false;   //!< the last compute() ran on the CUDA path (getSearchedFraction)
    bool unitsWarned_ = false;   //!< the units check has said that a map had no value in range (once per matcher)
    CpuPipeline cpu_;
    CudaPipeline gpu_;
};

Ptr<StereoLidarSGM> StereoLidarSGM::create(int minDisparity, int numDisparities, int P1, int P2, int Q1, int Q2,
                                           double alpha, int mode, int check, double uniquenessRatio, int LRMaxDiff,
                                           int numPaths, bool subpixel, int semidenseRadius, int semidenseThreshold,
                                           int checkRadius, double checkThreshold, int medianSize,
                                           int visibilityRadiusX, int visibilityRadiusY, double visibilityParallax,
                                           int edgeThreshold, double edgeP2Ratio, double ringGapFactor,
                                           double semidenseWeight, int searchWindow, int outputType)
{
    // In the table's order (LIDARSGM_PARAMETERS).
    return makePtr<StereoLidarSGMImpl>(minDisparity, numDisparities, P1, P2, Q1, Q2, alpha, uniquenessRatio, LRMaxDiff,
                                       numPaths, subpixel, semidenseRadius, semidenseThreshold, checkRadius,
                                       checkThreshold, medianSize, visibilityRadiusX, visibilityRadiusY,
                                       visibilityParallax, edgeThreshold, edgeP2Ratio, ringGapFactor, semidenseWeight,
                                       searchWindow, mode, check, outputType, true);
}

Ptr<StereoLidarSGM> StereoLidarSGM::load(const String& filename, const String& objname)
{
    if (!utils::fs::exists(filename))
        LIDARSGM_Error(Error::StsObjectNotFound, "lidarsgm: the parameter file " + filename + " does not exist");
    FileStorage fs;
    try
    {
        fs.open(filename, FileStorage::READ);
    }
    catch (const cv::Exception& e)   // the parser's message names the line
    {
        // OpenCV's YAML parser needs the version line that save() writes first.
        const size_t dot = filename.rfind('.');
        const String ext = dot == String::npos ? String() : filename.substr(dot + 1);
        String first;
        std::getline(std::ifstream(filename), first);
        const bool noHeader = (ext == "yml" || ext == "yaml") && first.compare(0, 5, "%YAML") != 0;
        LIDARSGM_Error(Error::StsParseError, "lidarsgm: the parameter file " + filename + " cannot be parsed: " +
                                             parserMessage(e) +
                                             (noHeader ? " (a YAML file starts with the line %YAML:1.0, as save() "
                                                         "writes it)"
                                                       : ""));
    }
    if (!fs.isOpened())
        LIDARSGM_Error(Error::StsParseError, "lidarsgm: the parameter file " + filename + " cannot be read as YAML, XML "
                                             "or JSON (write it with StereoLidarSGM::save)");
    const FileNode fn = objname.empty() ? fs.getFirstTopLevelNode() : fs[objname];
    if (fn.empty())
        LIDARSGM_Error(Error::StsParseError, "lidarsgm: the parameter file " + filename + " holds no " +
                                             (objname.empty() ? String("parameters") : "node " + objname));
    if (objname.empty() && !fn.isMap())
        LIDARSGM_Error(Error::StsParseError, "lidarsgm: the parameter file " + filename + " has its keys at the top "
                                             "level: they go under a node lidarsgm_StereoLidarSGM: (as save() "
                                             "writes them)");
    Ptr<StereoLidarSGM> m = create();
    try
    {
        m->read(fn);
    }
    catch (const cv::Exception& e)
    {
        // The file goes in front of what the setters and read() say.
        LIDARSGM_Error(e.code, "lidarsgm: " + filename + ": " + withoutModulePrefix(e.err));
    }
    return m;
}

namespace detail {

void copySettings(const StereoLidarSGM& from, StereoLidarSGM& to)
{
#define LIDARSGM_COPY(type, Name, key, def, valid, range, what) to.set##Name(from.get##Name());
    LIDARSGM_PARAMETERS(LIDARSGM_COPY)
#undef LIDARSGM_COPY
}

PipelineParams pipelineParamsOf(const StereoLidarSGM& matcher)
{
    const StereoLidarSGMImpl* impl = dynamic_cast<const StereoLidarSGMImpl*>(&matcher);
    CV_Assert(impl);
    return impl->pipelineParams();
}

} // namespace detail

}} // namespace cv::lidarsgm

namespace cv { namespace cuda {

void computeStereoLidarSGM(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left, InputArray right,
                           InputArray sparseDisparity, OutputArray disparity, Stream& stream)
{
    LIDARSGM_Check(!matcher.empty(), "lidarsgm: the matcher is empty");
    matcher->compute(left, right, sparseDisparity, disparity, stream);
}

void computeStereoLidarSGMWithConfidence(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left,
                                         InputArray right, InputArray sparseDisparity, OutputArray disparity,
                                         OutputArray confidence, Stream& stream)
{
    LIDARSGM_Check(!matcher.empty(), "lidarsgm: the matcher is empty");
    matcher->compute(left, right, sparseDisparity, disparity, confidence, stream);
}

void semidensifyStereoLidarSGM(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left, InputArray right,
                               InputArray sparseDisparity, OutputArray semidense, Stream& stream)
{
    LIDARSGM_Check(!matcher.empty(), "lidarsgm: the matcher is empty");
    matcher->semidensify(left, right, sparseDisparity, semidense, stream);
}

}} // namespace cv::cuda
