#!/usr/bin/env python3
"""The disparity windows (StereoLidarSGM::setSearchWindow) on the 20 shared KITTI frames and the Middlebury scenes,
against the full range, with doc/params/kitti_best.yml (doc/design.md, "Disparity windows").

  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/search_windows.py [MARGIN, default 4] [shared data dir]

Per LiDAR line count (64, 32, 16; every 2nd / 4th ring, as the tool's --lidar-lines): the share of the
W x H x numDisparities cells searched (mean and range over the frames), and where no prior reaches (the tiles whose
windows come from the coarse pass: no semidensified prior in the tile or the eight around it) the share of the pixels
valid in both outputs whose disparities are equal, and within 1 px. The Middlebury scenes the same (their sparse
input samples the ground truth over the whole image, so few tiles lack a prior).
"""
import os
import sys

import numpy as np
import cv2 as cv

HERE = os.path.dirname(os.path.abspath(__file__))
MARGIN = int(sys.argv[1]) if len(sys.argv) > 1 else 4
DATA = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "..", "..", "..", "shared", "data")
BEST = os.path.join(HERE, "..", "..", "doc", "params", "kitti_best.yml")
TILE = 32


def no_prior_mask(semidense, invalid):
    """Pixels of the tiles without a prior in the tile or the eight around it (where the coarse pass decides)."""
    h, w = semidense.shape
    ty, tx = (h + TILE - 1) // TILE, (w + TILE - 1) // TILE
    valid = np.zeros((ty * TILE, tx * TILE), bool)
    valid[:h, :w] = semidense != invalid
    has = valid.reshape(ty, TILE, tx, TILE).any(axis=(1, 3))
    padded = np.pad(has, 1)
    near = np.zeros_like(has)
    for dy in range(3):
        for dx in range(3):
            near |= padded[dy:dy + ty, dx:dx + tx]
    return np.kron(~near, np.ones((TILE, TILE), bool))[:h, :w]


def compare(frames, make):
    """(fractions, equal, within 1 px, pixels compared) over the frames where no prior reaches."""
    full, windowed = make(), make()
    windowed.setSearchWindow(MARGIN)
    fractions, eq, near, n = [], 0, 0, 0
    for l, r, sp in frames:
        a = full.compute(l, r, sp)
        b = windowed.compute(l, r, sp)
        fractions.append(windowed.getSearchedFraction())
        invalid = (full.getMinDisparity() - 1) * 16
        mask = no_prior_mask(full.semidensify(l, r, sp), invalid) & (a != invalid) & (b != invalid)
        diff = np.abs(a.astype(np.int32) - b.astype(np.int32))[mask]
        eq += int((diff == 0).sum())
        near += int((diff <= 16).sum())
        n += int(mask.sum())
    return np.array(fractions), eq, near, n


def report(name, result):
    f, eq, near, n = result
    share = "%.2f %% equal, %.2f %% within 1 px of %d pixels" % (100.0 * eq / n, 100.0 * near / n, n) if n else \
        "no such pixels"
    print("| %-26s | %5.1f %% (%4.1f-%4.1f) | %s |" % (name, 100 * f.mean(), 100 * f.min(), 100 * f.max(), share))


def main():
    cv.setNumThreads(2)
    print("disparity windows, margin %d, doc/params/kitti_best.yml, against the full range" % MARGIN)
    print("| data | cells searched: mean (range) | where no prior reaches: windowed = full range |")
    print("|---|---|---|")
    kitti = os.path.join(DATA, "kitti2015_lidar")
    ids = cv.lidarsgm.readKittiFrameIds(kitti)
    for lines, every in ((64, 1), (32, 2), (16, 4)):
        frames = []
        for i in ids:
            fr = cv.lidarsgm.loadKittiFrame(kitti, i, every, 0)
            frames.append((fr.left, fr.right, fr.sparse))
        report("KITTI, %d lines" % lines, compare(frames, lambda: cv.lidarsgm.StereoLidarSGM.load(BEST)))
    # Middlebury as the tool's --middlebury: 1 % of the ground truth (seed 1), the range from its largest value.
    mb = os.path.join(DATA, "middlebury")
    by_range = {}
    for scene in sorted(os.listdir(mb)):
        d = os.path.join(mb, scene)
        if not os.path.isdir(d):
            continue
        l, r, gt = cv.lidarsgm.loadMiddleburyScene(d)
        nd = min(256, max(64, (int(np.ceil(gt.max())) + 1 + 15) // 16 * 16))
        by_range.setdefault(nd, []).append((l, r, cv.lidarsgm.sampleGroundTruth(gt, 0.01, 1)))
    for nd, fr in sorted(by_range.items()):
        def make(nd=nd):
            m = cv.lidarsgm.StereoLidarSGM.load(BEST)
            m.setNumDisparities(nd)
            return m
        report("Middlebury, %d disparities" % nd, compare(fr, make))


if __name__ == "__main__":
    main()
