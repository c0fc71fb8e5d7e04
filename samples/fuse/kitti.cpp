// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Folder runs: every frame of a KITTI-layout folder (frames.txt) or of a KITTI raw drive (in order) with each mode,
// sums of the devkit's counts over the frames where there is ground truth, one summary table per LiDAR line count
// (the paper's Tables III-VI). A frame that cannot be read or computed is reported and skipped; the run goes on and
// exits with 1 at the end. With --out each frame's counts go to <frame>/metrics.yml, written last, so --resume can
// take a finished frame's counts instead of computing it again.

#include "tool.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

using namespace cv;

namespace lidarsgm_fuse {

std::vector<Row*> PassRows::all()
{
    std::vector<Row*> r;
    for (Row& m : modes) r.push_back(&m);
    r.push_back(&lidar);
    r.push_back(&semi);
    for (Row& t : table5) r.push_back(&t);
    return r;
}

namespace {

//! The frame's folder, without the partial files of a run killed mid-write.
void prepareFrameDir(const std::string& dir)
{
    makeDir(dir);
    std::vector<String> names;
    utils::fs::glob(dir, ".*.partial-*", names);
    for (const String& n : names)
        std::remove(n.c_str());
}

//! The options that decide a frame's results (not the output folder, the device, threads, the progress line).
std::string optionsKey(const Options& o)
{
    std::string key;
    for (const auto& kv : o.kv)
        if (kv.first != "out" && kv.first != "quiet" && kv.first != "threads" && kv.first != "resume" &&
            kv.first != "streams" && kv.first != "cuda" &&   // CPU and CUDA outputs are the same
            kv.first != "check-calibration")
            key += "--" + kv.first + " " + kv.second + " ";
    return key;
}

void writeMetrics(const std::string& path, const std::string& key, PassRows& fr)
{
    writeAtomically(path, [&](const std::string& tmp) {
        FileStorage fs(tmp, FileStorage::WRITE);
        fs << "options" << key << "rows" << "[";
        for (const Row* r : fr.all())
            fs << "{" << "label" << r->label << "gt" << (double)r->stats.groundTruthPixels
               << "est" << (double)r->stats.estimatedPixels << "estBad" << (double)r->stats.estimatedOutliers
               << "totalBad" << (double)r->stats.totalOutliers << "ms" << (r->ms.empty() ? -1.0 : r->ms[0]) << "}";
        fs << "]";
        fs << "matchingResidual" << fr.residual << "residualFailure" << fr.residualFailure
           << "shiftedResidual" << fr.shiftedResidual << "shift" << fr.shift << "turn" << fr.turn
           << "misplaced" << (int)fr.misplaced
           << "stereoAlone" << (int)fr.stereoAlone;
        return fs.isOpened();
    });
}

//! A finished frame's rows from its metrics.yml; false where the file cannot be taken (why says so).
bool readMetrics(const std::string& path, const std::string& key, PassRows& fr, std::string& why)
{
    why = " was written with other options";
    FileStorage fs(path, FileStorage::READ);
    if ((std::string)fs["options"] != key)
        return false;
    FileNode rows = fs["rows"];
    std::vector<Row*> all = fr.all();
    if ((int)rows.size() != (int)all.size())
        return false;
    for (size_t i = 0; i < all.size(); i++)
    {
        const FileNode n = rows[(int)i];
        if ((std::string)n["label"] != all[i]->label)
            return false;
        all[i]->stats.groundTruthPixels = (int64)(double)n["gt"];
        all[i]->stats.estimatedPixels = (int64)(double)n["est"];
        all[i]->stats.estimatedOutliers = (int64)(double)n["estBad"];
        all[i]->stats.totalOutliers = (int64)(double)n["totalBad"];
        // Its time ("ms") stays out: the summary times only the frames this run computes.
    }
    if (!fs["matchingResidual"].empty())
    {
        fr.residual = (double)fs["matchingResidual"];
        fr.residualFailure = (std::string)fs["residualFailure"];
    }
    // The summary needs the frame's LiDAR check verdict (misplaced): a file without one cannot be taken.
    why = " was written by an earlier version of the tool, without the frame's LiDAR check";
    if (fs["misplaced"].empty())
        return false;
    fr.shiftedResidual = (double)fs["shiftedResidual"];
    fs["shift"] >> fr.shift;
    fr.turn = fs["turn"].empty() ? 0.0 : (double)fs["turn"];   // absent: no turn searched
    fr.misplaced = (int)fs["misplaced"] != 0;
    fr.stereoAlone = (int)fs["stereoAlone"] != 0;
    return true;
}

//! Where a folder run's frames come from: their names and how to load one (with the LiDAR rings given); the
//! loader raises cv::Exception for a frame that cannot be read, or lacks ground truth its source requires.
struct FrameSource
{
    std::string label;   //!< "KITTI DIR" or "KITTI raw DRIVE", for the table's title
    std::vector<std::string> ids;
    std::function<Frame(const std::string& id, LidarRings rings)> load;
};

//! What a frame gave: its rows, or why it failed; whether it was taken from an earlier run.
struct FrameResult
{
    PassRows rows;
    std::string failure;
    bool resumed = false;
};

//! A pass's rows with their labels and nothing counted: one per mode, the LiDAR alone, the semidense map, Table V's.
PassRows passRows(const Options& o)
{
    const std::vector<std::string> modes = o.list("modes", "sgm,dsgm,sdsgm");
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    PassRows sums;
    sums.modes.resize(modes.size());
    for (size_t k = 0; k < modes.size(); k++)
        sums.modes[k].label = std::string(modeLabel(modeFromName(modes[k]))) + " (" + checkLabel(check) + ")";
    for (int c = 0; o.has("table5") && c < 4; c++)
    {
        sums.table5.push_back(Row());
        sums.table5.back().label = std::string("SDSGM (") + checkLabel(c) + ")";
    }
    sums.lidar.label = "LiDAR points alone";
    sums.semi.label = "semidense map (SDSGM input)";
    return sums;
}

/* The frames of a pass into results (labels from rows): they go to --streams workers (default 1), each on its own
thread taking the next frame when done with one, so that reading and writing on the CPU overlap the other workers'
matching. A frame with --resume and a metrics.yml is taken from it; a frame that fails keeps why. total: the pass's
time so far, for the progress line. */
void computeFrames(const Options& o, const FrameSource& src, int lines, bool lineTitle, const PassRows& rows,
                   std::vector<FrameResult>& results, TickMeter& total)
{
    const std::vector<std::string>& ids = src.ids;
    const std::string out = o.str("out"), key = optionsKey(o);
    results.assign(ids.size(), FrameResult());
    std::atomic<size_t> next(0);
    size_t done = 0, computedSoFar = 0;
    std::mutex progressLock;
    auto runOne = [&](FrameWorker& worker, size_t n) {
        const std::string frameOut =
            out.empty() ? "" : out + "/" + ids[n] + (lineTitle ? format("_%dlines", lines) : "");
        const std::string metrics = frameOut + "/metrics.yml";
        FrameResult& res = results[n];
        res.rows = rows;   // labels; counts and times start empty
        try
        {
            if (o.has("resume") && utils::fs::exists(metrics))
            {
                std::string why;
                if (!readMetrics(metrics, key, res.rows, why))
                    CV_Error(Error::StsBadArg, metrics + why + " (rerun without --resume, or into another --out)");
                res.resumed = true;
            }
            else
            {
                const Frame f = src.load(ids[n], lidarRings(o, lines));
                if (!frameOut.empty())
                    prepareFrameDir(frameOut);
                worker.compute(f, frameOut, res.rows);
                if (!frameOut.empty())
                    writeMetrics(metrics, key, res.rows);
            }
        }
        catch (const std::exception& e)
        {
            const cv::Exception* ce = dynamic_cast<const cv::Exception*>(&e);
            res.failure = ce ? ce->err : std::string(e.what());
        }
        std::lock_guard<std::mutex> lock(progressLock);
        if (!res.failure.empty() && !o.has("quiet"))
            fprintf(stderr, "\nlidarsgm_fuse: frame %s skipped: %s\n", ids[n].c_str(), res.failure.c_str());
        if (res.failure.empty() && !res.resumed)
            computedSoFar++;
        total.stop();
        progress(o, ++done, computedSoFar, ids.size(), total.getTimeSec());
        total.start();
    };
    std::exception_ptr workerError;   // a worker that cannot start (no CUDA device, ...): the first one's reason
    auto work = [&]() {
        try
        {
            FrameWorker worker(o);
            for (size_t n; (n = next++) < ids.size(); )
                runOne(worker, n);
        }
        catch (...)
        {
            std::lock_guard<std::mutex> lock(progressLock);
            if (!workerError)
                workerError = std::current_exception();
            next = ids.size();   // the others stop after their frame
        }
    };
    std::vector<std::thread> threads;
    for (int t = 1; t < o.i("streams", 1); t++)
        threads.emplace_back(work);
    work();
    for (std::thread& t : threads)
        t.join();
    if (workerError)
        std::rethrow_exception(workerError);
}

//! The pass's tables from sums (scored: some frame has ground truth), its confidence and residual lines.
void printPass(const Options& o, const FrameSource& src, int lines, bool lineTitle, const PassRows& sums,
               size_t computed, size_t resumed, bool scored)
{
    const std::string title = format("%s: %zu frames%s, D1 (KITTI devkit rules), sums over frames, %s",
                                     src.label.c_str(), computed + resumed,
                                     lineTitle ? format(", %d LiDAR lines", lines).c_str() : "",
                                     o.has("cuda") ? format("CUDA, %d stream(s), ms = GPU time per call",
                                                            o.i("streams", 1)).c_str()
                                                   : format("CPU, %d threads", getNumThreads()).c_str());
    std::vector<Row> table = sums.modes;
    if (computed + resumed == 0)
        printf("\n%s: no frame to sum, every frame failed (the reasons follow)\n", src.label.c_str());
    else if (scored)
    {
        table.push_back(sums.lidar);
        printTable(title, "D1", table);
        printf("| %-28s | %6.2f %% | %11.2f %% | %11s | %8s |\n", sums.semi.label.c_str(),
               sums.semi.stats.coverage(), sums.semi.stats.coveredError(), "-", "-");
    }
    else
        printTimes(title.substr(0, title.find(", D1")) + ", no ground truth", table);
    if (scored && !sums.table5.empty())
        printTable("Consistency checks on SDSGM (the paper's Table V)", "D1", sums.table5);
    for (const Row& r : sums.modes)
        printConfidence(r, "D1", format("%zu computed frames", computed));
}

/* One pass over the frames (computeFrames); failed frames are appended to failures ("id: why"). The sums are taken in
frame order at the end. */
void kittiPass(const Options& o, const FrameSource& src, int lines, bool lineTitle, std::vector<std::string>& failures)
{
    const std::vector<std::string>& ids = src.ids;
    PassRows sums = passRows(o);
    std::vector<FrameResult> results;
    TickMeter total;
    total.start();
    computeFrames(o, src, lines, lineTitle, sums, results, total);

    size_t computed = 0, resumed = 0, failed = 0;
    bool scored = false;
    std::vector<std::pair<std::string, const PassRows*> > residuals;
    for (size_t n = 0; n < ids.size(); n++)
    {
        FrameResult& res = results[n];
        if (!res.failure.empty())
        {
            failed++;
            failures.push_back(ids[n] + (lineTitle ? format(" (%d lines)", lines) : "") + ": " + res.failure);
            continue;
        }
        (res.resumed ? resumed : computed)++;
        residuals.push_back(std::make_pair(ids[n], &res.rows));
        scored = scored || res.rows.lidar.stats.groundTruthPixels > 0;
        std::vector<Row*> all = sums.all(), one = res.rows.all();
        for (size_t i = 0; i < all.size(); i++)
        {
            all[i]->stats.add(one[i]->stats);
            all[i]->confidence.add(one[i]->confidence);
            all[i]->ms.insert(all[i]->ms.end(), one[i]->ms.begin(), one[i]->ms.end());
        }
    }
    total.stop();
    printPass(o, src, lines, lineTitle, sums, computed, resumed, scored);
    printResiduals(residuals);
    // A rate only of frames computed here: frames taken from an earlier run cost nothing to read back.
    printf("frames: %zu computed, %zu taken from earlier runs (--resume), %zu failed%s\n", computed, resumed, failed,
           computed ? format("; %.2f frames/s computed", computed / std::max(total.getTimeSec(), 1e-9)).c_str() : "");
}

//! Every pass of a folder run (one per LiDAR line count), then the failed frames; 1 where a frame failed.
int runPasses(const Options& o, const FrameSource& src)
{
    std::vector<std::string> failures;
    const std::vector<int> lines = lidarLineCounts(o);
    for (int n : lines)
        kittiPass(o, src, n, lines.size() > 1 || n != 64, failures);
    if (failures.empty())
        return 0;
    fprintf(stderr, "lidarsgm_fuse: %zu frame(s) failed:\n", failures.size());
    for (const std::string& f : failures)
        fprintf(stderr, "  %s\n", f.c_str());
    return 1;
}


/** --check-calibration, --refine-calibration: the LiDAR-to-camera transform measured against the stereo pairs of
the frames given (cv::lidarsgm::LidarCalibration); prints the residual and, when refining, the correction, and
returns the calibration the run fuses with (calib itself, or corrected). A frame that cannot be read is left out;
a refinement the data cannot support (refine() refuses), or a LiDAR still far from the stereo pairs after it, sets
stereoOnly: the run then fuses nothing and gives stereo alone, saying so, rather than fusing with a guess. */
lidarsgm::KittiCalibration calibrationFromData(const Options& o, const lidarsgm::KittiCalibration& calib, const std::vector<std::string>& ids,
                               const std::function<FramePaths(const std::string&)>& paths, bool& stereoOnly)
{
    stereoOnly = false;
    if (!o.has("check-calibration") && !o.has("refine-calibration"))
        return calib;
    TickMeter tm;
    tm.start();
    Ptr<lidarsgm::LidarCalibration> cal =
        lidarsgm::LidarCalibration::create(calib.projection, calib.focalBaseline, 128, o.d("scan-rate", 10));
    for (const std::string& id : ids)
    {
        try
        {
            const FramePaths p = paths(id);
            cal->addFrame(readGrey(p.left), readGrey(p.right), lidarsgm::readVelodyneScan(p.scan));
        }
        catch (const cv::Exception& e)
        {
            fprintf(stderr, "lidarsgm_fuse: frame %s left out of the calibration: %s\n", id.c_str(), e.err.c_str());
        }
    }
    if (cal->getNumFrames() == 0)
        CV_Error(Error::StsError, "no frame could be read for the calibration");
    printf("calibration residual: %.3f px (median |LiDAR - stereo disparity|, %d frames)\n",
           cal->residual(calib.lidarToCamera), cal->getNumFrames());
    if (!o.has("refine-calibration"))
        return calib;
    lidarsgm::CalibrationCorrection c;
    try
    {
        c = cal->refine(calib.lidarToCamera, o.has("refine-translation"));
    }
    catch (const cv::Exception& e)
    {
        printf("calibration refinement refused: %s\nthe LiDAR is left out: stereo alone (SGM, left-right check)\n",
               e.err.c_str());
        stereoOnly = true;
        return calib;
    }
    tm.stop();
    const double k = 180 / CV_PI;
    printf("calibration correction (camera frame, degrees): pitch %+.3f +- %.3f, yaw %+.3f +- %.3f, roll %+.3f +- %.3f",
           c.rotation[0] * k, c.rotationStd[0] * k, c.rotation[1] * k, c.rotationStd[1] * k, c.rotation[2] * k,
           c.rotationStd[2] * k);
    if (o.has("refine-translation"))
        printf(", x %+.3f +- %.3f m", c.translation[0], c.translationStd[0]);
    printf("\ncalibration residual after the correction: %.3f px (%d points, %d frames, %.2f s)\n", c.residualAfter,
           c.points, c.frames, tm.getTimeSec());
    // A LiDAR that stays more than one disparity step (the DDC's Q1 band) from the stereo match at most of its
    // points steers the fusion wrong instead of helping it: it is left out.
    if (c.residualAfter > lidarsgm::LidarFailSafe::maxResidual())
    {
        printf("the corrected calibration still leaves the LiDAR %.3f px (median) from the stereo pairs, more than "
               "%.1f px: the LiDAR is left out: stereo alone (SGM, left-right check)\n", c.residualAfter,
               lidarsgm::LidarFailSafe::maxResidual());
        stereoOnly = true;
    }
    lidarsgm::KittiCalibration refined = calib;
    refined.lidarToCamera = c.lidarToCamera;
    return refined;
}

//! The run's options with the LiDAR left out: one row, the fail-safe's stereo-alone matcher on every frame.
Options stereoAlone(const Options& o)
{
    Options s = o;
    const int mode0 = modeFromName(o.list("modes", "sgm,dsgm,sdsgm").front());
    const Ptr<Matcher> alone = lidarsgm::LidarFailSafe::stereoAloneMatcher(
        makeMatcher(o, mode0, checkFromName(o.str("check", "stereo-lidar"))));
    s.kv["modes"] = modeName(alone->getMode());
    s.kv["check"] = checkLabel(alone->getConsistencyCheck());
    s.kv[kLidarLeftOut] = "1";
    s.kv.erase("table5");
    return s;
}

} // namespace

int runKittiFolder(const Options& o)
{
    const std::string dir = o.str("kitti");
    FrameSource src;
    src.label = "KITTI " + dir;
    src.ids = lidarsgm::readKittiFrameIds(dir);
    if (src.ids.empty())
        CV_Error(Error::StsObjectNotFound, dir + "/frames.txt lists no frame");
    bool stereoOnly = false;
    const lidarsgm::KittiCalibration calib = calibrationFromData(o, lidarsgm::readKittiCalibration(dir + "/calib.txt"), src.ids,
        [&dir](const std::string& id) { return kittiFramePaths(dir, id); }, stereoOnly);
    src.load = [dir, calib](const std::string& id, LidarRings rings) {
        Frame f = lidarsgm::loadKittiFrame(dir, id, calib, rings.every, rings.first);
        if (f.groundTruth.empty())
            CV_Error(Error::StsObjectNotFound, "no ground truth " + dir + "/disp_occ_0/" + id + "_10.png");
        return f;
    };
    return runPasses(stereoOnly ? stereoAlone(o) : o, src);
}

int runKittiRaw(const Options& o)
{
    const std::string drive = o.str("kitti-raw"), gtDir = o.str("gt-depth");
    // The calibration is the drive's, read once: a missing file or key stops the run before any frame.
    bool stereoOnly = false;
    const lidarsgm::KittiCalibration given = lidarsgm::readKittiRawDriveCalibration(drive);
    FrameSource src;
    src.label = "KITTI raw " + drive;
    src.ids = lidarsgm::readKittiRawFrameNames(drive);
    // A drive pools 20 of its frames, spread evenly over it, for the calibration.
    std::vector<std::string> pool;
    const size_t poolSize = std::min<size_t>(20, src.ids.size());
    for (size_t k = 0; k < poolSize; k++)
        pool.push_back(src.ids[k * src.ids.size() / poolSize]);
    const lidarsgm::KittiCalibration calib = calibrationFromData(o, given, pool,
        [&drive](const std::string& id) { return kittiRawFramePaths(drive, id); }, stereoOnly);
    src.load = [drive, calib, gtDir](const std::string& id, LidarRings rings) {
        Frame f = lidarsgm::loadKittiRawFrame(drive, id, calib, rings.every, rings.first);
        if (!gtDir.empty())
            f.groundTruth = lidarsgm::readKittiDepthAsDisparity(gtDir + "/" + id + ".png", calib.focalBaseline);
        return f;
    };
    return runPasses(stereoOnly ? stereoAlone(o) : o, src);
}

int runRigFolder(const Options& o)
{
    const std::string dir = o.str("rig-folder");
    // The rig is read once: a bad file stops the run before any frame.
    const Ptr<lidarsgm::StereoRig> rig = lidarsgm::StereoRig::fromFile(dir + "/rig.yml");
    FrameSource src;
    src.label = "rig " + dir;
    std::vector<String> lefts;
    glob(dir + "/left/*.png", lefts, false);
    for (const String& p : lefts)
    {
        const size_t slash = p.find_last_of("/\\");
        src.ids.push_back(p.substr(slash + 1, p.size() - slash - 1 - 4));
    }
    std::sort(src.ids.begin(), src.ids.end());
    if (src.ids.empty())
        CV_Error(Error::StsObjectNotFound, "no frame: " + dir + "/left/ holds no .png");
    src.load = [dir, rig](const std::string& id, LidarRings rings) {
        Frame f;
        f.name = id;
        Mat leftRect, rightRect;
        rig->rectify(readImage(dir + "/left/" + id + ".png"), readGrey(dir + "/right/" + id + ".png"), leftRect,
                     rightRect);
        f.leftImage = leftRect;
        f.left = toGrey(leftRect);
        f.right = rightRect;
        std::string cloud;
        for (const char* ext : { ".pcd", ".ply", ".bin" })
            if (cloud.empty() && utils::fs::exists(dir + "/points/" + id + ext))
                cloud = dir + "/points/" + id + ext;
        if (cloud.empty())
            CV_Error(Error::StsObjectNotFound, "no cloud " + dir + "/points/" + id + ".pcd (or .ply, .bin)");
        // Rings by the scan's order, as for KITTI scans (--lidar-lines): clouds saved in the driver's order.
        rig->projectCloud(lidarsgm::selectLidarRings(lidarsgm::readPointCloud(cloud), rings.every, rings.first),
                          f.sparse);
        f.calibration = rig->getCalibration();
        const std::string gt = dir + "/gt/" + id + ".png";
        if (utils::fs::exists(gt))
            f.groundTruth = lidarsgm::readKittiDisparity(gt);
        return f;
    };
    return runPasses(o, src);
}

} // namespace lidarsgm_fuse
