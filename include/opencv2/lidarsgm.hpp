// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_HPP
#define OPENCV_LIDARSGM_HPP

#include "opencv2/core.hpp"
#include "opencv2/core/cuda.hpp"

/**
@defgroup lidarsgm Stereo-LiDAR fusion by semi-global matching

Dense disparity from a rectified stereo pair and a sparse (LiDAR) disparity map, after Yao, Ishikawa and Oishi,
"Stereo-LiDAR Fusion by Semi-Global Matching with Discrete Disparity-Matching Cost and Semidensification"
@cite Yao2025. The pipeline:

1. census transform of both images (centre-symmetric 9x7 window, 31 bits) and Hamming matching cost H(p, d);
2. semidensification (SDSGM only): each pixel takes, among the sparse disparities in a (2 rs + 1)^2 window, the one
   whose census cost at that pixel is lowest, if that cost is below Ts; otherwise its own sparse value, if any;
3. the discrete disparity-matching cost (DDC, DSGM and SDSGM), the paper's Eq. 4 as written: the matching cost is
   (1 - alpha) H at every pixel, plus alpha {0, Q1, Q2} for |d - s| = 0, 1, > 1 where a (semidense) sparse
   disparity s exists; plain SGM uses H alone;
4. semi-global aggregation over 4 or 8 paths with penalties P1, P2; winner-takes-all, uniqueness check and a
   parabola fit for subpixel disparities; the right view's disparities from the same aggregated costs;
5. a 3x3 median filter on the disparity maps of both views (a step of the paper's public code that its text leaves
   out; setMedianSize(1) switches it off): invalid pixels rank above every value, so a hole closes when at most 4 of
   its 8 neighbours are invalid, and an isolated disparity takes its neighbours' value;
6. the consistency check: a disparity survives the left-right check, or (stereo-LiDAR check) if some original sparse
   disparity within a (2 rc + 1)^2 window differs from it by at most Tc. A disparity whose right-view pixel lies
   outside the right image cannot be verified by the left-right check and fails it (the public code keeps such
   pixels; rejecting them measured better on KITTI and Middlebury, doc/decisions.md); the LiDAR test can still keep it.

Semi-global aggregation follows @cite Hirschmuller2008.

Parameters (setters on StereoLidarSGM; out-of-range values raise cv::Exception naming the parameter):

| parameter | meaning | range | default (paper) |
| --- | --- | --- | --- |
| minDisparity | smallest disparity searched | [-1024, 1024] | 0 |
| numDisparities | disparities searched | multiple of 16 in [16, 512] | 128 |
| P1, P2 | SGM penalties for a disparity change of 1 / more than 1 (census-bit units) | 0 <= P1 <= P2 <= 1000 | 10, 120 |
| Q1, Q2 | DDC penalties for abs(d - s) = 1 / > 1 | 0 <= Q1 <= Q2 <= 1000 | 5, 160 |
| alpha | weight of the DDC against the census cost | [0, 1] | 0.7 |
| semidenseRadius (rs), semidenseThreshold (Ts) | semidensification window radius, census-cost threshold | [0, 32], [0, 32] | 6, 2 |
| checkRadius (rc), checkThreshold (Tc) | LiDAR consistency-check window radius, disparity tolerance (pixels) | [0, 64], [0, 64] | 20, 2 |
| uniquenessRatio | best cost <= ratio x lowest cost more than 1 disparity away, else invalid | (0, 1] (1 = off) | 0.95 |
| LRMaxDiff | left-right check tolerance (pixels) | [0, 16] | 1 |
| numPaths | aggregation paths | 4 or 8 | 8 |
| subpixel | parabola fit | on/off | on |
| mode | MODE_SGM, MODE_DSGM, MODE_SDSGM | | MODE_SDSGM |
| consistencyCheck | CHECK_NONE, CHECK_STEREO, CHECK_CAMERA_LIDAR, CHECK_STEREO_LIDAR | | CHECK_STEREO_LIDAR |
| medianSize | median filter before the check: 1 (off) or 3 | 1, 3 | 3 (the public code's) |
| visibilityRadiusX, visibilityRadiusY | visibility filter of the sparse input (beyond the paper) | [0, 16] each | 0, 0 (off) |
| visibilityParallax | growth of the visibility window per pixel of disparity step: the LiDAR's offset across the line of sight over the baseline (beyond the paper) | [0, 1] | 0 (off) |
| edgeThreshold, edgeP2Ratio | P2 x ratio across left-image steps above the threshold (beyond the paper) | [0, 65535], (0, 1] | 0 (off), 0.5 |
| ringGapFactor | interpolation between LiDAR rings after semidensification and the ring check, longest gap in measured ring spacings (beyond the paper) | [0, 16] | 0 (off) |
| semidenseWeight | SDSGM on LiDAR scans: the DDC terms of priors copied from other pixels, relative to the LiDAR's own values (beyond the paper) | (0, 1] | 1 (as the paper) |
| searchWindow | disparity windows per 32 x 32 tile from the priors around it, margin in disparities (beyond the paper) | [0, 512] | 0 (off) |
| outputType | CV_16S (disparity x 16) or CV_32F (pixels) | | CV_16S |

Beyond the paper: `doc/params/kitti_best.yml` (StereoLidarSGM::load) switches on the visibility filter with the
HDL-64E's footprint (2 x 4) and its parallax growth (0.18), the edge rule (32 grey levels, P2 halved), ring
interpolation (factor 2) and copied priors at half weight (semidenseWeight 0.5): on the 20 KITTI development frames
SDSGM's total D1 falls from 2.01 % to 1.62 % (64 lines), 2.63 % to 2.27 % (32) and 4.44 % to 3.67 % (16), DSGM's from
2.53 % to 1.82 %, and the Middlebury sums improve too (doc/accuracy.md).

Inputs: rectified 8- or 16-bit single-channel images of one size; a sparse disparity map of the left view of that
size, CV_16UC1 (KITTI encoding, value / 256, 0 = none) or CV_32FC1 (pixels; 0, negative, NaN, infinite = none),
for example from cv::lidarsgm::projectPointsToDisparity. Output: see StereoLidarSGM.

Evaluation: opencv2/lidarsgm/evaluation.hpp scores disparity maps with the KITTI devkit's rules (D1, background
interpolation) or Middlebury's bad-N and draws the devkit's colour maps.

CPU and CUDA: cv::Mat inputs run on the CPU (parallelised with cv::parallel_for_; the hot loops are compiled for
SSE4.1/4.2 and AVX2 too and picked at run time), cv::cuda::GpuMat inputs on the GPU
(optionally asynchronously on a cv::cuda::Stream). Both compute the same integer arithmetic and give identical
outputs, bit for bit, for every parameter, size and input type.
*/

namespace cv {
namespace lidarsgm {

//! @addtogroup lidarsgm
//! @{

/** @brief Stereo-LiDAR semi-global matcher (plain SGM, DSGM, SDSGM).

Input images: rectified, 8-bit or 16-bit, single channel, same size and type. Colour images are refused (convert
with cv::cvtColor). Sparse disparity: CV_16UC1 in KITTI encoding (value / 256 pixels, 0 = no measurement) or
CV_32FC1 in pixels (0, negative, NaN and infinite values = no measurement); values are taken to 1/16 pixel
(rounded to nearest); values below minDisparity, or at or above minDisparity + numDisparities - 1/2 (they would
round out of the search range), are ignored as no measurement. The sparse disparity is left-view disparity: left
pixel (x, y) matches right pixel (x - d, y).

Units: a map whose measurements (nonzero CV_16U values, positive finite CV_32F ones) mostly lie outside the search
range and at or beyond the image's width, where no point seen by both cameras can be (more than half of at least 64),
is refused with cv::Error::StsOutOfRange naming the fraction and the likely cause (KITTI's x256 disparity PNG passed
as CV_32F pixels, a wrong focalBaseline). A range too small for the scene is no such mistake: its values are dropped.
A map that a mode needs (DSGM, SDSGM, the LiDAR check) but that has no value in the range (all zero, NaN or beyond it)
runs as given, the fusion without the LiDAR, and the matcher logs one warning (CV_LOG_WARNING, once per matcher).
On the CUDA path the counts come from the device: a call waits at its end for them (the first stage's, long done
unless the stream holds earlier work), and a call captured into a CUDA graph is not checked.

Borders and small images: any size from 1x1 up is accepted, including images narrower than the disparity range or
smaller than the census window. Image coordinates outside the image are clamped (replicated border) for the census
window, and a right pixel x - d left of (or right of) the image is taken from the nearest column, so every pixel gets
a matching cost at every disparity; the median filter's window is clamped the same way (a border pixel's window
repeats its edge row or column); the left-right check rejects a disparity whose right pixel lies outside the
image. Output values are invalid or lie in [minDisparity, minDisparity + numDisparities - 1]. CPU and CUDA follow the
same rules.

Output: by default CV_16SC1 with 4 fractional bits (disparity x 16) and invalid pixels set to
(minDisparity - 1) * 16, as cv::StereoSGBM, so cv::reprojectImageTo3D and the ximgproc filters accept it; with
setOutputType(CV_32F), CV_32FC1 in pixels with invalid pixels set to minDisparity - 1.

Costs are integers. The energy is scaled by one factor K, the largest for which the sum of all path costs fits in
16 bits (K is about 33 for the paper's parameters with 8 paths); K alpha Q1, K alpha Q2, K P1 and K P2 are rounded
to the nearest integer, and the census term K (1 - alpha) H (K H in plain SGM) is computed with the weight carried
to 1/256 and rounded per term. Scaling the whole energy does not change the minimiser, the uniqueness ratio or the
parabola, so alpha is honoured as given (0.7 stays 0.7, to within 1/256 of a cost unit) rather than quantised.

Threads and streams: one instance serialises its own calls (a mutex) because its work buffers are members; use one
instance per thread for parallel work. On the CUDA path, calls of one instance on different cv::cuda::Stream objects
are ordered on the GPU: a call on another stream than the previous call first waits (cudaStreamWaitEvent, no host
synchronisation) until the previous call has finished with the buffers, so results are as if the calls ran alone.
A call captured into a CUDA graph must follow a call of the same instance, at the same size, on the capturing
stream, and the graph must not be replayed while the instance runs other calls. With disparity windows
(setSearchWindow) a CUDA call stores only the windows' sums, whose total only the device knows: the call waits on the
host once, after the windows, for the work queued on its stream up to there; a call captured into a graph does not
wait, and its graph allocates (and frees) a volume of the full range's size instead.
 */
class CV_EXPORTS_W StereoLidarSGM : public Algorithm
{
public:
    //! Which fusion pipeline runs.
    enum FusionMode
    {
        MODE_SGM   = 0, //!< plain stereo SGM on census cost; the sparse input is only used by the LiDAR check
        MODE_DSGM  = 1, //!< SGM with the discrete disparity-matching cost (DDC) on the sparse input
        MODE_SDSGM = 2  //!< semidensification, then SGM with DDC on the semidense map
    };
    //! Which consistency check filters the result (the paper's Table V).
    enum ConsistencyCheck
    {
        CHECK_NONE         = 0, //!< keep every disparity that passes the uniqueness check
        CHECK_STEREO       = 1, //!< left-right check only
        CHECK_CAMERA_LIDAR = 2, //!< keep a disparity only if a sparse disparity within rc is within Tc of it
        CHECK_STEREO_LIDAR = 3  //!< keep it if it passes the left-right check or the camera-LiDAR test
    };

    /** @brief Creates the matcher; the defaults are the paper's parameters (each one also has a setter, documented
    there). Python takes every one as a keyword: `cv2.lidarsgm.StereoLidarSGM.create(numPaths=4, searchWindow=4)`.
    @param minDisparity smallest disparity searched, in [-1024, 1024].
    @param numDisparities number of disparities searched: a multiple of 16 in [16, 512], on both paths.
    @param P1 penalty for a disparity change of 1 between neighbours (census-bit units), 0 <= P1 <= P2.
    @param P2 penalty for larger changes, P1 <= P2 <= 1000.
    @param Q1 DDC penalty for |d - sparse| = 1, 0 <= Q1 <= Q2.
    @param Q2 DDC penalty for |d - sparse| > 1, Q1 <= Q2 <= 1000.
    @param alpha blend between census cost and DDC, in [0, 1].
    @param mode one of StereoLidarSGM::FusionMode.
    @param check one of StereoLidarSGM::ConsistencyCheck.
    @param uniquenessRatio see setUniquenessRatio, in (0, 1] (1: off).
    @param LRMaxDiff the left-right check's tolerance in pixels, in [0, 16].
    @param numPaths aggregation paths, 4 or 8.
    @param subpixel the parabola fit.
    @param semidenseRadius rs, in [0, 32].
    @param semidenseThreshold Ts, in [0, 32].
    @param checkRadius rc, in [0, 64].
    @param checkThreshold Tc in pixels, in [0, 64].
    @param medianSize 1 (off) or 3.
    @param visibilityRadiusX see setVisibilityRadiusX, in [0, 16] (0 and 0: off).
    @param visibilityRadiusY see setVisibilityRadiusY, in [0, 16].
    @param visibilityParallax see setVisibilityParallax, in [0, 1] (0: off).
    @param edgeThreshold see setEdgeThreshold, in [0, 65535] (0: off).
    @param edgeP2Ratio see setEdgeP2Ratio, in (0, 1].
    @param ringGapFactor see setRingGapFactor, in [0, 16] (0: off).
    @param semidenseWeight see setSemidenseWeight, in (0, 1] (1: the paper's DDC).
    @param searchWindow see setSearchWindow, in [0, 512] (0: off).
    @param outputType CV_16S (disparity x 16) or CV_32F (pixels).
    A value out of its range raises cv::Exception naming the parameter.
     */
    CV_WRAP static Ptr<StereoLidarSGM> create(int minDisparity = 0, int numDisparities = 128,
                                              int P1 = 10, int P2 = 120, int Q1 = 5, int Q2 = 160,
                                              double alpha = 0.7, int mode = StereoLidarSGM::MODE_SDSGM,
                                              int check = StereoLidarSGM::CHECK_STEREO_LIDAR,
                                              double uniquenessRatio = 0.95, int LRMaxDiff = 1, int numPaths = 8,
                                              bool subpixel = true, int semidenseRadius = 6,
                                              int semidenseThreshold = 2, int checkRadius = 20,
                                              double checkThreshold = 2.0, int medianSize = 3,
                                              int visibilityRadiusX = 0, int visibilityRadiusY = 0,
                                              double visibilityParallax = 0.0, int edgeThreshold = 0,
                                              double edgeP2Ratio = 0.5, double ringGapFactor = 0.0,
                                              double semidenseWeight = 1.0, int searchWindow = 0,
                                              int outputType = CV_16S);

    /** @brief Computes the fused disparity map of the left image.
    @param left left image, CV_8UC1 or CV_16UC1.
    @param right right image, same size and type as left.
    @param sparseDisparity sparse disparity of the left view, same size, CV_16UC1 (x256) or CV_32FC1; may be empty
    in MODE_SGM with CHECK_NONE or CHECK_STEREO.
    @param disparity output, CV_16SC1 (x16) or CV_32FC1 (see setOutputType).
    Inputs given as cv::cuda::GpuMat run the CUDA path (when built with CUDA) and return a GpuMat.
     */
    CV_WRAP virtual void compute(InputArray left, InputArray right, InputArray sparseDisparity,
                                 OutputArray disparity) = 0;

    /** @brief CUDA path: GpuMat inputs and output, asynchronous on the given stream. */
    virtual void compute(InputArray left, InputArray right, InputArray sparseDisparity,
                         OutputArray disparity, cuda::Stream& stream) = 0;

    /** @brief Computes the fused disparity map and each pixel's confidence in it.

    The disparity map is the one compute() gives (the same bits). The confidence is in [0, 1], 0 where there is no
    disparity, from what the consistency check knows of each output pixel: its evidence (both the left-right test
    and a LiDAR value within the check's threshold in the semidensification window (2 rs + 1)^2, or the ring check,
    confirm it: 1; the LiDAR alone: 3/4; the left-right test alone: 1/2; neither, with the check off: 1/4), times
    32 / (32 + r) with r the spread of the disparities of its 3x3 neighbourhood in 1/16 pixel (a pixel on a depth
    edge, where matching fails most, counts less; a spread of 2 px halves it). Both tests run for the confidence whatever setConsistencyCheck keeps; the LiDAR evidence needs
    sparseDisparity. Sort or threshold it: most errors lie in the least confident pixels (doc/accuracy.md).
    @param left, right, sparseDisparity, disparity as compute().
    @param confidence output, CV_32FC1 (a GpuMat for GpuMat inputs), the size of the images.
     */
    CV_WRAP_AS(computeWithConfidence) virtual void compute(InputArray left, InputArray right,
                                                          InputArray sparseDisparity, OutputArray disparity,
                                                          OutputArray confidence) = 0;

    /** @brief CUDA path of the confidence overload: asynchronous on the given stream. */
    virtual void compute(InputArray left, InputArray right, InputArray sparseDisparity, OutputArray disparity,
                         OutputArray confidence, cuda::Stream& stream) = 0;

    /** @brief The semidense disparity map on its own (the paper's Table IV).
    @param left left image, as for compute.
    @param right right image, as for compute.
    @param sparseDisparity sparse disparity, as for compute.
    @param semidense output in the same format as compute's output (CV_16SC1 x16 by default).
     */
    CV_WRAP virtual void semidensify(InputArray left, InputArray right, InputArray sparseDisparity,
                                     OutputArray semidense) = 0;

    /** @brief CUDA path of semidensify. */
    virtual void semidensify(InputArray left, InputArray right, InputArray sparseDisparity,
                             OutputArray semidense, cuda::Stream& stream) = 0;

    /** Smallest disparity searched (any integer in [-1024, 1024]; default 0). */
    CV_WRAP virtual int getMinDisparity() const = 0;
    /** Sets the smallest disparity searched, in [-1024, 1024]. */
    CV_WRAP virtual void setMinDisparity(int minDisparity) = 0;
    /** Number of disparities: a multiple of 16 in [16, 512] (default 128). */
    CV_WRAP virtual int getNumDisparities() const = 0;
    /** Sets the number of disparities: a multiple of 16 in [16, 512]. */
    CV_WRAP virtual void setNumDisparities(int numDisparities) = 0;
    /** SGM penalty for a disparity step of 1, in census-bit units: 0 <= P1 <= P2 (paper: 10). */
    CV_WRAP virtual int getP1() const = 0;
    /** Sets the SGM penalty for a disparity step of 1: 0 <= P1 <= P2. */
    CV_WRAP virtual void setP1(int P1) = 0;
    /** SGM penalty for larger steps: P1 <= P2 <= 1000 (paper: 120). */
    CV_WRAP virtual int getP2() const = 0;
    /** Sets the SGM penalty for larger steps: P1 <= P2 <= 1000. */
    CV_WRAP virtual void setP2(int P2) = 0;
    /** DDC penalty for |d - sparse| = 1: 0 <= Q1 <= Q2 (paper: 5). */
    CV_WRAP virtual int getQ1() const = 0;
    /** Sets the DDC penalty for |d - sparse| = 1: 0 <= Q1 <= Q2. */
    CV_WRAP virtual void setQ1(int Q1) = 0;
    /** DDC penalty for |d - sparse| > 1: Q1 <= Q2 <= 1000 (paper: 160). */
    CV_WRAP virtual int getQ2() const = 0;
    /** Sets the DDC penalty for |d - sparse| > 1: Q1 <= Q2 <= 1000. */
    CV_WRAP virtual void setQ2(int Q2) = 0;
    /** Weight of DDC against census cost where a sparse disparity exists, in [0, 1] (paper: 0.7). */
    CV_WRAP virtual double getAlpha() const = 0;
    /** Sets the weight of DDC against the census cost, in [0, 1]. */
    CV_WRAP virtual void setAlpha(double alpha) = 0;
    /** Uniqueness: a disparity is kept only if its aggregated cost is at most ratio times the lowest cost at
    disparities more than 1 away from it; in (0, 1], 1 disables the check (default 0.95). */
    CV_WRAP virtual double getUniquenessRatio() const = 0;
    /** Sets the uniqueness ratio, in (0, 1] (1: off); see getUniquenessRatio. */
    CV_WRAP virtual void setUniquenessRatio(double ratio) = 0;
    /** Largest difference, in whole pixels, between left and right disparities in the left-right check, in [0, 16]
    (default 1). */
    CV_WRAP virtual int getLRMaxDiff() const = 0;
    /** Sets the left-right check's tolerance in whole pixels, in [0, 16]. */
    CV_WRAP virtual void setLRMaxDiff(int maxDiff) = 0;
    /** Number of aggregation paths: 4 or 8 (default 8). */
    CV_WRAP virtual int getNumPaths() const = 0;
    /** Sets the number of aggregation paths: 4 or 8. */
    CV_WRAP virtual void setNumPaths(int numPaths) = 0;
    /** Subpixel refinement by a parabola through the costs at d-1, d, d+1 (default on). */
    CV_WRAP virtual bool getSubpixel() const = 0;
    /** Switches the parabola fit for subpixel disparities on or off. */
    CV_WRAP virtual void setSubpixel(bool subpixel) = 0;
    /** Semidensification window radius rs, in [0, 32] (paper: 6). */
    CV_WRAP virtual int getSemidenseRadius() const = 0;
    /** Sets the semidensification window radius rs, in [0, 32]. */
    CV_WRAP virtual void setSemidenseRadius(int rs) = 0;
    /** Semidensification threshold Ts on the census cost (a candidate is taken if its cost is below Ts), in [0, 32]
    (paper: 2). */
    CV_WRAP virtual int getSemidenseThreshold() const = 0;
    /** Sets the semidensification threshold Ts, in [0, 32]. */
    CV_WRAP virtual void setSemidenseThreshold(int Ts) = 0;
    /** Consistency-check window radius rc, in [0, 64] (paper: 20). */
    CV_WRAP virtual int getCheckRadius() const = 0;
    /** Sets the consistency-check window radius rc, in [0, 64]. */
    CV_WRAP virtual void setCheckRadius(int rc) = 0;
    /** Consistency-check threshold Tc in pixels, in [0, 64] (paper: 2); compared at 1/16 pixel. */
    CV_WRAP virtual double getCheckThreshold() const = 0;
    /** Sets the consistency-check threshold Tc in pixels, in [0, 64]. */
    CV_WRAP virtual void setCheckThreshold(double Tc) = 0;
    /** Fusion mode, one of FusionMode (default MODE_SDSGM). */
    CV_WRAP virtual int getMode() const = 0;
    /** Sets the fusion mode, one of FusionMode. */
    CV_WRAP virtual void setMode(int mode) = 0;
    /** Consistency check, one of ConsistencyCheck (default CHECK_STEREO_LIDAR). */
    CV_WRAP virtual int getConsistencyCheck() const = 0;
    /** Sets the consistency check, one of ConsistencyCheck. */
    CV_WRAP virtual void setConsistencyCheck(int check) = 0;
    /** Median filter on the disparity maps of both views before the consistency check: 1 (off) or 3 (3x3, default).
    A pixel with 5 or more invalid neighbours stays invalid; the border is clamped. */
    CV_WRAP virtual int getMedianSize() const = 0;
    /** Sets the median filter before the check: 1 (off) or 3. */
    CV_WRAP virtual void setMedianSize(int size) = 0;
    /** Visibility filter of the sparse input (off by default: the paper has none): a sparse disparity is dropped when
    another one within (2 radiusX + 1) x (2 radiusY + 1) pixels around it is larger (nearer) by more than the
    checkThreshold Tc. A LiDAR beside the camera sees past the edges of near objects; those background points land
    on the near object in the image, among the object's own points, and mislead semidensification, DDC and the LiDAR
    check. The window should be the LiDAR's sample footprint in the image: half the spacing of neighbouring samples,
    rounded up, plus the half pixel of rounding. KITTI's HDL-64E (0.17 degrees between shots, 0.4-0.5 degrees
    between rings, f = 721 px): radiusX 2, radiusY 4 (doc/params/kitti_best.yml). Both in [0, 16]; 0 and 0: off. */
    CV_WRAP virtual int getVisibilityRadiusX() const = 0;
    /** Sets the visibility filter's half width, in [0, 16]; see getVisibilityRadiusX. */
    CV_WRAP virtual void setVisibilityRadiusX(int radiusX) = 0;
    /** See getVisibilityRadiusX. */
    CV_WRAP virtual int getVisibilityRadiusY() const = 0;
    /** Sets the visibility filter's half height, in [0, 16]; see getVisibilityRadiusX. */
    CV_WRAP virtual void setVisibilityRadiusY(int radiusY) = 0;
    /** Parallax growth of the visibility window (off by default): on a LiDAR scan the window grows on every side by
    this many pixels per pixel by which the nearer value exceeds the farther one (at most 32 pixels). Beside a near
    object the LiDAR sees background that the camera cannot see, in a band whose width is the disparity step times the
    LiDAR's offset from the left camera across the line of sight, divided by the stereo baseline: set it to that
    ratio. KITTI's HDL-64E sits 0.095 m from the left colour camera across the line of sight (0.057 m sideways,
    0.075 m up; Tr_velo_to_cam and P2), with a 0.533 m baseline: 0.18 (doc/params/kitti_best.yml). The growth applies
    only where the sparse map is a scan, its points closer along the rows than across them (the lower medians of the
    distance to the next point to the right and to the next point below within 2 columns): a scattered sample, such
    as ground-truth pixels drawn from the camera's own view, has no sensor apart from the camera. In [0, 1]; 0: the
    fixed window of visibilityRadiusX/Y. */
    CV_WRAP virtual double getVisibilityParallax() const = 0;
    /** Sets the visibility window's growth per pixel of disparity step, in [0, 1]; see getVisibilityParallax. */
    CV_WRAP virtual void setVisibilityParallax(double ratio) = 0;
    /** Edge-aware jump penalty (off by default: the paper has none): on every aggregation path, a disparity jump between
    neighbours whose left-image intensities differ by more than this threshold (in the images' grey levels) costs
    edgeP2Ratio x P2 instead of P2 (at least P1), as intensity edges are likely depth edges (Hirschmueller's SGM
    adapts P2 to the intensity step likewise). In [0, 65535]; 0: off. doc/params/kitti_best.yml: 32 (8-bit). */
    CV_WRAP virtual int getEdgeThreshold() const = 0;
    /** Sets the edge-aware jump penalty's threshold in grey levels, in [0, 65535] (0: off); see getEdgeThreshold. */
    CV_WRAP virtual void setEdgeThreshold(int threshold) = 0;
    /** P2's factor across an intensity edge (see getEdgeThreshold), in (0, 1]; default 0.5. */
    CV_WRAP virtual double getEdgeP2Ratio() const = 0;
    /** Sets P2's factor across an intensity edge, in (0, 1]. */
    CV_WRAP virtual void setEdgeP2Ratio(double ratio) = 0;
    /** Ring interpolation (off by default: the paper has none; SDSGM and semidensify() only): a pixel that
    semidensification leaves without a value takes the disparity interpolated linearly between the nearest sparse
    points above and below it (within 2 columns on either side) if its census cost there is below Ts and the two
    points are at most ringGapFactor x the ring spacing apart; below the last ring (above the first) the line through
    the two nearest rings above (below) is extended, each step at most that far. The ring spacing is measured on each
    sparse map (the median vertical distance from a point to the next one below it), so one setting serves 64, 32 and
    16 lines. A LiDAR's rings leave bands of rows without points (about 20 px at 16 lines on KITTI); the surfaces seen
    from both neighbouring rings (road, walls, vehicle sides) are locally planar and a plane's disparity is linear in
    the image. With it, where the LiDAR test runs, the consistency check also keeps a disparity within Tc of that
    line at the pixel (census test aside), and a winner that failed the uniqueness check and that the median left
    empty when it passes the same test: the ring check. In [0, 16]; 0: off. doc/params/kitti_best.yml: 2 (a ring's
    neighbours, one missing return bridged). */
    CV_WRAP virtual double getRingGapFactor() const = 0;
    /** Sets the ring interpolation's longest gap in ring spacings, in [0, 16] (0: off); see getRingGapFactor. */
    CV_WRAP virtual void setRingGapFactor(double factor) = 0;
    /** The weight of copied priors (SDSGM only): at a pixel whose prior semidensification or ring interpolation
    brought from another pixel (it differs from the pixel's own sparse value), the DDC terms alpha Q1 and alpha Q2
    are scaled by semidenseWeight; the LiDAR's own values keep them. A copy is an inference from the census test, a
    LiDAR value a measurement: on KITTI with doc/params/kitti_best.yml 1.95 % of the copies are wrong against 0.44 %
    of the own values (doc/decisions.md, "Wrong priors at 64 lines"). It applies to LiDAR scans only, by the scan test
    of visibilityParallax (points closer along the rows than across them): a sample drawn from the camera's own ground
    truth (the Middlebury protocol) has copies as good as its values. In (0, 1]; 1: the paper's DDC everywhere.
    doc/params/kitti_best.yml: 0.5 (a copy counts half a measurement). */
    CV_WRAP virtual double getSemidenseWeight() const = 0;
    /** Sets the DDC weight of copied priors on LiDAR scans, in (0, 1]; see getSemidenseWeight. */
    CV_WRAP virtual void setSemidenseWeight(double weight) = 0;
    /** The disparity windows' margin (beyond the paper): with searchWindow > 0 the aggregation searches each 32 x 32
    tile of the image only over the disparities of the priors (semidensified and ring-interpolated in SDSGM, the
    LiDAR's otherwise) in that tile and the eight around it, widened by searchWindow on each side and rounded out to
    multiples of 16; tiles without any prior around them take their range from a coarse pass (plain SGM on the pair
    at quarter size). Along a path, a disparity outside the previous pixel's window is reached through the P2 jump
    only. Fewer cells, less time and memory; a surface outside its tile's window cannot be found (see
    doc/design.md). 0 (default): every pixel searches the whole range, as the paper. The CPU and CUDA paths give the
    same output bit for bit with windows too. In [0, 512]. */
    CV_WRAP virtual int getSearchWindow() const = 0;
    /** Sets the disparity windows' margin, in [0, 512] (0: off); see getSearchWindow. */
    CV_WRAP virtual void setSearchWindow(int margin) = 0;
    /** The share of the width x height x numDisparities cells that the last compute() searched (1 without windows, 0
    before any call). After a call on the CUDA path it waits for that call to finish. */
    CV_WRAP virtual double getSearchedFraction() const = 0;
    /** Output type: CV_16S (disparity x 16, default) or CV_32F (pixels). */
    CV_WRAP virtual int getOutputType() const = 0;
    /** Sets the output type: CV_16S (disparity x 16) or CV_32F (pixels). */
    CV_WRAP virtual void setOutputType(int type) = 0;

    /** @brief Loads a matcher saved with save() (cv::FileStorage, YAML/XML/JSON). */
    CV_WRAP static Ptr<StereoLidarSGM> load(const String& filename, const String& objname = String());
};

/** @brief Projects a LiDAR point cloud into a sparse disparity map of the left (reference) camera.

Each point X (LiDAR frame) is moved to the rectified camera frame by the rigid transform lidarToCamera, then
projected by the 3x4 projection: [u v 1]^T ~ projection [R t] [X 1]^T. Its depth z is the third component, its
disparity focalBaseline / z (focal length in pixels times baseline in metres, e.g. P2[0,3] - P3[0,3] in KITTI).
Pixels are (round(u), round(v)); where several points fall on one pixel the nearest (largest disparity) wins;
points with z <= 0, outside the image or with a non-finite coordinate are dropped.

@param points N x 3 or N x 4 CV_32F (x, y, z[, reflectance]), or an N x 1 CV_32FC3/CV_32FC4 array.
@param projection 3x4 projection matrix (CV_32F or CV_64F) of the rectified left camera.
@param lidarToCamera 3x4 or 4x4 rigid transform (rotation with orthonormal rows, det 1) from LiDAR to rectified
camera coordinates; for KITTI, R0_rect * Tr_velo_to_cam.
@param focalBaseline focal length (pixels) times baseline (metres), > 0.
@param imageSize size of the disparity map.
@param sparseDisparity output, CV_32FC1 in pixels (0 = none) or CV_16UC1 in KITTI encoding (round(d * 256),
0 = none, saturated at 65535).
@param dtype CV_32F or CV_16U.
 */
CV_EXPORTS_W void projectPointsToDisparity(InputArray points, InputArray projection, InputArray lidarToCamera,
                                           double focalBaseline, Size imageSize, OutputArray sparseDisparity,
                                           int dtype = CV_32F);

/** @brief The number of laser rings of a Velodyne scan in the driver's order: a new ring starts where the azimuth,
taken in [0, 360), falls back by more than 90 degrees (each ring sweeps once round from straight ahead).
@param points N x 3 or more CV_32FC1 (x, y, z first), as readVelodyneScan returns them.
 */
CV_EXPORTS_W int countLidarRings(InputArray points);

/** @brief Thins a Velodyne scan to every keepEvery-th laser ring, counted from the top, starting with ring firstRing.

The rings come from the scan's order (countLidarRings) and are ranked by their median elevation angle (elevation
alone does not separate them: near points of neighbouring rings overlap by up to a degree, as the lasers sit off the
sensor's centre). keepEvery 2 and 4 simulate 32- and 16-line LiDARs from a 64-line scan, as the paper's Table VI
does; the keepEvery offsets firstRing = 0 .. keepEvery - 1 split the scan into disjoint parts.
@param points N x 3 or more CV_32FC1, in the driver's order.
@param keepEvery >= 1; 1 returns the scan unchanged.
@param firstRing in [0, keepEvery).
@return the kept points (whole rings), a copy.
 */
CV_EXPORTS_W Mat selectLidarRings(InputArray points, int keepEvery, int firstRing = 0);

//! @}

}} // namespace cv::lidarsgm

namespace cv { namespace cuda {

//! @addtogroup lidarsgm
//! @{

/** @brief CUDA path of cv::lidarsgm::StereoLidarSGM::compute, for the Python bindings (which give GpuMat variants only
to declarations in namespace cv::cuda): `disp = cv2.cuda.computeStereoLidarSGM(matcher, gpuLeft, gpuRight, gpuSparse)`.
C++ users call matcher->compute(...) with GpuMats directly. Inputs and output are cv::cuda::GpuMat. */
CV_EXPORTS_W void computeStereoLidarSGM(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left,
                                        InputArray right, InputArray sparseDisparity, OutputArray disparity,
                                        Stream& stream = Stream::Null());

/** @brief CUDA path of cv::lidarsgm::StereoLidarSGM::compute with the confidence map, for the Python bindings (see
computeStereoLidarSGM): `disp, conf = cv2.cuda.computeStereoLidarSGMWithConfidence(matcher, gl, gr, gs)`. */
CV_EXPORTS_W void computeStereoLidarSGMWithConfidence(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher,
                                                      InputArray left, InputArray right, InputArray sparseDisparity,
                                                      OutputArray disparity, OutputArray confidence,
                                                      Stream& stream = Stream::Null());

//! @brief CUDA path of cv::lidarsgm::StereoLidarSGM::semidensify, for the Python bindings (see computeStereoLidarSGM).
CV_EXPORTS_W void semidensifyStereoLidarSGM(const Ptr<cv::lidarsgm::StereoLidarSGM>& matcher, InputArray left,
                                            InputArray right, InputArray sparseDisparity, OutputArray semidense,
                                            Stream& stream = Stream::Null());

/** @brief CUDA version of cv::lidarsgm::projectPointsToDisparity: points (N x 3 / N x 4 CV_32F) and the
output are cv::cuda::GpuMat; the result equals the CPU version's bit for bit. cv::lidarsgm::projectPointsToDisparity
given a GpuMat calls this on the default stream. */
CV_EXPORTS_W void projectPointsToDisparity(InputArray points, InputArray projection, InputArray lidarToCamera,
                                           double focalBaseline, Size imageSize, OutputArray sparseDisparity,
                                           int dtype = CV_32F, Stream& stream = Stream::Null());

//! @}

}} // namespace cv::cuda

// The core: the matcher, the projection, depth and points, the fail-safe. The add-ons have headers of their own, included
// by name: opencv2/lidarsgm/datasets.hpp (KITTI and Middlebury readers, point-cloud files, writers),
// opencv2/lidarsgm/evaluation.hpp (the KITTI devkit's metrics, colour maps, legends), opencv2/lidarsgm/calibration.hpp
// (LidarCalibration) and opencv2/lidarsgm/rig.hpp (StereoRig).
#include "opencv2/lidarsgm/depth.hpp"
#include "opencv2/lidarsgm/fail_safe.hpp"

#endif // OPENCV_LIDARSGM_HPP
