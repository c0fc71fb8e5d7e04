// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Semidensification's rows (semidensification.dispatch.cpp), compiled once per instruction set. Each sparse point
// offers itself to the pixels of its row span [c - rs, c + rs] in the rows within rs of it: the census costs of one
// point at consecutive pixels are one vector of popcounts, and each pixel keeps the lowest semidenseKey, whose offset
// names the winning point.

#include "cpu_stages.hpp"
#include "sparse_window.hpp"
#include "opencv2/core/hal/intrin.hpp"

namespace cv { namespace lidarsgm { namespace detail {
CV_CPU_OPTIMIZATION_NAMESPACE_BEGIN

void semidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                     const PipelineParams& p, Mat& semidense16, const Range& r);

#ifndef CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

#if CV_SIMD
//! The Hamming distance of each 32-bit lane: byte popcounts, then the bytes of each lane added.
static inline v_int32 popcount32Lanes(const v_uint32& x)
{
#if CV_AVX2 && CV_SIMD_WIDTH == 32
    const __m256i b = v_popcount(v_reinterpret_as_u8(x)).val;
    return v_int32(_mm256_madd_epi16(_mm256_maddubs_epi16(b, _mm256_set1_epi8(1)), _mm256_set1_epi16(1)));
#else
    return v_reinterpret_as_s32(v_popcount(x));
#endif
}
#endif

void semidensifyRows(const Mat& censusL, const Mat& censusR, const Mat& sparse16, const SparseColumns& cols,
                     const PipelineParams& p, Mat& semidense16, const Range& r)
{
    const int W = censusL.cols, H = censusL.rows, rs = p.semidenseRadius, Ts = p.semidenseThreshold;
    const int span = 2 * rs + 1;
    // Sparse values are in the search range, so their rounded disparities k lie in [minD, minD + D - 1]: the right
    // row padded (clamped) by that much on both sides gives R[clamp(x - k)] at Rp[pad + x - k] without a branch.
    const int kLo = std::min(p.minDisparity, 0), kHi = std::max(p.minDisparity + p.numDisparities - 1, 0);
#if CV_SIMD
    const int n = VTraits<v_uint32>::nlanes;
#else
    const int n = 1;
#endif
    // Whole vectors cover a span: the pixels and keys run n past the row's end, and the lanes past a span's end
    // carry the largest key (they never win). Keys are compared as signed 32-bit values (a key has 31 bits), the
    // largest one, INT_MAX, standing for "no candidate".
    const int spanV = (span + n - 1) / n * n;
    const int padL = kHi, padR = -kLo + spanV;
    const int NONE = INT_MAX;
    AutoBuffer<unsigned> rpBuf(W + padL + padR), lBuf(W + spanV);
    AutoBuffer<int> keyBuf(W + spanV), colBuf(spanV + n);
    unsigned *Rp = rpBuf.data(), *Lp = lBuf.data();
    int *keys = keyBuf.data(), *colPart = colBuf.data();
    std::fill(Lp + W, Lp + W + spanV, 0u);
    // The column part of the key at span position j (pixel x = c - rs + j, dx = rs - j); a span that starts at the
    // image's left edge starts at j > 0, so its last vector may reach j = span + n - 2.
    for (int j = 0; j < spanV + n; j++)
        colPart[j] = j < span ? (int)(semidenseKey(0, rs - j, 0, rs) - semidenseKey(0, 0, 0, rs)) : NONE;
    for (int y = r.start; y < r.end; y++)
    {
        const unsigned* R = censusR.ptr<unsigned>(y);
        std::fill(Rp, Rp + padL, R[0]);
        memcpy(Rp + padL, R, W * sizeof(unsigned));
        std::fill(Rp + padL + W, Rp + padL + W + padR, R[W - 1]);
        memcpy(Lp, censusL.ptr<unsigned>(y), W * sizeof(unsigned));
        std::fill(keys, keys + W + spanV, NONE);
        // Every point of the rows within rs offers itself to the pixels of its span in this row; the lowest key
        // wins (keys differ for different candidates, so the order of the offers does not matter).
        for (int q = std::max(y - rs, 0); q <= std::min(y + rs, H - 1); q++)
        {
            const int dy = q - y;
            const int rowPart = (int)semidenseKey(0, 0, dy, rs);
            for (int i = cols.rowStart[q]; i < cols.rowStart[q + 1]; i++)
            {
                const int c = cols.column[i], k = roundDisp16(cols.rowValue[i]);
                const unsigned* Rk = Rp + padL - k;
                const int xs = std::max(c - rs, 0), xe = std::min(c + rs, W - 1);
                int x = xs;
#if CV_SIMD
                const v_int32 vrow = vx_setall_s32(rowPart);
                for (; x <= xe; x += n)
                {
                    // Past xe, colPart holds NONE: the maximum keeps it there whatever the sum wrapped to.
                    const v_int32 cost = popcount32Lanes(v_xor(vx_load(Lp + x), vx_load(Rk + x)));
                    const v_int32 col = vx_load(colPart + (x - c + rs));
                    const v_int32 key = v_max(v_add(v_add(v_shl<26>(cost), col), vrow), col);
                    v_store(keys + x, v_min(key, vx_load(keys + x)));
                }
#endif
                for (; x <= xe; x++)
                    keys[x] = std::min(keys[x], (int)semidenseKey(popcount32(Lp[x] ^ Rk[x]), c - x, dy, rs));
            }
        }
        // The winner's value from its offset in the key (semidenseKey's low 14 bits).
        const short* own = sparse16.ptr<short>(y);
        short* out = semidense16.ptr<short>(y);
        for (int x = 0; x < W; x++)
        {
            const int key = keys[x];
            if (key != NONE && semidenseKeyCost((unsigned)key) < Ts)
                out[x] = sparse16.at<short>(y + ((key >> 7) & 127) - rs, x + (key & 127) - rs);
            else
                out[x] = own[x];
        }
    }
}

#endif // CV_CPU_OPTIMIZATION_DECLARATIONS_ONLY

CV_CPU_OPTIMIZATION_NAMESPACE_END
}}} // namespace cv::lidarsgm::detail
