// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Internal interface of the pipeline stages. The CPU stages live in src/<stage>.cpp, the CUDA ones in
// src_cuda/<stage>.cu; both follow the integer definitions written down here, so their outputs are identical.

#ifndef OPENCV_LIDARSGM_PIPELINE_HPP
#define OPENCV_LIDARSGM_PIPELINE_HPP

#include "opencv2/core.hpp"
#include <climits>

// Helpers shared by host and device code.
#ifdef __CUDACC__
#  define LIDARSGM_HD __host__ __device__ __forceinline__
#else
#  define LIDARSGM_HD inline
#endif


namespace cv { namespace lidarsgm { namespace detail {

//! Centre-symmetric census: a 9x7 window, each of the 31 pixel pairs (p + o, p - o) gives one bit.
enum { CENSUS_WIDTH = 9, CENSUS_HEIGHT = 7, CENSUS_BITS = (CENSUS_WIDTH * CENSUS_HEIGHT - 1) / 2 };

//! Marks "no disparity" in the internal 1/16-pixel maps (CV_16SC1).
const short NO_DISP = SHRT_MIN;

//! Integer weights of the scaled energy (see StereoLidarSGM's documentation and computeCostWeights).
struct CostWeights
{
    int census256;     //!< census weight x 256: round(256 K (1 - alpha)) with DDC, round(256 K) for plain SGM
    int q1, q2;        //!< round(K alpha Q1), round(K alpha Q2)
    int p1, p2;        //!< round(K P1), round(K P2)
    double scale;      //!< K
};

//! The census term of the matching cost: census256 * h / 256, rounded to nearest (halves up).
static LIDARSGM_HD int censusTerm(int census256, int h) { return (census256 * h + 128) >> 8; }

/** Picks the scale K, the largest whose worst-case sum of path costs, numPaths * (max cost + P2), fits in 16 bits,
and rounds the weights. With ddc false there is no prior term (plain SGM). */
CV_EXPORTS CostWeights computeCostWeights(int P1, int P2, int Q1, int Q2, double alpha, int numPaths, bool ddc);
//! numPaths * (largest matching cost + P2): the bound on the aggregated cost.
CV_EXPORTS int maxPathSum(const CostWeights& w, int numPaths);

//! Everything a stage needs, already validated and converted to integers.
struct PipelineParams
{
    int minDisparity;
    int numDisparities;
    int numPaths;          //!< 4 or 8
    bool subpixel;
    int uniqueness1024;    //!< round(uniquenessRatio * 1024)
    int lrMaxDiff;
    int semidenseRadius;   //!< rs
    int semidenseThreshold;//!< Ts
    int checkRadius;       //!< rc
    int checkThreshold16;  //!< round(Tc * 16)
    int medianSize;        //!< 1 (off) or 3: the median filter before the check
    int mode;              //!< StereoLidarSGM::FusionMode
    int check;             //!< StereoLidarSGM::ConsistencyCheck
    CostWeights w;
};

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

//! Integer disparity (pixels) of a 1/16-pixel value, rounded to nearest (halves up).
static LIDARSGM_HD int roundDisp16(int d16) { return (d16 + 8) >> 4; }

/** Whether a 1/16-pixel sparse value is kept as a measurement for the search range [lo, hi] (whole pixels): the value
itself must not lie below lo (so no output, semidense maps included, falls below minDisparity) and its rounded integer
disparity must not lie above hi (so it indexes the cost volume). */
static LIDARSGM_HD bool sparseInRange(int d16, int lo, int hi) { return d16 >= lo * 16 && roundDisp16(d16) <= hi; }

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

// ---- CPU stages (exported for the per-stage unit tests; not part of the public API) ------------------------------------------------------------------------------------------------

/** Sparse input (CV_16UC1 x256 or CV_32FC1 pixels) to the internal CV_16SC1 1/16-pixel map with NO_DISP for "none".
Values below minDisparity, or whose rounded integer disparity is above minDisparity + numDisparities - 1, become
NO_DISP (sparseInRange). */
CV_EXPORTS void convertSparse(const Mat& sparse, int minDisparity, int numDisparities, Mat& sparse16);

//! Census transform (CV_8UC1 or CV_16UC1 in, CV_32SC1 bit strings out); pixels outside the image are clamped.
CV_EXPORTS void censusTransform(const Mat& image, Mat& census);

/** Semidensification (paper Eq. 5): among the sparse disparities q in the (2 rs + 1)^2 window of p, the one with the
lowest census cost H(p, round(q)) wins if that cost is below Ts; ties go to the nearest q, then to the first in
raster order. Otherwise p keeps its own sparse value (or none). */
CV_EXPORTS void semidensify(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                 Mat& semidense16);

/** Matching cost volume, rows = image rows, cols = width * numDisparities, CV_16UC1, d fastest.
C(p, d) = censusTerm(census256, H(p, d)), plus {0, q1, q2} for |d - round(prior)| = 0, 1, > 1 where prior16 has a value. prior16 may be empty (plain SGM). The right pixel x - d is clamped to the image. */
CV_EXPORTS void computeMatchingCost(const Mat& censusL, const Mat& censusR, const Mat& prior16, const PipelineParams& p,
                         Mat& cost);

//! Sums the path costs of 4 or 8 SGM paths into sum (same layout as cost).
CV_EXPORTS void aggregateCosts(const Mat& cost, int width, const PipelineParams& p, Mat& sum);

/** Winner-takes-all with the uniqueness check and the parabola fit.
disp16: left disparity x16 (subpixel if enabled) or NO_DISP where the uniqueness check fails;
dispInt: the integer left disparity (NO_DISP where not unique);
dispRight: the integer right-view disparity from the same volume (lowest cost along the diagonal x + d). */
CV_EXPORTS void winnerTakesAll(const Mat& sum, int width, const PipelineParams& p, Mat& disp16, Mat& dispInt, Mat& dispRight);

/** 3x3 median of a CV_16SC1 disparity map (1/16 or whole pixels), "no disparity" ranked above every value,
coordinates clamped at the border (medianKey, medianOfColumns). src and dst must differ. */
CV_EXPORTS void medianFilter(const Mat& src, Mat& dst);

/** Consistency check (paper Eq. 6), in place on disp16: left-right test (|dL - dR(x - dL)| <= lrMaxDiff) and/or the
LiDAR test (some sparse16 value within the (2 rc + 1)^2 window is within checkThreshold16 of disp16). */
CV_EXPORTS void consistencyCheck(Mat& disp16, const Mat& dispInt, const Mat& dispRight, const Mat& sparse16,
                      const PipelineParams& p);

}}} // namespace cv::lidarsgm::detail

#endif
