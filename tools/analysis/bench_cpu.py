#!/usr/bin/env python3
"""lidarsgm SDSGM against cv::StereoSGBM MODE_SGBM_3WAY on KITTI 000002 of the shared data, alternating in one loop:
the quick check used between the CPU steps of doc/perf.md (the tool's --timing is the reference measurement).

  PYTHONPATH=<opencv build>/python_loader OPENBLAS_NUM_THREADS=1 python3 tools/analysis/bench_cpu.py PATHS RUNS [THREADS]
"""
import os
import sys
import time

import numpy as np
import cv2 as cv

sys.path.insert(0, os.path.dirname(__file__))
import lidar_points  # noqa: E402  (reads the KITTI frames)

paths, runs = int(sys.argv[1]), int(sys.argv[2])
threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
l, r, sp, _, _ = next(lidar_points.frames())   # the first frame of frames.txt: 000002
cv.setNumThreads(threads)
m = cv.lidarsgm.StereoLidarSGM.create()
m.setNumPaths(paths)
sgbm = cv.StereoSGBM.create(0, 128, 3, 72, 288, 1, 0, 10, 100, 2, cv.STEREO_SGBM_MODE_SGBM_3WAY)
m.compute(l, r, sp)
sgbm.compute(l, r)
ours, theirs = [], []
for _ in range(runs):
    t0 = time.perf_counter()
    m.compute(l, r, sp)
    ours.append(1000 * (time.perf_counter() - t0))
    t0 = time.perf_counter()
    sgbm.compute(l, r)
    theirs.append(1000 * (time.perf_counter() - t0))
ours, theirs = np.array(ours), np.array(theirs)
print("paths %d threads %d: lidarsgm min %.1f median %.1f ms | MODE_SGBM_3WAY min %.1f median %.1f ms | "
      "ratio of medians %.2f, of minima %.2f" % (paths, threads, ours.min(), np.median(ours), theirs.min(),
                                                  np.median(theirs), np.median(ours) / np.median(theirs),
                                                  ours.min() / theirs.min()))
