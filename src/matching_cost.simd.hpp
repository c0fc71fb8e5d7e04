// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Matching cost of one pixel at every disparity: Hamming distance of census strings, blended with the discrete
// disparity-matching cost (DDC) where a prior (sparse or semidense) disparity exists (matchingCost, pipeline.hpp).
// Included by aggregation.simd.hpp, inside its CPU-dispatch namespace: compiled once per instruction set.

/** The reversed, clamped right census row, split into 16-bit halves: rv[j] = R[clamp(W - 1 - minD - j)], low halves
in rvLo, high halves in rvHi, for the left pixels [x0, x1), i.e. j in [W - x1, W - x0 + D - 1) (the rest is not
written). The right pixels x - minD - d of left pixel x are at j = W - 1 - x + d: contiguous and increasing in d.
16-bit halves keep the Hamming distances in 16-bit lanes. */
static inline void reversedRightRow(const unsigned* R, int W, int minD, int D, int x0, int x1, ushort* rvLo,
                                    ushort* rvHi)
{
    for (int j = W - x1; j < W - x0 + D - 1; j++)
    {
        const unsigned r = R[std::min(std::max(W - 1 - minD - j, 0), W - 1)];
        rvLo[j] = (ushort)(r & 0xFFFF);
        rvHi[j] = (ushort)(r >> 16);
    }
}

#if CV_AVX2 && CV_SIMD_WIDTH == 32
#define LIDARSGM_EXACT_CENSUS_MUL 1
//! Each 16-bit lane's two bytes added (unsigned bytes).
static inline v_uint16 bytePairSums(const v_uint8& b) { return v_uint16(_mm256_maddubs_epi16(b.val, _mm256_set1_epi8(1))); }
//! (a b + 2^14) >> 15 per 16-bit lane (a, b < 2^15).
static inline v_uint16 mulRound15(const v_uint16& a, const v_uint16& b) { return v_uint16(_mm256_mulhrs_epi16(a.val, b.val)); }
#elif CV_SSSE3 && CV_SIMD_WIDTH == 16
#define LIDARSGM_EXACT_CENSUS_MUL 1
static inline v_uint16 bytePairSums(const v_uint8& b) { return v_uint16(_mm_maddubs_epi16(b.val, _mm_set1_epi8(1))); }
static inline v_uint16 mulRound15(const v_uint16& a, const v_uint16& b) { return v_uint16(_mm_mulhrs_epi16(a.val, b.val)); }
#endif

/** C(p, d) for d in [lo, lo + D) into c[d - lo]: left census string l, the right strings' halves at rvLo[d], rvHi[d]
(offset W - 1 - x), prior index k (-1: none; it may lie outside the window). The vector loop adds Q2 at every
disparity where a prior exists; the costs at k - 1 .. k + 1 in the window then follow the rule. */
static inline void costVector(const ushort* rvLo, const ushort* rvHi, unsigned l, int k, const CostWeights& w, int lo,
                              int D, ushort* c)
{
    const int k0 = k;
    rvLo += lo;
    rvHi += lo;
    k = k >= 0 ? k - lo : -1;   // below: the prior index relative to the window (any value where k0 >= 0)
    int d = 0;
#if (CV_SIMD || CV_SIMD_SCALABLE)
    // The Hamming distance: byte popcounts of both halves added (at most 16 a byte), then the two bytes of each
    // 16-bit lane. census256 * h / 256 rounded: with census256 = 256 hi + lo, it is hi h + (lo h + 128) / 256 (exact:
    // 256 hi h is a multiple of 256), and both products stay below 2^13 for h <= 31: wrapping multiplies (one
    // instruction; OpenCV's v_mul saturates 16-bit products, which costs several) give the same.
    const int n16 = VTraits<v_uint16>::vlanes();
    const v_uint16 vlLo = vx_setall_u16((ushort)(l & 0xFFFF)), vlHi = vx_setall_u16((ushort)(l >> 16)),
                   vbyte = vx_setall_u16(0xFF), vhi = vx_setall_u16((ushort)(w.census256 >> 8)),
                   vlo = vx_setall_u16((ushort)(w.census256 & 255)), vhalf = vx_setall_u16(128),
                   vadd = vx_setall_u16(k0 >= 0 ? (ushort)w.q2 : (ushort)0);
#ifdef LIDARSGM_EXACT_CENSUS_MUL
    // census256 < 2^15 (every configuration but plain SGM with small penalties): (128 h census256 + 2^14) >> 15 is
    // (census256 h + 128) >> 8 exactly, one rounding high multiply (and the lanes' byte sums one multiply-add).
    if (w.census256 < 32768)
    {
        const v_uint16 vweight = vx_setall_u16((ushort)w.census256);
        for (; d <= D - n16; d += n16)
        {
            const v_uint8 pc = v_add(v_popcount(v_reinterpret_as_u8(v_xor(vx_load(rvLo + d), vlLo))),
                                     v_popcount(v_reinterpret_as_u8(v_xor(vx_load(rvHi + d), vlHi))));
            v_store(c + d, v_add(mulRound15(v_shl<7>(bytePairSums(pc)), vweight), vadd));
        }
    }
#endif
    for (; d <= D - n16; d += n16)
    {
        const v_uint8 pc = v_add(v_popcount(v_reinterpret_as_u8(v_xor(vx_load(rvLo + d), vlLo))),
                                 v_popcount(v_reinterpret_as_u8(v_xor(vx_load(rvHi + d), vlHi))));
        const v_uint16 pw = v_reinterpret_as_u16(pc);
        const v_uint16 h = v_add(v_and(pw, vbyte), v_shr<8>(pw));
        const v_uint16 t = v_add(v_mul_wrap(h, vhi), v_shr<8>(v_add(v_mul_wrap(h, vlo), vhalf)));
        v_store(c + d, v_add(t, vadd));
    }
#endif
    for (; d < D; d++)
        c[d] = (ushort)matchingCost(popcount32((((unsigned)rvHi[d] << 16) | rvLo[d]) ^ l), d + lo, k0, w);
    for (int j = std::max(k - 1, 0); k0 >= 0 && j <= std::min(k + 1, D - 1); j++)
        c[j] = (ushort)matchingCost(popcount32((((unsigned)rvHi[j] << 16) | rvLo[j]) ^ l), j + lo, k0, w);
}

//! The prior index of a prior value (1/16 pixel, NO_DISP: none): round(prior) - minD, or -1.
static inline int priorIndex(short prior16, int minD)
{
    return prior16 != NO_DISP ? roundDisp16(prior16) - minD : -1;
}
