// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Integer weights of the scaled SGM energy. Path costs are kept in 16 bits on both the CPU and the GPU (the GPU
// holds one W x H x D sum volume); the scale K is the largest that keeps the worst case in range, refined so that
// rounding the weights distorts their ratios (alpha above all) as little as possible.

#include "precomp.hpp"
#include "pipeline.hpp"

namespace cv { namespace lidarsgm { namespace detail {

static int maxPathSum(const CostWeights& w, int numPaths, bool ddc)
{
    const int cmax = w.census * CENSUS_BITS + (ddc ? w.q2 : 0);
    // A path cost never exceeds the matching cost plus P2 (the recursion subtracts the previous minimum).
    return numPaths * (cmax + w.p2);
}

CostWeights computeCostWeights(int P1, int P2, int Q1, int Q2, double alpha, int numPaths, bool ddc)
{
    CV_Assert(numPaths == 4 || numPaths == 8);
    // Paper Eq. 4 taken as written: with DDC on, the census term is (1 - alpha) H at every pixel, and the DDC term
    // is added where a prior exists. (Weighting H by 1 only where no prior exists was measured too, see
    // doc/notes.md: it makes SDSGM clearly worse on KITTI.) Plain SGM has no alpha: weight 1.
    const double censusW = ddc ? 1.0 - alpha : 1.0;
    const double target[5] = { censusW, ddc ? alpha * Q1 : 0.0, ddc ? alpha * Q2 : 0.0, (double)P1, (double)P2 };
    const double cmax = censusW * CENSUS_BITS + (ddc ? alpha * Q2 : 0.0);
    const double kmax = 65535.0 / (numPaths * (cmax + P2 + 1.0));

    CostWeights best = CostWeights();
    double bestErr = DBL_MAX;
    const int steps = 4096;
    for (int i = 0; i <= steps; i++)
    {
        const double k = kmax * (1.0 - 0.5 * i / steps);
        int v[5];
        double err = 0.0;
        for (int j = 0; j < 5; j++)
        {
            const double t = k * target[j];
            v[j] = cvRound(t);
            if (target[j] > 0.0)
                err = std::max(err, std::abs(v[j] - t) / t);
        }
        CostWeights w;
        w.census = v[0]; w.q1 = v[1]; w.q2 = v[2]; w.p1 = v[3]; w.p2 = v[4]; w.scale = k;
        if (maxPathSum(w, numPaths, ddc) > 65535)
            continue;
        if (err < bestErr - 1e-12)
        {
            bestErr = err;
            best = w;
        }
    }
    CV_Assert(bestErr < DBL_MAX);
    return best;
}

}}} // namespace cv::lidarsgm::detail
