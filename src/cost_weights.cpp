// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Integer weights of the scaled SGM energy. Path costs are kept in 16 bits on both the CPU and the GPU (the GPU
// holds one W x H x D sum volume), so the energy is scaled by the largest K that keeps the worst case in range.
// The census weight K (1 - alpha) is carried with 8 fractional bits and each census term rounded on its own, so
// alpha is honoured to within 1/256 of a cost unit even when K (1 - alpha) is small (alpha close to 1).

#include "precomp.hpp"
#include "pipeline.hpp"

namespace cv { namespace lidarsgm { namespace detail {

int maxPathSum(const CostWeights& w, int numPaths)
{
    // A path cost never exceeds the matching cost plus P2 (the recursion subtracts the previous minimum).
    return numPaths * (censusTerm(w.census256, CENSUS_BITS) + w.q2 + w.p2);
}

CostWeights scaleDdcWeights(const CostWeights& w, double alpha, int Q1, int Q2, double factor)
{
    CV_Assert(factor > 0.0 && factor <= 1.0);
    CostWeights s = w;
    s.q1 = cvRound(w.scale * alpha * Q1 * factor);
    s.q2 = cvRound(w.scale * alpha * Q2 * factor);
    return s;
}

CostWeights computeCostWeights(int P1, int P2, int Q1, int Q2, double alpha, int numPaths, bool ddc,
                               double edgeP2Ratio)
{
    CV_Assert(numPaths == 4 || numPaths == 8);
    CV_Assert(edgeP2Ratio > 0 && edgeP2Ratio <= 1);
    CV_Assert(alpha >= 0.0 && alpha <= 1.0 && P1 >= 0 && P2 >= 0 && Q1 >= 0 && Q2 >= 0);
    // Paper Eq. 4 taken as written: with DDC on, the census term is (1 - alpha) H at every pixel, and the DDC term
    // is added where a prior exists. (Weighting H by 1 where no prior exists makes SDSGM clearly worse on KITTI:
    // doc/decisions.md, "DDC weighting".) Plain SGM has no alpha: weight 1.
    const double censusW = ddc ? 1.0 - alpha : 1.0;
    const double aQ1 = ddc ? alpha * Q1 : 0.0, aQ2 = ddc ? alpha * Q2 : 0.0;
    // + 1 leaves room for the rounding of each term.
    double k = 65535.0 / (numPaths * (censusW * CENSUS_BITS + aQ2 + P2 + 1.0));
    for (;;)
    {
        CostWeights w;
        w.scale = k;
        w.census256 = cvRound(k * censusW * 256.0);
        w.q1 = cvRound(k * aQ1);
        w.q2 = cvRound(k * aQ2);
        w.p1 = cvRound(k * P1);
        w.p2 = cvRound(k * P2);
        w.p2Edge = std::max(w.p1, cvRound(k * P2 * edgeP2Ratio));
        if (maxPathSum(w, numPaths) <= 65535)
            return w;
        k *= 0.999;
    }
}

}}} // namespace cv::lidarsgm::detail
