// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all of one pixel (paper Eq. 3) from its aggregated costs, with
//  - the uniqueness check: best * 1024 <= uniqueness1024 * (lowest cost more than one disparity away), else invalid;
//  - the parabola fit through the costs at d - 1, d, d + 1 (subpixelOffset16, pipeline.hpp);
//  - the right view: the pixel offers (cost << 16 | d) to the right pixel x - minD - d; each right pixel keeps the
//    lowest key, so the right-view disparity is the lowest cost along its diagonal x + d.
// Ties go to the smallest disparity everywhere (the CUDA twin compares the same keys).
// Included by aggregation.simd.hpp, inside its CPU-dispatch namespace: compiled once per instruction set.

static inline void selectPixel(ushort* s, int x, int W, const PipelineParams& p, short& d16, short& dInt, unsigned* rightKey)
{
    const int D = p.numDisparities, minD = p.minDisparity;
    int d = 0;
    ushort minv = 0xFFFF;
    int best = -1;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n16 = VTraits<v_uint16>::vlanes();
    {
        v_uint16 vmin = vx_setall_u16(0xFFFF);
        for (; d <= D - n16; d += n16)
            vmin = v_min(vmin, vx_load(s + d));
        minv = (ushort)v_reduce_min(vmin);
    }
#endif
    for (; d < D; d++)
        minv = std::min(minv, s[d]);
    d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    {
        const v_uint16 vm = vx_setall_u16(minv);
        while (d <= D - n16 && !v_check_any(v_eq(vx_load(s + d), vm)))
            d += n16;
    }
#endif
    for (; best < 0; d++)
        if (s[d] == minv)
            best = d;

    // Right view, before the uniqueness check may reject this pixel (it does not affect the right view).
    const int xr0 = x - minD;
    const int kEnd = std::min(D, xr0 + 1);
    int k = std::max(0, xr0 - (W - 1));
#if (CV_SIMD || CV_SIMD_SCALABLE)
    {
        const int n32 = VTraits<v_uint32>::vlanes();
        static const unsigned iota[64] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
            21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46,
            47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63 };
        const v_uint32 vi = vx_load(iota);
        // Keys of disparities k .. k + n32 - 1 go to right pixels xr0 - k down to xr0 - k - n32 + 1: reversed lanes.
        for (; n32 <= 64 && k <= kEnd - n32; k += n32)
        {
            const v_uint32 key = v_or(v_shl<16>(vx_load_expand(s + k)), v_add(vi, vx_setall_u32((unsigned)k)));
            unsigned* r = rightKey + xr0 - k - n32 + 1;
            v_store(r, v_min(vx_load(r), v_reverse(key)));
        }
    }
#endif
    for (; k < kEnd; k++)
    {
        const unsigned key = ((unsigned)s[k] << 16) | (unsigned)k;
        unsigned& r = rightKey[xr0 - k];
        r = std::min(r, key);
    }

    if (p.uniqueness1024 < 1024)
    {
        // The lowest cost more than one disparity away: the three around the best masked out for the search.
        ushort saved[3] = { 0, 0, 0 };
        for (int j = -1; j <= 1; j++)
            if (best + j >= 0 && best + j < D)
            {
                saved[j + 1] = s[best + j];
                s[best + j] = 0xFFFF;
            }
        ushort second = 0xFFFF;
        d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        v_uint16 vmin = vx_setall_u16(0xFFFF);
        for (; d <= D - n16; d += n16)
            vmin = v_min(vmin, vx_load(s + d));
        second = (ushort)v_reduce_min(vmin);
#endif
        for (; d < D; d++)
            second = std::min(second, s[d]);
        for (int j = -1; j <= 1; j++)
            if (best + j >= 0 && best + j < D)
                s[best + j] = saved[j + 1];
        if ((int)minv * 1024 > p.uniqueness1024 * (int)second)
        {
            d16 = NO_DISP;
            dInt = NO_DISP;
            return;
        }
    }
    int v16 = (best + minD) * 16;
    if (p.subpixel && best > 0 && best < D - 1)
        v16 += subpixelOffset16(s[best - 1], s[best], s[best + 1]);
    d16 = (short)v16;
    dInt = (short)(best + minD);
}
