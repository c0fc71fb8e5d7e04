// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// What the front class (stereo_lidar_sgm.cpp) and the two backends share, and the only header that src/ and
// src_cuda/ both include: the validated parameters, every arithmetic rule whose result must be identical on the CPU
// and the GPU (written once, for host and device), and the two backends' interfaces. The CPU stages are declared in
// src/cpu_stages.hpp, the CUDA stages in src_cuda/cuda_stages.hpp; a stage has the same name on both sides.

#ifndef OPENCV_LIDARSGM_PIPELINE_HPP
#define OPENCV_LIDARSGM_PIPELINE_HPP

#include "opencv2/core.hpp"
#include <climits>

#ifdef __CUDACC__
#  define LIDARSGM_HD __host__ __device__ __forceinline__
#else
#  define LIDARSGM_HD inline
#  include "opencv2/core/cuda.hpp"
#endif

namespace cv { namespace lidarsgm {

class StereoLidarSGM;

namespace detail {

//! Centre-symmetric census: a 9x7 window, each of the 31 pixel pairs (p + o, p - o) gives one bit.
enum { CENSUS_WIDTH = 9, CENSUS_HEIGHT = 7, CENSUS_BITS = (CENSUS_WIDTH * CENSUS_HEIGHT - 1) / 2 };
//! The most disparities a call searches, on both paths (the CUDA path kernel holds at most eight pairs of
//! disparities per lane of a warp).
enum { MAX_DISPARITIES = 512 };

//! Marks "no disparity" in the internal 1/16-pixel maps (CV_16SC1).
const short NO_DISP = SHRT_MIN;

//! Integer weights of the scaled energy (see StereoLidarSGM's documentation and computeCostWeights).
struct CostWeights
{
    int census256;     //!< census weight x 256: round(256 K (1 - alpha)) with DDC, round(256 K) for plain SGM
    int q1, q2;        //!< round(K alpha Q1), round(K alpha Q2)
    int p1, p2;        //!< round(K P1), round(K P2)
    int p2Edge;        //!< max(p1, round(K P2 edgeP2Ratio)): P2 across a step of the left image (jumpPenalty)
    double scale;      //!< K
};

/** Picks the scale K, the largest whose worst-case sum of path costs, numPaths * (max cost + P2), fits in 16 bits,
and rounds the weights. With ddc false there is no prior term (plain SGM). */
CV_EXPORTS CostWeights computeCostWeights(int P1, int P2, int Q1, int Q2, double alpha, int numPaths, bool ddc,
                                          double edgeP2Ratio = 1.0);
/** w with its DDC terms for factor x alpha x Q1 and Q2 (the copied priors' weights, PipelineParams::wCopy); the sums
stay within 16 bits for factor <= 1. */
CV_EXPORTS CostWeights scaleDdcWeights(const CostWeights& w, double alpha, int Q1, int Q2, double factor);
//! numPaths * (largest matching cost + P2): the bound on the aggregated cost.
CV_EXPORTS int maxPathSum(const CostWeights& w, int numPaths);

//! Everything a stage needs, validated by the front class and converted to integers.
struct PipelineParams
{
    int minDisparity;
    int numDisparities;
    int numPaths;          //!< 4 or 8
    bool subpixel;
    int uniqueness1024;    //!< round(uniquenessRatio * 1024); 1024 = off
    int lrMaxDiff;
    int semidenseRadius;   //!< rs
    int semidenseThreshold;//!< Ts
    int checkRadius;       //!< rc
    int checkThreshold16;  //!< round(Tc * 16)
    int medianSize;        //!< 1 (off) or 3: the median filter before the check
    int visibilityRadiusX; //!< half width of the visibility filter's window (0 and visibilityRadiusY 0: off)
    int visibilityRadiusY; //!< half height
    int visibilityParallax256; //!< round(visibilityParallax * 256): the window's growth per pixel of disparity step
    int edgeThreshold;     //!< left-image step above which a disparity jump costs w.p2Edge (0: off)
    int ringGapFactor16;   //!< round(ringGapFactor * 16): ring interpolation's longest gap in ring spacings (0: off)
    bool semidense;        //!< SDSGM: the prior is the semidense map
    bool ddc;              //!< DSGM, SDSGM: the matching cost has the DDC term
    bool stereoCheck;      //!< the left-right test
    bool lidarCheck;       //!< the test against the sparse map (alone: camera-LiDAR; with stereoCheck: either passes)
    bool floatOutput;      //!< CV_32F pixels instead of CV_16S x16
    bool weighCopies;      //!< SDSGM with semidenseWeight < 1: copied priors take wCopy on LiDAR scans (copiedPrior)
    bool confidence;       //!< the check also writes each output pixel's confidence (outputConfidence)
    int searchWindow;      //!< the disparity windows' margin (searchWindowOn; 0: every pixel searches the full range)
    CostWeights w;
    CostWeights wCopy;     //!< w with the DDC terms (q1, q2) scaled by semidenseWeight
};

//! A matcher's parameters as the stages take them (for the per-stage tests; the front class passes its own).
CV_EXPORTS PipelineParams pipelineParamsOf(const StereoLidarSGM& matcher);
//! Every setting of `from` (its parameter table) set on `to`: the fail-safe's stereo-alone copy of a matcher.
void copySettings(const StereoLidarSGM& from, StereoLidarSGM& to);

// ---- Rules shared by both backends --------------------------------------------------------------------------------

//! Number of set bits (the Hamming distance of two census strings is popcount32(a ^ b)).
static LIDARSGM_HD int popcount32(unsigned v)
{
#if defined(__CUDA_ARCH__)
    return __popc(v);
#elif defined(__GNUC__) || defined(__clang__)
    return __builtin_popcount(v);
#else
    v = v - ((v >> 1) & 0x55555555u);
    v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
    return (int)((((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
#endif
}

/** Census string of one pixel: for each offset o of the first half of the window (rows above the centre, then the
pixels left of it, in raster order) one bit, I(p + o) > I(p - o), the first offset in the most significant of the
31 bits. at(dx, dy) returns the pixel at offset (dx, dy), clamped to the image by the caller. */
template <class Pixel>
static LIDARSGM_HD unsigned censusString(const Pixel& at)
{
    const int rx = CENSUS_WIDTH / 2, ry = CENSUS_HEIGHT / 2;
    unsigned c = 0;
    for (int dy = -ry; dy <= 0; dy++)
    {
        const int dxEnd = dy < 0 ? rx : -1;
        for (int dx = -rx; dx <= dxEnd; dx++)
            c = (c << 1) | (at(dx, dy) > at(-dx, -dy) ? 1u : 0u);
    }
    return c;
}

/** Whether the matching cost at a pixel whose prior is prior16 and whose own (filtered) sparse value is own16 takes
the copied priors' weights (wCopy: the DDC terms scaled by semidenseWeight) instead of w. On a LiDAR scan (scan:
weighCopies and the scan test, visibilityGrowthApplies, passed) a prior that semidensification or ring interpolation
brought from elsewhere is an inference, not a measurement. */
static LIDARSGM_HD bool copiedPrior(bool scan, int prior16, int own16)
{
    return scan && prior16 != NO_DISP && prior16 != own16;
}

//! The census term of the matching cost: census256 * h / 256, rounded to nearest (halves up).
static LIDARSGM_HD int censusTerm(int census256, int h) { return (census256 * h + 128) >> 8; }

//! The DDC term (paper Eq. 4) for disparity index d and prior index k (k < 0: no prior): 0, Q1 or Q2.
static LIDARSGM_HD int ddcTerm(int d, int k, const CostWeights& w)
{
    return k < 0 || d == k ? 0 : (d == k - 1 || d == k + 1) ? w.q1 : w.q2;
}

//! The matching cost C(p, d) from the Hamming distance h of the census strings at disparity index d.
static LIDARSGM_HD int matchingCost(int h, int d, int k, const CostWeights& w)
{
    return censusTerm(w.census256, h) + ddcTerm(d, k, w);
}

/** The penalty of a disparity jump on a path step from q to p (the P2 of paper Eq. 2): P2, or the smaller w.p2Edge
where the left image steps by more than edgeThreshold between q and p (an intensity edge is a likely depth edge;
Hirschmueller 2008 adapts P2 to the step likewise). edgeThreshold 0: always P2. intensityEdge is the test alone,
symmetric in p and q. */
static LIDARSGM_HD bool intensityEdge(int ip, int iq, int edgeThreshold)
{
    return edgeThreshold > 0 && (ip > iq ? ip - iq : iq - ip) > edgeThreshold;
}
static LIDARSGM_HD int jumpPenalty(int ip, int iq, int edgeThreshold, const CostWeights& w)
{
    return intensityEdge(ip, iq, edgeThreshold) ? w.p2Edge : w.p2;
}

//! Integer disparity (pixels) of a 1/16-pixel value, rounded to nearest (halves up).
static LIDARSGM_HD int roundDisp16(int d16) { return (d16 + 8) >> 4; }

/** Whether a 1/16-pixel sparse value is kept as a measurement for the search range [lo, hi] (whole pixels): the value
itself must not lie below lo (so no output, semidense maps included, falls below minDisparity) and its rounded integer
disparity must not lie above hi (so it indexes the cost volume). */
static LIDARSGM_HD bool sparseInRange(int d16, int lo, int hi) { return d16 >= lo * 16 && roundDisp16(d16) <= hi; }

//! A KITTI-encoded sparse value (d * 256, 0 = none) to 1/16 pixel, rounded to nearest; NO_DISP outside [lo, hi].
static LIDARSGM_HD int sparseFromKitti16(int v, int lo, int hi)
{
    const int d16 = (v + 8) >> 4;
    return v != 0 && sparseInRange(d16, lo, hi) ? d16 : NO_DISP;
}

//! A float sparse value (pixels; <= 0, NaN, infinite = none) to 1/16 pixel, rounded to nearest; NO_DISP outside [lo, hi].
static LIDARSGM_HD int sparseFromFloat(float v, int lo, int hi)
{
    // False for NaN; the upper bound keeps the cast in range. v * 16 is exact in double.
    if (!(v > 0.f && v < 1536.f))
        return NO_DISP;
    const int d16 = (int)floor((double)v * 16.0 + 0.5);
    return sparseInRange(d16, lo, hi) ? d16 : NO_DISP;
}

/* The units check. A sparse value the input convention counts as a measurement, in the search range or not (KITTI:
nonzero; pixels: positive and finite); one at or beyond the image's width, where no point seen by both cameras can be
(sparseBeyondImage); and the counts of a map. compute refuses a map most of whose measurements lie outside the search
range and beyond the image (unitsLookWrong: KITTI's x256 PNG passed as float pixels puts them there, a range too
small for the scene does not), and says once when a map that the mode needs has no value in the range
(checkSparseUnits, src/sparse_input.cpp). */
static LIDARSGM_HD bool sparseMeasured(unsigned short v) { return v != 0; }
static LIDARSGM_HD bool sparseMeasured(float v) { return v > 0.f && v <= 3.402823466e+38f; }   // false for NaN, inf
static LIDARSGM_HD bool sparseBeyondImage(unsigned short v, int width) { return (int)v >= width * 256; }
static LIDARSGM_HD bool sparseBeyondImage(float v, int width) { return v >= (float)width; }
struct SparseCounts
{
    int measured;   //!< values that are measurements (sparseMeasured)
    int inRange;    //!< of them, the values kept (sparseFromKitti16 / sparseFromFloat != NO_DISP)
    int beyond;     //!< of them, the values outside the range and beyond the image (sparseBeyondImage)
};
//! One value's part of SparseCounts (d16: its converted value), in the order of the struct: measured, kept, beyond.
template <typename T>
static LIDARSGM_HD void countSparseValue(T v, int d16, int width, bool& measured, bool& kept, bool& beyond)
{
    measured = sparseMeasured(v);
    kept = d16 != NO_DISP;
    beyond = measured && !kept && sparseBeyondImage(v, width);
}
//! Fewer measurements than this say too little of the units to refuse a map.
static const int UNITS_CHECK_MIN_MEASURED = 64;
static inline bool unitsLookWrong(const SparseCounts& c)
{
    return c.measured >= UNITS_CHECK_MIN_MEASURED && 2 * (long long)c.beyond > c.measured;
}

/* Disparity windows (searchWindowOn): the aggregation searches each WINDOW_TILE x WINDOW_TILE tile of the image over
[lo, hi) instead of [0, D): the prior indices (round(prior) - minD of the call's prior map: semidensified and
ring-interpolated values in SDSGM, the LiDAR's elsewhere) of the tile dilated by one tile on every side, widened by
the margin on both sides and rounded out to multiples of WINDOW_ALIGN (the CPU's widest vector, eight pairs of the
GPU's), clamped to the range. A tile whose dilated neighbourhood has no prior takes the coarse pass's disparities
instead (coarseDisparities: the same rule on the pair at 1 / COARSE_SCALE scale). Along a path, a disparity outside the
previous pixel's window has no path cost there (infinite): it is reached only through the previous minimum + P2. */
enum { WINDOW_TILE = 32, WINDOW_ALIGN = 16, COARSE_SCALE = 4 };

static LIDARSGM_HD bool searchWindowOn(const PipelineParams& p) { return p.searchWindow > 0; }

/** A tile's window [lo, hi) from the lowest and highest index 0 <= kMin <= kMax < D seen in its dilated
neighbourhood, the margin (>= 0) and the number of disparities D (a multiple of 16); lo < hi follows. */
static LIDARSGM_HD void tileWindow(int kMin, int kMax, int margin, int D, int& lo, int& hi)
{
    const int a = kMin - margin, b = kMax + margin + 1;
    lo = a <= 0 ? 0 : a / WINDOW_ALIGN * WINDOW_ALIGN;
    hi = b >= D ? D : (b + WINDOW_ALIGN - 1) / WINDOW_ALIGN * WINDOW_ALIGN;
}

/** The coarse pass's parameters: plain SGM with the paper's P1 and P2 over 4 paths, the whole range of coarse
disparities (their count rounded up to a multiple of 16), no uniqueness check or subpixel (every pixel gives a
disparity; only their range in a tile counts). */
CV_EXPORTS PipelineParams coarseParams(const PipelineParams& p);

//! A coarse pixel: the mean of a COARSE_SCALE^2 block of pixels (their sum), rounded to nearest.
static LIDARSGM_HD int coarseMean(int sum)
{
    return (sum + COARSE_SCALE * COARSE_SCALE / 2) / (COARSE_SCALE * COARSE_SCALE);
}

/** The uniqueness check (uniqueness1024 < 1024): the winner's aggregated cost best against second, the lowest cost more
than one disparity away (there is one: numDisparities >= 16). best * 1024 <= uniqueness1024 * second, and best
strictly below second: a cost curve that is flat at its minimum (a textureless patch where every disparity costs 0)
has no unique winner, though 0 <= ratio * 0. */
static LIDARSGM_HD bool uniqueWinner(int best, int second, int uniqueness1024)
{
    return best * 1024 <= uniqueness1024 * second && best < second;
}

/** Parabola through the aggregated costs at d - 1, d, d + 1, as a 1/16-pixel offset:
round(8 (S[d-1] - S[d+1]) / max(S[d-1] + S[d+1] - 2 S[d], 1)), halves away from zero. */
static LIDARSGM_HD int subpixelOffset16(int sm, int s0, int sp)
{
    const int num = 8 * (sm - sp);
    const int den = (sm + sp - 2 * s0) > 1 ? (sm + sp - 2 * s0) : 1;
    return num >= 0 ? (num + den / 2) / den : -((-num + den / 2) / den);
}

//! The most the visibility window grows on each side beyond its radii (hiddenBy).
enum { VISIBILITY_MAX_GROWTH = 32 };
/** The largest growth k (hiddenBy) that a value diff16 above a point allows: k * 16 * 256 <= visibilityParallax256 *
diff16, at most VISIBILITY_MAX_GROWTH; 0 where diff16 <= 0. The product fits an int: visibilityParallax <= 1. */
static LIDARSGM_HD int visibilityGrowthAllowed(int diff16, const PipelineParams& p)
{
    const int k = p.visibilityParallax256 * diff16 / 4096;   // truncated: the floor for a product >= 0
    return k < 0 ? 0 : k < (int)VISIBILITY_MAX_GROWTH ? k : (int)VISIBILITY_MAX_GROWTH;
}

/** The visibility filter: a sparse value d16 is hidden (a LiDAR point the camera cannot see, projected onto the
surface in front of it) by a value other16 at offset (dx, dy) when other16 is nearer, i.e. larger, by more than Tc and
the offset lies within the (2 rx + 1) x (2 ry + 1) window grown on every side by visibilityParallax pixels per pixel
of their difference: the band beside a near object in which a LiDAR apart from the camera sees background that the
camera cannot see widens in proportion to the disparity step, by the LiDAR's offset across the line of sight over the
stereo baseline (the stage sets parallax256 to 0 where the sparse map is no scan: visibilityGrowthApplies). In
integers: a growth of k pixels needs k * 16 * 256 <= parallax256 * (other16 - d16), and k is at most
VISIBILITY_MAX_GROWTH (visibilityGrowthAllowed). */
static LIDARSGM_HD bool hiddenBy(int other16, int d16, int dx, int dy, const PipelineParams& p)
{
    if (other16 == NO_DISP || other16 - d16 <= p.checkThreshold16)
        return false;
    const int ax = dx < 0 ? -dx : dx, ay = dy < 0 ? -dy : dy;
    const int kx = ax - p.visibilityRadiusX, ky = ay - p.visibilityRadiusY;
    const int k = kx > ky ? kx : ky;
    return k <= 0 || k <= visibilityGrowthAllowed(other16 - d16, p);
}

//! The most the visibility window grows on each side (sparse values differ by less than numDisparities pixels).
static LIDARSGM_HD int visibilityGrowth(const PipelineParams& p)
{
    const int g = p.visibilityParallax256 * p.numDisparities / 256;
    return g < (int)VISIBILITY_MAX_GROWTH ? g : (int)VISIBILITY_MAX_GROWTH;
}

//! Whether the visibility filter runs.
static inline bool visibilityFilterOn(const PipelineParams& p)
{
    return p.visibilityRadiusX > 0 || p.visibilityRadiusY > 0 || p.visibilityParallax256 > 0;
}

/** Semidensification's candidate order (paper Eq. 5 is an argmin; most winners cost 0, so ties are common): the
lowest census cost, then the nearest (squared distance), then the first row, then the first column, packed into one
31-bit key, the lowest wins: cost (5 bits), dx^2 + dy^2 (12 bits), dy + rs and dx + rs (7 bits each), where
(dx, dy) = (c - x, q - y) is the candidate's offset from the pixel and rs <= 32 the radius. For one pixel, dy and dx
order candidates as their rows and columns do. */
static LIDARSGM_HD unsigned semidenseKey(int cost, int dx, int dy, int rs)
{
    return ((unsigned)cost << 26) | ((unsigned)(dx * dx + dy * dy) << 14) | ((unsigned)(dy + rs) << 7) | (unsigned)(dx + rs);
}
//! The census cost of a key.
static LIDARSGM_HD int semidenseKeyCost(unsigned key) { return (int)(key >> 26); }

/* Ring interpolation (interpolateRings), after semidensification: a pixel left without a value takes the disparity
on the line through two sparse points of its column (ringCandidate16) if its census cost there is below Ts: the
nearest points above and below it (within RING_COLUMNS columns on either side) when they are at most ringGapLimit
apart; beyond the last ring below (or above), the nearest two above (or below), each step at most ringGapLimit. The
gap limit scales with the ring spacing measured on the sparse map: the lower median of each point's vertical distance
to the next point below it within the same columns (distances of RING_GAP_BINS - 1 and more share the last bin). */
enum { RING_COLUMNS = 2, RING_GAP_BINS = 256 };

//! The i-th column offset searched, i in [0, 2 RING_COLUMNS]: 0, -1, 1, -2, 2 (on equal rows the nearer column wins).
static LIDARSGM_HD int ringColumnOffset(int i) { return (i & 1) ? -((i + 1) >> 1) : (i >> 1); }

//! The longest gap bridged: round(ringGapFactor * spacing) from round(16 ringGapFactor).
static LIDARSGM_HD int ringGapLimit(int factor16, int spacing) { return (factor16 * spacing + 8) >> 4; }

/** The lower median of a histogram of n values (0 where n is 0): the smallest bin whose cumulative count exceeds
(n - 1) / 2. */
static LIDARSGM_HD int histogramLowerMedian(const int* hist, int bins)
{
    int n = 0;
    for (int i = 0; i < bins; i++)
        n += hist[i];
    if (n == 0)
        return 0;
    for (int i = 0, c = 0; i < bins; i++)
        if ((c += hist[i]) > (n - 1) / 2)
            return i;
    return bins - 1;
}

/* The visibility window's parallax growth applies to LiDAR scans only (visibilityGrowthApplies): a scan's points are
closer along its rows (the shots of a ring) than across them (the rings), while a scattered sample, such as
Middlebury's protocol of ground-truth pixels drawn from the camera's own view, has no scan lines and no sensor apart
from the camera. Per sparse point, the distance to the next point to its right in its row (rowPointGap) and to the
next point below it within RING_COLUMNS columns (columnPointGap), both capped to the last of SCAN_GAP_BINS bins (-1:
the image ends first); the map is a scan when the lower median of the first is below that of the second. The cap
keeps each point's search short (on the GPU one thread searches); where both medians reach it, there is no growth.
columnPointGap is ringPointGap's distance found by a direct search: the test runs before the visibility filter, where
ring interpolation's above / below maps (built later, on the filtered map, and only with ringGapFactor) do not exist. */
enum { SCAN_GAP_BINS = 32 };
static LIDARSGM_HD int rowPointGap(const short* row, int x, int W)
{
    for (int u = x + 1; u < W; u++)
    {
        if (u - x >= SCAN_GAP_BINS - 1)
            return SCAN_GAP_BINS - 1;
        if (row[u] != NO_DISP)
            return u - x;
    }
    return -1;
}

//! See rowPointGap: sparse16 with `step` elements per row.
static LIDARSGM_HD int columnPointGap(const short* sparse16, size_t step, int x, int y, int W, int H)
{
    const int c0 = x - RING_COLUMNS > 0 ? x - RING_COLUMNS : 0;
    const int c1 = x + RING_COLUMNS < W - 1 ? x + RING_COLUMNS : W - 1;
    for (int v = y + 1; v < H; v++)
    {
        if (v - y >= SCAN_GAP_BINS - 1)
            return SCAN_GAP_BINS - 1;
        const short* row = sparse16 + (size_t)v * step;
        for (int c = c0; c <= c1; c++)
            if (row[c] != NO_DISP)
                return v - y;
    }
    return -1;
}

//! From the lower medians of rowPointGap and columnPointGap: whether the map is a scan.
static LIDARSGM_HD bool scanGapsApply(int rowMedian, int columnMedian) { return rowMedian < columnMedian; }

//! From the histograms of rowPointGap and columnPointGap (SCAN_GAP_BINS bins each): whether the map is a scan.
static LIDARSGM_HD bool visibilityGrowthApplies(const int* rowGaps, const int* columnGaps)
{
    return scanGapsApply(histogramLowerMedian(rowGaps, SCAN_GAP_BINS), histogramLowerMedian(columnGaps, SCAN_GAP_BINS));
}

/** va + (vb - va) (y - ya) / (yb - ya) in 1/16 pixel, rounded to nearest (halves up), for ya < yb: the disparity at
row y (between the points or beyond them) of the plane through both points (a plane's disparity is linear in the
image). */
static LIDARSGM_HD int ringLine16(int va, int ya, int vb, int yb, int y)
{
    const int num = 2 * (vb - va) * (y - ya) + (yb - ya), den = 2 * (yb - ya);
    return va + (num >= 0 ? num / den : -((-num + den - 1) / den));   // floor division
}

/** The nearest sparse points above and below pixel x of a row, from that row's maps above[c] / below[c] (the row of
column c's nearest point strictly above / below, -1: none): rows ya, yb (-1: none) and columns xa, xb. Rows closer to
the pixel win, then the order of ringColumnOffset. */
static LIDARSGM_HD void nearestRingPoints(const short* above, const short* below, int x, int W, int& xa, int& ya,
                                          int& xb, int& yb)
{
    xa = ya = xb = yb = -1;
    for (int i = 0; i <= 2 * RING_COLUMNS; i++)
    {
        const int c = x + ringColumnOffset(i);
        if (c < 0 || c >= W)
            continue;
        if (above[c] > ya)
        {
            ya = above[c];
            xa = c;
        }
        if (below[c] >= 0 && (yb < 0 || below[c] < yb))
        {
            yb = below[c];
            xb = c;
        }
    }
}

/** A sparse point's vertical distance to the nearest point below it (nearestRingPoints on the maps of its row),
capped to the last bin; -1: none. */
static LIDARSGM_HD int ringPointGap(const short* above, const short* below, int x, int W, int y)
{
    int xa, ya, xb, yb;
    nearestRingPoints(above, below, x, W, xa, ya, xb, yb);
    return yb < 0 ? -1 : yb - y < RING_GAP_BINS - 1 ? yb - y : RING_GAP_BINS - 1;
}

/** nearestRingPoints on the maps above and below of a whole image (`step` elements per row), for ringCandidateOf. */
struct RingMapsNearest
{
    const short* above;
    const short* below;
    size_t step;
    int W;
    LIDARSGM_HD void operator()(int x, int y, int& xa, int& ya, int& xb, int& yb) const
    {
        nearestRingPoints(above + (size_t)y * step, below + (size_t)y * step, x, W, xa, ya, xb, yb);
    }
};

/** The ring interpolation's value at pixel (x, y) in 1/16 pixel, NO_DISP where the rule gives none: nearest(x, y, xa,
ya, xb, yb) gives nearestRingPoints at a pixel (RingMapsNearest, or the CPU's maps of them), the sparse map (sparseStep
elements per row), the gap limit. The caller checks its range and census cost. */
template <class Nearest>
static LIDARSGM_HD int ringCandidateOf(const Nearest& nearest, const short* sparse, size_t sparseStep, int x, int y,
                                       int gap)
{
    int xa, ya, xb, yb;
    nearest(x, y, xa, ya, xb, yb);
    if (ya < 0 && yb < 0)
        return NO_DISP;
    if (ya < 0 || yb < 0)
    {
        // Below the last ring (above the first): the line through the nearest point and the next one beyond it.
        const bool belowLast = ya >= 0;
        const int xn = belowLast ? xa : xb, yn = belowLast ? ya : yb;
        int xu, yu, xd, yd;
        nearest(xn, yn, xu, yu, xd, yd);
        const int x2 = belowLast ? xu : xd, y2 = belowLast ? yu : yd;
        if (y2 < 0 || (belowLast ? y - yn : yn - y) > gap || (belowLast ? yn - y2 : y2 - yn) > gap)
            return NO_DISP;
        xa = belowLast ? x2 : xn;
        ya = belowLast ? y2 : yn;
        xb = belowLast ? xn : x2;
        yb = belowLast ? yn : y2;
    }
    else if (yb - ya > gap)
        return NO_DISP;
    return ringLine16(sparse[(size_t)ya * sparseStep + xa], ya, sparse[(size_t)yb * sparseStep + xb], yb, y);
}

//! ringCandidateOf on the maps above and below (rows of each column's nearest sparse point, -1: none).
static LIDARSGM_HD int ringCandidate16(const short* above, const short* below, size_t step, const short* sparse,
                                       size_t sparseStep, int x, int y, int W, int gap)
{
    const RingMapsNearest nearest = { above, below, step, W };
    return ringCandidateOf(nearest, sparse, sparseStep, x, y, gap);
}

/* The ring check, with ring interpolation in SDSGM where the LiDAR test runs (ringCheckOn): the LiDAR test also
passes a disparity within checkThreshold16 of the ring line at the pixel itself (ringCandidate16), and a winner that
failed the uniqueness check (and that the median left without a value) is kept when it passes this test. Between
rings farther apart than the check's threshold allows for a slanted surface (the road), no sparse value of the
window agrees with the pixel, but the line through the rings above and below is that surface at the pixel. */
static LIDARSGM_HD bool ringCheckOn(const PipelineParams& p)
{
    return p.ringGapFactor16 > 0 && p.semidense && p.lidarCheck;
}

//! The ring check's test of disparity v16 at (x, y): the arguments of ringCandidateOf, then the threshold.
template <class Nearest>
static LIDARSGM_HD bool ringLineSupportsOf(int v16, const Nearest& nearest, const short* sparse, size_t sparseStep,
                                           int x, int y, int gap, int tc)
{
    const int line = ringCandidateOf(nearest, sparse, sparseStep, x, y, gap);
    return line != NO_DISP && (v16 > line ? v16 - line : line - v16) <= tc;
}
//! ringLineSupportsOf on the maps above and below.
static LIDARSGM_HD bool ringLineSupports(int v16, const short* above, const short* below, size_t step,
                                         const short* sparse, size_t sparseStep, int x, int y, int W, int gap, int tc)
{
    const RingMapsNearest nearest = { above, below, step, W };
    return ringLineSupportsOf(v16, nearest, sparse, sparseStep, x, y, gap, tc);
}

/* The 3x3 median of a disparity map: "no disparity" ranks above every value (so a pixel with 5 or more invalid
neighbours stays invalid, as in the paper's public code), coordinates outside the image are clamped (the census'
border rule). The median of 9 is taken as med3(max3(lows), med3(mids), min3(highs)) over the three columns of the
window, each sorted (low, mid, high) first: exact, and the column sorts are shared by neighbouring pixels. */
static LIDARSGM_HD int medianKey(int v) { return v == NO_DISP ? SHRT_MAX : v; }
static LIDARSGM_HD int medianValue(int key) { return key == SHRT_MAX ? NO_DISP : key; }

//! Min/max of scalars; the CPU's vector code passes its own with the same two members.
struct ScalarMinMax
{
    static LIDARSGM_HD int lo(int a, int b) { return a < b ? a : b; }
    static LIDARSGM_HD int hi(int a, int b) { return a < b ? b : a; }
};

//! Sorts a column of three: a <= b <= c afterwards.
template <class M, typename T>
static LIDARSGM_HD void sortColumn3(T& a, T& b, T& c)
{
    const T l = M::lo(a, b), h = M::hi(a, b);
    const T h2 = M::hi(h, c);
    const T m = M::lo(h, c);
    a = M::lo(l, m);
    b = M::hi(l, m);
    c = h2;
}

template <class M, typename T>
static LIDARSGM_HD T median3(T a, T b, T c)
{
    return M::hi(M::lo(a, b), M::lo(M::hi(a, b), c));
}

//! Median of nine from three sorted columns (low i, mid i, high i), i = left, centre, right.
template <class M, typename T>
static LIDARSGM_HD T medianOfColumns(T l0, T l1, T l2, T m0, T m1, T m2, T h0, T h1, T h2)
{
    const T maxLow = M::hi(M::hi(l0, l1), l2);
    const T midMid = median3<M>(m0, m1, m2);
    const T minHigh = M::lo(M::lo(h0, h1), h2);
    return median3<M>(maxLow, midMid, minHigh);
}

/** The confidence of an output disparity, from what the check knows of it (the rule of the confidence map, see
StereoLidarSGM::compute and doc/design.md):
- its evidence: 4 where both confirm it (the left-right test, and a LiDAR value within Tc in the (2 rs + 1)^2 window
  of semidensification or the ring check), 3 the LiDAR alone, 2 the left-right test alone, 1 neither (kept without a
  check), 0 no disparity. Two independent confirmations before one; a LiDAR measurement before the left-right test,
  which shares the matching cost's failure modes (repetitive texture, the same occluded surface). The LiDAR evidence
  takes the window within which semidensification hands a LiDAR value to a pixel, not the check's (2 rc + 1)^2,
  which confirms almost any disparity (doc/decisions.md, "Uniqueness");
- its neighbourhood's agreement: range16, the largest minus the smallest disparity (1/16 px) among the disparities of
  its 3x3 neighbourhood in the check's input (confidenceRange16): a pixel whose neighbours disagree lies on a depth
  edge or in noise, where matching fails most.
confidence = evidence / 4 * 32 / (32 + min(range16, 2048)): a range of 2 px halves it. In integers, out of
CONFIDENCE_MAX; the output map is that over CONFIDENCE_MAX, in [0, 1]. */
enum { CONFIDENCE_MAX = 4 * 16383 };
static LIDARSGM_HD int outputConfidence(int evidence, int range16)
{
    const int r = range16 < 2048 ? range16 : 2048;
    return evidence * 16383 * 32 / (32 + r);
}
static LIDARSGM_HD int checkEvidence(bool lrPass, bool lidarPass)
{
    return lrPass ? (lidarPass ? 4 : 2) : (lidarPass ? 3 : 1);
}
static LIDARSGM_HD float confidenceValue(int confidence) { return (float)confidence / (float)CONFIDENCE_MAX; }
/** range16 of outputConfidence at (x, y): over the 3x3 neighbourhood within the image, NO_DISP values left out; at(x,
y) reads the map. */
template <typename At> static LIDARSGM_HD int confidenceRange16(const At& at, int x, int y, int W, int H)
{
    int lo = SHRT_MAX, hi = SHRT_MIN + 1;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
        {
            const int u = x + dx, v = y + dy;
            if (u < 0 || v < 0 || u >= W || v >= H)
                continue;
            const int d = at(u, v);
            if (d == NO_DISP)
                continue;
            lo = d < lo ? d : lo;
            hi = d > hi ? d : hi;
        }
    return hi >= lo ? hi - lo : 0;
}

//! Output encodings (cv::StereoSGBM's): CV_16S x16 with (minD - 1) * 16 for "none", or CV_32F pixels with minD - 1.
static LIDARSGM_HD short encodeOutput16(int d16, int minD) { return (short)(d16 == NO_DISP ? (minD - 1) * 16 : d16); }
static LIDARSGM_HD float encodeOutput32(int d16, int minD)
{
    return d16 == NO_DISP ? (float)(minD - 1) : d16 * (1.f / 16);
}

//! KITTI's 16-bit disparity encoding: round(d * 256), 0 for d <= 0 ("none"), at least 1 for d > 0, at most 65535.
static LIDARSGM_HD unsigned short kittiEncode(double d)
{
    if (!(d > 0))
        return 0;
    const double v = floor(d * 256.0 + 0.5);   // d * 256 is exact: no rounding step to fuse
    return (unsigned short)(v < 1.0 ? 1.0 : v > 65535.0 ? 65535.0 : v);
}

/** One row of a 3x4 projection applied to (X, Y, Z, 1), in the order ((r0 X + r1 Y) + r2 Z) + r3, each operation
rounded on its own (the module is built with -ffp-contract=off, the device uses the explicitly rounded intrinsics). */
static LIDARSGM_HD double projectRow(const double* r, double X, double Y, double Z)
{
#ifdef __CUDA_ARCH__
    return __dadd_rn(__dadd_rn(__dadd_rn(__dmul_rn(r[0], X), __dmul_rn(r[1], Y)), __dmul_rn(r[2], Z)), r[3]);
#else
    return r[0] * X + r[1] * Y + r[2] * Z + r[3];
#endif
}

//! u / z (or v / z) rounded to the nearest pixel, halves up.
static LIDARSGM_HD double projectPixel(double u, double z)
{
#ifdef __CUDA_ARCH__
    return floor(__dadd_rn(__ddiv_rn(u, z), 0.5));
#else
    return floor(u / z + 0.5);
#endif
}

//! The disparity of a point at depth z: focalBaseline / z.
static LIDARSGM_HD float projectDisparity(double focalBaseline, double z)
{
#ifdef __CUDA_ARCH__
    return (float)__ddiv_rn(focalBaseline, z);
#else
    return (float)(focalBaseline / z);
#endif
}

// ---- The backends --------------------------------------------------------------------------------------------------
#ifndef __CUDACC__

struct AggregationState;   // the CPU aggregation's buffers (src/aggregation.simd.hpp)
struct SparseColumns;      // a sparse map's points by column and by row (src/sparse_window.hpp)

/** Ring interpolation's maps (interpolateRings), kept for the ring check: for each pixel the rows of its column's
nearest sparse point above and below (-1: none), nearestRingPoints of each pixel on them (CV_16SC4: xa, ya, xb, yb),
and the gap limit; valid false where the rule did not run. */
struct RingMaps
{
    Mat above16, below16, nearest;
    int gap = 0;
    bool valid = false;
};

/** The winner-takes-all's maps (aggregateCosts on the CPU, winnerTakesAll on the GPU), CV_16SC1:
disp16: left disparity x16 (subpixel if enabled) or NO_DISP where the uniqueness check fails;
dispInt: the integer left disparity (NO_DISP where not unique);
dispRight: the integer right-view disparity (lowest aggregated cost along the diagonal x + d);
nonUnique16 (written only where ringCheckOn(p)): the winner x16 where the uniqueness check fails, NO_DISP
elsewhere. */
struct WinnerMaps
{
    Mat disp16, dispInt, dispRight, nonUnique16;
};

//! nearestRingPoints read from RingMaps::nearest, for ringCandidateOf.
struct RingNearestMap
{
    const Vec4s* map;
    size_t step;   // elements (Vec4s) per row
    void operator()(int x, int y, int& xa, int& ya, int& xb, int& yb) const
    {
        const Vec4s& v = map[(size_t)y * step + x];
        xa = v[0];
        ya = v[1];
        xb = v[2];
        yb = v[3];
    }
};

/** The CPU pipeline (src/cpu_pipeline.cpp): its work buffers and the order of the stage calls. Inputs are checked by
the front class. semidenseOnly stops after semidensification and writes the semidense map. */
class CpuPipeline
{
public:
    /** confidence: written where p.confidence (consistencyCheck). warned: the matcher's flag of the units check's
    warning (checkSparseUnits). */
    void run(const Mat& left, const Mat& right, const Mat& sparse, const PipelineParams& p, bool semidenseOnly,
             OutputArray out, bool& warned, OutputArray confidence = noArray());
    //! The share of the cells the last run searched (windowCells over W H D; 0 before any).
    double searchedFraction() const { return searched_; }
private:
    double searched_ = 0;
    Mat windows_;
    Mat censusL_, censusR_, sparse16_, visible16_, semidense16_;
    WinnerMaps winners_;
    RingMaps rings_;
    Ptr<AggregationState> aggregation_, coarseAggregation_;
    Ptr<SparseColumns> points_;   // sparse16_'s points, listed once for semidensification and the check
    Mat med16_, medInt_, medRight_;
};

/** The CUDA pipeline (src_cuda/cuda_pipeline.cpp): GpuMat buffers, the element-type dispatch, and the ordering of
calls made on different streams. Without CUDA every call raises an error. */
class CudaPipeline
{
public:
    CudaPipeline();
    ~CudaPipeline();
    /** stream == nullptr: the default stream. The units check's counts come from the device: outside a graph capture
    the call waits at its end for the conversion's event (long done by then unless the stream had work queued). */
    void run(const cuda::GpuMat& left, const cuda::GpuMat& right, const cuda::GpuMat& sparse, const PipelineParams& p,
             bool semidenseOnly, OutputArray out, cuda::Stream* stream, bool& warned,
             OutputArray confidence = noArray());
    //! cv::cuda::projectPointsToDisparity's device work; PT = projection * lidarToCamera, row-major 3x4.
    static void projectPoints(const cuda::GpuMat& points, int n, int strideFloats, const double PT[12],
                              double focalBaseline, Size imageSize, int dtype, OutputArray out, cuda::Stream& stream);
    //! As CpuPipeline's; waits for the last call to finish.
    double searchedFraction() const;
private:
    struct Buffers;
    Buffers* b_;
    CudaPipeline(const CudaPipeline&);
    CudaPipeline& operator=(const CudaPipeline&);
};

#endif

}}} // namespace cv::lidarsgm::detail

#endif
