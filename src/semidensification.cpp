// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification (paper Sec. IV-B, Eq. 5): spread the LiDAR disparities to pixels whose census matches them.
// No smoothness here on purpose (the paper: keeps thin structures; SGM smooths later).

#include "precomp.hpp"
#include "cpu_stages.hpp"
#include "sparse_window.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void semidensify(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const PipelineParams& p,
                 Mat& semidense16)
{
    const int W = censusL.cols, H = censusL.rows, rs = p.semidenseRadius, Ts = p.semidenseThreshold;
    CV_Assert(sparse16.type() == CV_16SC1 && sparse16.size() == censusL.size());
    semidense16.create(censusL.size(), CV_16SC1);
    const SparseColumns cols(sparse16);

    parallel_for_(Range(0, H), [&](const Range& r) {
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
    }, std::max(1, H / 16));
}

}}} // namespace cv::lidarsgm::detail
