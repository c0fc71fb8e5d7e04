// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification's rows (semidensification.dispatch.cpp), compiled once per instruction set. Each sparse point
// offers itself to the pixels of its row span [c - rs, c + rs] in the rows within rs of it: the census costs of one
// point at consecutive pixels are one vector of popcounts, and each pixel keeps the lowest semidenseKey.

#include "cpu_stages.hpp"
#include "sparse_window.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void semidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                     const PipelineParams& p, Mat& semidense16, const Range& r);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

void semidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                     const PipelineParams& p, Mat& semidense16, const Range& r)
{
    const int W = censusL.cols, rs = p.semidenseRadius, Ts = p.semidenseThreshold, span = 2 * rs + 1;
    // Sparse values are in the search range, so their rounded disparities k lie in [minD, minD + D - 1]: the right
    // row padded (clamped) by that much on both sides gives R[clamp(x - k)] at Rp[pad + x - k] without a branch.
    const int kLo = std::min(p.minDisparity, 0), kHi = std::max(p.minDisparity + p.numDisparities - 1, 0);
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n = VTraits<v_uint32>::vlanes();
#else
    const int n = 1;
#endif
    // Whole vectors cover a span: the pixels, keys and values run n past the row's end, and the lanes past a span's
    // end carry the largest key (they never win).
    const int spanV = (span + n - 1) / n * n;
    const int padL = kHi, padR = -kLo + spanV;
    AutoBuffer<unsigned> rpBuf(W + padL + padR), lBuf(W + spanV), keyBuf(W + spanV), valBuf(W + spanV),
                         colBuf(spanV + n);
    unsigned *Rp = rpBuf.data(), *Lp = lBuf.data(), *keys = keyBuf.data(), *vals = valBuf.data(),
             *colPart = colBuf.data();
    std::fill(Lp + W, Lp + W + spanV, 0u);
    // The column part of the key at span position j (pixel x = c - rs + j, dx = rs - j); a span that starts at the
    // image's left edge starts at j > 0, so its last vector may reach j = span + n - 2.
    for (int j = 0; j < spanV + n; j++)
        colPart[j] = j < span ? semidenseKey(0, rs - j, 0, rs) - semidenseKey(0, 0, 0, rs) : 0xFFFFFFFFu;
    WindowCursor cur(cols, rs, r.start);
    for (int y = r.start; y < r.end; y++)
    {
        cur.moveTo(y);
        const unsigned* R = censusR.ptr<unsigned>(y);
        for (int j = -padL; j < W + padR; j++)
            Rp[padL + j] = R[std::min(std::max(j, 0), W - 1)];
        memcpy(Lp, censusL.ptr<unsigned>(y), W * sizeof(unsigned));
        std::fill(keys, keys + W + spanV, 0xFFFFFFFFu);
        for (int c = 0; c < W; c++)
            for (int i = cur.lo[c]; i < cur.hi[c]; i++)
            {
                const int dy = cols.row[i] - y, k = roundDisp16(cols.value[i]);
                const unsigned v = (unsigned)(ushort)cols.value[i];
                const unsigned rowPart = semidenseKey(0, 0, dy, rs);
                const unsigned* Rk = Rp + padL - k;
                const int xs = std::max(c - rs, 0), xe = std::min(c + rs, W - 1);
                int x = xs;
#if (CV_SIMD || CV_SIMD_SCALABLE)
                const v_uint32 vrow = vx_setall_u32(rowPart), vv = vx_setall_u32(v);
                for (; x <= xe; x += n)
                {
                    // Past xe, colPart holds the largest key: v_max keeps it there whatever the sum wrapped to.
                    const v_uint32 cost = v_popcount(v_xor(vx_load(Lp + x), vx_load(Rk + x)));
                    const v_uint32 col = vx_load(colPart + (x - c + rs));
                    const v_uint32 key = v_max(v_add(v_add(v_shl<26>(cost), col), vrow), col);
                    const v_uint32 old = vx_load(keys + x);
                    const v_uint32 better = v_lt(key, old);
                    v_store(keys + x, v_select(better, key, old));
                    v_store(vals + x, v_select(better, vv, vx_load(vals + x)));
                }
#endif
                for (; x <= xe; x++)
                {
                    const unsigned key = semidenseKey(popcount32(Lp[x] ^ Rk[x]), c - x, dy, rs);
                    if (key < keys[x])
                    {
                        keys[x] = key;
                        vals[x] = v;
                    }
                }
            }
        const short* own = sparse16.ptr<short>(y);
        short* out = semidense16.ptr<short>(y);
        for (int x = 0; x < W; x++)
            out[x] = semidenseKeyCost(keys[x]) < Ts ? (short)vals[x] : own[x];
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
