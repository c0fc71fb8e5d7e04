// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Matching cost volume: Hamming distance of census strings, blended with the discrete disparity-matching cost (DDC)
// where a prior (sparse or semidense) disparity exists.

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void computeMatchingCost(const Mat& censusL, const Mat& censusR, const Mat& prior16, const PipelineParams& p,
                         Mat& cost)
{
    const int W = censusL.cols, H = censusL.rows, D = p.numDisparities, minD = p.minDisparity;
    CV_Assert(censusL.type() == CV_32SC1 && censusR.type() == CV_32SC1 && censusR.size() == censusL.size());
    CV_Assert(prior16.empty() || (prior16.type() == CV_16SC1 && prior16.size() == censusL.size()));
    cost.create(H, W * D, CV_16UC1);

    parallel_for_(Range(0, H), [&](const Range& r) {
        // Right census of row y reversed and clamped: rv[j] = R[clamp(W - 1 - minD - j)], so that the right
        // pixels x - minD - d of left pixel x are rv[W - 1 - x + d], contiguous and increasing in d.
        AutoBuffer<unsigned> rvBuf(W + D);
        unsigned* rv = rvBuf.data();
        for (int y = r.start; y < r.end; y++)
        {
            const unsigned* L = censusL.ptr<unsigned>(y);
            const unsigned* R = censusR.ptr<unsigned>(y);
            for (int j = 0; j < W + D - 1; j++)
                rv[j] = R[std::min(std::max(W - 1 - minD - j, 0), W - 1)];
            const short* prior = prior16.empty() ? nullptr : prior16.ptr<short>(y);
            ushort* out = cost.ptr<ushort>(y);
            for (int x = 0; x < W; x++)
            {
                const unsigned* base = rv + (W - 1 - x);
                ushort* c = out + (size_t)x * D;
                const int k = (prior && prior[x] != NO_DISP) ? roundDisp16(prior[x]) - minD : -1;
                int d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
                const ushort add = k >= 0 ? (ushort)p.w.q2 : (ushort)0;
                const int n32 = VTraits<v_uint32>::vlanes(), n16 = VTraits<v_uint16>::vlanes();
                const v_uint32 vl = vx_setall_u32(L[x]), vw = vx_setall_u32((unsigned)p.w.census256), vhalf = vx_setall_u32(128);
                const v_uint16 vadd = vx_setall_u16(add);
                for (; d <= D - n16; d += n16)
                {
                    v_uint32 h0 = v_popcount(v_xor(vx_load(base + d), vl));
                    v_uint32 h1 = v_popcount(v_xor(vx_load(base + d + n32), vl));
                    h0 = v_shr<8>(v_add(v_mul(h0, vw), vhalf));
                    h1 = v_shr<8>(v_add(v_mul(h1, vw), vhalf));
                    v_store(c + d, v_add(v_pack(h0, h1), vadd));
                }
#endif
                for (; d < D; d++)
                    c[d] = (ushort)matchingCost(popcount32(base[d] ^ L[x]), d, k, p.w);
                // The vector loop added Q2 everywhere; the three costs around the prior follow the rule in full.
                for (int j = std::max(k - 1, 0); k >= 0 && j <= std::min(k + 1, D - 1); j++)
                    c[j] = (ushort)matchingCost(popcount32(base[j] ^ L[x]), j, k, p.w);
            }
        }
    }, std::max(1, H / 32));
}

}}} // namespace cv::lidarsgm::detail
