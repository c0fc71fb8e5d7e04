// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The matching residual's rows (matching_residual.dispatch.cpp), compiled once per instruction set: the Hamming
// distances are most of its work, and the builds with SSE 4.2 and AVX2 count bits in one instruction.

#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void matchingOffsetRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, int radius, int uniqueness1024,
                        const Range& rows, std::vector<int>* offsets16);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

void matchingOffsetRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, int radius, int uniqueness1024,
                        const Range& rows, std::vector<int>* offsets16)
{
    const int W = censusL.cols, n = 2 * radius + 1;
    std::vector<int> cost(n);
    for (int y = rows.start; y < rows.end; y++)
    {
        const short* s = sparse16.ptr<short>(y);
        const unsigned* l[3] = { censusL.ptr<unsigned>(y - 1), censusL.ptr<unsigned>(y), censusL.ptr<unsigned>(y + 1) };
        const unsigned* r[3] = { censusR.ptr<unsigned>(y - 1), censusR.ptr<unsigned>(y), censusR.ptr<unsigned>(y + 1) };
        for (int x = 1; x < W - 1; x++)
        {
            if (s[x] == NO_DISP)
                continue;
            const int lo = roundDisp16(s[x]) - radius;
            if (x - 1 - (lo + n - 1) < 0 || x + 1 - lo > W - 1)
                continue;   // the 3x3 block's match would leave the right image
            // cost[k]: the block at disparity lo + k, its right pixels at x + dx - lo - k.
            std::fill(cost.begin(), cost.end(), 0);
            for (int dy = 0; dy < 3; dy++)
                for (int dx = -1; dx <= 1; dx++)
                {
                    const unsigned a = l[dy][x + dx];
                    const unsigned* b = r[dy] + x + dx - lo;
                    for (int k = 0; k < n; k++)
                        cost[k] += popcount32(a ^ b[-k]);
                }
            int best = 0, worst = cost[0];
            for (int k = 1; k < n; k++)
            {
                best = cost[k] < cost[best] ? k : best;
                worst = std::max(worst, cost[k]);
            }
            if (worst == cost[best])
                continue;   // flat: no texture to match
            // The matcher's uniqueness check at its default ratio: an ambiguous block (repetitive or faint texture)
            // has no match to compare with, and would add chance offsets.
            int second = INT_MAX;
            for (int k = 0; k < n; k++)
                if (k < best - 1 || k > best + 1)
                    second = std::min(second, cost[k]);
            if (!uniqueWinner(cost[best], second, uniqueness1024))
                continue;
            int matched16 = (lo + best) * 16;
            if (best > 0 && best < n - 1)
                matched16 += subpixelOffset16(cost[best - 1], cost[best], cost[best + 1]);
            offsets16[y].push_back(std::abs(s[x] - matched16));
        }
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
