#!/usr/bin/env python3
"""Where the KITTI error is: cars against the rest, for the fused maps and for the LiDAR points themselves.

KITTI's object map (obj_map > 0: the cars, whose ground truth comes from fitted CAD models) splits the ground-truth
pixels of a KITTI-layout folder. For each number of LiDAR lines it prints
  1. SDSGM's total D1 (the devkit's rule after its background interpolation) on cars and elsewhere, the cars' share of
     all errors, and the share of the car errors that lie farther than the truth (a smaller disparity);
  2. the projected LiDAR points scored by the same rule where they have ground truth: on cars and elsewhere, and the
     share of the bad ones that lie farther than the truth (behind the surface the cameras see).
Sums are over the pixels of all frames. The folder needs image_2, image_3, velodyne, calib.txt, disp_occ_0, obj_map
and frames.txt (the layout of ../shared/data/kitti2015_lidar).

    PYTHONPATH=<opencv build>/python_loader python3 tools/car_split.py --data ../shared/data/kitti2015_lidar
        [--params doc/params/kitti_best.yml] [--lidar-lines 64,32,16]
"""
import argparse
import os
import sys

import numpy as np


def d1_bad(d, g):
    """The devkit's D1 outliers: more than 3 px and more than 5 % off."""
    e = np.abs(d - g)
    return (e > 3) & (e > 0.05 * g)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", required=True, help="a KITTI-layout folder with obj_map")
    ap.add_argument("--params", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "doc",
                                                     "params", "kitti_best.yml"))
    ap.add_argument("--lidar-lines", default="64", help="comma-separated: 64 (every ring), 32, 16")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    import cv2 as cv
    cv.setNumThreads(a.threads)
    ids = cv.lidarsgm.readKittiFrameIds(a.data)
    for name in ("disp_occ_0", "obj_map", "velodyne"):
        if not os.path.isdir(os.path.join(a.data, name)):
            sys.exit("car_split.py: %s has no %s/ folder" % (a.data, name))
    m = cv.lidarsgm.StereoLidarSGM.load(a.params)
    mind = m.getMinDisparity()
    print("KITTI %s: %d frames, %s, SDSGM as the file sets it (mode %d), CPU" % (a.data, len(ids), a.params,
                                                                               m.getMode()))
    for lines in [int(v) for v in a.lidar_lines.split(",")]:
        if lines not in (64, 32, 16):
            sys.exit("car_split.py: --lidar-lines takes 64, 32 and 16")
        gt_n = {True: 0, False: 0}
        bad = {True: 0, False: 0}
        far = {True: 0, False: 0}
        pts = {True: 0, False: 0}
        pts_bad = {True: 0, False: 0}
        pts_far = {True: 0, False: 0}
        for i in ids:
            f = cv.lidarsgm.loadKittiFrame(a.data, i)
            c = f.calibration
            scan = cv.lidarsgm.readVelodyneScan(os.path.join(a.data, "velodyne", i + ".bin"))
            if lines != 64:
                scan = cv.lidarsgm.selectLidarRings(scan, 64 // lines, 0)
            sparse = cv.lidarsgm.projectPointsToDisparity(scan, c.projection, c.lidarToCamera, c.focalBaseline,
                                                         (f.left.shape[1], f.left.shape[0]))
            g16 = cv.imread(os.path.join(a.data, "disp_occ_0", i + "_10.png"), cv.IMREAD_UNCHANGED)
            obj = cv.imread(os.path.join(a.data, "obj_map", i + "_10.png"), cv.IMREAD_UNCHANGED)
            if g16 is None or obj is None:
                sys.exit("car_split.py: frame %s lacks disp_occ_0 or obj_map" % i)
            g = g16.astype(np.float32) / 256
            has = g16 > 0
            car = obj > 0
            d16 = m.compute(f.left, f.right, sparse)
            d = np.where(d16 >= mind * 16, d16.astype(np.float32) / 16, -1).astype(np.float32)
            filled = cv.lidarsgm.interpolateBackground(d)
            filled = np.where(filled < 0, -1, filled)   # a pixel it cannot fill scores as -1, as in the devkit
            b = d1_bad(filled, g) & has
            p = (sparse > 0) & has
            pb = d1_bad(sparse, g) & p
            for k in (True, False):
                sel = car if k else ~car
                gt_n[k] += int(np.count_nonzero(has & sel))
                bad[k] += int(np.count_nonzero(b & sel))
                far[k] += int(np.count_nonzero(b & sel & (filled < g)))
                pts[k] += int(np.count_nonzero(p & sel))
                pts_bad[k] += int(np.count_nonzero(pb & sel))
                pts_far[k] += int(np.count_nonzero(pb & sel & (sparse < g)))
        pct = lambda x, n: 100.0 * x / n if n else float("nan")
        allgt, allbad = gt_n[True] + gt_n[False], bad[True] + bad[False]
        print("\n%d LiDAR lines: SDSGM total D1" % lines)
        print("| | share of GT pixels | total D1 | share of all errors | errors farther than the truth |")
        print("| --- | --- | --- | --- | --- |")
        for k, label in ((True, "cars (obj_map > 0)"), (False, "elsewhere")):
            print("| %s | %.1f %% | %.2f %% | %.0f %% | %.0f %% |" % (label, pct(gt_n[k], allgt), pct(bad[k], gt_n[k]),
                                                                pct(bad[k], allbad), pct(far[k], bad[k])))
        print("| all | 100 %% | %.2f %% | 100 %% | %.0f %% |" % (pct(allbad, allgt),
                                                               pct(far[True] + far[False], allbad)))
        print("the projected LiDAR points, D1 against the ground truth where they have it")
        print("| | points | D1 | of the bad ones, farther than the truth |")
        print("| --- | --- | --- | --- |")
        for k, label in ((True, "on cars"), (False, "elsewhere")):
            print("| %s | %d | %.2f %% | %.0f %% |" % (label, pts[k], pct(pts_bad[k], pts[k]),
                                                       pct(pts_far[k], pts_bad[k])))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
