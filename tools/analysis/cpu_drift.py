#!/usr/bin/env python3
"""lidarsgm SDSGM and cv::StereoSGBM MODE_SGBM_3WAY alternating in ONE process for a while, KITTI 000002 of the shared
data: the medians of each window of seconds. Tells a slow state fixed at a process's start-up (every window of a
process alike) from a condition of the machine that comes and goes (windows differ within one process). After each
window: the steal time /proc/stat reports for it (in a virtual machine: CPU time the host gave elsewhere) and, where
g++ and two CPUs are there, the round trip of a cache line between CPU 0 and CPU 1 (core_probe.cpp): where the host
runs the two virtual CPUs at that moment.

  PYTHONPATH=<opencv build>/python_loader OPENBLAS_NUM_THREADS=1 python3 tools/analysis/cpu_drift.py [SECONDS [WINDOW [THREADS [PATHS]]]]
"""
import ctypes
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import bench_cpu  # noqa: E402  (the frame and the two matchers)


def cpu_ticks():
    """(steal, all) ticks summed over the CPUs (/proc/stat), or None where there is none: the time a virtual
    machine's CPUs were ready but the host ran something else."""
    try:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        return v[7], sum(v[:8])
    except (OSError, ValueError, IndexError):
        return None


def core_probe():
    """core_probe.cpp built into a temporary folder, or None where that fails (no g++, one CPU)."""
    if (os.cpu_count() or 1) < 2:
        return None
    so = os.path.join(tempfile.mkdtemp(), "core_probe.so")
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "core_probe.cpp")
    try:
        subprocess.run(["g++", "-O2", "-shared", "-fPIC", src, "-o", so, "-lpthread"], check=True)
        lib = ctypes.CDLL(so)
    except (OSError, subprocess.CalledProcessError):
        return None
    lib.roundTripNs.restype = ctypes.c_double
    lib.roundTripNs.argtypes = [ctypes.c_int]
    return lib


secs = float(sys.argv[1]) if len(sys.argv) > 1 else 40
window = float(sys.argv[2]) if len(sys.argv) > 2 else 4
threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
paths = int(sys.argv[4]) if len(sys.argv) > 4 else 8
probe = core_probe()
step = bench_cpu.setup(paths, threads)
start = time.time()
t_next = start + window
ours, theirs, out = [], [], []
ticks = cpu_ticks()
while time.time() < start + secs:
    a, b = step()
    ours.append(a)
    theirs.append(b)
    if time.time() >= t_next:
        now = cpu_ticks()
        steal = "" if not ticks or not now or now[1] == ticks[1] else \
            "(%.0f%%)" % (100.0 * (now[0] - ticks[0]) / (now[1] - ticks[1]))
        ticks = now
        rtt = "" if probe is None else "[%.0f ns]" % probe.roundTripNs(20000)
        out.append("%.0f/%.0f%s%s" % (np.median(ours), np.median(theirs), steal, rtt))
        ours, theirs = [], []
        t_next += window
print("%d threads, %d paths, medians per %g s window, lidarsgm SDSGM / MODE_SGBM_3WAY in ms "
      "(steal: the share of CPU time the host took) [cache line round trip CPU 0 - CPU 1]: %s"
      % (threads, paths, window, " ".join(out)))
