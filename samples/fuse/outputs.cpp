// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// What the tool writes: per-frame files (disparity formats, pictures) and the summary tables and progress line.

#include "tool.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <unistd.h>

using namespace cv;

namespace lidarsgm_fuse {

void makeDir(const std::string& dir)
{
    utils::fs::createDirectories(dir);
    if (!utils::fs::isDirectory(dir))
        CV_Error(Error::StsError, "cannot create the output folder " + dir);
}

void writeAtomically(const std::string& path, const std::function<bool(const std::string&)>& write)
{
    // A hidden name beside the file, the extension kept last (imwrite picks the format by it), unique per run and
    // per call (the workers of --streams write at once).
    static std::atomic<unsigned> calls(0);
    const size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    const size_t nameAt = slash == std::string::npos ? 0 : slash + 1;
    const size_t extAt = dot == std::string::npos || dot < nameAt ? path.size() : dot;
    const std::string tmp = path.substr(0, nameAt) + "." + path.substr(nameAt, extAt - nameAt) +
                            format(".partial-%d-%u", (int)getpid(), calls++) + path.substr(extAt);
    bool ok = false;
    try
    {
        ok = write(tmp);
    }
    catch (const cv::Exception&)
    {
        std::remove(tmp.c_str());
        throw;
    }
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0)
    {
        std::remove(tmp.c_str());
        CV_Error(Error::StsError, "cannot write " + path);
    }
}

static void writeImage(const std::string& path, const Mat& img)
{
    writeAtomically(path, [&](const std::string& tmp) { return imwrite(tmp, img); });
}

namespace {

Mat withLegend(const Mat& picture, double maxDisparity, const std::string& title, bool none)
{
    Mat out;
    lidarsgm::addDisparityLegend(picture, out, maxDisparity, title, none);
    return out;
}

Mat withErrorLegend(const Mat& picture)
{
    Mat out;
    lidarsgm::addErrorLegend(picture, out);
    return out;
}

} // namespace

void writeDisparity(const Options& o, const std::string& dir, const std::string& suffix, const Mat& disp16,
                    int minD, int numD, const Frame& f, const Mat& confidence)
{
    const Mat d = disparityToFloat(disp16, minD), &gt = f.groundTruth;
    const std::string base = dir + "/disparity" + suffix;
    for (const std::string& format : o.list("format", "kitti"))
    {
        if ((format == "depth" || format == "ply") && !(f.calibration.focalBaseline > 0))
            CV_Error(Error::StsBadArg, "--format " + format + " needs a calibration, and " + f.name + " has none");
        if (format == "confidence")
        {
            // 16 bits: round(confidence x 65535), 0 = no disparity.
            CV_Assert(confidence.type() == CV_32FC1 && confidence.size() == disp16.size());
            Mat c16;
            confidence.convertTo(c16, CV_16U, 65535.0);
            writeImage(dir + "/confidence" + suffix + ".png", c16);
        }
        else if (format == "kitti")
            writeImage(base + ".png", lidarsgm::encodeKittiDisparity(d));
        else if (format == "pfm")
            writeAtomically(base + ".pfm", [&](const std::string& tmp) { lidarsgm::writePfm(tmp, d); return true; });
        else if (format == "s16")
            writeAtomically(base + ".s16", [&](const std::string& tmp) { return writeRawS16(tmp, disp16); });
        else if (format == "depth")
        {
            Mat depth;
            lidarsgm::disparityToDepth(disp16, f.calibration.focalBaseline, depth, minD);
            writeImage(dir + "/depth" + suffix + ".png", lidarsgm::encodeKittiDepth(depth));
        }
        else if (format == "ply")
        {
            Mat points;
            const lidarsgm::KittiCalibration& c = f.calibration;
            lidarsgm::disparityToPoints(disp16, lidarsgm::reprojectionMatrix(c.projection, c.focalBaseline), points,
                                        minD);
            const Mat& colour = f.leftImage.empty() ? f.left : f.leftImage;
            writeAtomically(dir + "/points" + suffix + ".ply",
                            [&](const std::string& tmp) { lidarsgm::writePly(tmp, points, colour); return true; });
        }
    }
    Mat colour;
    lidarsgm::colorizeDisparity(d, colour, minD + numD);
    writeImage(base + "_color.png", withLegend(colour, minD + numD, "disparity (px)", true));
    if (!gt.empty())
    {
        Mat filled;
        lidarsgm::interpolateBackground(d, filled);
        lidarsgm::colorizeDisparityError(filled, gt, colour);
        writeImage(dir + "/error" + suffix + ".png", withErrorLegend(colour));
    }
}

void writeInputs(const std::string& dir, const Frame& f, int minD, int numD, const Mat& semidense16)
{
    if (f.sparse.empty())
        return;
    Mat s;
    f.sparse.convertTo(s, CV_32F, f.sparse.depth() == CV_16U ? 1.0 / 256 : 1.0);
    s.setTo(0.f, ~(s > 0));
    const float maxD = (float)(minD + numD);
    Mat overlay;
    lidarsgm::drawSparseDisparity(f.left, s, overlay, maxD);
    writeImage(dir + "/lidar_points.png", withLegend(overlay, maxD, "LiDAR disparity (px)", false));
    if (!semidense16.empty())
    {
        Mat colour;
        const Mat sf = disparityToFloat(semidense16, minD);
        writeImage(dir + "/semidense.png", lidarsgm::encodeKittiDisparity(sf));
        lidarsgm::colorizeDisparity(sf, colour, maxD);
        writeImage(dir + "/semidense_color.png", withLegend(colour, maxD, "semidense disparity (px)", true));
    }
}

void printTable(const std::string& title, const std::string& metric, const std::vector<Row>& rows)
{
    printf("\n%s\n", title.c_str());
    printf("| %-28s | coverage | covered %-5s | total %-5s | ms/frame |\n", "method", metric.c_str(), metric.c_str());
    printf("|------------------------------|----------|---------------|-------------|----------|\n");
    for (const Row& r : rows)
    {
        char t[32] = "-";
        if (!r.ms.empty())
            snprintf(t, sizeof(t), "%.1f", medianMs(r.ms));
        printf("| %-28s | %6.2f %% | %11.2f %% | %9.2f %% | %8s |\n", r.label.c_str(), r.stats.coverage(),
               r.stats.coveredError(), r.stats.totalError(), t);
    }
}

bool writesConfidence(const Options& o, const std::string& out)
{
    const std::vector<std::string> formats = o.list("format", "kitti");
    return !out.empty() && std::find(formats.begin(), formats.end(), "confidence") != formats.end();
}

void printConfidence(const Row& r, const std::string& metric, const std::string& over)
{
    if (r.confidence.pixels.empty())
        return;
    printf("confidence of %s, %s: the 10 %% least confident hold %.1f %% of the %s outliers; AUC %.5f (oracle %.5f, "
           "random %.5f); covered %s of the pixels kept:", r.label.c_str(), over.c_str(),
           r.confidence.leastConfidentShare(0.1), metric.c_str(), r.confidence.auc(), r.confidence.oracleAuc(),
           r.confidence.totalOutliers() / std::max(1.0, r.confidence.total()), metric.c_str());
    for (int k = 10; k >= 1; k--)
        printf(" %d %%: %.2f%s", 10 * k, r.confidence.keptError(k / 10.0), k > 1 ? "," : "\n");
}

void printTimes(const std::string& title, const std::vector<Row>& rows)
{
    printf("\n%s\n", title.c_str());
    printf("| %-28s | ms/frame |\n", "method");
    printf("|------------------------------|----------|\n");
    for (const Row& r : rows)
        printf("| %-28s | %8s |\n", r.label.c_str(), r.ms.empty() ? "-" : format("%.1f", medianMs(r.ms)).c_str());
}

void progress(const Options& o, size_t done, size_t computed, size_t total, double seconds)
{
    if (o.has("quiet"))
        return;
    // The rate of the frames computed here; frames taken from an earlier run or failed cost next to nothing.
    const double fps = computed / std::max(seconds, 1e-9);
    if (computed > 0)
        fprintf(stderr, "\r[%zu/%zu] frames, %.2f frames/s computed, %.0f s left   ", done, total, fps,
                (total - done) / fps);
    else
        fprintf(stderr, "\r[%zu/%zu] frames, none computed   ", done, total);
    if (done == total)
        fprintf(stderr, "\n");
}

double medianMs(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

} // namespace lidarsgm_fuse
