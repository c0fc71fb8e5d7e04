#!/usr/bin/env python3
"""Would filling the matcher's holes beat the devkit's background interpolation? (doc/design.md, "Filling holes")

  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/hole_fill.py [shared data dir]

For the 20 shared KITTI frames (D1) and the Middlebury scenes (1 % of the ground truth, sampled here with numpy,
bad-2), SDSGM with create()'s defaults, the total error when each row gap is filled by: the devkit's rule (the smaller
end), the end whose intensity is closer, or the background unless the pixel looks clearly (2x closer in intensity)
like the foreground end. Row ends are extended as the devkit does; then the devkit's interpolation runs.
"""
import os
import sys

import numpy as np
import cv2 as cv

sys.path.insert(0, os.path.dirname(__file__))
import lidar_points  # noqa: E402  (reads the KITTI frames)

SHARED = os.path.dirname(lidar_points.DATA)


def middlebury():
    layouts = [("im2.png", "im6.png", "disp2.png", 4.0), ("view1.png", "view5.png", "disp1.png", 2.0),
               ("im0.png", "im1.png", "disp0.pfm", 1.0), ("aloeL.jpg", "aloeR.jpg", "aloeGT.png", 1.0)]
    root = os.path.join(SHARED, "middlebury")
    for scene in sorted(os.listdir(root)):
        rng = np.random.default_rng(1)
        for a, b, g, scale in layouts:
            if os.path.exists(os.path.join(root, scene, g)):
                raw = cv.imread(os.path.join(root, scene, g), cv.IMREAD_UNCHANGED)
                gt = raw.astype(np.float32) / scale
                gt[~(raw < np.inf) if raw.dtype == np.float32 else raw == 0] = -1
                l = cv.imread(os.path.join(root, scene, a), cv.IMREAD_GRAYSCALE)
                r = cv.imread(os.path.join(root, scene, b), cv.IMREAD_GRAYSCALE)
                nd = min(256, max(64, (int(np.ceil(gt.max())) + 1 + 15) // 16 * 16))
                sp = np.where((gt > 0) & (rng.random(gt.shape) < 0.01), gt, 0).astype(np.float32)
                yield l, r, sp, gt, nd
                break


def fill(d, img, rule):
    out, I = d.copy(), img.astype(np.float32)
    for y in range(out.shape[0]):
        row = out[y]
        valid = np.flatnonzero(row >= 0)
        if valid.size == 0:
            continue
        for a, b in zip(valid[:-1], valid[1:]):
            if b > a + 1:
                xs = np.arange(a + 1, b)
                if rule == "devkit":
                    row[xs] = min(row[a], row[b])
                elif rule == "closer intensity":
                    ca, cb = np.abs(I[y, xs] - I[y, a]), np.abs(I[y, xs] - I[y, b])
                    row[xs] = np.where((ca < cb) | ((ca == cb) & (row[a] <= row[b])), row[a], row[b])
                else:
                    lo, hi = (a, b) if row[a] <= row[b] else (b, a)
                    clo, chi = np.abs(I[y, xs] - I[y, lo]), np.abs(I[y, xs] - I[y, hi])
                    row[xs] = np.where(chi * 2 < clo, row[hi], row[lo])
        row[:valid[0]] = row[valid[0]]
        row[valid[-1] + 1:] = row[valid[-1]]
    return cv.lidarsgm.interpolateBackground(out)


def run(name, items, outlier):
    for rule in ("devkit", "closer intensity", "background unless clearly foreground"):
        n = bad = 0
        for l, r, sp, gt, nd in items:
            m = cv.lidarsgm.StereoLidarSGM.create()
            m.setNumDisparities(nd)
            m.setOutputType(cv.CV_32F)
            d = m.compute(l, r, sp)
            f = fill(np.where(d >= 0, d, -1).astype(np.float32), l, rule)
            has = gt >= 0
            n += has.sum()
            bad += (outlier(f, gt) & has).sum()
        print("%-10s %-38s total %.3f %%" % (name, rule, 100.0 * bad / n))


kitti = []
for l, r, sp, g16, obj in lidar_points.frames():
    gt = g16.astype(np.float32) / 256
    gt[g16 == 0] = -1
    kitti.append((l, r, sp, gt, 128))
run("KITTI", kitti, lambda d, g: (np.abs(d - g) > 3) & (np.abs(d - g) > 0.05 * g))
run("Middlebury", list(middlebury()), lambda d, g: np.abs(d - g) > 2)
