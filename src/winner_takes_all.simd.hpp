// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// Winner-takes-all of one pixel (paper Eq. 3) from its aggregated costs: one pass over them (selectSums, right after
// the up sweep's path loop stored them) keeps per lane what the decision needs (selectPixel), with
//  - the uniqueness check (uniqueWinner, pipeline.hpp), else invalid
//    (the winner goes to nonUnique where given: the ring check may keep it);
//  - the parabola fit through the costs at d - 1, d, d + 1 (subpixelOffset16, pipeline.hpp);
//  - the right view: the pixel offers its cost at d to the right pixel x - minD - d; each right pixel keeps the lowest
//    cost (of equal ones the smallest d, see RightView), so its disparity is the lowest cost along its diagonal x + d.
// Ties go to the smallest disparity everywhere (the CUDA twin compares the same keys).
// Included by aggregation.simd.hpp, inside its CPU-dispatch namespace: compiled once per instruction set.
// (RightView is defined in aggregation.simd.hpp, outside that namespace.)

//! A pixel's candidates for the right view: cost[d], index[d] for the d-th disparity of its window (RightView).
struct RightOffer
{
    ushort* cost;
    ushort* index;
};

/** The winner's state as a pixel's sums arrive a vector at a time, per lane: the lowest sum, the disparity index of
its first occurrence, and the lowest of the lane's other sums. A lane holds every lanes-th disparity, so the three
disparities around the winner lie in three different lanes: the lowest sum more than one disparity away is each
lane's lowest, or its second where the lowest is the excluded one (selectPixel). Without vectors selectPixel scans
the sums. */
struct WinnerLanes
{
    const ushort* iota;   // iota[i] = i for i < MAX_DISPARITIES
    int base;             // the window's first disparity index
#if CV_SIMD
    v_uint16 min1, idx1, min2;
#endif
    void reset(int lo)
    {
        base = lo;
#if CV_SIMD
        min1 = min2 = vx_setall_u16(0xFFFF);
        idx1 = vx_load(iota + lo);   // the first vector's indices: its sums are at most 0xFFFF
#endif
    }
};

#if CV_SIMD
//! The sums s at the window's disparities d .. d + lanes - 1: the winner's lanes and the right view's candidates.
static inline void trackSums(WinnerLanes& w, const RightOffer& r, const v_uint16& s, int d)
{
    const v_uint16 idx = vx_load(w.iota + w.base + d);
    const v_uint16 m = v_min(s, w.min1);
    w.idx1 = v_select(v_eq(m, w.min1), w.idx1, idx);   // a later lane value takes it only when lower
    w.min2 = v_min(w.min2, v_max(s, w.min1));
    w.min1 = m;
    const v_uint16 oc = vx_load(r.cost + d), oi = vx_load(r.index + d);
    const v_uint16 mc = v_min(s, oc);
    v_store(r.cost + d, mc);
    v_store(r.index + d, v_select(v_eq(mc, s), idx, oi));   // s <= the cost so far: a smaller d at equal cost
}
#endif

//! The same for one disparity (the scalar path: the right view only, selectPixel scans the sums).
static inline void trackSums(WinnerLanes& w, const RightOffer& r, ushort s, int d)
{
    if (s <= r.cost[d])
    {
        r.cost[d] = s;
        r.index[d] = (ushort)(w.base + d);
    }
}

//! trackSums over a pixel's n sums.
static inline void selectSums(const ushort* s, int n, WinnerLanes& w, const RightOffer& r)
{
    int d = 0;
#if CV_SIMD
    const int N = VTraits<v_uint16>::nlanes;
    for (; d <= n - N; d += N)
        trackSums(w, r, vx_load(s + d), d);
    CV_DbgAssert(d == n);
#endif
    for (; d < n; d++)
        trackSums(w, r, s[d], d);
}

//! The winner's disparity x16 (s: the window's sums from lo, n of them): with the parabola's offset where enabled
//! and both neighbours are in the window.
static inline int winner16(const ushort* s, int best, int lo, int n, const PipelineParams& p)
{
    int v16 = (lo + best + p.minDisparity) * 16;
    if (p.subpixel && best > 0 && best < n - 1)
        v16 += subpixelOffset16(s[best - 1], s[best], s[best + 1]);
    return v16;
}

/** The pixel's winner from its sums s over its window [lo, lo + n) (searchWindows; lo 0 and n numDisparities without
windows; a multiple of the vector width where there are vectors) and the lanes trackSums kept: indices below are the
window's, disparities lo + index. */
static inline void selectPixel(const WinnerLanes& w, const ushort* s, int lo, int n, const PipelineParams& p,
                               short& d16, short& dInt, short* nonUnique)
{
    int best, minv, second = 0xFFFF;
    const bool checkUnique = p.uniqueness1024 < 1024;
#if CV_SIMD
    (void)n;
    minv = minLane(w.min1);
    const int bestIndex = minLane(v_select(v_eq(w.min1, vx_setall_u16((ushort)minv)), w.idx1, vx_setall_u16(0xFFFF)));
    best = bestIndex - lo;
    if (checkUnique)
    {
        // A lane whose lowest sum sits at best - 1, best or best + 1 (index - (best - 1) <= 2, unsigned) offers its
        // second instead.
        const v_uint16 rel = v_sub_wrap(w.idx1, vx_setall_u16((ushort)(bestIndex - 1)));
        const v_uint16 two = vx_setall_u16(2);
        second = minLane(v_select(v_eq(v_min(rel, two), rel), w.min2, w.min1));
    }
#else
    (void)w;
    best = 0;
    for (int d = 1; d < n; d++)
        if (s[d] < s[best])
            best = d;
    minv = s[best];
    for (int d = 0; checkUnique && d < n; d++)
        if (d < best - 1 || d > best + 1)
            second = std::min(second, (int)s[d]);
#endif
    if (checkUnique && !uniqueWinner(minv, second, p.uniqueness1024))
    {
        if (nonUnique)
            *nonUnique = (short)winner16(s, best, lo, n, p);
        d16 = NO_DISP;
        dInt = NO_DISP;
        return;
    }
    if (nonUnique)
        *nonUnique = NO_DISP;
    d16 = (short)winner16(s, best, lo, n, p);
    dInt = (short)(lo + best + p.minDisparity);
}
