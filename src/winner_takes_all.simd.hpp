// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all of one pixel (paper Eq. 3) from its aggregated costs, with
//  - the uniqueness check (uniqueWinner, pipeline.hpp), else invalid
//    (the winner goes to nonUnique where given: the ring check may keep it);
//  - the parabola fit through the costs at d - 1, d, d + 1 (subpixelOffset16, pipeline.hpp);
//  - the right view: the pixel offers its cost at d to the right pixel x - minD - d; each right pixel keeps the lowest
//    cost (the first of equal ones, see RightView), so its disparity is the lowest cost along its diagonal x + d.
// Ties go to the smallest disparity everywhere (the CUDA twin compares the same keys).
// Included by aggregation.simd.hpp, inside its CPU-dispatch namespace: compiled once per instruction set.
// (RightView is defined in aggregation.simd.hpp, outside that namespace.)

//! The winner's disparity x16 (s: the window's sums from lo, D of them): with the parabola's offset where enabled
//! and both neighbours are in the window.
static inline int winner16(const ushort* s, int best, int lo, int D, const PipelineParams& p)
{
    int v16 = (lo + best + p.minDisparity) * 16;
    if (p.subpixel && best > 0 && best < D - 1)
        v16 += subpixelOffset16(s[best - 1], s[best], s[best + 1]);
    return v16;
}

/** The pixel's winner from s, its sums over its window [lo, lo + D) (searchWindows; lo 0 and D numDisparities without
windows): indices below are the window's, disparities lo + index. */
static inline void selectPixel(ushort* s, int x, int W, const PipelineParams& p, int lo, int D, short& d16,
                               short& dInt, short* nonUnique, RightView rv)
{
    const int minD = p.minDisparity;
    // Right view, before the uniqueness check may reject this pixel (it does not affect the right view). In the
    // reversed index u = W - 1 - xr this pixel's candidates are contiguous: u = u0 + d (d the disparity index).
    const int u0 = W - 1 - x + minD;
    const int k0 = std::max(lo, -u0), n = std::min(lo + D, W - u0) - k0;
    // rc[j], ri[j]: the candidate at u = u0 + k0 + j (disparity index k0 + j); pointers formed only inside the view.
    ushort* rc = n > 0 ? rv.cost + (u0 + k0 - rv.lo) : nullptr;
    ushort* ri = n > 0 ? rv.index + (u0 + k0 - rv.lo) : nullptr;
    const ushort* sk = s + (k0 - lo);
    // Where the pixel offers all its costs (away from the left border), the minimum is taken in the same pass.
    const bool whole = k0 == lo && n == D;
    ushort minv = 0xFFFF;
    int j = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n16 = VTraits<v_uint16>::vlanes();
    {
        static const ushort iota[128] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
            21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46,
            47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63, 64, 65, 66, 67, 68, 69, 70, 71, 72,
            73, 74, 75, 76, 77, 78, 79, 80, 81, 82, 83, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95, 96, 97, 98,
            99, 100, 101, 102, 103, 104, 105, 106, 107, 108, 109, 110, 111, 112, 113, 114, 115, 116, 117, 118, 119,
            120, 121, 122, 123, 124, 125, 126, 127 };
        const v_uint16 vnone = vx_setall_u16(RightView::NONE), vstep = vx_setall_u16((ushort)n16);
        v_uint16 vmin = vx_setall_u16(0xFFFF);
        v_uint16 vi = v_add(vx_load(iota), vx_setall_u16((ushort)k0));   // disparity indices of lanes j ..
        for (; n16 <= 128 && j <= n - n16; j += n16, vi = v_add(vi, vstep))
        {
            const v_uint16 c = vx_load(sk + j), oc = vx_load(rc + j), oi = vx_load(ri + j);
            const v_uint16 take = v_or(v_lt(c, oc), v_eq(oi, vnone));
            v_store(rc + j, v_select(take, c, oc));
            v_store(ri + j, v_select(take, vi, oi));
            vmin = v_min(vmin, c);
        }
        if (whole)
            minv = minLane(vmin);
    }
#endif
    for (; j < n; j++)
    {
        if (sk[j] < rc[j] || ri[j] == RightView::NONE)
        {
            rc[j] = sk[j];
            ri[j] = (ushort)(k0 + j);
        }
        minv = std::min(minv, sk[j]);
    }
    int d = 0;
    if (!whole)
    {
        minv = 0xFFFF;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        v_uint16 vmin = vx_setall_u16(0xFFFF);
        for (; d <= D - n16; d += n16)
            vmin = v_min(vmin, vx_load(s + d));
        minv = minLane(vmin);
#endif
        for (; d < D; d++)
            minv = std::min(minv, s[d]);
    }
    int best = -1;
    d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    {
        const v_uint16 vm = vx_setall_u16(minv);
        for (; d <= D - n16; d += n16)
        {
            const v_uint16 eq = v_eq(vx_load(s + d), vm);
            if (v_check_any(eq))
            {
                best = d + v_scan_forward(eq);   // the first lane that holds the minimum
                break;
            }
        }
    }
#endif
    for (; best < 0; d++)
        if (s[d] == minv)
            best = d;

    if (p.uniqueness1024 < 1024)
    {
        // The lowest cost more than one disparity away: the costs at best - 1 .. best + 1 masked out in registers
        // (writing them in s and reading s back in vectors would stall each load on the little stores).
        const int exLo = best - 1, exHi = best + 1;
        ushort second = 0xFFFF;
        d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
        static const ushort iota16[64] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
            21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43, 44, 45, 46,
            47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63 };
        v_uint16 vmin = vx_setall_u16(0xFFFF);
        for (; n16 <= 64 && d <= D - n16; d += n16)
        {
            v_uint16 v = vx_load(s + d);
            if (d + n16 > exLo && d <= exHi)
            {
                // index - exLo <= 2 (unsigned: indices below exLo wrap to large values) marks best - 1 .. best + 1
                const v_uint16 rel = v_sub_wrap(v_add_wrap(vx_load(iota16), vx_setall_u16((ushort)d)),
                                                vx_setall_u16((ushort)exLo));
                v = v_select(v_le(rel, vx_setall_u16(2)), vx_setall_u16(0xFFFF), v);
            }
            vmin = v_min(vmin, v);
        }
        second = minLane(vmin);
#endif
        for (; d < D; d++)
            if (d < exLo || d > exHi)
                second = std::min(second, s[d]);
        if (!uniqueWinner((int)minv, (int)second, p.uniqueness1024))
        {
            if (nonUnique)
                *nonUnique = (short)winner16(s, best, lo, D, p);
            d16 = NO_DISP;
            dInt = NO_DISP;
            return;
        }
    }
    if (nonUnique)
        *nonUnique = NO_DISP;
    d16 = (short)winner16(s, best, lo, D, p);
    dInt = (short)(lo + best + minD);
}
