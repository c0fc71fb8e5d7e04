// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification's rows (semidensification.dispatch.cpp), compiled once per instruction set: the census costs of
// the candidates are popcounts, one instruction where the CPU has it.

#include "cpu_stages.hpp"
#include "sparse_window.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void semidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                     const PipelineParams& p, Mat& semidense16, const Range& r);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

void semidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                     const PipelineParams& p, Mat& semidense16, const Range& r)
{
    const int W = censusL.cols, rs = p.semidenseRadius, Ts = p.semidenseThreshold;
    WindowCursor cur(cols, rs, r.start);
    for (int y = r.start; y < r.end; y++)
    {
        cur.moveTo(y);
        const unsigned* L = censusL.ptr<unsigned>(y);
        const unsigned* R = censusR.ptr<unsigned>(y);
        const short* own = sparse16.ptr<short>(y);
        short* out = semidense16.ptr<short>(y);
        for (int x = 0; x < W; x++)
        {
            SemidenseCandidate best = { INT_MAX, INT_MAX, INT_MAX, INT_MAX };
            short bestVal = NO_DISP;
            const int c0 = std::max(0, x - rs), c1 = std::min(W - 1, x + rs);
            for (int c = c0; c <= c1; c++)
            {
                for (int i = cur.lo[c]; i < cur.hi[c]; i++)
                {
                    const int q = cols.row[i];
                    const short v = cols.value[i];
                    const int xr = std::min(std::max(x - roundDisp16(v), 0), W - 1);
                    const SemidenseCandidate cand = { popcount32(L[x] ^ R[xr]),
                                                      (c - x) * (c - x) + (q - y) * (q - y), q, c };
                    if (cand.betterThan(best))
                    {
                        best = cand;
                        bestVal = v;
                    }
                }
            }
            out[x] = best.cost < Ts ? bestVal : own[x];
        }
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
