// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all over the aggregated volume (paper Eq. 3), with
//  - the uniqueness check: best * 1024 <= uniqueness1024 * (lowest cost more than one disparity away), else invalid;
//  - the parabola fit through the costs at d - 1, d, d + 1, rounded to 1/16 pixel (subpixelOffset16);
//  - the right-view disparity: for right pixel xr, the d with the lowest S(xr + minD + d, d).
// Ties go to the smallest disparity everywhere.

#include "precomp.hpp"
#include "cpu_stages.hpp"

namespace cv { namespace lidarsgm { namespace detail {

void winnerTakesAll(const Mat& sum, int width, const PipelineParams& p, Mat& disp16, Mat& dispInt, Mat& dispRight)
{
    const int W = width, H = sum.rows, D = p.numDisparities, minD = p.minDisparity;
    CV_Assert(sum.type() == CV_16UC1 && sum.cols == W * D);
    disp16.create(H, W, CV_16SC1);
    dispInt.create(H, W, CV_16SC1);
    dispRight.create(H, W, CV_16SC1);
    const bool uniq = p.uniqueness1024 < 1024;

    parallel_for_(Range(0, H), [&](const Range& r) {
        std::vector<int> bestR(W);
        for (int y = r.start; y < r.end; y++)
        {
            const ushort* S = sum.ptr<ushort>(y);
            short* out16 = disp16.ptr<short>(y);
            short* outInt = dispInt.ptr<short>(y);
            short* outR = dispRight.ptr<short>(y);
            std::fill(bestR.begin(), bestR.end(), INT_MAX);
            for (int x = 0; x < W; x++)
                outR[x] = NO_DISP;

            for (int x = 0; x < W; x++)
            {
                const ushort* s = S + (size_t)x * D;
                int d = 0;
                ushort minv = 0xFFFF;
#if (CV_SIMD || CV_SIMD_SCALABLE)
                const int n = VTraits<v_uint16>::vlanes();
                v_uint16 vmin = vx_setall_u16(0xFFFF);
                for (; d <= D - n; d += n)
                    vmin = v_min(vmin, vx_load(s + d));
                minv = (ushort)v_reduce_min(vmin);
#endif
                for (; d < D; d++)
                    minv = std::min(minv, s[d]);
                int best = 0;
                while (s[best] != minv)
                    best++;

                bool valid = true;
                if (uniq)
                {
                    int second = INT_MAX;
                    for (int k = 0; k < D; k++)
                        if (k < best - 1 || k > best + 1)
                            second = std::min(second, (int)s[k]);
                    valid = second == INT_MAX || minv * 1024 <= p.uniqueness1024 * second;
                }

                // Right view: left pixel x at disparity index k sees right pixel x - minD - k.
                const int xr0 = x - minD;
                const int kEnd = std::min(D, xr0 + 1);
                for (int k = std::max(0, xr0 - (W - 1)); k < kEnd; k++)
                {
                    const int xr = xr0 - k;
                    if (s[k] < bestR[xr])
                    {
                        bestR[xr] = s[k];
                        outR[xr] = (short)(k + minD);
                    }
                }

                if (!valid)
                {
                    out16[x] = NO_DISP;
                    outInt[x] = NO_DISP;
                    continue;
                }
                int d16 = (best + minD) * 16;
                if (p.subpixel && best > 0 && best < D - 1)
                    d16 += subpixelOffset16(s[best - 1], s[best], s[best + 1]);
                out16[x] = (short)d16;
                outInt[x] = (short)(best + minD);
            }
        }
    }, std::max(1, H / 32));
}

}}} // namespace cv::lidarsgm::detail
