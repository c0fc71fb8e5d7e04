// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Ring interpolation's rows (ring_interpolation.dispatch.cpp), compiled once per instruction set: the maps of each
// column's nearest sparse point above and below, each pixel's nearest ring points on them (nearestRingPoints,
// pipeline.hpp) a vector of pixels at a time, and the pixels filled (ringCandidateOf, the census test).

#include "cpu_stages.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void ringAboveBelow(const Mat& sparse16, Mat& above16, Mat& below16);
void ringNearestRows(const Mat& above16, const Mat& below16, Mat& nearest, const Range& r);
void ringFillRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const Mat& nearest,
                  const PipelineParams& p, int gap, Mat& semidense16, const Range& r);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

void ringAboveBelow(const Mat& sparse16, Mat& above16, Mat& below16)
{
    const int W = sparse16.cols, H = sparse16.rows;
    // Row y's maps from row y - 1's (above) and row y + 1's (below): one pass each way, row by row.
    const auto pass = [&](Mat& map, int y, int from) {
        const short *s = sparse16.ptr<short>(from), *prev = map.ptr<short>(from);
        short* m = map.ptr<short>(y);
        int x = 0;
#if CV_SIMD
        const int N = VTraits<v_int16>::nlanes;
        const v_int16 none = vx_setall_s16(NO_DISP), row = vx_setall_s16((short)from);
        for (; x + N <= W; x += N)
            v_store(m + x, v_select(v_eq(vx_load(s + x), none), vx_load(prev + x), row));
#endif
        for (; x < W; x++)
            m[x] = s[x] != NO_DISP ? (short)from : prev[x];
    };
    above16.row(0).setTo(Scalar::all(-1));
    for (int y = 1; y < H; y++)
        pass(above16, y, y - 1);
    below16.row(H - 1).setTo(Scalar::all(-1));
    for (int y = H - 2; y >= 0; y--)
        pass(below16, y, y + 1);
}

void ringNearestRows(const Mat& above16, const Mat& below16, Mat& nearest, const Range& r)
{
    const int W = above16.cols, H = above16.rows, R = RING_COLUMNS;
    CV_Assert(R == 2);   // the five columns below: ringColumnOffset's order 0, -1, 1, -2, 2
#if CV_SIMD
    const int N = VTraits<v_int16>::nlanes;
    // Per column a key: above, (row + 1) << 3 (0: none), or'ed with 4 - i for the column's place i in
    // ringColumnOffset's order, so that the largest picks the nearest row and of equal rows the first column; below,
    // row << 3 (NONE_BELOW: none) or'ed with i, the smallest. Rows below 4095 fit 16-bit keys.
    const short NONE_BELOW = 0x7FF8;
    const bool vectors = H < 4095;
    AutoBuffer<short> keyBuf(2 * (W + 2 * R + N) + N), iotaBuf(N);
    short* ka = keyBuf.data() + R;
    short* kb = ka + W + 2 * R + N;
    for (int i = 0; i < N; i++)
        iotaBuf[i] = (short)i;
    const v_int16 iota = vx_load(iotaBuf.data());
    const v_int16 one = vx_setall_s16(1), seven = vx_setall_s16(7), none = vx_setall_s16(-1);
    // The column offset of place i (ringColumnOffset): h = (i + 1) >> 1, negated where i is odd.
    const auto offsetOf = [&](const v_int16& i) {
        const v_int16 h = v_shr<1>(v_add(i, one)), odd = v_and(i, one);
        return v_add(v_xor(h, v_sub(vx_setzero_s16(), odd)), odd);
    };
#endif
    for (int y = r.start; y < r.end; y++)
    {
        const short* A = above16.ptr<short>(y);
        const short* B = below16.ptr<short>(y);
        short* out = (short*)nearest.ptr<Vec4s>(y);
        int x = 0;
#if CV_SIMD
        if (vectors)
        {
            for (int c = -R; c < 0; c++)
            {
                ka[c] = 0;
                kb[c] = NONE_BELOW;
            }
            for (int c = W; c < W + R + N; c++)
            {
                ka[c] = 0;
                kb[c] = NONE_BELOW;
            }
            int c = 0;
            for (; c + N <= W; c += N)
            {
                const v_int16 a = vx_load(A + c), b = vx_load(B + c);
                v_store(ka + c, v_shl<3>(v_add(a, one)));
                v_store(kb + c, v_select(v_lt(b, vx_setzero_s16()), vx_setall_s16(NONE_BELOW), v_shl<3>(b)));
            }
            for (; c < W; c++)
            {
                ka[c] = (short)((A[c] + 1) << 3);
                kb[c] = B[c] < 0 ? NONE_BELOW : (short)(B[c] << 3);
            }
            for (; x + N <= W; x += N)
            {
                v_int16 a = v_or(vx_load(ka + x), vx_setall_s16(4)), b = vx_load(kb + x);
                for (int i = 1; i <= 2 * R; i++)
                {
                    const int o = ringColumnOffset(i);
                    a = v_max(a, v_or(vx_load(ka + x + o), vx_setall_s16((short)(4 - i))));
                    b = v_min(b, v_or(vx_load(kb + x + o), vx_setall_s16((short)i)));
                }
                const v_int16 xs = v_add(iota, vx_setall_s16((short)x));
                const v_int16 ya = v_sub(v_shr<3>(a), one);
                const v_int16 xa = v_select(v_lt(ya, vx_setzero_s16()), none,
                                            v_add(xs, offsetOf(v_sub(vx_setall_s16(4), v_and(a, seven)))));
                const v_int16 hasB = v_lt(b, vx_setall_s16(NONE_BELOW));
                const v_int16 yb = v_select(hasB, v_shr<3>(b), none);
                const v_int16 xb = v_select(hasB, v_add(xs, offsetOf(v_and(b, seven))), none);
                v_store_interleave(out + 4 * x, xa, ya, xb, yb);
            }
        }
#endif
        for (; x < W; x++)
        {
            int xa, ya, xb, yb;
            nearestRingPoints(A, B, x, W, xa, ya, xb, yb);
            out[4 * x] = (short)xa;
            out[4 * x + 1] = (short)ya;
            out[4 * x + 2] = (short)xb;
            out[4 * x + 3] = (short)yb;
        }
    }
}

void ringFillRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const Mat& nearest,
                  const PipelineParams& p, int gap, Mat& semidense16, const Range& r)
{
    const int W = censusL.cols, Ts = p.semidenseThreshold, lo = p.minDisparity;
    const int hi = p.minDisparity + p.numDisparities - 1;
    const RingNearestMap near = { nearest.ptr<Vec4s>(), nearest.step1() / 4 };
    const short* sparse = sparse16.ptr<short>();
    const size_t sparseStep = sparse16.step1();
    for (int y = r.start; y < r.end; y++)
    {
        const unsigned* L = censusL.ptr<unsigned>(y);
        const unsigned* R = censusR.ptr<unsigned>(y);
        short* out = semidense16.ptr<short>(y);
        for (int x = 0; x < W; x++)
        {
            if (out[x] != NO_DISP)
                continue;
            const int v = ringCandidateOf(near, sparse, sparseStep, x, y, gap);
            if (v == NO_DISP || !sparseInRange(v, lo, hi))
                continue;
            const int xr = std::min(std::max(x - roundDisp16(v), 0), W - 1);
            if (popcount32(L[x] ^ R[xr]) < Ts)
                out[x] = (short)v;
        }
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
