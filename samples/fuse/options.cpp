// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The tool's options, declared once (kOptions: name, kind of value, help, default, matcher parameter), their parsing,
// the help, the checks of the command line (values, the input, options that conflict or do nothing with it) and the
// matcher they describe.

#include "tool.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <cstdio>
#include <cstdlib>
#include <climits>
#include <cstdint>
#include <algorithm>
#include <sstream>

using namespace cv;

namespace lidarsgm_fuse {

namespace {

//! type: 's' text, 'i' integer, 'd' number, 'f' switch (no value). def: the default as help shows it (nullptr: none,
//! or, for a matcher parameter, create()'s value at run time). param: the matcher's key in write()/read().
struct OptionSpec
{
    const char* name;
    char type;
    const char* value;
    const char* help;
    const char* def;
    const char* param;
};

const OptionSpec kOptions[] = {
    { nullptr, 0, nullptr, "Input (give one):", nullptr, nullptr },
    { "kitti-frame", 's', "DIR", "one frame of a KITTI-layout folder (image_2/ID_10.png, image_3/ID_10.png, "
      "velodyne/ID.bin, calib.txt, optional disp_occ_0/ID_10.png as ground truth); the frame is --id", nullptr,
      nullptr },
    { "left", 's', "L", "your own rectified left image, with --right and a LiDAR: --sparse, --points (with --calib "
      "or --rig) or --velodyne (with --calib); without one: --modes sgm --check stereo", nullptr, nullptr },
    { "right", 's', "R", "the right image of --left", nullptr, nullptr },
    { "kitti", 's', "DIR", "every frame listed in DIR/frames.txt of a KITTI-layout folder, scored with the KITTI "
      "devkit's rules", nullptr, nullptr },
    { "kitti-raw", 's', "DRIVE", "every frame of a KITTI raw drive in order (DRIVE = <date>/<date>_drive_<n>_sync: "
      "image_02/data, image_03/data, velodyne_points/data; the calibration from <date>/calib_cam_to_cam.txt and "
      "<date>/calib_velo_to_cam.txt); no ground truth needed", nullptr, nullptr },
    { "rig-folder", 's', "DIR", "every frame of your own rig's recording: DIR/rig.yml (as --rig), DIR/left/NAME.png, "
      "DIR/right/NAME.png, DIR/points/NAME.pcd|.ply|.bin, optional DIR/gt/NAME.png (KITTI disparity PNG in the "
      "rectified left view); NAME in sorted order", nullptr, nullptr },
    { "middlebury", 's', "DIR", "every scene folder of DIR, 1 % of its ground truth as the sparse input", nullptr,
      nullptr },
    { nullptr, 0, nullptr, "One frame (--kitti-frame, --left/--right):", nullptr, nullptr },
    { "id", 's', "ID", "the frame of --kitti-frame", "000002", nullptr },
    { "sparse", 's', "S", "(--left) sparse LiDAR disparities of the left view: PNG (uint16, value / 256) or .exr/.pfm "
      "(float pixels)", nullptr, nullptr },
    { "points", 's', "P", "(--left) a LiDAR cloud: .pcd, .ply or KITTI .bin, projected with --calib or --rig",
      nullptr, nullptr },
    { "velodyne", 's', "V", "(--left) a raw Velodyne scan (float32 x y z r), projected with --calib", nullptr,
      nullptr },
    { "calib", 's', "C", "(--left) KITTI calibration file (P2, P3, R0_rect, Tr_velo_to_cam): projects --points or "
      "--velodyne, and gives --format depth and ply their scale", nullptr, nullptr },
    { "rig", 's', "FILE", "(--left) your own rig (cv::lidarsgm::StereoRig::fromFile: stereoCalibrate's M1 D1 M2 D2 R "
      "T, optional R1 R2 P1 P2, image_width, image_height, lidar_to_left): --left/--right are raw images, rectified "
      "first; --points the cloud; outputs in the rectified left view", nullptr, nullptr },
    { "gt", 's', "G", "(--left) ground truth (KITTI 16-bit disparity PNG)", nullptr, nullptr },
    { "timing", 'i', "N", "time N runs and compare with OpenCV's matchers in the same process (CPU: every "
      "cv::StereoSGBM mode; with --cuda: cv::cuda::StereoSGM, CUDA events, device memory)", nullptr, nullptr },
    { "rounds", 'i', "N", "(--timing with --cuda) repeat the timing table N times, to show the spread", "1",
      nullptr },
    { "sm-count", 'i', "N", "(--timing with --cuda) also time lidarsgm and cv::cuda::StereoSGM on N of the GPU's SMs "
      "(a CUDA green context: a small GPU's parallelism on a big one)", nullptr, nullptr },
    { "resize", 's', "WxH", "(--kitti-frame) scale the frame to W x H first, for speed runs (no ground truth then)",
      "the frame's size", nullptr },
    { nullptr, 0, nullptr, "Folder runs (--kitti, --kitti-raw, --rig-folder, --middlebury):", nullptr, nullptr },
    { "resume", 'f', nullptr, "(not --middlebury; with --out) take the frames whose outputs are complete (their "
      "metrics.yml, written last) from the earlier run instead of computing them again", nullptr, nullptr },
    { "streams", 'i', "N", "(not --middlebury) N workers fuse frames at once, each on its own thread with its own "
      "matchers (with --cuda: own CUDA stream, page-locked buffers)", "1", nullptr },
    { "quiet", 'f', nullptr, "no progress line", nullptr, nullptr },
    { "table5", 'f', nullptr, "(--kitti, --rig-folder, --kitti-raw with --gt-depth) also run SDSGM with each "
      "consistency check (the paper's Table V)", nullptr, nullptr },
    { "gt-depth", 's', "DIR", "(--kitti-raw) ground truth as KITTI depth PNGs DIR/<frame>.png (metres x 256, e.g. the "
      "depth-completion set's proj_depth/groundtruth/image_02): scored as disparity fB / depth", nullptr, nullptr },
    { "seed", 'i', "N", "(--middlebury) random seed of the 1 % sampling", "1", nullptr },
    { "bad", 'd', "N", "(--middlebury) error threshold in pixels (bad-N)", "2", nullptr },
    { nullptr, 0, nullptr, "Output:", nullptr, nullptr },
    { "out", 's', "DIR", "write per frame (folder runs: DIR/<frame>/): disparity[_mode].png|.pfm|.s16, "
      "disparity[_mode]_color.png, error[_mode].png (with ground truth), semidense.png and semidense_color.png "
      "(SDSGM), lidar_points.png; the pictures have a legend below the frame", "nothing written", nullptr },
    { "format", 's', "LIST", "(with --out) comma list of kitti (16-bit PNG, d * 256, 0 = invalid), pfm (float, "
      "invalid = inf), s16 (the matcher's CV_16S x16, little-endian, no header), depth (depth[_mode].png: KITTI "
      "depth, uint16 metres x 256, 0 = none), ply (points[_mode].ply: binary PLY, x y z metres in the left camera "
      "frame and the left image's colour, one vertex per valid pixel), confidence (confidence[_mode].png: uint16, "
      "the confidence map x 65535, 0 = no disparity; KITTI inputs; with ground truth the run also prints its "
      "sparsification figures). depth and ply need a calibration (KITTI inputs, --calib, --rig)", "kitti",
      nullptr },
    { nullptr, 0, nullptr, "Method:", nullptr, nullptr },
    { "modes", 's', "LIST", "comma list of sgm, dsgm, sdsgm", "sdsgm for one frame, sgm,dsgm,sdsgm for a folder",
      nullptr },
    { "check", 's', "C", "consistency check: none, stereo, camera-lidar or stereo-lidar", "stereo-lidar", nullptr },
    { "params", 's', "FILE", "matcher parameters saved with StereoLidarSGM::save (e.g. doc/params/kitti_best.yml) "
      "instead of create()'s; the parameter options below override it", nullptr, nullptr },
    { "lidar-lines", 's', "LIST", "(KITTI scans, clouds of --rig-folder) LiDAR line counts, comma list of 64, 32, 16: "
      "every 2nd / 4th ring of the 64-line scans (the paper's Table VI); a folder run prints one table per count, "
      "one frame takes one count", "64", nullptr },
    { "lidar-ring-offset", 'i', "K", "(--lidar-lines 32 or 16) the first ring kept, counted from the top, modulo the "
      "2 or 4 (3 keeps the lowest ring at 16 lines)", "0, the top ring", nullptr },
    { "trust-lidar", 'f', nullptr, "(not --middlebury) fuse every frame with its LiDAR; without it a frame whose "
      "LiDAR lands misplaced on its images (cv::lidarsgm::LidarFailSafe: the matching residual above 1 px and lowered "
      "by a fifth when the points are moved together: a LiDAR-to-camera transform that is off) is fused as stereo "
      "alone, and the run says so per frame", nullptr, nullptr },
    { nullptr, 0, nullptr, "Calibration from the data (--kitti, --kitti-raw):", nullptr, nullptr },
    { "check-calibration", 'f', nullptr, "print the calibration residual: the median |LiDAR disparity - stereo "
      "disparity| over the LiDAR points (cv::lidarsgm::LidarCalibration)", nullptr, nullptr },
    { "refine-calibration", 'f', nullptr, "estimate the LiDAR-to-camera rotation's correction from the run's frames "
      "(a raw drive: 20 frames spread over it), print it with its standard errors and the residual before and "
      "after, and fuse with the corrected transform", nullptr, nullptr },
    { "scan-rate", 'd', "HZ", "(--check-calibration, --refine-calibration) the LiDAR's sweep rate for scans that are "
      "not motion-compensated (KITTI's HDL-64E: 10; 0: compensated scans)", "10", nullptr },
    { "refine-translation", 'f', nullptr, "(--refine-calibration) also estimate the translation along the camera's x "
      "axis", nullptr, nullptr },
    { nullptr, 0, nullptr, "Device:", nullptr, nullptr },
    { "cuda", 'f', nullptr, "(not --middlebury) run on the GPU (GpuMat in and out)", nullptr, nullptr },
    { "threads", 'i', "N", "CPU threads (cv::setNumThreads)", nullptr, nullptr },
    { nullptr, 0, nullptr, "Matcher parameters (StereoLidarSGM's; defaults: create()'s, the paper's; --params FILE "
      "replaces them):", nullptr, nullptr },
    { "num-disparities", 'i', "N", "numDisparities, the disparities searched: a multiple of 16 (--middlebury: the "
      "scene's range unless given)", nullptr, "numDisparities" },
    { "min-disparity", 'i', "N", "minDisparity, the smallest disparity", nullptr, "minDisparity" },
    { "P1", 'i', "N", "P1, the penalty of a disparity step of 1", nullptr, "P1" },
    { "P2", 'i', "N", "P2, the penalty of larger steps (>= P1)", nullptr, "P2" },
    { "Q1", 'i', "N", "Q1, the DDC penalty for |d - LiDAR| = 1", nullptr, "Q1" },
    { "Q2", 'i', "N", "Q2, the DDC penalty for |d - LiDAR| > 1 (>= Q1)", nullptr, "Q2" },
    { "alpha", 'd', "A", "alpha, the weight of the DDC against the census cost, in [0, 1]", nullptr, "alpha" },
    { "uniqueness", 'd', "U", "uniquenessRatio, in (0, 1] (1: off)", nullptr, "uniquenessRatio" },
    { "lr-max-diff", 'i', "N", "lrMaxDiff, the left-right tolerance in pixels", nullptr, "lrMaxDiff" },
    { "paths", 'i', "4|8", "numPaths, the aggregation paths", nullptr, "numPaths" },
    { "subpixel", 'i', "0|1", "subpixel, the parabola fit", nullptr, "subpixel" },
    { "rs", 'i', "N", "semidenseRadius, the semidensification radius", nullptr, "semidenseRadius" },
    { "Ts", 'i', "N", "semidenseThreshold, the semidensification threshold", nullptr, "semidenseThreshold" },
    { "rc", 'i', "N", "checkRadius, the consistency-check radius", nullptr, "checkRadius" },
    { "Tc", 'd', "T", "checkThreshold, the consistency-check threshold in pixels", nullptr, "checkThreshold" },
    { "median-size", 'i', "1|3", "medianSize, the median filter (1: off)", nullptr, "medianSize" },
    { "visibility-rx", 'i', "N", "visibilityRadiusX, the visibility filter's half width (0: off)", nullptr,
      "visibilityRadiusX" },
    { "visibility-ry", 'i', "N", "visibilityRadiusY, the visibility filter's half height", nullptr,
      "visibilityRadiusY" },
    { "visibility-parallax", 'd', "R", "visibilityParallax, the visibility window's growth per pixel of disparity "
      "step", nullptr, "visibilityParallax" },
    { "edge-threshold", 'i', "N", "edgeThreshold, the left-image step that makes a disparity jump cheaper (0: off)",
      nullptr, "edgeThreshold" },
    { "edge-p2-ratio", 'd', "R", "edgeP2Ratio, P2's factor across an image edge", nullptr, "edgeP2Ratio" },
    { "ring-gap-factor", 'd', "F", "ringGapFactor, the ring interpolation's longest gap in ring spacings (0: off)",
      nullptr, "ringGapFactor" },
    { "semidense-weight", 'd', "F", "semidenseWeight, the DDC weight of copied priors on LiDAR scans", nullptr,
      "semidenseWeight" },
    { "search-window", 'i', "N", "searchWindow, the disparity windows' margin (0: off, the full range)", nullptr,
      "searchWindow" },
};

const OptionSpec* findOption(const std::string& name)
{
    for (const OptionSpec& s : kOptions)
        if (s.name && name == s.name)
            return &s;
    return nullptr;
}

//! The option whose name is fewest single-letter edits away from name (for "did you mean").
std::string nearestOption(const std::string& name)
{
    std::string best;
    size_t bestEdits = SIZE_MAX;
    for (const OptionSpec& s : kOptions)
    {
        if (!s.name)
            continue;
        const std::string known = s.name;
        // edits[i][j]: between the first i letters of name and the first j of known.
        std::vector<std::vector<size_t> > edits(name.size() + 1, std::vector<size_t>(known.size() + 1));
        for (size_t i = 0; i <= name.size(); i++)
            for (size_t j = 0; j <= known.size(); j++)
                edits[i][j] = i == 0 || j == 0 ? i + j
                                               : std::min({ edits[i - 1][j] + 1, edits[i][j - 1] + 1,
                                                            edits[i - 1][j - 1] + (name[i - 1] != known[j - 1]) });
        if (edits[name.size()][known.size()] < bestEdits)
        {
            bestEdits = edits[name.size()][known.size()];
            best = known;
        }
    }
    return best;
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
            fprintf(stderr, "lidarsgm_fuse: unknown option --%s (did you mean --%s? see --help)\n", a.c_str(),
                    nearestOption(a).c_str());
            return 2;
        }
        if (s->type == 'f')
        {
            // A switch; it also takes 0 or 1 after it (--cuda 1, --quiet 0), the form a base build's tool needs, so
            // that one command line of tools/device_check.sh runs both: 0 turns it off.
            const bool value = i + 1 < argc && (std::string(argv[i + 1]) == "0" || std::string(argv[i + 1]) == "1");
            if (value && std::string(argv[++i]) == "0")
                o.kv.erase(a);
            else
                o.kv[a] = "1";
            continue;
        }
        // An option name where the value should be: the value was left out.
        if (i + 1 >= argc || (std::string(argv[i + 1]).compare(0, 2, "--") == 0 &&
                              (findOption(argv[i + 1] + 2) || std::string(argv[i + 1]) == "--help")))
        {
            fprintf(stderr, "lidarsgm_fuse: option --%s needs a value (%s; see --help)\n", a.c_str(), s->value);
            return 2;
        }
        o.kv[a] = argv[++i];
    }
    return 0;
}

namespace {

//! text wrapped to lines of at most width characters, every line after the first indented by indent spaces.
std::string wrap(const std::string& text, size_t indent, size_t width)
{
    std::string out, line;
    std::stringstream words(text);
    std::string w;
    while (words >> w)
    {
        if (!line.empty() && indent + line.size() + 1 + w.size() > width)
        {
            out += line + "\n" + std::string(indent, ' ');
            line.clear();
        }
        line += (line.empty() ? "" : " ") + w;
    }
    return out + line;
}

//! create()'s value of every matcher parameter, by its key in write(): the library's defaults, not a copy of them.
std::map<std::string, std::string> matcherDefaults()
{
    FileStorage fs(".yml", FileStorage::WRITE | FileStorage::MEMORY | FileStorage::FORMAT_YAML);
    Matcher::create()->write(fs);
    FileStorage in(fs.releaseAndGetString(), FileStorage::READ | FileStorage::MEMORY);
    std::map<std::string, std::string> defaults;
    for (const OptionSpec& s : kOptions)
        if (s.param && !in[s.param].empty())
            defaults[s.param] = s.type == 'd' ? format("%g", (double)in[s.param]) : format("%d", (int)in[s.param]);
    return defaults;
}

} // namespace

void printHelp()
{
    printf("Usage: lidarsgm_fuse INPUT [OPTION]...\n");
    printf("%s\n", wrap("Fuses a rectified stereo pair with LiDAR into a dense disparity map by semi-global matching "
                        "(SGM, DSGM, SDSGM), for one frame or every frame of a folder, and scores it against ground "
                        "truth with the KITTI devkit's rules (D1) or Middlebury's bad-N.", 0, 118).c_str());
    printf("\nExamples:\n"
           "  lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --out out\n"
           "      one KITTI frame (stereo pair, raw Velodyne scan): its D1 error; maps and pictures in out/\n"
           "  lidarsgm_fuse --left left.png --right right.png --sparse lidar.png --out out\n"
           "      your own rectified pair and LiDAR disparities (16-bit PNG, value / 256)\n"
           "  lidarsgm_fuse --kitti DIR --modes sdsgm --out out --resume\n"
           "      every frame of DIR/frames.txt, summed; run again, it computes only the frames still missing\n");
    const std::map<std::string, std::string> matcher = matcherDefaults();
    for (const OptionSpec& s : kOptions)
    {
        if (!s.name)
        {
            printf("\n%s\n", wrap(s.help, 0, 118).c_str());
            continue;
        }
        const std::string flag = std::string("--") + s.name + (s.value ? std::string(" ") + s.value : "");
        std::string def = s.def ? s.def : "";
        if (s.param)
            def = matcher.at(s.param);
        else if (std::string(s.name) == "threads")
            def = format("%d, OpenCV's", getNumThreads());
        const std::string help = std::string(s.help) + (def.empty() ? "" : " (default " + def + ")");
        if (flag.size() > 21)   // too long for its column: the help starts on the next line
            printf("  %s\n%24s%s\n", flag.c_str(), "", wrap(help, 24, 118).c_str());
        else
            printf("  %-22s%s\n", flag.c_str(), wrap(help, 24, 118).c_str());
    }
    printf("\n%s\n", wrap("Switches take no value (the older --cuda 1, --quiet 0 still work). An option given twice "
                          "takes its last value.", 0, 118).c_str());
    printf("%s\n", wrap("Exit codes: 0 done; 1 a failed run (a file that cannot be read or written, a computation "
                        "that fails; a folder run: some frame failed, the others are done); 2 a bad command line "
                        "(a value, a combination of options; nothing was run).", 0, 118).c_str());
}

int modeFromName(const std::string& s)
{
    if (s == "sgm") return Matcher::MODE_SGM;
    if (s == "dsgm") return Matcher::MODE_DSGM;
    if (s == "sdsgm") return Matcher::MODE_SDSGM;
    CV_Error(Error::StsBadArg, "unknown mode '" + s + "' (sgm, dsgm, sdsgm)");
}

const char* modeName(int m)
{
    return m == Matcher::MODE_SGM ? "sgm" : m == Matcher::MODE_DSGM ? "dsgm" : "sdsgm";
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

namespace {

/** The parameter options onto m, written as the file format that read() takes (it checks every value); a value it
refuses is named by its option. */
void applyParameterOptions(const Options& o, const Ptr<Matcher>& m)
{
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
    try
    {
        m->read(in.root());
    }
    catch (const cv::Exception& e)
    {
        // The library's message starts with the parameter's key ("lidarsgm: alpha (...) must be ...").
        std::string why = e.err;
        if (why.compare(0, 10, "lidarsgm: ") == 0)
            why = why.substr(10);
        const std::string key = why.substr(0, why.find_first_of(" ("));
        for (const OptionSpec& s : kOptions)
            if (s.param && key == s.param && o.has(s.name))
                CV_Error(Error::StsOutOfRange, "--" + std::string(s.name) + " " + o.str(s.name) + " is refused: " +
                         why);
        CV_Error(Error::StsOutOfRange, "the matcher parameters are refused: " + why);
    }
}

} // namespace

Ptr<Matcher> makeMatcher(const Options& o, int mode, int check, int sceneNumDisparities)
{
    Ptr<Matcher> m = o.has("params") ? Matcher::load(o.str("params")) : Matcher::create();
    if (m.empty())
        CV_Error(Error::StsParseError, "--params " + o.str("params") + " holds no lidarsgm_StereoLidarSGM");
    m->setMode(mode);
    m->setConsistencyCheck(check);
    if (sceneNumDisparities > 0)
        m->setNumDisparities(sceneNumDisparities);
    applyParameterOptions(o, m);
    return m;
}

namespace {

//! The inputs, one of which a run takes ("left" stands for --left/--right).
const char* const kInputs[] = { "kitti-frame", "left", "kitti", "kitti-raw", "rig-folder", "middlebury" };

std::string inputFlag(const std::string& input)
{
    return input == "left" ? "--left/--right" : "--" + input;
}

//! "--a, --b or --c" of a space-separated list of inputs.
std::string inputFlags(const std::string& inputs)
{
    std::vector<std::string> v;
    std::stringstream ss(inputs);
    for (std::string w; ss >> w; )
        v.push_back(inputFlag(w));
    std::string out;
    for (size_t k = 0; k < v.size(); k++)
        out += (k == 0 ? "" : k + 1 == v.size() ? " or " : ", ") + v[k];
    return out;
}

//! The options that work with some inputs only (a space-separated list); an option not listed works with every input.
struct Scope
{
    const char* option;
    const char* inputs;
};

const Scope kScopes[] = {
    { "id", "kitti-frame" },
    { "sparse", "left" }, { "points", "left" }, { "velodyne", "left" }, { "calib", "left" }, { "rig", "left" },
    { "gt", "left" },
    { "timing", "kitti-frame left" }, { "resize", "kitti-frame" },
    { "resume", "kitti kitti-raw rig-folder" }, { "streams", "kitti kitti-raw rig-folder" },
    { "quiet", "kitti kitti-raw rig-folder middlebury" }, { "table5", "kitti kitti-raw rig-folder" },
    { "gt-depth", "kitti-raw" }, { "seed", "middlebury" }, { "bad", "middlebury" },
    { "lidar-lines", "kitti-frame left kitti kitti-raw rig-folder" },
    { "lidar-ring-offset", "kitti-frame left kitti kitti-raw rig-folder" },
    { "trust-lidar", "kitti-frame left kitti kitti-raw rig-folder" },
    { "check-calibration", "kitti kitti-raw" }, { "refine-calibration", "kitti kitti-raw" },
    { "cuda", "kitti-frame left kitti kitti-raw rig-folder" },
};

//! Where an input's frames get their LiDAR, calibration and ground truth, for the messages.
std::string ownLidar(const std::string& input)
{
    if (input == "kitti-frame") return "the frame's velodyne scan is its LiDAR";
    if (input == "kitti") return "each frame's velodyne scan is its LiDAR";
    if (input == "kitti-raw") return "each frame's velodyne_points scan is its LiDAR";
    if (input == "rig-folder") return "each frame's points/ cloud is its LiDAR";
    return "1 % of each scene's ground truth is its LiDAR";
}

//! Why option does nothing with input, where "it goes with" its inputs does not say it well; empty elsewhere.
std::string whyIdle(const std::string& option, const std::string& input)
{
    if (option == "sparse" || option == "points" || option == "velodyne")
        return ownLidar(input);
    if (option == "calib" || option == "rig")
        return input == "kitti-frame" || input == "kitti" ? "calib.txt is the calibration"
               : input == "kitti-raw" ? "the drive's calib_*.txt are its calibration"
               : input == "rig-folder" ? "DIR/rig.yml is the rig" : "Middlebury runs need no calibration";
    if (option == "gt")
        return input == "kitti-frame" || input == "kitti" ? "disp_occ_0/ is the ground truth"
               : input == "kitti-raw" ? "--gt-depth gives the ground truth"
               : input == "rig-folder" ? "DIR/gt/ is the ground truth" : "each scene holds its ground truth";
    if (option == "quiet" && (input == "kitti-frame" || input == "left"))
        return "one frame prints no progress line";
    if (option == "streams" && (input == "kitti-frame" || input == "left"))
        return "the workers share out a folder's frames";
    if (option == "cuda" && input == "middlebury")
        return "Middlebury runs compute on the CPU";
    if (option == "trust-lidar" && input == "middlebury")
        return "Middlebury runs sample their LiDAR from the ground truth, never misplaced";
    return "";
}

void refuse(const std::string& what)
{
    CV_Error(Error::StsBadArg, what);
}

void refuseTogether(const std::string& a, const std::string& b, const std::string& why)
{
    refuse(a + " does nothing with " + b + " (" + why + "); drop one of them");
}

//! The input the command line names; refuses none, two, and half a pair.
std::string inputOf(const Options& o)
{
    std::string input;
    for (const char* in : kInputs)
        if (o.has(in) || (std::string(in) == "left" && o.has("right")))
        {
            if (!input.empty())
                refuse(inputFlag(input) + " and " + inputFlag(in) + " are two inputs: give one of them");
            input = in;
        }
    if (input.empty())
        refuse("give --kitti-frame, --left/--right, --kitti, --kitti-raw, --rig-folder or --middlebury (see --help)");
    if (input == "left" && !(o.has("left") && o.has("right")))
        refuse(o.has("left") ? "--left goes with --right (the pair's right image): give both"
                             : "--right goes with --left (the pair's left image): give both");
    return input;
}

//! Whether the run writes a format that needs the calibration.
bool writesMetric(const Options& o)
{
    for (const std::string& f : o.list("format", "kitti"))
        if (f == "depth" || f == "ply")
            return o.has("out");
    return false;
}

//! The options that do nothing with the input, or conflict with each other, or lack the one they go with.
void checkCombination(const Options& o)
{
    const std::string input = inputOf(o), flag = inputFlag(input);
    for (const Scope& s : kScopes)
        if (o.has(s.option) && (" " + std::string(s.inputs) + " ").find(" " + input + " ") == std::string::npos)
        {
            const std::string own = whyIdle(s.option, input);
            refuseTogether("--" + std::string(s.option), flag, own.empty() ? "it goes with " + inputFlags(s.inputs)
                                                                           : own);
        }
    const bool single = input == "kitti-frame" || input == "left";
    if (o.has("format") && !o.has("out"))
        refuse("--format does nothing without --out (nothing is written): add --out DIR, or drop --format");

    // One frame of your own: one LiDAR, and what projects it.
    const char* lidars[] = { "sparse", "points", "velodyne" };
    std::string lidar;
    for (const char* l : lidars)
        if (o.has(l))
        {
            if (!lidar.empty())
                refuse("--" + lidar + " and --" + l + " are two LiDAR inputs: give one of them");
            lidar = l;
        }
    if (o.has("rig"))
    {
        if (o.has("calib"))
            refuseTogether("--calib", "--rig", "the rig file holds the calibration");
        if (o.has("sparse"))
            refuseTogether("--sparse", "--rig", "the rig projects --points into its rectified left view");
        if (lidar.empty())
            refuse("--rig needs --points (the cloud it projects into the rectified view)");
    }
    else if ((lidar == "points" || lidar == "velodyne") && !o.has("calib"))
        refuse("--" + lidar + " needs the calibration that projects it: add --calib C (KITTI's calib.txt) or --rig "
               "RIG");
    if (o.has("calib") && lidar != "points" && lidar != "velodyne" && !writesMetric(o))
        refuse(lidar == "sparse" ? "--calib does nothing with --sparse (the sparse map is projected already) unless "
                                   "--out writes --format depth or ply; drop --calib, or add --format depth"
                                 : "--calib does nothing without --points, --velodyne or --format depth / ply (it "
                                   "projects a cloud, and scales depth); drop --calib, or add one of those");
    if (input == "left" && lidar.empty())
    {
        // Stereo alone: plain SGM with a check without the LiDAR; anything else fuses one.
        std::string needs;
        for (const std::string& m : o.list("modes", "sdsgm"))
            if (needs.empty() && m != "sgm")
                needs = std::string(o.has("modes") ? "" : "the default ") + "--modes " + m + " fuses one";
        const std::string check = o.str("check", "stereo-lidar");
        if (needs.empty() && (check == "camera-lidar" || check == "stereo-lidar"))
            needs = std::string(o.has("check") ? "" : "the default ") + "--check " + check + " compares with one";
        if (needs.empty() && o.has("timing") && o.has("cuda"))
            needs = "--timing with --cuda times SDSGM and DSGM, which fuse one";
        if (!needs.empty())
            refuse("--left/--right give no LiDAR, but " + needs + ": add --sparse S (LiDAR disparities), --points P "
                   "with --calib C or --rig RIG (a cloud), or --velodyne V with --calib C (a KITTI scan); or run "
                   "stereo alone with --modes sgm --check stereo");
    }

    // LiDAR rings: only raw scans have them, one frame takes one count, an offset needs fewer than 64 lines.
    if (o.has("lidar-lines") || o.has("lidar-ring-offset"))
    {
        const std::string opt = o.has("lidar-lines") ? "--lidar-lines" : "--lidar-ring-offset";
        if (o.has("rig"))
            refuseTogether(opt, "--rig", "it keeps rings of KITTI scans and --rig-folder clouds");
        if (input == "left" && lidar != "velodyne")
            refuseTogether(opt, lidar.empty() ? "--left/--right" : "--" + lidar,
                           "it keeps rings of a raw --velodyne scan");
    }
    const std::vector<int> lines = lidarLineCounts(o);
    if (single && lines.size() > 1)
        refuse("one frame takes one --lidar-lines count, got " + o.str("lidar-lines") + " (a folder run prints a "
               "table per count)");
    if (o.has("lidar-ring-offset") && *std::min_element(lines.begin(), lines.end()) == 64)
        refuse("--lidar-ring-offset does nothing without --lidar-lines 32 or 16 (at 64 lines every ring is kept)");

    if (o.has("resume") && !o.has("out"))
        refuse("--resume needs --out (the earlier run's outputs)");
    if (o.has("rounds") && !(o.has("timing") && o.has("cuda")))
        refuse("--rounds does nothing without --timing and --cuda (it repeats the GPU timing table)");
    if (o.has("sm-count") && !(o.has("timing") && o.has("cuda")))
        refuse("--sm-count does nothing without --timing and --cuda (it times the GPU on some of its SMs)");
    if (o.has("scan-rate") && !o.has("refine-calibration") && !o.has("check-calibration"))
        refuse("--scan-rate does nothing without --refine-calibration or --check-calibration");
    if (o.has("refine-translation") && !o.has("refine-calibration"))
        refuse("--refine-translation does nothing without --refine-calibration");
    if (o.has("table5") && input == "kitti-raw" && !o.has("gt-depth"))
        refuse("--table5 scores each check against ground truth: with --kitti-raw give --gt-depth");
    for (const std::string& f : o.list("format", "kitti"))
    {
        if (f == "confidence" && input == "middlebury")
            refuse("--format confidence is written for KITTI inputs; Middlebury runs score only "
                   "(tools/confidence_benchmark.py evaluates the confidence there)");
        if ((f == "depth" || f == "ply") && input == "middlebury")
            refuse("--format " + f + " needs a calibration, which Middlebury runs do not read");
        if ((f == "depth" || f == "ply") && input == "left" && !o.has("calib") && !o.has("rig"))
            refuse("--format " + f + " needs the calibration: give --calib or --rig");
    }
}

//! Every value alone: numbers, names, ranges.
void checkValues(const Options& o)
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
    if (o.has("modes") && o.list("modes", "").empty())
        refuse("--modes takes a comma list of sgm, dsgm, sdsgm, got '" + o.str("modes") + "'");
    checkFromName(o.str("check", "stereo-lidar"));
    for (const std::string& f : o.list("format", "kitti"))
        if (f != "kitti" && f != "pfm" && f != "s16" && f != "depth" && f != "ply" && f != "confidence")
            refuse("unknown --format '" + f + "' (kitti, pfm, s16, depth, ply, confidence)");
    if (lidarLineCounts(o).empty())
        refuse("--lidar-lines takes 64, 32 or 16 (a comma list), got '" + o.str("lidar-lines") + "'");
    const int ringOffset = o.i("lidar-ring-offset", 0);
    if (ringOffset < 0 || ringOffset > 63)
        refuse("--lidar-ring-offset takes a ring 0..63, got " + o.str("lidar-ring-offset"));
    int w = 0, h = 0;
    char rest = 0;
    if (o.has("resize") && (sscanf(o.str("resize").c_str(), "%dx%d%c", &w, &h, &rest) != 2 || w <= 0 || h <= 0))
        refuse("--resize takes WIDTHxHEIGHT (e.g. 1920x1080), got '" + o.str("resize") + "'");
    if (o.i("streams", 1) < 1 || o.i("streams", 1) > 64)
        refuse("--streams takes 1 to 64 workers, got " + o.str("streams"));
    if (o.has("threads") && o.i("threads", 1) < 1)
        refuse("--threads takes 1 or more, got " + o.str("threads"));
    if (o.has("timing") && o.i("timing", 1) < 1)
        refuse("--timing takes 1 or more runs, got " + o.str("timing"));
    if (o.i("rounds", 1) < 1)
        refuse("--rounds takes 1 or more, got " + o.str("rounds"));
    if (o.has("sm-count") && o.i("sm-count", 1) < 1)
        refuse("--sm-count takes 1 or more SMs, got " + o.str("sm-count"));
    if (!(o.d("bad", 2) > 0))
        refuse("--bad takes a threshold above 0 pixels, got " + o.str("bad"));
    if (!(o.d("scan-rate", 10) >= 0))
        refuse("--scan-rate takes 0 (compensated scans) or a rate in Hz, got " + o.str("scan-rate"));
}

} // namespace

int checkOptions(const Options& o)
{
    try
    {
        checkValues(o);
        checkCombination(o);
    }
    catch (const cv::Exception& e)
    {
        fprintf(stderr, "lidarsgm_fuse: %s\n", e.err.c_str());
        return 2;
    }
    // --params: a file that cannot be read fails the run (1); its values with the options given, the command line.
    Ptr<Matcher> m;
    try
    {
        if (o.has("params") && !utils::fs::exists(o.str("params")))
            CV_Error(Error::StsObjectNotFound, "cannot open --params " + o.str("params"));
        m = o.has("params") ? Matcher::load(o.str("params")) : Matcher::create();
        if (m.empty())
            CV_Error(Error::StsParseError, "--params " + o.str("params") + " holds no lidarsgm_StereoLidarSGM");
    }
    catch (const cv::Exception& e)
    {
        fprintf(stderr, "lidarsgm_fuse: error: %s\n", e.err.c_str());
        return 1;
    }
    try
    {
        applyParameterOptions(o, m);
    }
    catch (const cv::Exception& e)
    {
        fprintf(stderr, "lidarsgm_fuse: %s\n", e.err.c_str());
        return 2;
    }
    return 0;
}

} // namespace lidarsgm_fuse
