#!/usr/bin/env python3
"""What semidensification's wrong priors cost with doc/params/kitti_best.yml at 64 lines, and whether anything seen
without the ground truth tells them apart (doc/design.md, "Wrong priors at 64 lines").

  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/semidense_priors.py [shared data dir]

A numpy copy of the visibility filter and of semidensification (census, candidate keys) that must match the module's
semidensify() pixel for pixel (ring interpolation off; printed first), so that each prior's source and competitors
are known. The matcher run on a prior map is kitti_best.yml in DSGM mode with its own sparse filters off: on the
module's semidense map it reproduces SDSGM within a few thousandths, so a changed map shows what a change of
semidensification would give. Needs numpy >= 2 (bitwise_count); about 5 minutes on 2 cores.
"""
import os
import sys

import numpy as np
import cv2 as cv

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lidar_points as lp  # noqa: E402  (frames, d1; reads the data folder from the command line)

BEST = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "doc", "params", "kitti_best.yml")
NONE = -1


def census(img):
    """The module's census strings (censusString): 31 bits, I(p + o) > I(p - o) over the upper half of 9 x 7."""
    img = img.astype(np.int32)
    h, w = img.shape
    p = np.pad(img, ((3, 3), (4, 4)), mode="edge")
    c = np.zeros((h, w), np.uint32)
    for dy in range(-3, 1):
        for dx in range(-4, 5):
            if dy < 0 or dx < 0:
                a = p[3 + dy:3 + dy + h, 4 + dx:4 + dx + w]
                b = p[3 - dy:3 - dy + h, 4 - dx:4 - dx + w]
                c = (c << np.uint32(1)) | (a > b).astype(np.uint32)
    return c


def sparse16(sp, m):
    """The module's 1/16-pixel sparse values (sparseFromFloat), NONE outside the search range."""
    s = np.where(sp > 0, np.floor(sp.astype(np.float64) * 16 + 0.5), NONE).astype(np.int64)
    return np.where((s >= 0) & (((s + 8) >> 4) <= m.getMinDisparity() + m.getNumDisparities() - 1), s, NONE)


def visible(s, m):
    """hiddenBy over the map: a point with a nearer one (by more than Tc) in the footprint grown by the parallax."""
    rx, ry = m.getVisibilityRadiusX(), m.getVisibilityRadiusY()
    par256, tc16 = round(m.getVisibilityParallax() * 256), round(m.getCheckThreshold() * 16)
    v = np.where(s >= 0, s, -100000).astype(np.float32)
    hidden = np.zeros(s.shape, bool)
    for k in range(0, min(par256 * m.getNumDisparities() // 256, 32) + 1):
        diff = cv.dilate(v, np.ones((2 * (ry + k) + 1, 2 * (rx + k) + 1), np.uint8)) - v
        hidden |= (diff > tc16) & ((k == 0) | (k * 4096 <= par256 * diff))
    return np.where((s >= 0) & ~hidden, s, NONE)


def candidates(cl, cr, s, rs):
    """For each window offset: the candidate's value and source position at every pixel, its census cost there, and
    its semidenseKey (cost, squared distance, row, column)."""
    h, w = cl.shape
    k = np.where(s >= 0, (s + 8) >> 4, 0)
    yy, xx = np.mgrid[0:h, 0:w]
    for dy in range(-rs, rs + 1):
        for dx in range(-rs, rs + 1):
            v = np.full((h, w), NONE, np.int64)
            kk = np.zeros((h, w), np.int64)
            y0, y1, x0, x1 = max(0, -dy), min(h, h - dy), max(0, -dx), min(w, w - dx)
            v[y0:y1, x0:x1] = s[y0 + dy:y1 + dy, x0 + dx:x1 + dx]
            kk[y0:y1, x0:x1] = k[y0 + dy:y1 + dy, x0 + dx:x1 + dx]
            cost = np.bitwise_count(cl ^ np.take_along_axis(cr, np.clip(xx - kk, 0, w - 1), axis=1)).astype(np.int64)
            key = (cost << 26) | ((dx * dx + dy * dy) << 14) | ((dy + rs) << 7) | (dx + rs)
            yield v, cost, key, dx * dx + dy * dy, (yy + dy, xx + dx)


def semidensify(cl, cr, s, rs, ts, order="cost", exclude=None):
    """Semidensification (paper Eq. 5 with the module's keys); order "nearest" takes the nearest candidate below Ts
    instead of the cheapest. exclude: points that may not be candidates (they keep their own pixel). Returns the map,
    the winner's cost and its source."""
    big = np.int64(1) << 50
    best = np.full(cl.shape, big, np.int64)
    val = np.full(cl.shape, NONE, np.int64)
    cost_w = np.zeros(cl.shape, np.int64)
    src = [np.zeros(cl.shape, np.int64), np.zeros(cl.shape, np.int64)]
    cand = s if exclude is None else np.where(exclude, NONE, s)
    for v, cost, key, d2, (sy, sx) in candidates(cl, cr, cand, rs):
        if order == "nearest":
            key = np.where(cost < ts, (d2 << 20) | (cost << 14) | (key & 0x3FFF), big)
        key = np.where(v >= 0, key, big)
        b = key < best
        best, val, cost_w = np.where(b, key, best), np.where(b, v, val), np.where(b, cost, cost_w)
        src[0], src[1] = np.where(b, sy, src[0]), np.where(b, sx, src[1])
    take = (best < big) & (cost_w < ts)
    return np.where(take, val, s), take, src


def main():
    m = cv.lidarsgm.StereoLidarSGM.load(BEST)
    m.setRingGapFactor(0)
    rs, ts, tc16 = m.getSemidenseRadius(), m.getSemidenseThreshold(), round(m.getCheckThreshold() * 16)
    dsgm = cv.lidarsgm.StereoLidarSGM.load(BEST)
    dsgm.setMode(cv.lidarsgm.StereoLidarSGM_MODE_DSGM)
    for setter in ("setVisibilityRadiusX", "setVisibilityRadiusY", "setVisibilityParallax", "setRingGapFactor"):
        getattr(dsgm, setter)(0)
    maps = ["module semidense map", "the same without its wrong values (oracle)",
            "the same without its wrong copies (oracle)", "copies need 2 agreeing candidates",
            "copies need more agreeing than disagreeing candidates", "nearest candidate below Ts first",
            "points that lose their own pixel to another surface are no candidates",
            "copies that stereo alone contradicts dropped", "points that stereo alone contradicts dropped"]
    err = {k: cv.lidarsgm.DisparityErrors() for k in maps}
    n = dict(mismatch=0, gt=0, prior=0, wrong=0, own=0, own_wrong=0, src_nogt=0, src_right=0, src_right_step=0,
             src_wrong=0, points=0, points_wrong=0, points_wrong_car=0, points_wrong_far=0)
    full = cv.lidarsgm.StereoLidarSGM.load(BEST)   # SDSGM as shipped, ring interpolation included
    est = np.zeros(4, np.int64)   # wrong estimates: all, without a prior, a prior within 2 px, a wrong one followed
    near_first = dict((h, 0) for h in (4, 8, 12, 16, 24, 32, 0))
    dist = np.zeros((2, 2 * rs * rs + 1), np.int64)
    support = np.zeros((2, 3), np.int64)   # right / wrong copies: one agreeing candidate, disagreeing >= agreeing
    lost = np.zeros(2, np.int64)
    contradicted = np.zeros(2, np.int64)   # right / wrong copies that stereo alone contradicts
    stereo = cv.lidarsgm.StereoLidarSGM.load(BEST)   # plain SGM, left-right checked: the camera's own answer
    stereo.setMode(cv.lidarsgm.StereoLidarSGM_MODE_SGM)
    stereo.setConsistencyCheck(cv.lidarsgm.StereoLidarSGM_CHECK_STEREO)
    for l, r, sp, g16, obj in lp.frames():
        gt, has = g16 / 256.0, g16 > 0
        s = visible(sparse16(sp, m), m)
        cl, cr = census(l), census(r)
        semi, copied_any, (sy, sx) = semidensify(cl, cr, s, rs, ts)
        ref = m.semidensify(l, r, sp).astype(np.int64)
        n["mismatch"] += int((np.where(ref >= 0, ref, NONE) != semi).sum())
        yy, xx = np.mgrid[0:l.shape[0], 0:l.shape[1]]
        copied = copied_any & ~((sy == yy) & (sx == xx)) & has
        wrong = (semi >= 0) & has & lp.d1(semi / 16.0, gt)
        n["gt"] += int(has.sum())
        n["prior"] += int(((semi >= 0) & has).sum())
        n["wrong"] += int(wrong.sum())
        n["own"] += int(((semi >= 0) & has & ~copied).sum())
        n["own_wrong"] += int((wrong & ~copied).sum())
        src_has = has[sy, sx]
        src_right = src_has & ~lp.d1(semi / 16.0, gt[sy, sx])
        n["src_nogt"] += int((wrong & copied & ~src_has).sum())
        n["src_right"] += int((wrong & copied & src_right).sum())
        n["src_right_step"] += int((wrong & copied & src_right & (np.abs(gt - gt[sy, sx]) > 3)).sum())
        n["src_wrong"] += int((wrong & copied & src_has & ~src_right).sum())
        d2 = (sy - yy) ** 2 + (sx - xx) ** 2
        for w_ in (0, 1):
            sel = copied & (wrong if w_ else ~wrong)
            dist[w_] += np.bincount(d2[sel], minlength=dist.shape[1])[:dist.shape[1]]
        # Support: candidates below Ts whose value agrees with the winner's (within Tc) or not.
        agree = np.zeros(l.shape, np.int64)
        disagree = np.zeros(l.shape, np.int64)
        for v, cost, _, _, _ in candidates(cl, cr, s, rs):
            ok = (v >= 0) & (cost < ts)
            agree += ok & (np.abs(v - semi) <= tc16)
            disagree += ok & (np.abs(v - semi) > tc16)
        for w_ in (0, 1):
            sel = copied & (wrong if w_ else ~wrong)
            support[w_] += [sel.sum(), (sel & (agree < 2)).sum(), (sel & (disagree >= agree)).sum()]
        # Points whose own pixel takes another surface's value.
        loses = (s >= 0) & copied_any & (np.abs(semi - s) > tc16)
        pbad = (s >= 0) & has & lp.d1(s / 16.0, gt)
        lost += [(loses & has & ~pbad).sum(), (loses & pbad).sum()]
        # The smallest square half-size holding a nearer point (by more than Tc) around each wrong point (0: none).
        v = np.where(s >= 0, s, -100000).astype(np.float32)
        left = pbad.copy()
        for h in (4, 8, 12, 16, 24, 32):
            hit = left & (cv.dilate(v, np.ones((2 * h + 1, 2 * h + 1), np.uint8)) - v > tc16)
            near_first[h] += int(hit.sum())
            left &= ~hit
        near_first[0] += int(left.sum())
        # SDSGM's wrong estimates without a prior of their own, and the priors within 2 px of them.
        d16 = full.compute(l, r, sp)
        prior = full.semidensify(l, r, sp).astype(np.int64)
        filled = cv.lidarsgm.interpolateBackground(np.where(d16 >= 0, d16 / 16.0, -1).astype(np.float32))
        bad_est = (d16 >= 0) & has & lp.d1(filled, gt)
        lone = bad_est & (prior < 0)
        near = np.zeros(l.shape, bool)
        agrees = np.zeros(l.shape, bool)
        for dy in range(-2, 3):
            for dx in range(-2, 3):
                q = np.roll(prior, (-dy, -dx), axis=(0, 1))
                near |= q >= 0
                agrees |= (q >= 0) & (np.abs(q - d16) <= tc16) & lp.d1(q / 16.0, gt)
        est += [bad_est.sum(), lone.sum(), (lone & near).sum(), (lone & agrees).sum()]
        n["points"] += int(((s >= 0) & has).sum())
        n["points_wrong"] += int(pbad.sum())
        n["points_wrong_car"] += int((pbad & (obj > 0)).sum())
        n["points_wrong_far"] += int((pbad & (s / 16.0 < gt)).sum())
        copied_all = copied_any & ~((sy == yy) & (sx == xx))
        d_st = stereo.compute(l, r, sp).astype(np.int64)
        def contradicts(x):
            return (d_st >= 0) & (x >= 0) & (np.abs(d_st - x) > tc16)
        contradicted += [(copied & ~wrong & contradicts(semi)).sum(), (copied & wrong & contradicts(semi)).sum()]
        variants = [semi, np.where(wrong, NONE, semi), np.where(wrong & copied, NONE, semi),
                    np.where(copied_all & (agree < 2), s, semi), np.where(copied_all & (disagree >= agree), s, semi),
                    semidensify(cl, cr, s, rs, ts, "nearest")[0], semidensify(cl, cr, s, rs, ts, exclude=loses)[0],
                    np.where(copied_all & contradicts(semi), s, semi),
                    semidensify(cl, cr, np.where(contradicts(s), NONE, s), rs, ts)[0]]
        for name, prior in zip(maps, variants):
            f = np.where(prior >= 0, prior / 16.0, 0).astype(np.float32)
            err[name].add(cv.lidarsgm.evaluateDisparity(dsgm.compute(l, r, f), g16))
    g = n["gt"]
    print("numpy semidensification against the module's (ring interpolation off): %d pixels differ" % n["mismatch"])
    print("priors at %.2f %% of the ground truth, %.2f %% of them wrong; own LiDAR values %.2f %% wrong, copies %.2f %%"
          % (100.0 * n["prior"] / g, 100.0 * n["wrong"] / n["prior"], 100.0 * n["own_wrong"] / n["own"],
             100.0 * (n["wrong"] - n["own_wrong"]) / (n["prior"] - n["own"])))
    print("wrong copies %d: source without ground truth %d, source right at its own pixel %d (across a step of more "
          "than 3 px: %d), source wrong %d" % (n["wrong"] - n["own_wrong"], n["src_nogt"], n["src_right"],
                                               n["src_right_step"], n["src_wrong"]))
    for lim in (1, 4, 9, 16):
        print("copies from farther than %d px: %.1f %% of the wrong, %.1f %% of the right" % (
            round(lim ** 0.5), 100.0 * dist[1, lim + 1:].sum() / dist[1].sum(),
            100.0 * dist[0, lim + 1:].sum() / dist[0].sum()))
    print("copies with one agreeing candidate: wrong %d, right %d; with as many disagreeing: wrong %d, right %d" % (
        support[1, 1], support[0, 1], support[1, 2], support[0, 2]))
    print("points that lose their own pixel to another surface: wrong %d, right %d" % (lost[1], lost[0]))
    print("copies that stereo alone (SGM, left-right checked) contradicts by more than Tc: wrong %d, right %d" % (
        contradicted[1], contradicted[0]))
    print("LiDAR points after the visibility filter %d, D1 outliers %d (%.0f %% on cars, %.0f %% farther than the "
          "ground truth)" % (n["points"], n["points_wrong"], 100.0 * n["points_wrong_car"] / n["points_wrong"],
                             100.0 * n["points_wrong_far"] / n["points_wrong"]))
    print("wrong points with a nearer point first within a half-size of 4 / 8 / 12 / 16 / 24 / 32 px / none: %s"
          % " / ".join(str(near_first[h]) for h in (4, 8, 12, 16, 24, 32, 0)))
    print("SDSGM's wrong estimates %.2f %% of the ground truth; without a prior of their own %.2f %%, of which a prior "
          "within 2 px %.2f %%, a wrong prior within 2 px that the estimate follows (within Tc) %.2f %%" % tuple(
              100.0 * est / g))
    print("DSGM (kitti_best.yml, its filters off) on a prior map: coverage / covered D1 / total D1")
    for name in maps:
        e = err[name]
        print("  %-72s %.2f / %.2f / %.2f %%" % (name, e.coverage(), e.coveredError(), e.totalError()))


if __name__ == "__main__":
    if len(sys.argv) > 1:
        lp.DATA = os.path.join(sys.argv[1], "kitti2015_lidar")
    main()
