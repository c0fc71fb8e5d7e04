// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The tool's options, declared once (kOptions: name, kind of value, help, matcher parameter), their parsing and
// checks, and the matcher they describe.

#include "tool.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <cstdio>
#include <cstdlib>
#include <climits>
#include <sstream>

using namespace cv;

namespace lidarsgm_fuse {

namespace {

//! type: 's' text, 'i' integer, 'd' number, 'f' flag (no value). param: the matcher's key in write()/read().
struct OptionSpec
{
    const char* name;
    char type;
    const char* value;
    const char* help;
    const char* param;
};

const OptionSpec kOptions[] = {
    { nullptr, 0, nullptr, "Inputs (one of):", nullptr },
    { "kitti-frame", 's', "DIR", "a KITTI-layout folder: image_2/ID_10.png, image_3/ID_10.png, velodyne/ID.bin,\n"
      "calib.txt, optional disp_occ_0/ID_10.png (ground truth); with --id", nullptr },
    { "id", 's', "ID", "the frame of --kitti-frame (default 000002)", nullptr },
    { "left", 's', "L", "left image (with --right and --sparse, or --velodyne and --calib)", nullptr },
    { "right", 's', "R", "right image", nullptr },
    { "sparse", 's', "S", "sparse disparity: PNG (uint16, value / 256) or .exr/.pfm float", nullptr },
    { "velodyne", 's', "V", "raw Velodyne scan (float32 x y z r), projected with --calib", nullptr },
    { "calib", 's', "C", "KITTI calibration file (P2, P3, R0_rect, Tr_velo_to_cam); with --sparse only for\n"
      "--format depth / ply", nullptr },
    { "rig", 's', "FILE", "your own rig (cv::lidarsgm::StereoRig::fromFile: stereoCalibrate's M1 D1 M2 D2 R T,\n"
      "optional R1 R2 P1 P2, image_width, image_height, lidar_to_left): --left/--right are raw images,\n"
      "rectified first; --points the cloud; outputs in the rectified left view", nullptr },
    { "points", 's', "P", "LiDAR cloud of a single frame: .pcd, .ply or KITTI .bin (with --rig or --calib)", nullptr },
    { "gt", 's', "G", "ground truth of a single frame (KITTI 16-bit PNG)", nullptr },
    { "kitti", 's', "DIR", "every frame of DIR/frames.txt, scored with the KITTI devkit's rules", nullptr },
    { "kitti-raw", 's', "DRIVE", "every frame of a KITTI raw drive in order (DRIVE = <date>/<date>_drive_<n>_sync:\n"
      "image_02/data, image_03/data, velodyne_points/data; calibration from <date>/calib_cam_to_cam.txt\n"
      "and <date>/calib_velo_to_cam.txt); no ground truth needed", nullptr },
    { "rig-folder", 's', "DIR", "every frame of your own rig's recording: DIR/rig.yml (as --rig), DIR/left/NAME.png,\n"
      "DIR/right/NAME.png, DIR/points/NAME.pcd|.ply|.bin, optional DIR/gt/NAME.png (KITTI disparity PNG in the\n"
      "rectified left view); NAME in sorted order", nullptr },
    { "gt-depth", 's', "DIR", "(--kitti-raw) ground truth as KITTI depth PNGs DIR/<frame>.png (metres x 256, e.g.\n"
      "the depth-completion set's proj_depth/groundtruth/image_02): scored as disparity fB / depth", nullptr },
    { "middlebury", 's', "DIR", "every scene folder of DIR, 1 % of its ground truth as the sparse input", nullptr },
    { nullptr, 0, nullptr, "Outputs:", nullptr },
    { "out", 's', "DIR", "write per frame (folder runs: DIR/<frame>/): disparity[_mode].png|.pfm|.s16,\n"
      "disparity[_mode]_color.png, error[_mode].png (with ground truth), semidense.png and\n"
      "semidense_color.png (SDSGM), lidar_points.png", nullptr },
    { "format", 's', "LIST", "output formats, comma list of kitti (16-bit PNG, d * 256, 0 = invalid), pfm (float,\n"
      "invalid = inf), s16 (the matcher's CV_16S x16, little-endian, no header), depth\n"
      "(depth[_mode].png: KITTI depth, uint16 metres x 256, 0 = none), ply (points[_mode].ply:\n"
      "binary PLY, x y z metres in the left camera frame and the left image's colour, one vertex\n"
      "per valid pixel), confidence (confidence[_mode].png: uint16, the confidence map x 65535, 0 =\n"
      "no disparity; KITTI inputs; with ground truth the run also prints its sparsification\n"
      "figures); default kitti. depth and ply need a calibration (KITTI inputs, --calib)", nullptr },
    { "quiet", 'i', "1", "no progress line on folder runs", nullptr },
    { "resume", 'f', nullptr, "(KITTI folder with --out) take the frames whose outputs are complete (their\n"
      "metrics.yml, written last) from the earlier run instead of computing them again", nullptr },
    { nullptr, 0, nullptr, "What runs:", nullptr },
    { "modes", 's', "LIST", "comma list of sgm, dsgm, sdsgm (default: sdsgm for a frame, all for a folder)", nullptr },
    { "check", 's', "C", "none | stereo | camera-lidar | stereo-lidar (default stereo-lidar)", nullptr },
    { "table5", 'f', nullptr, "also run SDSGM with each consistency check (the paper's Table V)", nullptr },
    { "lidar-lines", 's', "LIST", "LiDAR line counts, comma list of 64, 32, 16 (default 64): every 2nd / 4th ring of\n"
      "the 64-line scans (the paper's Table VI); a folder run prints one table per count", nullptr },
    { "lidar-ring-offset", 'i', "K", "with --lidar-lines: the first ring kept, counted from the top, modulo the 2 or 4\n"
      "(default 0: the top ring; 3 keeps the lowest ring at 16 lines)", nullptr },
    { "trust-lidar", 'f', nullptr, "fuse every frame with its LiDAR; by default a frame whose LiDAR lands misplaced on\n"
      "its images (cv::lidarsgm::checkLidar: the matching residual above 1 px and lowered by a\n"
      "fifth when the points are moved together: a LiDAR-to-camera transform that is off) is\n"
      "fused as stereo alone, and the run says so per frame", nullptr },
    { "check-calibration", 'f', nullptr, "(KITTI folder, raw drive) print the calibration residual: the median\n"
      "|LiDAR disparity - stereo disparity| over the LiDAR points (cv::lidarsgm::LidarCalibration)", nullptr },
    { "refine-calibration", 'f', nullptr, "(KITTI folder, raw drive) estimate the LiDAR-to-camera rotation's\n"
      "correction from the run's frames (a raw drive: 20 frames spread over it), print it with\n"
      "its standard errors and the residual before and after, and fuse with the corrected transform", nullptr },
    { "scan-rate", 'd', "HZ", "with --check-calibration / --refine-calibration: the LiDAR's sweep rate for scans\n"
      "that are not motion-compensated (default 10: KITTI's HDL-64E; 0: compensated scans)", nullptr },
    { "refine-translation", 'f', nullptr, "with --refine-calibration: also estimate the translation along the\n"
      "camera's x axis", nullptr },
    { "params", 's', "FILE", "matcher parameters saved with StereoLidarSGM::save (e.g. doc/params/kitti_best.yml);\n"
      "the parameter options below override it", nullptr },
    { "seed", 'i', "N", "random seed of the Middlebury sampling (default 1)", nullptr },
    { "bad", 'd', "N", "Middlebury error threshold in pixels (default 2: bad-2)", nullptr },
    { "timing", 'i', "N", "time N runs and compare with OpenCV's matchers in the same process (CPU: every\n"
      "cv::StereoSGBM mode; with --cuda: cv::cuda::StereoSGM, CUDA events, device memory)", nullptr },
    { "cuda", 'i', "1", "run on the GPU (GpuMat in and out)", nullptr },
    { "threads", 'i', "N", "cv::setNumThreads", nullptr },
    { "streams", 'i', "N", "(KITTI folder) N workers fuse frames at once, each on its own thread with its own\n"
      "matchers (with --cuda: own CUDA stream, page-locked buffers); default 1", nullptr },
    { "resize", 's', "WxH", "(speed runs) scale the frame to W x H first", nullptr },
    { "rounds", 'i', "N", "(GPU timing) repeat the timing table N times, to show the spread", nullptr },
    { nullptr, 0, nullptr, "Matcher parameters (StereoLidarSGM's; default: the paper's, or --params):", nullptr },
    { "num-disparities", 'i', "N", "numDisparities (Middlebury default: the scene's range)", "numDisparities" },
    { "min-disparity", 'i', "N", "minDisparity", "minDisparity" },
    { "P1", 'i', "N", "P1", "P1" },
    { "P2", 'i', "N", "P2", "P2" },
    { "Q1", 'i', "N", "Q1", "Q1" },
    { "Q2", 'i', "N", "Q2", "Q2" },
    { "alpha", 'd', "A", "alpha", "alpha" },
    { "uniqueness", 'd', "U", "uniquenessRatio", "uniquenessRatio" },
    { "lr-max-diff", 'i', "N", "LRMaxDiff", "lrMaxDiff" },
    { "paths", 'i', "4|8", "numPaths", "numPaths" },
    { "subpixel", 'i', "0|1", "subpixel", "subpixel" },
    { "rs", 'i', "N", "semidenseRadius", "semidenseRadius" },
    { "Ts", 'i', "N", "semidenseThreshold", "semidenseThreshold" },
    { "rc", 'i', "N", "checkRadius", "checkRadius" },
    { "Tc", 'd', "T", "checkThreshold", "checkThreshold" },
    { "median-size", 'i', "1|3", "medianSize", "medianSize" },
    { "visibility-rx", 'i', "N", "visibilityRadiusX", "visibilityRadiusX" },
    { "visibility-ry", 'i', "N", "visibilityRadiusY", "visibilityRadiusY" },
    { "visibility-parallax", 'd', "R", "visibilityParallax", "visibilityParallax" },
    { "edge-threshold", 'i', "N", "edgeThreshold", "edgeThreshold" },
    { "edge-p2-ratio", 'd', "R", "edgeP2Ratio", "edgeP2Ratio" },
    { "ring-gap-factor", 'd', "F", "ringGapFactor", "ringGapFactor" },
    { "semidense-weight", 'd', "F", "semidenseWeight", "semidenseWeight" },
    { "search-window", 'i', "N", "searchWindow", "searchWindow" },
};

const OptionSpec* findOption(const std::string& name)
{
    for (const OptionSpec& s : kOptions)
        if (s.name && name == s.name)
            return &s;
    return nullptr;
}

} // namespace

std::string Options::str(const std::string& k, const std::string& def) const
{
    auto it = kv.find(k);
    return it == kv.end() ? def : it->second;
}

int Options::i(const std::string& k, int def) const
{
    if (!has(k))
        return def;
    char* end = nullptr;
    const std::string v = str(k);
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || x < INT_MIN || x > INT_MAX)
        CV_Error(Error::StsBadArg, "--" + k + " takes an integer, got '" + v + "'");
    return (int)x;
}

double Options::d(const std::string& k, double def) const
{
    if (!has(k))
        return def;
    char* end = nullptr;
    const std::string v = str(k);
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0')
        CV_Error(Error::StsBadArg, "--" + k + " takes a number, got '" + v + "'");
    return x;
}

std::vector<std::string> Options::list(const std::string& k, const std::string& def) const
{
    std::vector<std::string> out;
    std::stringstream ss(str(k, def));
    std::string t;
    while (std::getline(ss, t, ','))
        if (!t.empty())
            out.push_back(t);
    return out;
}

int parseCommandLine(int argc, char** argv, Options& o, bool& help)
{
    help = false;
    for (int i = 1; i < argc; i++)
    {
        std::string a = argv[i];
        if (a == "--help" || a == "-h")
        {
            help = true;
            return 0;
        }
        if (a.size() < 3 || a.compare(0, 2, "--") != 0)
        {
            fprintf(stderr, "lidarsgm_fuse: unexpected argument '%s' (see --help)\n", a.c_str());
            return 2;
        }
        a = a.substr(2);
        const OptionSpec* s = findOption(a);
        if (!s)
        {
            fprintf(stderr, "lidarsgm_fuse: unknown option --%s (see --help)\n", a.c_str());
            return 2;
        }
        if (s->type != 'f' && i + 1 >= argc)
        {
            fprintf(stderr, "lidarsgm_fuse: option --%s needs a value (see --help)\n", a.c_str());
            return 2;
        }
        o.kv[a] = s->type == 'f' ? "1" : argv[++i];
    }
    return 0;
}

void printHelp()
{
    printf("lidarsgm_fuse: stereo-LiDAR fusion by semi-global matching (SGM / DSGM / SDSGM)\n");
    for (const OptionSpec& s : kOptions)
    {
        if (!s.name)
        {
            printf("%s\n", s.help);
            continue;
        }
        const std::string flag = std::string("--") + s.name + (s.value ? std::string(" ") + s.value : "");
        std::string help = s.help;
        for (size_t p = help.find('\n'); p != std::string::npos; p = help.find('\n', p + 1))
            help.insert(p + 1, 24, ' ');
        printf("  %-20s  %s\n", flag.c_str(), help.c_str());
    }
    printf("Exit codes: 0 done, 1 error (unreadable input, bad value, ...; a folder run: some frame failed, the others\n"
           "are done), 2 bad command line.\n");
}

int modeFromName(const std::string& s)
{
    if (s == "sgm") return Matcher::MODE_SGM;
    if (s == "dsgm") return Matcher::MODE_DSGM;
    if (s == "sdsgm") return Matcher::MODE_SDSGM;
    CV_Error(Error::StsBadArg, "unknown mode '" + s + "' (sgm, dsgm, sdsgm)");
}

const char* modeLabel(int m)
{
    return m == Matcher::MODE_SGM ? "SGM" : m == Matcher::MODE_DSGM ? "DSGM" : "SDSGM";
}

int checkFromName(const std::string& s)
{
    if (s == "none") return Matcher::CHECK_NONE;
    if (s == "stereo") return Matcher::CHECK_STEREO;
    if (s == "camera-lidar") return Matcher::CHECK_CAMERA_LIDAR;
    if (s == "stereo-lidar") return Matcher::CHECK_STEREO_LIDAR;
    CV_Error(Error::StsBadArg, "unknown check '" + s + "' (none, stereo, camera-lidar, stereo-lidar)");
}

const char* checkLabel(int c)
{
    static const char* n[] = { "none", "stereo", "camera-lidar", "stereo-lidar" };
    return n[c];
}

std::vector<int> lidarLineCounts(const Options& o)
{
    std::vector<int> lines;
    for (const std::string& s : o.list("lidar-lines", "64"))
    {
        if (s != "64" && s != "32" && s != "16")
            CV_Error(Error::StsBadArg, "--lidar-lines takes 64, 32 or 16 (a comma list), got '" + s + "'");
        lines.push_back(std::atoi(s.c_str()));
    }
    return lines;
}

LidarRings lidarRings(const Options& o, int lines)
{
    const int every = 64 / lines;
    return { every, o.i("lidar-ring-offset", 0) % every };
}

Ptr<Matcher> makeMatcher(const Options& o, int mode, int check, int sceneNumDisparities)
{
    Ptr<Matcher> m = o.has("params") ? Matcher::load(o.str("params")) : Matcher::create();
    if (m.empty())
        CV_Error(Error::StsParseError, "--params " + o.str("params") + " holds no lidarsgm_StereoLidarSGM");
    m->setMode(mode);
    m->setConsistencyCheck(check);
    if (sceneNumDisparities > 0)
        m->setNumDisparities(sceneNumDisparities);
    // The parameter options, written as the file format that read() takes (it checks every value).
    FileStorage fs(".yml", FileStorage::WRITE | FileStorage::MEMORY | FileStorage::FORMAT_YAML);
    fs << "name" << m->getDefaultName();
    for (const OptionSpec& s : kOptions)
        if (s.param && o.has(s.name))
        {
            if (s.type == 'd')
                fs << s.param << o.d(s.name, 0);
            else
                fs << s.param << o.i(s.name, 0);
        }
    FileStorage in(fs.releaseAndGetString(), FileStorage::READ | FileStorage::MEMORY);
    m->read(in.root());
    return m;
}

void checkOptions(const Options& o)
{
    for (const auto& kv : o.kv)
    {
        const OptionSpec* s = findOption(kv.first);
        if (s->type == 'i')
            o.i(kv.first, 0);
        else if (s->type == 'd')
            o.d(kv.first, 0);
    }
    for (const std::string& m : o.list("modes", "sdsgm"))
        modeFromName(m);
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    for (const std::string& f : o.list("format", "kitti"))
    {
        if (f != "kitti" && f != "pfm" && f != "s16" && f != "depth" && f != "ply" && f != "confidence")
            CV_Error(Error::StsBadArg, "unknown --format '" + f + "' (kitti, pfm, s16, depth, ply, confidence)");
        if (f == "confidence" && o.has("middlebury"))
            CV_Error(Error::StsBadArg, "--format confidence is written for KITTI inputs; Middlebury runs score only "
                                       "(tools/confidence_benchmark.py evaluates the confidence there)");
        if ((f == "depth" || f == "ply") && o.has("middlebury"))
            CV_Error(Error::StsBadArg, "--format " + f + " needs a calibration, which Middlebury runs do not read");
        if ((f == "depth" || f == "ply") && o.has("left") && !o.has("calib") && !o.has("rig"))
            CV_Error(Error::StsBadArg, "--format " + f + " needs the calibration: give --calib or --rig");
    }
    if ((o.has("refine-calibration") || o.has("check-calibration")) && !o.has("kitti") && !o.has("kitti-raw"))
        CV_Error(Error::StsBadArg, "--refine-calibration and --check-calibration go with --kitti or --kitti-raw");
    if (o.has("scan-rate") && !o.has("refine-calibration") && !o.has("check-calibration"))
        CV_Error(Error::StsBadArg, "--scan-rate goes with --refine-calibration or --check-calibration");
    if (o.has("refine-translation") && !o.has("refine-calibration"))
        CV_Error(Error::StsBadArg, "--refine-translation goes with --refine-calibration");
    if (o.has("gt-depth") && !o.has("kitti-raw"))
        CV_Error(Error::StsBadArg, "--gt-depth goes with --kitti-raw");
    if (o.has("table5") && o.has("kitti-raw") && !o.has("gt-depth"))
        CV_Error(Error::StsBadArg, "--table5 scores each check against ground truth: with --kitti-raw give --gt-depth");
    lidarLineCounts(o);
    const int ringOffset = o.i("lidar-ring-offset", 0);
    if (ringOffset < 0 || ringOffset > 63)
        CV_Error(Error::StsBadArg, "--lidar-ring-offset takes a ring 0..63");
    int w = 0, h = 0;
    char rest = 0;
    if (o.has("resize") && (sscanf(o.str("resize").c_str(), "%dx%d%c", &w, &h, &rest) != 2 || w <= 0 || h <= 0))
        CV_Error(Error::StsBadArg, "--resize takes WIDTHxHEIGHT, got '" + o.str("resize") + "'");
    if (o.i("streams", 1) < 1 || o.i("streams", 1) > 64)
        CV_Error(Error::StsBadArg, "--streams takes 1 to 64 workers, got " + o.str("streams"));
    if (o.has("resume") && (!(o.has("kitti") || o.has("kitti-raw") || o.has("rig-folder")) || !o.has("out")))
        CV_Error(Error::StsBadArg, "--resume needs --kitti, --kitti-raw or --rig-folder, and --out (the earlier run's "
                                   "outputs)");
    if (o.has("rig") && (!o.has("left") || !o.has("right") || (!o.has("points") && !o.has("velodyne"))))
        CV_Error(Error::StsBadArg, "--rig goes with --left, --right and --points (the raw pair and its cloud)");
    if (o.has("rig") && (o.has("calib") || o.has("sparse")))
        CV_Error(Error::StsBadArg, "--rig holds the calibration: drop --calib and --sparse");
    if (o.has("points") && !o.has("rig") && !o.has("calib"))
        CV_Error(Error::StsBadArg, "--points needs the calibration that projects it: --rig or --calib");
    if (o.has("params") && !utils::fs::exists(o.str("params")))
        CV_Error(Error::StsObjectNotFound, "cannot open --params " + o.str("params"));
    makeMatcher(o, Matcher::MODE_SDSGM, check);   // every parameter value and relation
}

} // namespace lidarsgm_fuse
