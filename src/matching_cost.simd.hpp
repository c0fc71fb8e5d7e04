// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Matching cost of one pixel at every disparity: Hamming distance of census strings, blended with the discrete
// disparity-matching cost (DDC) where a prior (sparse or semidense) disparity exists (matchingCost, pipeline.hpp).
// Included by aggregation.simd.hpp, inside its CPU-dispatch namespace: compiled once per instruction set.

/** The reversed, clamped right census row: rv[j] = R[clamp(W - 1 - minD - j)], j in [0, W + D - 1). The right pixels
x - minD - d of left pixel x are then rv[W - 1 - x + d]: contiguous and increasing in d. */
static inline void reversedRightRow(const unsigned* R, int W, int minD, int D, unsigned* rv)
{
    for (int j = 0; j < W + D - 1; j++)
        rv[j] = R[std::min(std::max(W - 1 - minD - j, 0), W - 1)];
}

/** C(p, d) for d in [0, D): left census string l, right strings rvx[d] (rv + W - 1 - x), prior index k (-1: none).
The vector loop adds Q2 at every disparity where a prior exists; the three costs around it then follow the rule. */
static inline void costVector(const unsigned* rvx, unsigned l, int k, const CostWeights& w, int D, ushort* c)
{
    int d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    const int n32 = VTraits<v_uint32>::vlanes(), n16 = VTraits<v_uint16>::vlanes();
    const v_uint32 vl = vx_setall_u32(l), vw = vx_setall_u32((unsigned)w.census256), vhalf = vx_setall_u32(128);
    const v_uint16 vadd = vx_setall_u16(k >= 0 ? (ushort)w.q2 : (ushort)0);
    for (; d <= D - n16; d += n16)
    {
        v_uint32 h0 = v_popcount(v_xor(vx_load(rvx + d), vl));
        v_uint32 h1 = v_popcount(v_xor(vx_load(rvx + d + n32), vl));
        h0 = v_shr<8>(v_add(v_mul(h0, vw), vhalf));
        h1 = v_shr<8>(v_add(v_mul(h1, vw), vhalf));
        v_store(c + d, v_add(v_pack(h0, h1), vadd));
    }
#endif
    for (; d < D; d++)
        c[d] = (ushort)matchingCost(popcount32(rvx[d] ^ l), d, k, w);
    for (int j = std::max(k - 1, 0); k >= 0 && j <= std::min(k + 1, D - 1); j++)
        c[j] = (ushort)matchingCost(popcount32(rvx[j] ^ l), j, k, w);
}

//! The prior index of a prior value (1/16 pixel, NO_DISP: none): round(prior) - minD, or -1.
static inline int priorIndex(short prior16, int minD)
{
    return prior16 != NO_DISP ? roundDisp16(prior16) - minD : -1;
}
