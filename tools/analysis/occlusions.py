#!/usr/bin/env python3
"""How many of SDSGM's KITTI outliers lie where the right camera cannot see the surface (occluded in the ground
truth), and which test of the consistency check kept them (doc/design.md, "An occlusion rule in the check").

  lidarsgm_fuse --kitti DATA/kitti2015_lidar --modes sdsgm --out BOTH [--params ...]
  lidarsgm_fuse --kitti DATA/kitti2015_lidar --modes sdsgm --out LR --check stereo [--params ...]
  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/occlusions.py BOTH LR [DATA/kitti2015_lidar]

A ground-truth pixel (x, d) is occluded when a pixel to its right with ground truth lands more than 1 px left of
x - d in the right image (a nearer surface covers its match). An estimate that the stereo-LiDAR check keeps but the
left-right check alone drops was kept by the LiDAR test.
"""
import sys

import numpy as np
import cv2 as cv


def occluded(gt):
    occ = np.zeros(gt.shape, bool)
    W = gt.shape[1]
    xs = np.arange(W)
    for y in range(gt.shape[0]):
        g = gt[y]
        # the smallest x' - d' over the pixels with ground truth strictly to the right of each x
        right = np.where(g > 0, xs - g, np.inf)
        left_of = np.minimum.accumulate(right[::-1])[::-1]
        nearest_right = np.append(left_of[1:], np.inf)
        occ[y] = (g > 0) & (nearest_right < xs - g - 1.0)
    return occ


def read(path):
    d = cv.imread(path, cv.IMREAD_UNCHANGED)
    return d.astype(np.float32) / 256.0


def main():
    both, lr = sys.argv[1], sys.argv[2]
    data = sys.argv[3] if len(sys.argv) > 3 else "../shared/data/kitti2015_lidar"
    n = dict(gt=0, occ=0, bad=0, bad_occ=0, bad_occ_lidar=0, lidar=0, lidar_bad=0)
    for fid in open(data + "/frames.txt").read().split():
        gt = read("%s/disp_occ_0/%s_10.png" % (data, fid))
        d = read("%s/%s/disparity_sdsgm.png" % (both, fid))
        s = read("%s/%s/disparity_sdsgm.png" % (lr, fid))
        has = gt > 0
        err = np.abs(d - gt)
        bad = (d > 0) & has & (err > 3) & (err > 0.05 * gt)
        occ = occluded(gt)
        by_lidar = (d > 0) & (s == 0) & has
        n["gt"] += has.sum()
        n["occ"] += (occ & has).sum()
        n["bad"] += bad.sum()
        n["bad_occ"] += (bad & occ).sum()
        n["bad_occ_lidar"] += (bad & occ & by_lidar).sum()
        n["lidar"] += by_lidar.sum()
        n["lidar_bad"] += (by_lidar & bad).sum()
    pp = lambda k: 100.0 * n[k] / n["gt"]
    print("ground truth %d px, occluded %.2f %%" % (n["gt"], pp("occ")))
    print("outliers among estimates %d (%.3f pp of the total D1), at occluded pixels %d (%.3f pp), of which kept by "
          "the LiDAR test %d" % (n["bad"], pp("bad"), n["bad_occ"], pp("bad_occ"), n["bad_occ_lidar"]))
    print("estimates kept by the LiDAR test alone %d, outliers among them %d (%.3f pp)"
          % (n["lidar"], n["lidar_bad"], pp("lidar_bad")))


if __name__ == "__main__":
    main()
