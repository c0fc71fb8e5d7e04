// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// A KITTI-layout folder: every frame of frames.txt with each mode, sums of the devkit's counts over the frames, one
// summary table per LiDAR line count (the paper's Tables III-VI). A frame that cannot be read or computed is reported
// and skipped; the run goes on and exits with 1 at the end. With --out each frame's counts go to <frame>/metrics.yml,
// written last, so --resume can take a finished frame's counts instead of computing it again.

#include "tool.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <cstdio>

using namespace cv;
using namespace lidarsgm_data;

namespace lidarsgm_fuse {

namespace {

lidarsgm::DisparityErrors score(const Mat& disp, const Mat& gt, int minD)
{
    return lidarsgm::evaluateDisparity(disp, gt, lidarsgm::METRIC_KITTI_D1, 0, minD);
}

//! The rows of one pass: the modes, the LiDAR points, the semidense map, Table V.
struct PassRows
{
    std::vector<Row> modes, table5;
    Row lidar, semi;
    std::vector<Row*> all()
    {
        std::vector<Row*> r;
        for (Row& m : modes) r.push_back(&m);
        r.push_back(&lidar);
        r.push_back(&semi);
        for (Row& t : table5) r.push_back(&t);
        return r;
    }
};

//! One frame's rows, computed (and its files written when there is a folder for it).
void computeFrame(const Options& o, const Frame& f, const std::string& frameOut, PassRows& fr)
{
    const std::vector<std::string> modes = o.list("modes", "sgm,dsgm,sdsgm");
    const int check = checkFromName(o.str("check", "stereo-lidar"));
    for (size_t k = 0; k < modes.size(); k++)
    {
        Ptr<Matcher> m = makeMatcher(o, modeFromName(modes[k]), check);
        Mat disp;
        TickMeter tm;
        tm.start();
        m->compute(f.left, f.right, f.sparse, disp);
        tm.stop();
        fr.modes[k].stats = score(disp, f.gt, m->getMinDisparity());
        fr.modes[k].ms.push_back(tm.getTimeMilli());
        if (!frameOut.empty())
            writeDisparity(o, frameOut, "_" + modes[k], disp, m->getMinDisparity(), m->getNumDisparities(), f.gt);
    }
    for (size_t c = 0; c < fr.table5.size(); c++)
    {
        Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, (int)c);
        Mat disp;
        m->compute(f.left, f.right, f.sparse, disp);
        fr.table5[c].stats = score(disp, f.gt, m->getMinDisparity());
    }
    Mat sp = f.sparse.clone();
    sp.setTo(-1.f, f.sparse <= 0);
    fr.lidar.stats = score(sp, f.gt, 0);
    Ptr<Matcher> m = makeMatcher(o, Matcher::MODE_SDSGM, check);
    Mat sd;
    m->semidensify(f.left, f.right, f.sparse, sd);
    fr.semi.stats = score(sd, f.gt, m->getMinDisparity());
    if (!frameOut.empty())
        writeInputs(frameOut, f, m, true);
}

//! The frame's folder, without the partial files of a run killed mid-write.
void prepareFrameDir(const std::string& dir)
{
    makeDir(dir);
    std::vector<String> names;
    utils::fs::glob(dir, ".*.partial-*", names);
    for (const String& n : names)
        std::remove(n.c_str());
}

//! The options that decide a frame's results (not the output folder, the threads, the progress line).
std::string optionsKey(const Options& o)
{
    std::string key;
    for (const auto& kv : o.kv)
        if (kv.first != "out" && kv.first != "quiet" && kv.first != "threads" && kv.first != "resume")
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
        return fs.isOpened();
    });
}

//! A finished frame's rows from its metrics.yml; false where the file was written with other options.
bool readMetrics(const std::string& path, const std::string& key, PassRows& fr)
{
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
        if ((double)n["ms"] >= 0)
            all[i]->ms.push_back((double)n["ms"]);
    }
    return true;
}

//! One pass over the frames; failed frames are appended to failures ("id: why").
void kittiPass(const Options& o, const std::vector<std::string>& ids, int lines, bool lineTitle,
               std::vector<std::string>& failures)
{
    const std::string dir = o.str("kitti"), out = o.str("out"), key = optionsKey(o);
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

    size_t computed = 0, resumed = 0, failed = 0;
    TickMeter total;
    total.start();
    for (size_t n = 0; n < ids.size(); n++)
    {
        const std::string frameOut = out.empty() ? "" : out + "/" + ids[n] + (lineTitle ? format("_%dlines", lines) : "");
        const std::string metrics = frameOut + "/metrics.yml";
        PassRows fr = sums;   // labels; counts and times start empty
        for (Row* r : fr.all())
        {
            r->stats = lidarsgm::DisparityErrors();
            r->ms.clear();
        }
        try
        {
            if (o.has("resume") && utils::fs::exists(metrics))
            {
                if (!readMetrics(metrics, key, fr))
                    CV_Error(Error::StsBadArg, metrics + " was written with other options (rerun without --resume, "
                                               "or into another --out)");
                resumed++;
            }
            else
            {
                const Frame f = loadKittiFrame(dir, ids[n], 64 / lines);
                if (f.gt.empty())
                    CV_Error(Error::StsObjectNotFound, "no ground truth " + dir + "/disp_occ_0/" + ids[n] + "_10.png");
                if (!frameOut.empty())
                    prepareFrameDir(frameOut);
                computeFrame(o, f, frameOut, fr);
                if (!frameOut.empty())
                    writeMetrics(metrics, key, fr);
                computed++;
            }
            std::vector<Row*> all = sums.all(), one = fr.all();
            for (size_t i = 0; i < all.size(); i++)
            {
                all[i]->stats.add(one[i]->stats);
                all[i]->ms.insert(all[i]->ms.end(), one[i]->ms.begin(), one[i]->ms.end());
            }
        }
        catch (const std::exception& e)
        {
            const cv::Exception* ce = dynamic_cast<const cv::Exception*>(&e);
            const std::string why = ce ? ce->err : std::string(e.what());
            failed++;
            failures.push_back(ids[n] + (lineTitle ? format(" (%d lines)", lines) : "") + ": " + why);
            if (!o.has("quiet"))
                fprintf(stderr, "\nlidarsgm_fuse: frame %s skipped: %s\n", ids[n].c_str(), why.c_str());
        }
        total.stop();
        progress(o, n + 1, ids.size(), total.getTimeSec());
        total.start();
    }
    const std::string title = format("KITTI %s: %zu frames%s, D1 (KITTI devkit rules), sums over frames, %d threads",
                                     dir.c_str(), computed + resumed,
                                     lineTitle ? format(", %d LiDAR lines", lines).c_str() : "", getNumThreads());
    std::vector<Row> table = sums.modes;
    table.push_back(sums.lidar);
    printTable(title, "D1", table);
    printf("| %-28s | %6.2f %% | %11.2f %% | %11s | %8s |\n", sums.semi.label.c_str(), sums.semi.stats.coverage(),
           sums.semi.stats.coveredError(), "-", "-");
    if (!sums.table5.empty())
        printTable("Consistency checks on SDSGM (the paper's Table V)", "D1", sums.table5);
    printf("frames: %zu computed, %zu taken from earlier runs (--resume), %zu failed\n", computed, resumed, failed);
}

} // namespace

int runKittiFolder(const Options& o)
{
    const std::vector<std::string> ids = kittiFrameIds(o.str("kitti"));
    if (ids.empty())
        CV_Error(Error::StsObjectNotFound, o.str("kitti") + "/frames.txt lists no frame");
    std::vector<std::string> failures;
    const std::vector<int> lines = lidarLineCounts(o);
    for (int n : lines)
        kittiPass(o, ids, n, lines.size() > 1 || n != 64, failures);
    if (failures.empty())
        return 0;
    fprintf(stderr, "lidarsgm_fuse: %zu frame(s) failed:\n", failures.size());
    for (const std::string& f : failures)
        fprintf(stderr, "  %s\n", f.c_str());
    return 1;
}

} // namespace lidarsgm_fuse
