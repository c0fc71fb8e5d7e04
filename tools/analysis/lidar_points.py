#!/usr/bin/env python3
"""Where SDSGM's KITTI errors come from, and what wrong LiDAR points cost (doc/design.md, "Where the errors are").

  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/lidar_points.py [--filters] [--best] [shared data dir]

Prints, over the 20 shared KITTI frames with create()'s defaults: the split of the total D1 into wrong estimates and
wrongly filled holes, the share of cars (obj_map), how many wrong estimates have a wrong semidense prior, how many
projected LiDAR points are D1 outliers against the ground truth (and on which side), and SDSGM with exactly those
points removed (an oracle: it reads the ground truth). With --filters, also the visibility filter's rule (a point
with a nearer one, by more than a margin, within a window) for a few windows and margins: what each removes and
SDSGM / DSGM with it. With --best, the breakdown uses doc/params/kitti_best.yml instead of the defaults.
"""
import os
import sys

import numpy as np
import cv2 as cv

# The shared data beside the checkout, or the folder given on the command line (when run as a script).
_args = [a for a in sys.argv[1:] if not a.startswith("--")] if __name__ == "__main__" else []
DATA = os.path.join(_args[0] if _args else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..",
                                                         "shared", "data"), "kitti2015_lidar")


def frames():
    """Each shared frame as the tool reads it (cv2.lidarsgm.loadKittiFrame), with its stored ground truth and object map."""
    for i in cv.lidarsgm.readKittiFrameIds(DATA):
        f = cv.lidarsgm.loadKittiFrame(DATA, i)
        g16 = cv.imread(os.path.join(DATA, "disp_occ_0", i + "_10.png"), cv.IMREAD_UNCHANGED)
        obj = cv.imread(os.path.join(DATA, "obj_map", i + "_10.png"), cv.IMREAD_UNCHANGED)
        yield f.left, f.right, f.sparse, g16, obj


def d1(d, g):
    e = np.abs(d - g)
    return (e > 3) & (e > 0.05 * g)


def breakdown(data):
    best = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "doc", "params", "kitti_best.yml")
    m = cv.lidarsgm.StereoLidarSGM.load(best) if "--best" in sys.argv else cv.lidarsgm.StereoLidarSGM.create()
    n = dict(gt=0, est_bad=0, hole_bad=0, car_bad=0, car_gt=0, bad_with_prior=0, bad_prior_bad=0,
             pts=0, pts_bad=0, pts_far=0)
    oracle = cv.lidarsgm.DisparityErrors()
    for l, r, sp, g16, obj in data:
        gt = g16.astype(np.float32) / 256
        has_gt = g16 > 0
        d16 = m.compute(l, r, sp)
        semi = m.semidensify(l, r, sp).astype(np.float32) / 16
        d = d16.astype(np.float32) / 16
        est = d16 >= 0
        filled = cv.lidarsgm.interpolateBackground(np.where(est, d, -1).astype(np.float32))
        bad = d1(filled, gt) & has_gt
        n["gt"] += has_gt.sum()
        n["est_bad"] += (bad & est).sum()
        n["hole_bad"] += (bad & ~est).sum()
        n["car_bad"] += (bad & (obj > 0)).sum()
        n["car_gt"] += (has_gt & (obj > 0)).sum()
        n["bad_with_prior"] += (bad & est & (semi >= 0)).sum()
        n["bad_prior_bad"] += (bad & est & (semi >= 0) & d1(semi, gt)).sum()
        pts = sp > 0
        pbad = pts & has_gt & d1(sp, gt)
        n["pts"] += pts.sum()
        n["pts_bad"] += pbad.sum()
        n["pts_far"] += (pbad & (sp < gt)).sum()
        clean = sp.copy()
        clean[pbad] = 0
        oracle.add(cv.lidarsgm.evaluateDisparity(m.compute(l, r, clean), g16))
    g = n["gt"]
    print("SDSGM total D1 %.3f %% = wrong estimates %.3f + wrongly filled holes %.3f (points of the ground truth)"
          % (100.0 * (n["est_bad"] + n["hole_bad"]) / g, 100.0 * n["est_bad"] / g, 100.0 * n["hole_bad"] / g))
    print("cars: %.1f %% of the outliers, %.1f %% of the ground truth" % (
        100.0 * n["car_bad"] / (n["est_bad"] + n["hole_bad"]), 100.0 * n["car_gt"] / g))
    print("wrong estimates with a semidense prior: %.1f %%, of which the prior is wrong: %.1f %%" % (
        100.0 * n["bad_with_prior"] / n["est_bad"], 100.0 * n["bad_prior_bad"] / max(1, n["bad_with_prior"])))
    print("LiDAR points %d, D1 outliers against the ground truth %d (%.2f %%), %.0f %% of them farther than it" % (
        n["pts"], n["pts_bad"], 100.0 * n["pts_bad"] / n["pts"], 100.0 * n["pts_far"] / max(1, n["pts_bad"])))
    print("SDSGM without exactly those points (oracle): %.2f / %.2f / %.2f %%" % (
        oracle.coverage(), oracle.coveredError(), oracle.totalError()))


def filters(data):
    sd = cv.lidarsgm.StereoLidarSGM.create()
    ds = cv.lidarsgm.StereoLidarSGM.create()
    ds.setMode(cv.lidarsgm.StereoLidarSGM_MODE_DSGM)
    # (half width, half height, margin(d_near, d)): a point is hidden when some point in the window has d_near with
    # margin true.
    rules = [(1, 1, "10 % + 1 px", lambda m, d: m > d * 1.1 + 1), (1, 3, "10 % + 1 px", lambda m, d: m > d * 1.1 + 1),
             (2, 2, "10 % + 1 px", lambda m, d: m > d * 1.1 + 1), (2, 4, "10 % + 1 px", lambda m, d: m > d * 1.1 + 1),
             (2, 4, "max(10 %, 1 px)", lambda m, d: (m > d * 1.1) & (m > d + 1)),
             (2, 4, "D1: 3 px and 5 %", lambda m, d: (m > d * 1.05) & (m > d + 3)),
             (2, 4, "Tc = 2 px", lambda m, d: m > d + 2)]
    for rx, ry, name, hides in rules:
        a, b = cv.lidarsgm.DisparityErrors(), cv.lidarsgm.DisparityErrors()
        removed = np.zeros(3, np.int64)
        for l, r, sp, g16, obj in data:
            gt = g16.astype(np.float32) / 256
            near = cv.dilate(sp, np.ones((2 * ry + 1, 2 * rx + 1), np.uint8))
            hidden = (sp > 0) & hides(near, sp)
            bad = (sp > 0) & (g16 > 0) & d1(sp, gt)
            removed += [(hidden & bad).sum(), (hidden & (g16 > 0) & ~bad).sum(), (hidden & (g16 == 0)).sum()]
            kept = np.where(hidden, 0, sp).astype(np.float32)
            a.add(cv.lidarsgm.evaluateDisparity(sd.compute(l, r, kept), g16))
            b.add(cv.lidarsgm.evaluateDisparity(ds.compute(l, r, kept), g16))
        print("%d x %d, nearer by %-17s removes wrong %5d, right %5d, without ground truth %5d: SDSGM %.2f / %.2f / "
              "%.3f %%, DSGM total %.3f %%" % (rx, ry, name, removed[0], removed[1], removed[2], a.coverage(),
                                               a.coveredError(), a.totalError(), b.totalError()))


if __name__ == "__main__":
    data = list(frames())
    breakdown(data)
    if "--filters" in sys.argv:
        filters(data)
