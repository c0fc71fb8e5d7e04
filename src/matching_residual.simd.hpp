// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// The matching residual's rows (matching_residual.dispatch.cpp), compiled once per instruction set: the Hamming
// distances are most of its work: a vector of disparities at a time, and the builds with SSE 4.2 and AVX2 count the
// bits of the rest in one instruction.

#include "cpu_stages.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void matchingOffsets(const Mat& censusL, const Mat& censusR, const Point3i* points, int n, Point move, const Range& rows,
                     int radius, int uniqueness1024, std::vector<int>& offsets16);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

namespace {

/** cost[k], k < n: the Hamming distances of the 3x3 block of left strings around column x (rows l[0..2]) to the right
strings at x + dx - lo - k (rows r[0..2]), summed. The right strings of one left string lie side by side, lowest
disparity last: where whole vectors of them fit in the row, a vector of disparities at a time. */
inline void blockCosts(const unsigned* const* l, const unsigned* const* r, int x, int lo, int n, int W, int* cost)
{
#if CV_SIMD && !CV_SIMD_SCALABLE
    const int L = VTraits<v_uint32>::vlanes(), blocks = (n + L - 1) / L;
    enum { MAX_BLOCKS = 4 };
    // rev[j] = cost[n - 1 - j]; the loads reach column x + 1 - (lo + n - 1) + blocks * L - 1.
    if (blocks <= MAX_BLOCKS && x + 1 - (lo + n - 1) + blocks * L <= W)
    {
        v_uint32 acc[MAX_BLOCKS];
        for (int b = 0; b < blocks; b++)
            acc[b] = vx_setzero_u32();
        for (int dy = 0; dy < 3; dy++)
            for (int dx = -1; dx <= 1; dx++)
            {
                const v_uint32 a = vx_setall_u32(l[dy][x + dx]);
                const unsigned* base = r[dy] + x + dx - (lo + n - 1);
                for (int b = 0; b < blocks; b++)
                    acc[b] = v_add(acc[b], v_popcount(v_xor(a, vx_load(base + b * L))));
            }
        unsigned rev[MAX_BLOCKS * VTraits<v_uint32>::max_nlanes];
        for (int b = 0; b < blocks; b++)
            v_store(rev + b * L, acc[b]);
        for (int k = 0; k < n; k++)
            cost[k] = (int)rev[n - 1 - k];
        return;
    }
#endif
    std::fill(cost, cost + n, 0);
    for (int dy = 0; dy < 3; dy++)
        for (int dx = -1; dx <= 1; dx++)
        {
            const unsigned a = l[dy][x + dx];
            const unsigned* b = r[dy] + x + dx - lo;
            for (int k = 0; k < n; k++)
                cost[k] += popcount32(a ^ b[-k]);
        }
}

} // namespace

void matchingOffsets(const Mat& censusL, const Mat& censusR, const Point3i* points, int n, Point move, const Range& rows,
                     int radius, int uniqueness1024, std::vector<int>& offsets16)
{
    const int W = censusL.cols, k = 2 * radius + 1;
    std::vector<int> cost(k);
    for (int i = 0; i < n; i++)
    {
        const int x = points[i].x + move.x, y = points[i].y + move.y, s = points[i].z;
        if (y < rows.start || y >= rows.end || x < 1 || x > W - 2)
            continue;
        const int lo = roundDisp16(s) - radius;
        if (x - 1 - (lo + k - 1) < 0 || x + 1 - lo > W - 1)
            continue;   // the 3x3 block's match would leave the right image
        const unsigned* l[3] = { censusL.ptr<unsigned>(y - 1), censusL.ptr<unsigned>(y), censusL.ptr<unsigned>(y + 1) };
        const unsigned* r[3] = { censusR.ptr<unsigned>(y - 1), censusR.ptr<unsigned>(y), censusR.ptr<unsigned>(y + 1) };
        blockCosts(l, r, x, lo, k, W, cost.data());
        int best = 0, worst = cost[0];
        for (int j = 1; j < k; j++)
        {
            best = cost[j] < cost[best] ? j : best;
            worst = std::max(worst, cost[j]);
        }
        if (worst == cost[best])
            continue;   // flat: no texture to match
        // The matcher's uniqueness check at its default ratio: an ambiguous block (repetitive or faint texture)
        // has no match to compare with, and would add chance offsets.
        int second = INT_MAX;
        for (int j = 0; j < k; j++)
            if (j < best - 1 || j > best + 1)
                second = std::min(second, cost[j]);
        if (!uniqueWinner(cost[best], second, uniqueness1024))
            continue;
        int matched16 = (lo + best) * 16;
        if (best > 0 && best < k - 1)
            matched16 += subpixelOffset16(cost[best - 1], cost[best], cost[best + 1]);
        offsets16.push_back(std::abs(s - matched16));
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
