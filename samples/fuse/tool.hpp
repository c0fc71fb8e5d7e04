// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// lidarsgm_fuse, the command-line tool: what its parts share. options.cpp (the option table, parsing, checks, the
// matcher), outputs.cpp (files and summary tables), frame.cpp (one frame), kitti.cpp (a KITTI-layout folder),
// middlebury.cpp (a Middlebury folder), timing.cpp (CPU and GPU speed against OpenCV's matchers), files.cpp (the
// files beyond the module's datasets API), main.cpp.

#ifndef LIDARSGM_FUSE_TOOL_HPP
#define LIDARSGM_FUSE_TOOL_HPP

#include "opencv2/lidarsgm.hpp"
#include "opencv2/lidarsgm/calibration.hpp"
#include "opencv2/lidarsgm/datasets.hpp"
#include "opencv2/lidarsgm/evaluation.hpp"
#include "opencv2/lidarsgm/rig.hpp"
#include "opencv2/imgproc.hpp"
#include "opencv2/imgcodecs.hpp"
#include "files.hpp"
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace lidarsgm_fuse {

using Frame = cv::lidarsgm::StereoLidarFrame;
typedef cv::lidarsgm::StereoLidarSGM Matcher;

//! The command line, option name (without "--") to value; values are checked by checkOptions before any work.
struct Options
{
    std::map<std::string, std::string> kv;
    bool has(const std::string& k) const { return kv.count(k) != 0; }
    std::string str(const std::string& k, const std::string& def = "") const;
    int i(const std::string& k, int def) const;
    double d(const std::string& k, double def) const;
    std::vector<std::string> list(const std::string& k, const std::string& def) const;
};

//! Parses argv; 0 when the command line is well formed, else prints why and returns 2. Sets help on --help.
int parseCommandLine(int argc, char** argv, Options& o, bool& help);
void printHelp();
/** Checks the command line before any work: every value (numbers, names, parameter ranges), the input (exactly one),
the options that conflict, do nothing with the input or lack their companion, and the --params file. Prints why and
returns 2 for a bad command line, 1 for a --params file that cannot be read; 0 when all is well. */
int checkOptions(const Options& o);

int modeFromName(const std::string& s);
//! The --modes name of a mode (modeFromName's inverse); modeLabel: as the tables print it.
const char* modeName(int mode);
int checkFromName(const std::string& s);
const char* modeLabel(int mode);
const char* checkLabel(int check);

/** The matcher: create() defaults, then --params FILE, then the mode and check, then (Middlebury) the scene's
disparity count, then the parameter options of the command line. */
cv::Ptr<Matcher> makeMatcher(const Options& o, int mode, int check, int sceneNumDisparities = 0);
//! The LiDAR line counts to run (--lidar-lines, default 64).
std::vector<int> lidarLineCounts(const Options& o);
//! The rings of a 64-line scan that simulate `lines` lines: every `every`-th ring from ring `first` (selectLidarRings),
//! first = --lidar-ring-offset modulo every.
struct LidarRings { int every, first; };
LidarRings lidarRings(const Options& o, int lines);

// ---- outputs.cpp ------------------------------------------------------------------------------------------------
void makeDir(const std::string& dir);
/** Writes path through a temporary name beside it, renamed when write() returned true: a run killed mid-write leaves
no file under the final name. Raises cv::Exception naming path when writing fails. */
void writeAtomically(const std::string& path, const std::function<bool(const std::string&)>& write);
/** The disparity in the --format formats (depth and ply from f's calibration; confidence from confidence, the
matcher's confidence map), its colour picture and, with f's ground truth, the error picture. */
void writeDisparity(const Options& o, const std::string& dir, const std::string& suffix, const cv::Mat& disp16,
                    int minD, int numD, const Frame& f,
                    const cv::Mat& confidence = cv::Mat());
//! LiDAR points over the left image and, where semidense16 (semidensify()'s output) is not empty, the semidense map.
void writeInputs(const std::string& dir, const Frame& f, int minD, int numD, const cv::Mat& semidense16);

//! One line of a summary table.
struct Row
{
    std::string label;
    cv::lidarsgm::DisparityErrors stats;
    std::vector<double> ms;
    cv::lidarsgm::ConfidenceErrors confidence;   //!< with --format confidence and ground truth (computed frames only)
};
void printTable(const std::string& title, const std::string& metric, const std::vector<Row>& rows);
//! A summary table of times only (runs without ground truth).
void printTimes(const std::string& title, const std::vector<Row>& rows);
//! The sparsification figures of a row's confidence (nothing where it has none): the share of the outliers in the
//! least confident 10 %, the AUC beside the oracle's, the covered error of the pixels kept at 100 % .. 10 %.
void printConfidence(const Row& row, const std::string& metric, const std::string& over);
//! Whether the run writes the confidence map (--format confidence with --out), so its matchers compute it.
bool writesConfidence(const Options& o, const std::string& out);

/** Set (not a command-line option) where the calibration step leaves the LiDAR out of the whole run: every frame is
fused as stereo alone, without its sparse map, which otherwise still draws the disparity windows of MODE_SGM. */
const char* const kLidarLeftOut = "lidar-left-out";

// ---- kitti_frame.cpp --------------------------------------------------------------------------------------------
//! The rows of one frame or of a pass: the modes, the LiDAR points, the semidense map, Table V.
struct PassRows
{
    std::vector<Row> modes, table5;
    Row lidar, semi;
    //! The frame's matching residual (px; cv::lidarsgm::matchingResidual), -1 where it has no LiDAR, NaN where the
    //! images could not tell (residualFailure says why).
    double residual = -1;
    std::string residualFailure;
    //! cv::lidarsgm::checkLidar's lowest residual of the LiDAR turned by `turn` degrees and moved by `shift` (where it
    //! searched), and its verdict
    double shiftedResidual = -1;
    cv::Point shift;
    double turn = 0;
    bool misplaced = false;
    //! The frame was fused as stereo alone: its LiDAR misplaced and the run not told --trust-lidar.
    bool stereoAlone = false;
    std::vector<Row*> all();
};
/** The fail-safe (cv::lidarsgm::LidarFailSafe): a frame's LiDAR (f.sparse) checked against its images into fr; none
without a sparse map. Returns the sparse map to fuse: f.sparse, or one without values where fr.stereoAlone (then the
run fuses with the fail-safe's stereo-alone matchers). */
cv::Mat checkFrameLidar(const Options& o, const Frame& f, PassRows& fr);
/** What a run prints about its frames' matching residuals (frame name, its rows): the median and the largest, the
frames above the DDC's Q1 band (1 px), those whose LiDAR is misplaced (fused as stereo alone unless --trust-lidar)
and those the images could not tell; nothing where no frame has a LiDAR. */
void printResiduals(const std::vector<std::pair<std::string, const PassRows*> >& frames);

/** Computes the frames of a KITTI folder run, one at a time; several workers (--streams) run on their own threads.
Keeps its matchers and, with --cuda, its stream and page-locked buffers between frames. */
class FrameWorker
{
public:
    explicit FrameWorker(const Options& o);
    ~FrameWorker();
    //! One frame's rows (fr has the labels; counts empty), its files written when frameOut is not empty.
    void compute(const Frame& f, const std::string& frameOut, PassRows& fr);

private:
    FrameWorker(const FrameWorker&);
    FrameWorker& operator=(const FrameWorker&);
    cv::Ptr<Matcher> matcher(int mode, int check);
    //! The fail-safe's stereo-alone matcher of m (one of matchers_), kept between frames as they are.
    cv::Ptr<Matcher> stereoAlone(const cv::Ptr<Matcher>& m);
    struct Gpu;
    const Options& o_;
    Gpu* gpu_;
    std::map<int, cv::Ptr<Matcher> > matchers_;
    std::map<const Matcher*, cv::Ptr<Matcher> > alone_;
};
//! The progress line of folder runs (stderr): frames done (computed, taken from an earlier run or failed), the rate
//! of the computed ones, time left.
void progress(const Options& o, size_t done, size_t computed, size_t total, double seconds);
double medianMs(std::vector<double> v);

// ---- the commands -----------------------------------------------------------------------------------------------
int runFrame(const Options& o, Frame& f);
int runKittiFolder(const Options& o);
int runKittiRaw(const Options& o);
//! --rig-folder: every frame of a user's rig recording (rig.yml, left/, right/, points/, optional gt/).
int runRigFolder(const Options& o);
int runMiddlebury(const Options& o);
int runCpuTiming(const Options& o, const Frame& f, int reps);
int runCudaTiming(const Options& o, const Frame& f, int reps);

} // namespace lidarsgm_fuse

#endif
