#!/usr/bin/env python3
"""What a trust rule for LiDAR points on cars can reach with doc/params/kitti_best.yml at 64 lines, and what two
rules seen without the ground truth reach (doc/decisions.md, "Cars: the ceiling of a trust rule").

  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/car_points.py [shared data dir]

Over the 20 shared KITTI frames, SDSGM's total D1 (the devkit's background fill) on cars (obj_map > 0) and elsewhere:
  1. as shipped;
  2. oracles that read the ground truth: the projected points that are D1 outliers on cars removed (all of them, the
     ones the module's visibility filter keeps, the ones it drops), the car pixels the matcher leaves empty filled
     with the truth, and both;
  3. where the car errors lie: by distance to the car's outline in obj_map, and there the D1 of the estimates
     themselves (no fill) of SDSGM and of plain SGM with the left-right check (the images alone);
  4. two rules that see only the scan and the images, each dropping points before the module runs:
     enclosure (a nearer point, by more than 3 px, within 20 px to the left, right, above and below) and census
     contrast (a nearer surface, by the D1 bound, among the visible points within 10 px, whose disparity the 7 x 7
     mean census cost at the point prefers by more than 2 bits); what each drops on cars and elsewhere, right and
     wrong.
Needs numpy >= 2 (bitwise_count); about half a minute on 2 cores.
"""
import os
import sys

import numpy as np
import cv2 as cv

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lidar_points as lp  # noqa: E402  (frames, d1; reads the data folder from the command line)
from semidense_priors import BEST, census, sparse16, visible  # noqa: E402


def score(d16, gt, obj, fill=None):
    """Bad and ground-truth pixel counts on cars and elsewhere of a map after the devkit's fill; fill(d) may fill
    first."""
    d = np.where(d16 >= 0, d16 / 16.0, -1).astype(np.float32)
    if fill is not None:
        d = fill(d)
    filled = cv.lidarsgm.interpolateBackground(d)
    has = gt > 0
    bad = lp.d1(np.where(filled < 0, -1, filled), gt) & has
    return np.array([(bad & obj).sum(), (has & obj).sum(), (bad & ~obj).sum(), (has & ~obj).sum()], np.int64)


def enclosed(vv, radius=20, band=2, step=3.0):
    """Points with a nearer point (by more than step) within radius px on each of the four sides."""
    out = vv > 0
    for side in "LRUD":
        if side in "LR":
            k = np.ones((2 * band + 1, radius + 1), np.uint8)
            k[:, -1 if side == "L" else 0] = 0
            anchor = (radius, band) if side == "L" else (0, band)
        else:
            k = np.ones((radius + 1, 2 * band + 1), np.uint8)
            k[-1 if side == "U" else 0, :] = 0
            anchor = (band, radius) if side == "U" else (band, 0)
        out &= cv.dilate(vv, k, anchor=anchor, borderType=cv.BORDER_CONSTANT, borderValue=0) - vv > step
    return out


def census_contrast(l, r, vv, radius=10, half=3, margin=2.0):
    """Points with a nearer surface among the visible points around them that the census at the point prefers."""
    dn = cv.dilate(vv, np.ones((2 * radius + 1, 2 * radius + 1), np.uint8))
    cand = (vv > 0) & lp.d1(vv, dn) & (dn > vv)
    cl, cr = np.pad(census(l), half, mode="edge"), np.pad(census(r), half, mode="edge")
    out = np.zeros(vv.shape, bool)
    n = 2 * half + 1
    for y, x in zip(*np.nonzero(cand)):
        costs = []
        for d in (int(round(vv[y, x])), int(round(dn[y, x]))):
            costs.append(31.0 if x - d - half < 0 else
                         np.bitwise_count(cl[y:y + n, x:x + n] ^ cr[y:y + n, x - d:x - d + n]).mean())
        out[y, x] = costs[0] - costs[1] > margin
    return out


def main():
    m = cv.lidarsgm.StereoLidarSGM.load(BEST)
    runs = ["as shipped", "oracle: wrong car points removed", "oracle: the visible ones only",
            "oracle: the hidden ones only", "oracle: empty car pixels filled with the truth",
            "oracle: visible wrong car points removed + empty car pixels filled", "rule: enclosure",
            "rule: census contrast"]
    tot = {k: np.zeros(4, np.int64) for k in runs}
    dropped = {k: np.zeros(4, np.int64) for k in runs[-2:]}   # car wrong, car right, elsewhere wrong, right
    pts = np.zeros(3, np.int64)                               # wrong car points: all, visible, on the outline
    bands = [(0, 2), (2, 4), (4, 8), (8, 16), (16, 10**6)]
    by_band = np.zeros((len(bands), 2), np.int64)
    stereo = cv.lidarsgm.StereoLidarSGM.load(BEST)
    stereo.setMode(cv.lidarsgm.StereoLidarSGM_MODE_SGM)
    stereo.setConsistencyCheck(cv.lidarsgm.StereoLidarSGM_CHECK_STEREO)
    est_band = np.zeros((2, len(bands), 3), np.int64)   # SDSGM / SGM: estimates, wrong, wrong and farther
    for l, r, sp, g16, obj in lp.frames():
        gt, car = g16 / 256.0, obj > 0
        has = g16 > 0
        wrong = (sp > 0) & has & lp.d1(sp, gt)
        s = visible(sparse16(sp, m), m)
        vis = s >= 0
        vv = np.where(vis, s / 16.0, 0).astype(np.float32)
        outline = cv.distanceTransform(car.astype(np.uint8), cv.DIST_L2, 3)
        pts += [(wrong & car).sum(), (wrong & car & vis).sum(), (wrong & car & vis & (outline < 4)).sum()]
        fill_truth = lambda d: np.where((d < 0) & car & has, gt, d).astype(np.float32)
        without = lambda drop: m.compute(l, r, np.where(drop, 0, sp).astype(np.float32))
        d16, d16_vis = m.compute(l, r, sp), without(wrong & car & vis)
        tot[runs[0]] += score(d16, gt, car)
        tot[runs[1]] += score(without(wrong & car), gt, car)
        tot[runs[2]] += score(d16_vis, gt, car)
        tot[runs[3]] += score(without(wrong & car & ~vis), gt, car)
        tot[runs[4]] += score(d16, gt, car, fill_truth)
        tot[runs[5]] += score(d16_vis, gt, car, fill_truth)
        for name, drop in ((runs[6], enclosed(vv)), (runs[7], census_contrast(l, r, vv))):
            tot[name] += score(without(drop), gt, car)
            w = drop & has & lp.d1(vv, gt)
            dropped[name] += [(w & car).sum(), (drop & has & ~w & car).sum(), (w & ~car).sum(),
                              (drop & has & ~w & ~car).sum()]
        filled = cv.lidarsgm.interpolateBackground(np.where(d16 >= 0, d16 / 16.0, -1).astype(np.float32))
        bad = lp.d1(np.where(filled < 0, -1, filled), gt) & has & car
        for i, (lo, hi) in enumerate(bands):
            sel = car & has & (outline >= lo) & (outline < hi)
            by_band[i] += [(bad & sel).sum(), sel.sum()]
        for k, e16 in enumerate((d16, stereo.compute(l, r, sp))):
            est, e = e16 >= 0, e16 / 16.0
            for i, (lo, hi) in enumerate(bands):
                sel = car & has & est & (outline >= lo) & (outline < hi)
                w = sel & lp.d1(e, gt)
                est_band[k, i] += [sel.sum(), w.sum(), (w & (e < gt)).sum()]
    print("20 shared KITTI frames, kitti_best.yml SDSGM, 64 lines; total D1 on cars (obj_map > 0) and elsewhere")
    print("projected points that are D1 outliers on cars: %d, %d of them kept by the visibility filter, %d of those "
          "within 4 px of the car's outline" % tuple(pts))
    print("| run | cars | elsewhere | all |")
    print("| --- | --- | --- | --- |")
    for k in runs:
        b, n, be, ne = tot[k]
        print("| %s | %.2f %% | %.2f %% | %.2f %% |" % (k, 100.0 * b / n, 100.0 * be / ne, 100.0 * (b + be) / (n + ne)))
    print("points each rule drops (with ground truth): | rule | cars, wrong | cars, right | elsewhere, wrong | "
          "elsewhere, right |")
    for k, v in dropped.items():
        print("| %s | %d | %d | %d | %d |" % ((k,) + tuple(v)))
    print("car errors by distance to the outline: | px | car GT pixels | D1 | share of the car errors | estimates "
          "only, D1 (of the wrong, farther): SDSGM | plain SGM, left-right checked |")
    for i, ((lo, hi), (b, n)) in enumerate(zip(bands, by_band)):
        print("| %s | %d | %.2f %% | %.0f %% | %.2f %% (%.0f %%) | %.2f %% (%.0f %%) |" % (
            "%d-%d" % (lo, hi) if hi < 10**6 else ">= %d" % lo, n, 100.0 * b / n, 100.0 * b / by_band[:, 0].sum(),
            *(v for k in (0, 1) for v in (100.0 * est_band[k, i, 1] / est_band[k, i, 0],
                                          100.0 * est_band[k, i, 2] / max(1, est_band[k, i, 1])))))


if __name__ == "__main__":
    main()
