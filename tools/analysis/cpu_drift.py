#!/usr/bin/env python3
"""lidarsgm SDSGM and cv::StereoSGBM MODE_SGBM_3WAY alternating in ONE process for a while, KITTI 000002 of the shared
data: the medians of each window of seconds. Tells a slow state fixed at a process's start-up (every window of a
process alike) from a condition of the machine that comes and goes (windows differ within one process).

  PYTHONPATH=<opencv build>/python_loader OPENBLAS_NUM_THREADS=1 python3 tools/analysis/cpu_drift.py [SECONDS [WINDOW [THREADS [PATHS]]]]
"""
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import bench_cpu  # noqa: E402  (the frame and the two matchers)

secs = float(sys.argv[1]) if len(sys.argv) > 1 else 40
window = float(sys.argv[2]) if len(sys.argv) > 2 else 4
threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
paths = int(sys.argv[4]) if len(sys.argv) > 4 else 8
step = bench_cpu.setup(paths, threads)
start = time.time()
t_next = start + window
ours, theirs, out = [], [], []
while time.time() < start + secs:
    a, b = step()
    ours.append(a)
    theirs.append(b)
    if time.time() >= t_next:
        out.append("%.0f/%.0f" % (np.median(ours), np.median(theirs)))
        ours, theirs = [], []
        t_next += window
print("%d threads, %d paths, medians per %g s window, lidarsgm SDSGM / MODE_SGBM_3WAY in ms: %s"
      % (threads, paths, window, " ".join(out)))
