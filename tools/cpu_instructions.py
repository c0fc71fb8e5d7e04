#!/usr/bin/env python3
"""One process of tools/cpu_instructions.sh: CALLS compute() calls of one matcher on KITTI 000002 of testdata through
cv2, at 1 thread. Run under callgrind twice (1 and 2 calls): the difference is one steady-state call.

  PYTHONPATH=<opencv build>/python_loader python3 tools/cpu_instructions.py CONFIG CALLS

CONFIG: defaults (create()), best (doc/params/kitti_best.yml as the file sets it), best_w0 (the same with
searchWindow 0), best_w4 (searchWindow 4), 3way (cv::StereoSGBM MODE_SGBM_3WAY as the tool's --timing builds it).
"""
import os
import sys

import cv2 as cv

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def matcher(config):
    if config == "3way":
        # The tool's reference (samples/fuse/timing.cpp): OpenCV's penalties for blockSize 3, 128 disparities.
        s = cv.StereoSGBM.create(0, 128, 3, 72, 288, 1, 0, 10, 100, 2, cv.STEREO_SGBM_MODE_SGBM_3WAY)
        return lambda f: s.compute(f.left, f.right)
    if config == "defaults":
        m = cv.lidarsgm.StereoLidarSGM.create()
    else:
        m = cv.lidarsgm.StereoLidarSGM.load(os.path.join(ROOT, "doc", "params", "kitti_best.yml"))
        if config == "best_w0":
            m.setSearchWindow(0)
        elif config == "best_w4":
            m.setSearchWindow(4)
        elif config != "best":
            raise SystemExit("unknown configuration " + config)
    return lambda f: m.compute(f.left, f.right, f.sparse)


if __name__ == "__main__":
    config, calls = sys.argv[1], int(sys.argv[2])
    cv.setNumThreads(1)
    frame = cv.lidarsgm.loadKittiFrame(os.path.join(ROOT, "testdata", "kitti"), "000002")
    run = matcher(config)
    for _ in range(calls):
        run(frame)
