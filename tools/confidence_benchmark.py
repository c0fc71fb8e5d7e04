#!/usr/bin/env python3
"""The confidence map's sparsification curves (StereoLidarSGM.computeWithConfidence): covered error of the pixels kept,
most confident first, against the fraction kept; its area (AUC) beside the oracle's (the errors removed first) and a
random order's (the error rate itself); and the share of all covered errors that the 10 % least confident pixels hold.

  python3 tools/confidence_benchmark.py [--data ../shared/data] [--params doc/params/kitti_best.yml] [--threads N]

KITTI: the 20 frames of kitti2015_lidar at 64, 32 and 16 LiDAR lines (every 1st, 2nd, 4th ring), D1 (KITTI devkit:
|d - gt| > 3 px and > 5 % of gt). Middlebury: its scenes with 1 % of the ground truth as input (seed 1, as the tool's
--middlebury), bad-2 (|d - gt| > 2 px). Pixels with equal confidence are removed together in expectation (a tie
group's errors in proportion), so the order among ties cannot flatter the curve: the counts and figures are
cv2.lidarsgm.evaluateConfidence's (ConfidenceErrors), the tool's too. Also the time of the call with and
without the confidence on one KITTI frame (CPU, median of 15 alternating calls).
"""
import argparse
import os
import sys
import time

import numpy as np
import cv2 as cv

KEPT = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1]


def report(label, c):
    """One data set's figures from its summed cv2.lidarsgm.ConfidenceErrors (the library's sparsification counts)."""
    n, e = c.total(), c.totalOutliers()
    oracle, auc = c.oracleAuc(), c.auc()
    print("%-34s covered px %8d, errors %6.2f %% | 10 %% least confident hold %5.1f %% of the errors | "
          "AUC %.5f, oracle %.5f (%.1fx), random %.5f" % (label, n, 100 * e / n, c.leastConfidentShare(0.1), auc,
                                                          oracle, auc / oracle if oracle else 0, e / n))
    curve = "  ".join("%3d%%: %5.2f" % (100 * k, c.keptError(k)) for k in KEPT)
    print("%-34s error of the kept pixels (%%), by fraction kept: %s" % ("", curve))


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--data", default=os.path.join(here, "..", "..", "shared", "data"))
    p.add_argument("--params", default=os.path.join(here, "..", "doc", "params", "kitti_best.yml"))
    p.add_argument("--threads", type=int, default=2)
    a = p.parse_args(argv)
    cv.setNumThreads(a.threads)
    m = cv.lidarsgm.StereoLidarSGM.load(a.params)
    print("confidence of SDSGM, %s, check stereo-lidar, CPU, %d threads" % (os.path.relpath(a.params), a.threads))

    kitti = os.path.join(a.data, "kitti2015_lidar")
    ids = list(cv.lidarsgm.readKittiFrameIds(kitti))
    for lines, every in ((64, 1), (32, 2), (16, 4)):
        total = cv.lidarsgm.ConfidenceErrors()
        for i in ids:
            f = cv.lidarsgm.loadKittiFrame(kitti, i, every)
            disp, conf = m.computeWithConfidence(f.left, f.right, f.sparse)
            total.add(cv.lidarsgm.evaluateConfidence(disp, conf, f.groundTruth, cv.lidarsgm.METRIC_KITTI_D1, 2.0,
                                                     m.getMinDisparity()))
        report("KITTI, %d frames, %d lines (D1)" % (len(ids), lines), total)

    mb = os.path.join(a.data, "middlebury")
    total = cv.lidarsgm.ConfidenceErrors()
    scenes = 0
    for name in sorted(os.listdir(mb)):
        try:
            left, right, gt = cv.lidarsgm.loadMiddleburyScene(os.path.join(mb, name))
        except cv.error:
            continue
        sparse = cv.lidarsgm.sampleGroundTruth(gt, 0.01, 1)
        mm = cv.lidarsgm.StereoLidarSGM.load(a.params)
        # As the tool's --middlebury: the scene's range in multiples of 16, 64 to 256.
        mm.setNumDisparities(min(256, max(64, (int(np.ceil(gt.max())) + 1 + 15) // 16 * 16)))
        disp, conf = mm.computeWithConfidence(left, right, sparse)
        total.add(cv.lidarsgm.evaluateConfidence(disp, conf, gt, cv.lidarsgm.METRIC_BAD, 2.0, mm.getMinDisparity()))
        scenes += 1
    report("Middlebury, %d scenes, 1 %% GT (bad-2)" % scenes, total)

    f = cv.lidarsgm.loadKittiFrame(kitti, ids[0])
    t_plain, t_conf = [], []
    for _ in range(15):
        t0 = time.perf_counter()
        m.compute(f.left, f.right, f.sparse)
        t1 = time.perf_counter()
        m.computeWithConfidence(f.left, f.right, f.sparse)
        t2 = time.perf_counter()
        t_plain.append(t1 - t0)
        t_conf.append(t2 - t1)
    a_ms, b_ms = 1000 * np.median(t_plain), 1000 * np.median(t_conf)
    print("time, KITTI frame %s: compute %.1f ms, with confidence %.1f ms (+%.1f %%)" % (ids[0], a_ms, b_ms,
                                                                                         100 * (b_ms / a_ms - 1)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
