// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semi-global aggregation (paper Eq. 2; the jump penalty is jumpPenalty, pipeline.hpp) over 4 paths (left-right, right-left, top-down, bottom-up) or 8 (plus the
// four diagonals), summed into one 16-bit volume. Each path's cost stays below the matching cost plus P2, and the
// cost weights are scaled so that the sum of all paths fits in 16 bits: the saturating adds never saturate on real
// values, only on the 0xFFFF sentinels that stand for "d - 1 / d + 1 out of range".
//
// Work split: the horizontal paths are independent per row and run rows in parallel; the vertical and diagonal
// paths advance row by row (each row depends on the previous one) with the columns of a row in parallel.

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

namespace {

const ushort SENTINEL = 0xFFFF;

/** One step of the recursion for one pixel: Lout(d) = C(d) + min(Lp(d), Lp(d-1) + P1, Lp(d+1) + P1, minPrev + P2)
 - minPrev. Lp[-1] and Lp[D] must hold SENTINEL. Returns min_d Lout(d). */
inline ushort pathStep(const ushort* C, const ushort* Lp, ushort minPrev, ushort* Lout, int D, ushort P1, ushort P2)
{
    int d = 0;
    ushort m = SENTINEL;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n = VTraits<v_uint16>::vlanes();
    const v_uint16 vp1 = vx_setall_u16(P1), vjump = vx_setall_u16((ushort)(minPrev + P2)),
                   vmp = vx_setall_u16(minPrev);
    v_uint16 vmin = vx_setall_u16(SENTINEL);
    for (; d <= D - n; d += n)
    {
        v_uint16 a = vx_load(Lp + d);
        v_uint16 b = v_add(vx_load(Lp + d - 1), vp1);   // saturating: SENTINEL stays SENTINEL
        v_uint16 c = v_add(vx_load(Lp + d + 1), vp1);
        v_uint16 best = v_min(v_min(a, b), v_min(c, vjump));
        v_uint16 l = v_sub(v_add(vx_load(C + d), best), vmp);
        v_store(Lout + d, l);
        vmin = v_min(vmin, l);
    }
    m = (ushort)v_reduce_min(vmin);
#endif
    for (; d < D; d++)
    {
        int best = std::min(std::min((int)Lp[d], (int)Lp[d - 1] + P1), std::min((int)Lp[d + 1] + P1, minPrev + P2));
        ushort l = (ushort)(C[d] + best - minPrev);
        Lout[d] = l;
        m = std::min(m, l);
    }
    return m;
}

//! First pixel of a path: L = C.
inline ushort pathStart(const ushort* C, ushort* Lout, int D)
{
    ushort m = SENTINEL;
    for (int d = 0; d < D; d++)
    {
        Lout[d] = C[d];
        m = std::min(m, C[d]);
    }
    return m;
}

inline void addTo(ushort* S, const ushort* L, int D)
{
    int d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n = VTraits<v_uint16>::vlanes();
    for (; d <= D - n; d += n)
        v_store(S + d, v_add(vx_load(S + d), vx_load(L + d)));
#endif
    for (; d < D; d++)
        S[d] = (ushort)(S[d] + L[d]);
}

//! Buffer of per-pixel path costs, each slot padded with a sentinel on both sides.
struct PathRow
{
    int D, stride;
    std::vector<ushort> buf;
    std::vector<ushort> minv;
    void create(int n, int D_)
    {
        D = D_;
        stride = D + 2;
        buf.assign((size_t)n * stride, SENTINEL);
        minv.assign(n, 0);
    }
    ushort* at(int i) { return buf.data() + (size_t)i * stride + 1; }
};

//! The jump penalty from column xq to x of row y of the intensity map (empty: no edge rule).
inline ushort jump(const Mat& intensity, int y, int x, int yq, int xq, const PipelineParams& p)
{
    if (intensity.empty())
        return (ushort)p.w.p2;
    return (ushort)jumpPenalty(intensity.at<ushort>(y, x), intensity.at<ushort>(yq, xq), p.edgeThreshold, p.w);
}

// Horizontal paths of rows [r.start, r.end): sum = L(left->right) + L(right->left).
void horizontalPaths(const Mat& cost, const Mat& intensity, int W, const PipelineParams& p, Mat& sum, const Range& r)
{
    const int D = p.numDisparities;
    const ushort P1 = (ushort)p.w.p1;
    PathRow tmp;
    tmp.create(2, D);
    for (int y = r.start; y < r.end; y++)
    {
        const ushort* C = cost.ptr<ushort>(y);
        ushort* S = sum.ptr<ushort>(y);
        ushort* a = tmp.at(0);
        ushort* b = tmp.at(1);
        ushort m = pathStart(C, a, D);
        memcpy(S, a, D * sizeof(ushort));
        for (int x = 1; x < W; x++)
        {
            m = pathStep(C + (size_t)x * D, a, m, b, D, P1, jump(intensity, y, x, y, x - 1, p));
            memcpy(S + (size_t)x * D, b, D * sizeof(ushort));
            std::swap(a, b);
        }
        m = pathStart(C + (size_t)(W - 1) * D, a, D);
        addTo(S + (size_t)(W - 1) * D, a, D);
        for (int x = W - 2; x >= 0; x--)
        {
            m = pathStep(C + (size_t)x * D, a, m, b, D, P1, jump(intensity, y, x, y, x + 1, p));
            addTo(S + (size_t)x * D, b, D);
            std::swap(a, b);
        }
    }
}

/* Vertical and diagonal paths, rows visited from y0 towards y0 + (H - 1) * dir. For each of the (1 or 3) directions,
 the previous row's path costs are kept in prev[k] and the new row's written to cur[k]. Direction k takes its
 predecessor from column x - dx[k] of the previous row. */
void verticalPaths(const Mat& cost, const Mat& intensity, int W, int H, const PipelineParams& p, Mat& sum, int dir)
{
    const int D = p.numDisparities;
    const ushort P1 = (ushort)p.w.p1;
    const int nDirs = p.numPaths == 8 ? 3 : 1;
    const int dx[3] = { 0, 1, -1 };
    PathRow prev[3], cur[3];
    for (int k = 0; k < nDirs; k++)
    {
        prev[k].create(W, D);
        cur[k].create(W, D);
    }
    const int nstripes = std::max(1, std::min(getNumThreads(), W / 64));
    for (int i = 0; i < H; i++)
    {
        const int y = dir > 0 ? i : H - 1 - i;
        const ushort* C = cost.ptr<ushort>(y);
        ushort* S = sum.ptr<ushort>(y);
        parallel_for_(Range(0, W), [&](const Range& r) {
            for (int x = r.start; x < r.end; x++)
            {
                const ushort* c = C + (size_t)x * D;
                ushort* s = S + (size_t)x * D;
                for (int k = 0; k < nDirs; k++)
                {
                    const int xp = x - dx[k];
                    ushort* out = cur[k].at(x);
                    if (i == 0 || xp < 0 || xp >= W)
                        cur[k].minv[x] = pathStart(c, out, D);
                    else
                        cur[k].minv[x] = pathStep(c, prev[k].at(xp), prev[k].minv[xp], out, D, P1,
                                                  jump(intensity, y, x, y - dir, xp, p));
                    addTo(s, out, D);
                }
            }
        }, nstripes);
        for (int k = 0; k < nDirs; k++)
            std::swap(prev[k], cur[k]);
    }
}

} // namespace

void aggregateCosts(const Mat& cost, const Mat& left, const PipelineParams& p, Mat& sum)
{
    const int W = left.cols, H = cost.rows, D = p.numDisparities;
    CV_Assert(cost.type() == CV_16UC1 && cost.cols == W * D && left.rows == H);
    sum.create(cost.size(), CV_16UC1);
    // The edge rule reads the left image as 16-bit intensities (8-bit values unchanged).
    Mat intensity;
    if (p.edgeThreshold > 0)
        left.convertTo(intensity, CV_16U);
    parallel_for_(Range(0, H), [&](const Range& r) { horizontalPaths(cost, intensity, W, p, sum, r); },
                  std::max(1, H / 8));
    verticalPaths(cost, intensity, W, H, p, sum, +1);
    verticalPaths(cost, intensity, W, H, p, sum, -1);
}

}}} // namespace cv::lidarsgm::detail
