// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// lidarsgm_fuse: fuse a stereo pair with LiDAR into a dense disparity map, for one frame or a whole dataset folder,
// and score it against ground truth with the KITTI devkit's rules (D1) or Middlebury's bad-N.
//
//   lidarsgm_fuse --kitti-frame DIR --id 000002 [--out OUT]      one frame of a KITTI-layout folder (raw scan)
//   lidarsgm_fuse --left L --right R (--sparse S | --velodyne V --calib C) [--gt G] [--out OUT]
//   lidarsgm_fuse --kitti DIR [--table5]                        every frame listed in DIR/frames.txt
//   lidarsgm_fuse --middlebury DIR [--seed N]                   every scene folder in DIR (1 % of GT as input)
// Run with --help for every option.

#include "opencv2/lidarsgm.hpp"
#include "opencv2/calib3d.hpp"
#include "opencv2/core/utility.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include "lidarsgm_eval.hpp"
#include "opencv2/core/cuda.hpp"
#ifdef LIDARSGM_HAVE_CUDASTEREO
#include "opencv2/cudastereo.hpp"
#endif

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <functional>
#include <limits>
#include <set>

using namespace cv;
using namespace lidarsgm_eval;
typedef cv::lidarsgm::StereoLidarSGM Matcher;

namespace {

struct Options
{
    std::map<std::string, std::string> kv;
    bool has(const std::string& k) const { return kv.count(k) != 0; }
    std::string str(const std::string& k, const std::string& def = "") const
    {
        std::map<std::string, std::string>::const_iterator it = kv.find(k);
        return it == kv.end() ? def : it->second;
    }
    int i(const std::string& k, int def) const
    {
        if (!has(k))
            return def;
        char* end = nullptr;
        const long v = std::strtol(str(k).c_str(), &end, 10);
        if (str(k).empty() || *end != '\0' || v < INT_MIN || v > INT_MAX)
            CV_Error(Error::StsBadArg, "--" + k + " takes an integer, got '" + str(k) + "'");
        return (int)v;
    }
    double d(const std::string& k, double def) const
    {
        if (!has(k))
            return def;
        char* end = nullptr;
        const double v = std::strtod(str(k).c_str(), &end);
        if (str(k).empty() || *end != '\0')
            CV_Error(Error::StsBadArg, "--" + k + " takes a number, got '" + str(k) + "'");
        return v;
    }
};

const char* const kOptions[] = { "kitti-frame", "id", "left", "right", "sparse", "velodyne", "calib", "kitti",
    "middlebury", "gt", "out", "format", "modes", "check", "table5", "num-disparities", "min-disparity", "P1", "P2",
    "Q1", "Q2", "alpha", "uniqueness", "lr-max-diff", "paths", "subpixel", "rs", "Ts", "rc", "Tc", "seed", "bad",
    "timing", "cuda", "threads", "resize", "rounds", "quiet" };

const char* kHelp =
    "lidarsgm_fuse: stereo-LiDAR fusion by semi-global matching (SGM / DSGM / SDSGM)\n"
    "Inputs (one of):\n"
    "  --kitti-frame DIR --id ID      KITTI-layout folder: image_2/ID_10.png, image_3/ID_10.png, velodyne/ID.bin,\n"
    "                                 calib.txt, optional disp_occ_0/ID_10.png (ground truth)\n"
    "  --left L --right R --sparse S  sparse disparity PNG (uint16, value / 256) or .exr/.pfm float\n"
    "  --left L --right R --velodyne V --calib C   raw scan + KITTI calibration file\n"
    "  --kitti DIR                    benchmark every frame of DIR/frames.txt\n"
    "  --middlebury DIR               benchmark every scene folder of DIR (1 % of the ground truth as sparse input)\n"
    "Options:\n"
    "  --gt G              ground truth for a single frame (KITTI PNG)\n"
    "  --out DIR           write per frame (folder runs: DIR/<frame>/): disparity[_mode].png|.pfm|.s16,\n"
    "                      disparity[_mode]_color.png (KITTI colours), error[_mode].png (KITTI error colours, with\n"
    "                      ground truth), semidense.png + semidense_color.png (SDSGM), lidar_points.png (the\n"
    "                      LiDAR points over the left image)\n"
    "  --format LIST       disparity file formats, comma list of kitti (16-bit PNG, d * 256, 0 = invalid), pfm\n"
    "                      (float, invalid = inf), s16 (the matcher's raw CV_16S x16, little-endian, no header)\n"
    "                      (default kitti)\n"
    "  --quiet 1           no progress line on folder runs\n"
    "  --modes LIST        comma list of sgm, dsgm, sdsgm (default: sdsgm for a frame, all for a folder)\n"
    "  --check C           none | stereo | camera-lidar | stereo-lidar (default stereo-lidar)\n"
    "  --table5            also run SDSGM with each consistency check (the paper's Table V)\n"
    "  --num-disparities N --min-disparity N --P1 N --P2 N --Q1 N --Q2 N --alpha A --uniqueness U\n"
    "  --lr-max-diff N --paths 4|8 --subpixel 0|1 --rs N --Ts N --rc N --Tc T   algorithm parameters\n"
    "  --seed N            random seed of the Middlebury sampling (default 1)\n"
    "  --bad N             Middlebury error threshold in pixels (default 2: bad-2)\n"
    "  --timing N          time N runs per frame and compare with cv::StereoSGBM MODE_HH (same process)\n"
    "  --cuda 1            run on the GPU (GpuMat in and out); with --timing: CUDA-event medians against\n"
    "                      cv::cuda::StereoSGM, and the device memory one instance holds\n"
    "  --threads N         cv::setNumThreads\n"
    "  --resize WxH        (speed runs) scale the frame to W x H first\n"
    "  --rounds N          (GPU timing) repeat the whole timing table N times, to show the spread\n"
    "Exit codes: 0 done, 1 error (unreadable input, bad value, ...), 2 bad command line.\n";

int modeFromName(const std::string& s)
{
    if (s == "sgm") return Matcher::MODE_SGM;
    if (s == "dsgm") return Matcher::MODE_DSGM;
    if (s == "sdsgm") return Matcher::MODE_SDSGM;
    CV_Error(Error::StsBadArg, "unknown mode '" + s + "' (sgm, dsgm, sdsgm)");
}
const char* modeLabel(int m) { return m == Matcher::MODE_SGM ? "SGM" : m == Matcher::MODE_DSGM ? "DSGM" : "SDSGM"; }
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

std::vector<std::string> split(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string t;
    while (std::getline(ss, t, ','))
        if (!t.empty())
            out.push_back(t);
    return out;
}

Ptr<Matcher> makeMatcher(const Options& o, int mode, int check, int numDisparities)
{
    Ptr<Matcher> m = Matcher::create(o.i("min-disparity", 0), o.i("num-disparities", numDisparities),
                                     o.i("P1", 10), o.i("P2", 120), o.i("Q1", 5), o.i("Q2", 160),
                                     o.d("alpha", 0.7), mode, check);
    m->setUniquenessRatio(o.d("uniqueness", 0.95));
    m->setLRMaxDiff(o.i("lr-max-diff", 1));
    m->setNumPaths(o.i("paths", 8));
    m->setSubpixel(o.i("subpixel", 1) != 0);
    m->setSemidenseRadius(o.i("rs", 6));
    m->setSemidenseThreshold(o.i("Ts", 2));
    m->setCheckRadius(o.i("rc", 20));
    m->setCheckThreshold(o.d("Tc", 2.0));
    return m;
}

Mat readGrey(const std::string& path)
{
    Mat img = imread(path, IMREAD_UNCHANGED);
    if (img.empty())
        CV_Error(Error::StsObjectNotFound, "cannot read image " + path);
    if (img.channels() == 3)
        cvtColor(img, img, COLOR_BGR2GRAY);
    else if (img.channels() == 4)
        cvtColor(img, img, COLOR_BGRA2GRAY);
    return img;
}

struct Frame
{
    std::string name;
    Mat left, right, sparse, gt;  // sparse: CV_32F pixels (0 = none); gt: float, -1 = none
};

Frame loadKittiFrame(const std::string& dir, const std::string& id)
{
    Frame f;
    f.name = id;
    f.left = readGrey(dir + "/image_2/" + id + "_10.png");
    f.right = readGrey(dir + "/image_3/" + id + "_10.png");
    KittiCalib c = readKittiCalib(dir + "/calib.txt");
    Mat pts = readVelodyne(dir + "/velodyne/" + id + ".bin");
    cv::lidarsgm::projectPointsToDisparity(pts, c.P2, c.lidarToCamera, c.focalBaseline, f.left.size(), f.sparse);
    const std::string gt = dir + "/disp_occ_0/" + id + "_10.png";
    if (!imread(gt, IMREAD_UNCHANGED).empty())
        f.gt = readKittiDisparity(gt);
    return f;
}

/* Everything --out asks for, for one frame and one mode: the disparity in the requested formats, its colour
picture, and with ground truth the error picture. */
void writeDisparity(const Options& o, const std::string& dir, const std::string& suffix, const Mat& disp16,
                    int minD, int numD, const Mat& gt)
{
    const Mat d = disparityToFloat(disp16, minD);
    const std::vector<std::string> formats = split(o.str("format", "kitti"));
    for (size_t i = 0; i < formats.size(); i++)
    {
        bool ok;
        if (formats[i] == "kitti")
            ok = imwrite(dir + "/disparity" + suffix + ".png", toKittiPng(d));
        else if (formats[i] == "pfm")
            ok = writePfm(dir + "/disparity" + suffix + ".pfm", d);
        else if (formats[i] == "s16")
            ok = writeRawS16(dir + "/disparity" + suffix + ".s16", disp16);
        else
            CV_Error(Error::StsBadArg, "unknown --format '" + formats[i] + "' (kitti, pfm, s16)");
        if (!ok)
            CV_Error(Error::StsError, "cannot write " + dir + "/disparity" + suffix + " (" + formats[i] + ")");
    }
    if (!imwrite(dir + "/disparity" + suffix + "_color.png", colorizeDisparity(d, (float)(minD + numD))))
        CV_Error(Error::StsError, "cannot write " + dir + "/disparity" + suffix + "_color.png");
    if (!gt.empty())
        imwrite(dir + "/error" + suffix + ".png", colorizeError(interpolateBackground(d), gt));
}

//! The frame's own pictures: LiDAR points over the left image, and (SDSGM) the semidense map.
void writeInputs(const std::string& dir, const Frame& f, const Ptr<Matcher>& sdsgm, int minD, bool semidense)
{
    if (f.sparse.empty())
        return;
    Mat s;
    f.sparse.convertTo(s, CV_32F, f.sparse.depth() == CV_16U ? 1.0 / 256 : 1.0);
    s.setTo(0.f, ~(s > 0));
    const float maxD = (float)(minD + sdsgm->getNumDisparities());
    if (!imwrite(dir + "/lidar_points.png", overlayPoints(f.left, s, maxD)))
        CV_Error(Error::StsError, "cannot write " + dir + "/lidar_points.png");
    if (semidense)
    {
        Mat semi;
        sdsgm->semidensify(f.left, f.right, f.sparse, semi);
        const Mat sf = disparityToFloat(semi, minD);
        imwrite(dir + "/semidense.png", toKittiPng(sf));
        imwrite(dir + "/semidense_color.png", colorizeDisparity(sf, maxD));
    }
}

void makeDir(const std::string& dir)
{
    utils::fs::createDirectories(dir);
    if (!utils::fs::isDirectory(dir))
        CV_Error(Error::StsError, "cannot create the output folder " + dir);
}

//! The progress line of folder runs (stderr): frames done, frames per second, time left.
void progress(const Options& o, size_t done, size_t total, double seconds)
{
    if (o.has("quiet"))
        return;
    const double fps = done / std::max(seconds, 1e-9);
    fprintf(stderr, "\r[%zu/%zu] frames, %.2f frames/s, %.0f s left   ", done, total, fps, (total - done) / fps);
    if (done == total)
        fprintf(stderr, "\n");
}

double medianMs(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// ---- GPU timing: CUDA events on one stream, medians after a warm-up -----------------------------------------------
double eventMedian(const std::function<void(cuda::Stream&)>& fn, int reps)
{
    cuda::Stream st;
    cuda::Event e0, e1;
    for (int i = 0; i < 3; i++)
        fn(st);
    st.waitForCompletion();
    std::vector<double> t;
    for (int i = 0; i < reps; i++)
    {
        e0.record(st);
        fn(st);
        e1.record(st);
        e1.waitForCompletion();
        t.push_back(cuda::Event::elapsedTime(e0, e1));
    }
    return medianMs(t);
}

int cudaTiming(const Options& o, const Frame& f, int reps)
{
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const int ndisp = o.i("num-disparities", 128);
    cuda::GpuMat gl(f.left), gr(f.right), gs(f.sparse), gd;
    cuda::DeviceInfo info;
    printf("device: %s, %dx%d, %d disparities, %d paths, median of %d CUDA-event timings (ms)\n", info.name(),
           f.left.cols, f.left.rows, ndisp, o.i("paths", 8), reps);
    const int modes[3] = { Matcher::MODE_SDSGM, Matcher::MODE_DSGM, Matcher::MODE_SGM };
    for (int k = 0; k < 3 * o.i("rounds", 1); k++)
    {
        Ptr<Matcher> m = makeMatcher(o, modes[k % 3], check, ndisp);
        const size_t before = info.freeMemory();
        m->compute(gl, gr, gs, gd);
        cuda::Stream::Null().waitForCompletion();
        const size_t after = info.freeMemory();
        const double ms = eventMedian([&](cuda::Stream& st) { m->compute(gl, gr, gs, gd, st); }, reps);
        printf("| lidarsgm %-5s | %8.3f ms | device memory held %.1f MB |\n", modeLabel(modes[k % 3]), ms,
               before > after ? (before - after) / 1048576.0 : 0.0);
    }
#ifdef LIDARSGM_HAVE_CUDASTEREO
    for (int paths = 8; paths >= 4; paths -= 4)
    {
        try
        {
            Ptr<cuda::StereoSGM> sgm = cuda::createStereoSGM(0, ndisp, 10, 120, 5,
                                                              paths == 8 ? cuda::StereoSGM::MODE_HH : cuda::StereoSGM::MODE_HH4);
            const size_t before = info.freeMemory();
            sgm->compute(gl, gr, gd);
            cuda::Stream::Null().waitForCompletion();
            const size_t after = info.freeMemory();
            const double ms = eventMedian([&](cuda::Stream& st) { sgm->compute(gl, gr, gd, st); }, reps);
            printf("| cv::cuda::StereoSGM %d paths | %8.3f ms | device memory held %.1f MB |\n", paths, ms,
                   before > after ? (before - after) / 1048576.0 : 0.0);
        }
        catch (const cv::Exception& e)
        {
            printf("| cv::cuda::StereoSGM %d paths | failed: %s |\n", paths, e.what());
        }
    }
#endif
    return 0;
}

// ---- one frame ---------------------------------------------------------------------------------------------------
int runFrame(const Options& o, Frame& f)
{
    const std::vector<std::string> modes = split(o.str("modes", "sdsgm"));
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const std::string out = o.str("out");
    const int minD = o.i("min-disparity", 0);
    if (!out.empty())
        makeDir(out);
    for (size_t k = 0; k < modes.size(); k++)
    {
        const int mode = modeFromName(modes[k]);
        Ptr<Matcher> m = makeMatcher(o, mode, check, 128);
        Mat disp;
        TickMeter tm;
        if (o.has("cuda"))
        {
            cuda::GpuMat gl(f.left), gr(f.right), gs, gd;
            if (!f.sparse.empty())
                gs.upload(f.sparse);
            tm.start();
            m->compute(gl, gr, gs, gd);
            gd.download(disp);
            tm.stop();
        }
        else
        {
            tm.start();
            m->compute(f.left, f.right, f.sparse, disp);
            tm.stop();
        }
        const Mat d = disparityToFloat(disp, minD);
        printf("%s %-6s check %-12s %s %8.1f ms", f.name.c_str(), modeLabel(mode), checkLabel(check),
               o.has("cuda") ? "CUDA" : "CPU ", tm.getTimeMilli());
        if (!f.gt.empty())
        {
            ErrorStats s = evaluate(d, f.gt, isD1Outlier);
            printf("  coverage %6.2f %%  covered D1 %5.2f %%  total D1 %5.2f %%", s.coverage(), s.coveredError(),
                   s.totalError());
        }
        printf("\n");
        if (!out.empty())
            writeDisparity(o, out, modes.size() > 1 ? "_" + modes[k] : "", disp, minD, m->getNumDisparities(), f.gt);
    }
    if (!out.empty())
    {
        writeInputs(out, f, makeMatcher(o, Matcher::MODE_SDSGM, check, 128), minD,
                    std::find(modes.begin(), modes.end(), "sdsgm") != modes.end());
        printf("wrote %s/: disparity (%s), colour and error pictures, LiDAR points\n", out.c_str(),
               o.str("format", "kitti").c_str());
    }

    const int reps = o.i("timing", 0);
    if (reps > 0 && o.has("cuda"))
        return cudaTiming(o, f, reps);
    if (reps > 0)
    {
        Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, check, 128);
        Ptr<StereoSGBM> sgbm = StereoSGBM::create(0, 128, 3, 72, 288, 1, 0, 10, 100, 2, StereoSGBM::MODE_HH);
        Mat disp;
        m->compute(f.left, f.right, f.sparse, disp);  // warm-up (buffers)
        sgbm->compute(f.left, f.right, disp);
        std::vector<double> tl, ts;
        for (int r = 0; r < reps; r++)
        {
            TickMeter a, b;
            a.start(); m->compute(f.left, f.right, f.sparse, disp); a.stop();
            b.start(); sgbm->compute(f.left, f.right, disp); b.stop();
            tl.push_back(a.getTimeMilli());
            ts.push_back(b.getTimeMilli());
        }
        printf("timing (%d runs, %d threads, %dx%d, 128 disparities, 8 paths): SDSGM median %.1f ms, "
               "cv::StereoSGBM MODE_HH median %.1f ms, ratio %.2f\n", reps, getNumThreads(), f.left.cols,
               f.left.rows, medianMs(tl), medianMs(ts), medianMs(tl) / medianMs(ts));
    }
    return 0;
}

// ---- KITTI folder ------------------------------------------------------------------------------------------------
struct Row
{
    std::string label;
    ErrorStats stats;
    std::vector<double> ms;
};

//! One summary row per mode, labelled "MODE (check)".
std::vector<Row> modeRows(const std::vector<std::string>& modes, int check)
{
    std::vector<Row> rows(modes.size());
    for (size_t k = 0; k < modes.size(); k++)
        rows[k].label = std::string(modeLabel(modeFromName(modes[k]))) + " (" + checkLabel(check) + ")";
    return rows;
}

void printTable(const char* title, const char* metric, const std::vector<Row>& rows)
{
    printf("\n%s\n", title);
    printf("| %-28s | coverage | covered %-5s | total %-5s | ms/frame |\n", "method", metric, metric);
    printf("|------------------------------|----------|---------------|-------------|----------|\n");
    for (size_t i = 0; i < rows.size(); i++)
    {
        const Row& r = rows[i];
        char t[32] = "-";
        if (!r.ms.empty())
            snprintf(t, sizeof(t), "%.1f", medianMs(r.ms));
        printf("| %-28s | %6.2f %% | %11.2f %% | %9.2f %% | %8s |\n", r.label.c_str(), r.stats.coverage(),
               r.stats.coveredError(), r.stats.totalError(), t);
    }
}

int runKitti(const Options& o)
{
    const std::string dir = o.str("kitti");
    std::ifstream list((dir + "/frames.txt").c_str());
    if (!list)
        CV_Error(Error::StsObjectNotFound, "cannot open " + dir + "/frames.txt");
    std::vector<std::string> ids;
    std::string id;
    while (list >> id)
        ids.push_back(id);
    const std::vector<std::string> modes = split(o.str("modes", "sgm,dsgm,sdsgm"));
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const bool table5 = o.has("table5");
    const int minD = o.i("min-disparity", 0);

    std::vector<Row> rows = modeRows(modes, check);
    std::vector<Row> t5(4);
    for (int c = 0; c < 4; c++)
        t5[c].label = std::string("SDSGM (") + checkLabel(c) + ")";
    Row lidar, semi;
    lidar.label = "LiDAR points alone";
    semi.label = "semidense map (SDSGM input)";

    const std::string out = o.str("out");
    if (ids.empty())
        CV_Error(Error::StsObjectNotFound, dir + "/frames.txt lists no frame");
    TickMeter total;
    total.start();
    for (size_t n = 0; n < ids.size(); n++)
    {
        Frame f = loadKittiFrame(dir, ids[n]);
        if (f.gt.empty())
            CV_Error(Error::StsObjectNotFound, "no ground truth for frame " + ids[n]);
        const std::string frameOut = out.empty() ? "" : out + "/" + ids[n];
        if (!frameOut.empty())
            makeDir(frameOut);
        for (size_t k = 0; k < modes.size(); k++)
        {
            Ptr<Matcher> m = makeMatcher(o, modeFromName(modes[k]), check, 128);
            Mat disp;
            TickMeter tm;
            tm.start();
            m->compute(f.left, f.right, f.sparse, disp);
            tm.stop();
            rows[k].stats.add(evaluate(disparityToFloat(disp, minD), f.gt, isD1Outlier));
            rows[k].ms.push_back(tm.getTimeMilli());
            if (!frameOut.empty())
                writeDisparity(o, frameOut, "_" + modes[k], disp, minD, m->getNumDisparities(), f.gt);
        }
        if (table5)
            for (int c = 0; c < 4; c++)
            {
                Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, c, 128);
                Mat disp;
                m->compute(f.left, f.right, f.sparse, disp);
                t5[c].stats.add(evaluate(disparityToFloat(disp, minD), f.gt, isD1Outlier));
            }
        Mat sp = f.sparse.clone();
        sp.setTo(-1.f, f.sparse <= 0);
        lidar.stats.add(evaluate(sp, f.gt, isD1Outlier));
        Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, check, 128);
        Mat sd;
        m->semidensify(f.left, f.right, f.sparse, sd);
        semi.stats.add(evaluate(disparityToFloat(sd, minD), f.gt, isD1Outlier, false));
        if (!frameOut.empty())
            writeInputs(frameOut, f, m, minD, true);
        total.stop();
        progress(o, n + 1, ids.size(), total.getTimeSec());
        total.start();
    }
    char title[256];
    snprintf(title, sizeof(title), "KITTI %s: %zu frames, D1 (KITTI devkit rules), sums over frames, %d threads",
             dir.c_str(), ids.size(), getNumThreads());
    rows.push_back(lidar);
    printTable(title, "D1", rows);
    printf("| %-28s | %6.2f %% | %11.2f %% | %11s | %8s |\n", semi.label.c_str(), semi.stats.coverage(),
           semi.stats.coveredError(), "-", "-");
    if (table5)
        printTable("Consistency checks on SDSGM (the paper's Table V)", "D1", t5);
    return 0;
}

// ---- Middlebury folder -------------------------------------------------------------------------------------------
bool loadMiddleburyScene(const std::string& dir, const std::string& name, Frame& f)
{
    f.name = name;
    return loadMiddlebury(dir + "/" + name, f.left, f.right, f.gt);
}

int runMiddlebury(const Options& o)
{
    const std::string dir = o.str("middlebury");
    // cv::glob lists files: the scenes are the folders that hold them, one level down.
    std::vector<String> files;
    glob(dir + "/*", files, true);
    std::set<std::string> folders;
    for (size_t i = 0; i < files.size(); i++)
    {
        const std::string rel = files[i].substr(dir.size() + 1);
        const size_t slash = rel.find('/');
        if (slash != std::string::npos && rel.find('/', slash + 1) == std::string::npos)
            folders.insert(rel.substr(0, slash));
    }
    std::vector<Frame> scenes;
    for (std::set<std::string>::const_iterator it = folders.begin(); it != folders.end(); ++it)
    {
        Frame f;
        if (loadMiddleburyScene(dir, *it, f))
            scenes.push_back(f);
    }
    const std::vector<std::string> modes = split(o.str("modes", "sgm,dsgm,sdsgm"));
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    const int seed = o.i("seed", 1);
    const float badN = (float)o.d("bad", 2.0);
    printf("Middlebury %s: 1 %% of the ground truth as sparse input (seed %d), bad-%.0f errors, check %s\n",
           dir.c_str(), seed, badN, checkLabel(check));
    if (scenes.empty())
        CV_Error(Error::StsObjectNotFound, "no Middlebury scene (im0/im1/disp0.pfm, im2/im6/disp2.png, "
                                           "view1/view5/disp1.png) in the folders of " + dir);
    printf("| %-20s | ndisp | %-6s | coverage | covered bad | total bad |       ms |\n", "scene", "mode");
    printf("|----------------------|-------|--------|----------|-------------|-----------|----------|\n");
    std::vector<Row> rows = modeRows(modes, check);
    const std::string out = o.str("out");
    const int minD = o.i("min-disparity", 0);
    TickMeter total;
    total.start();
    for (size_t s = 0; s < scenes.size(); s++)
    {
        Frame& f = scenes[s];
        const std::string frameOut = out.empty() ? "" : out + "/" + f.name;
        if (!frameOut.empty())
            makeDir(frameOut);
        double maxGt = 0;
        minMaxLoc(f.gt, nullptr, &maxGt);
        const int ndisp = std::min(256, std::max(64, ((int)std::ceil(maxGt) + 1 + 15) / 16 * 16));
        f.sparse = sampleGroundTruth(f.gt, 0.01, (uint64)seed);  // 1 % of the ground truth, fixed seed
        for (size_t k = 0; k < modes.size(); k++)
        {
            Ptr<Matcher> m = makeMatcher(o, modeFromName(modes[k]), check, ndisp);  // --num-disparities overrides ndisp
            Mat disp;
            TickMeter tm;
            tm.start();
            m->compute(f.left, f.right, f.sparse, disp);
            tm.stop();
            rows[k].ms.push_back(tm.getTimeMilli());
            BadN bad = { badN };
            ErrorStats st = evaluate(disparityToFloat(disp, minD), f.gt, bad);
            rows[k].stats.add(st);
            printf("| %-20s | %5d | %-6s | %6.2f %% | %9.2f %% | %7.2f %% | %8.1f |\n", f.name.c_str(), ndisp,
                   modeLabel(modeFromName(modes[k])), st.coverage(), st.coveredError(), st.totalError(), tm.getTimeMilli());
            fflush(stdout);
            if (!frameOut.empty())
            {
                writeDisparity(o, frameOut, "_" + modes[k], disp, minD, m->getNumDisparities(), Mat());
                if (k == 0)
                    writeInputs(frameOut, f, makeMatcher(o, Matcher::MODE_SDSGM, check, ndisp), minD, true);
            }
        }
        total.stop();
        progress(o, s + 1, scenes.size(), total.getTimeSec());
        total.start();
    }
    char title[256];
    snprintf(title, sizeof(title), "Middlebury %s: %zu scenes, bad-%g (sums over scenes), %d threads", dir.c_str(),
             scenes.size(), badN, getNumThreads());
    printTable(title, format("bad-%g", badN).c_str(), rows);
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    Options o;
    for (int i = 1; i < argc; i++)
    {
        std::string a = argv[i];
        if (a == "--help" || a == "-h")
        {
            printf("%s", kHelp);
            return 0;
        }
        if (a.size() < 3 || a.compare(0, 2, "--") != 0)
        {
            fprintf(stderr, "lidarsgm_fuse: unexpected argument '%s' (see --help)\n", a.c_str());
            return 2;
        }
        a = a.substr(2);
        const bool flag = a == "table5";
        if (!flag && i + 1 >= argc)
        {
            fprintf(stderr, "lidarsgm_fuse: option --%s needs a value (see --help)\n", a.c_str());
            return 2;
        }
        if (std::find(std::begin(kOptions), std::end(kOptions), a) == std::end(kOptions))
        {
            fprintf(stderr, "lidarsgm_fuse: unknown option --%s (see --help)\n", a.c_str());
            return 2;
        }
        o.kv[a] = flag ? "1" : argv[++i];
    }
    try
    {
        if (o.has("threads"))
            setNumThreads(o.i("threads", -1));
        if (o.has("kitti"))
            return runKitti(o);
        if (o.has("middlebury"))
            return runMiddlebury(o);
        Frame f;
        if (o.has("kitti-frame"))
        {
            f = loadKittiFrame(o.str("kitti-frame"), o.str("id", "000002"));
            if (o.has("resize"))
            {
                // Speed runs at other sizes: the frame scaled (LiDAR disparities scaled with the width).
                int w = 0, h = 0;
                if (sscanf(o.str("resize").c_str(), "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0)
                    CV_Error(Error::StsBadArg, "--resize takes WIDTHxHEIGHT");
                const double sx = (double)w / f.left.cols;
                resize(f.left, f.left, Size(w, h), 0, 0, INTER_LINEAR);
                resize(f.right, f.right, Size(w, h), 0, 0, INTER_LINEAR);
                resize(f.sparse, f.sparse, Size(w, h), 0, 0, INTER_NEAREST);
                f.sparse *= sx;
                f.gt.release();
            }
        }
        else if (o.has("left") && o.has("right"))
        {
            f.name = o.str("left");
            f.left = readGrey(o.str("left"));
            f.right = readGrey(o.str("right"));
            if (o.has("sparse"))
            {
                Mat s = imread(o.str("sparse"), IMREAD_UNCHANGED);
                if (s.empty())
                    CV_Error(Error::StsObjectNotFound, "cannot read sparse disparity " + o.str("sparse"));
                f.sparse = s;
            }
            else if (o.has("velodyne") && o.has("calib"))
            {
                KittiCalib c = readKittiCalib(o.str("calib"));
                cv::lidarsgm::projectPointsToDisparity(readVelodyne(o.str("velodyne")), c.P2, c.lidarToCamera,
                                                       c.focalBaseline, f.left.size(), f.sparse);
            }
            if (o.has("gt"))
                f.gt = readKittiDisparity(o.str("gt"));
        }
        else
        {
            fprintf(stderr, "lidarsgm_fuse: give --kitti-frame, --left/--right, --kitti or --middlebury (see --help)\n");
            return 2;
        }
        return runFrame(o, f);
    }
    catch (const cv::Exception& e)
    {
        fprintf(stderr, "lidarsgm_fuse: error: %s\n", e.err.c_str());
        return 1;
    }
}
