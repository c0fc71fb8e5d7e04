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


def setup(paths, threads):
    """KITTI 000002 (the first frame of frames.txt), lidarsgm's create() matcher with `paths` paths and
    MODE_SGBM_3WAY, each called once; OpenCV set to `threads` threads. Returns a step(): one call of each, in ms."""
    l, r, sp, _, _ = next(lidar_points.frames())
    cv.setNumThreads(threads)
    m = cv.lidarsgm.StereoLidarSGM.create()
    m.setNumPaths(paths)
    sgbm = cv.StereoSGBM.create(0, 128, 3, 72, 288, 1, 0, 10, 100, 2, cv.STEREO_SGBM_MODE_SGBM_3WAY)
    m.compute(l, r, sp)
    sgbm.compute(l, r)

    def step():
        t0 = time.perf_counter()
        m.compute(l, r, sp)
        t1 = time.perf_counter()
        sgbm.compute(l, r)
        return 1000 * (t1 - t0), 1000 * (time.perf_counter() - t1)
    return step


if __name__ == "__main__":
    paths, runs = int(sys.argv[1]), int(sys.argv[2])
    threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
    step = setup(paths, threads)
    ours, theirs = (np.array(v) for v in zip(*[step() for _ in range(runs)]))
    print("paths %d threads %d: lidarsgm min %.1f median %.1f ms | MODE_SGBM_3WAY min %.1f median %.1f ms | "
          "ratio of medians %.2f, of minima %.2f" % (paths, threads, ours.min(), np.median(ours), theirs.min(),
                                                      np.median(theirs), np.median(ours) / np.median(theirs),
                                                      ours.min() / theirs.min()))
