// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Matching cost of one pixel at every disparity: Hamming distance of census strings, blended with the discrete
// disparity-matching cost (DDC) where a prior (sparse or semidense) disparity exists (matchingCost, pipeline.hpp).
// The DDC term comes from a table row per pixel (ddcTerm for its prior, or zeros), so the vector loop adds it with one
// load instead of fixing up the costs around the prior afterwards.
// Included by aggregation.simd.hpp, inside its CPU-dispatch namespace: compiled once per instruction set.

/** The reversed, clamped right census row, split into 16-bit halves: rv[j] = R[clamp(W - 1 - minD - j)] for j in
[j0, j1), low halves at rvLo[j - j0], high halves at rvHi[j - j0]. The right pixels x - minD - d of left pixel x
are at j = W - 1 - x + d: contiguous and increasing in d (left pixels [x0, x1) need j in [W - x1, W - x0 + D - 1)).
16-bit halves keep the Hamming distances in 16-bit lanes. */
static inline void reversedRightRow(const unsigned* R, int W, int minD, int j0, int j1, ushort* rvLo, ushort* rvHi)
{
    rvLo -= j0;
    rvHi -= j0;
    // j < jIn: clamped to W - 1; j in [jIn, jOut): R[W - 1 - minD - j] inside the row; j >= jOut: clamped to 0.
    const int jIn = std::min(std::max(-minD, j0), j1), jOut = std::min(std::max(W - minD, jIn), j1);
    int j = j0;
    for (; j < jIn; j++)
    {
        rvLo[j] = (ushort)(R[W - 1] & 0xFFFF);
        rvHi[j] = (ushort)(R[W - 1] >> 16);
    }
#if CV_SIMD
    const int n32 = VTraits<v_uint32>::nlanes;
    const v_uint32 lowMask = vx_setall_u32(0xFFFF);
    for (; j + 2 * n32 <= jOut; j += 2 * n32)
    {
        // R[W - 1 - minD - j - t] for t = 0 .. 2 n32 - 1: two vectors loaded below it, reversed.
        const unsigned* src = R + (W - minD - j - 2 * n32);
        const v_uint32 r1 = v_reverse(vx_load(src + n32)), r0 = v_reverse(vx_load(src));
        v_store(rvLo + j, v_pack(v_and(r1, lowMask), v_and(r0, lowMask)));
        v_store(rvHi + j, v_pack(v_shr<16>(r1), v_shr<16>(r0)));
    }
#endif
    for (; j < jOut; j++)
    {
        const unsigned r = R[W - 1 - minD - j];
        rvLo[j] = (ushort)(r & 0xFFFF);
        rvHi[j] = (ushort)(r >> 16);
    }
    for (; j < j1; j++)
    {
        rvLo[j] = (ushort)(R[0] & 0xFFFF);
        rvHi[j] = (ushort)(R[0] >> 16);
    }
}

/** One pixel's matching cost inputs: the right census halves at disparity index 0 of the pixel (rl[d], rh[d] for
disparity index d), its left census l, its DDC terms add[d], and the census weight (CostWeights::census256). */
struct CostInput
{
    const ushort* rl;
    const ushort* rh;
    unsigned l;
    const ushort* add;
    int census256;
};

// AArch64's NEON has the byte pairs' widening add and the rounding high multiply as single instructions too.
#if CV_NEON && defined(__aarch64__) && CV_SIMD_WIDTH == 16
#define LIDARSGM_NEON_EXACT 1
#else
#define LIDARSGM_NEON_EXACT 0
#endif

//! Whether the vector cost's exact rounding multiply applies (costAt: census256 < 2^14).
static inline bool censusMulExact(const CostWeights& w)
{
#if CV_SIMD && ((CV_AVX2 && CV_SIMD_WIDTH == 32) || (CV_SSSE3 && CV_SIMD_WIDTH == 16) || LIDARSGM_NEON_EXACT)
    return w.census256 < 16384;
#else
    (void)w;
    return false;
#endif
}

//! C(p, d) of one disparity index d.
static inline int costAt(const CostInput& in, int d)
{
    const int h = popcount32((((unsigned)in.rh[d] << 16) | in.rl[d]) ^ in.l);
    return censusTerm(in.census256, h) + in.add[d];
}

#if CV_SIMD
#if CV_AVX2 && CV_SIMD_WIDTH == 32
//! Each 16-bit lane's two bytes added (unsigned bytes), times f (f < 128).
static inline v_uint16 bytePairSums(const v_uint8& b, schar f = 1)
{
    return v_uint16(_mm256_maddubs_epi16(b.val, _mm256_set1_epi8(f)));
}
//! (a b + 2^14) >> 15 per 16-bit lane (a, b < 2^15).
static inline v_uint16 mulRound15(const v_uint16& a, const v_uint16& b) { return v_uint16(_mm256_mulhrs_epi16(a.val, b.val)); }
#elif CV_SSSE3 && CV_SIMD_WIDTH == 16
static inline v_uint16 bytePairSums(const v_uint8& b, schar f = 1)
{
    return v_uint16(_mm_maddubs_epi16(b.val, _mm_set1_epi8(f)));
}
static inline v_uint16 mulRound15(const v_uint16& a, const v_uint16& b) { return v_uint16(_mm_mulhrs_epi16(a.val, b.val)); }
#elif LIDARSGM_NEON_EXACT
static inline v_uint16 bytePairSums(const v_uint8& b, schar f = 1)
{
    return v_uint16(vmulq_n_u16(vpaddlq_u8(b.val), (ushort)f));
}
//! sqrdmulh: (2 a b + 2^15) >> 16, the same as (a b + 2^14) >> 15 (a, b < 2^15: no saturation).
static inline v_uint16 mulRound15(const v_uint16& a, const v_uint16& b)
{
    return v_uint16(vreinterpretq_u16_s16(vqrdmulhq_s16(vreinterpretq_s16_u16(a.val), vreinterpretq_s16_u16(b.val))));
}
#else
static inline v_uint16 bytePairSums(const v_uint8& b, schar f = 1)
{
    const v_uint16 w = v_reinterpret_as_u16(b);
    return v_mul_wrap(v_add(v_and(w, vx_setall_u16(0xFF)), v_shr<8>(w)), vx_setall_u16((ushort)f));
}
static inline v_uint16 mulRound15(const v_uint16& a, const v_uint16&) { return a; }   // not used (censusMulExact)
#endif

//! The broadcasts of one pixel's cost loop.
struct CostVectors
{
    v_uint16 lLo, lHi, weight, hi, lo;
    explicit CostVectors(const CostInput& in)
        : lLo(vx_setall_u16((ushort)(in.l & 0xFFFF))), lHi(vx_setall_u16((ushort)(in.l >> 16))),
          weight(vx_setall_u16((ushort)(2 * in.census256))), hi(vx_setall_u16((ushort)(in.census256 >> 8))),
          lo(vx_setall_u16((ushort)(in.census256 & 255)))
    {
    }
};

/** The costs at disparity indices d .. d + lanes - 1. The Hamming distance: byte popcounts of both halves added (at
most 16 a byte), then the two bytes of each 16-bit lane. EXACT (census256 < 2^14, every configuration but plain SGM
with small penalties): (64 h 2 census256 + 2^14) >> 15 is (census256 h + 128) >> 8 exactly, the factor 64 in the
byte pairs' multiply-add and one rounding high multiply. Otherwise with census256 = 256 hi + lo it is hi h + (lo h +
128) / 256 (exact: 256 hi h is a multiple of 256), both products below 2^13 for h <= 31: wrapping multiplies give the
same. */
template <bool EXACT>
static inline v_uint16 costAt(const CostVectors& v, const CostInput& in, int d)
{
    const v_uint8 pc = v_add(v_popcount(v_reinterpret_as_u8(v_xor(vx_load(in.rl + d), v.lLo))),
                             v_popcount(v_reinterpret_as_u8(v_xor(vx_load(in.rh + d), v.lHi))));
    v_uint16 t;
    if (EXACT)
        t = mulRound15(bytePairSums(pc, 64), v.weight);
    else
    {
        const v_uint16 h = bytePairSums(pc);
        t = v_add(v_mul_wrap(h, v.hi), v_shr<8>(v_add(v_mul_wrap(h, v.lo), vx_setall_u16(128))));
    }
    return v_add(t, vx_load(in.add + d));
}
#endif

//! C(p, d) for d in [0, D) into c (the volume form, for the tests).
static inline void costVector(const CostInput& in, const CostWeights& w, int D, ushort* c)
{
    int d = 0;
#if CV_SIMD
    const CostVectors v(in);
    const int n = VTraits<v_uint16>::nlanes;
    if (censusMulExact(w))
        for (; d <= D - n; d += n)
            v_store(c + d, costAt<true>(v, in, d));
    for (; d <= D - n; d += n)
        v_store(c + d, costAt<false>(v, in, d));
#else
    (void)w;
#endif
    for (; d < D; d++)
        c[d] = (ushort)costAt(in, d);
}
