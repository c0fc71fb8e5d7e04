#!/usr/bin/env python3
"""Stereo-LiDAR fusion of one KITTI frame with cv2.lidarsgm and numpy: the Python twin of the C++ tool's
single-frame run (samples/fuse/).

  python3 lidarsgm_fuse.py --kitti-frame testdata/kitti --id 000002 [--mode sdsgm] [--out DIR] [--cuda]

Reads the stereo pair, the raw Velodyne scan and the KITTI calibration and projects the scan into a sparse disparity
map (cv2.lidarsgm.loadKittiFrame), fuses, and (with ground truth in disp_occ_0/) prints coverage, covered D1 and total D1 under the KITTI devkit's
rules, background interpolation included (cv2.lidarsgm.evaluateDisparity). With --out it writes disparity.png
(KITTI 16-bit), disparity_color.png and lidar_points.png. Exit codes: 0 done, 1 error (unreadable input, ...), 2 bad command line.
"""
import argparse
import os
import sys
import time

import numpy as np
import cv2 as cv

MODES = {"sgm": 0, "dsgm": 1, "sdsgm": 2}
CHECKS = {"none": 0, "stereo": 1, "camera-lidar": 2, "stereo-lidar": 3}


def disparity_to_float(disp16, min_disparity=0):
    """A matcher's CV_16S (x16) output as float32 pixels, -1 = invalid ((minDisparity - 1) * 16 or below)."""
    disp = disp16.astype(np.float32) / np.float32(16)
    disp[disp16 <= (min_disparity - 1) * 16] = -1
    return disp


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--kitti-frame", required=True, help="KITTI-layout folder (image_2, image_3, velodyne, calib.txt)")
    p.add_argument("--id", default="000002")
    p.add_argument("--mode", choices=sorted(MODES), default="sdsgm")
    p.add_argument("--check", choices=sorted(CHECKS), default="stereo-lidar")
    p.add_argument("--num-disparities", type=int, help="default: 128, or the --params file's")
    p.add_argument("--params", help="matcher parameters saved with StereoLidarSGM.save (e.g. doc/params/kitti_best.yml)")
    p.add_argument("--out", help="folder for disparity.png, disparity_color.png, lidar_points.png")
    p.add_argument("--cuda", action="store_true", help="run on the GPU (cv2.cuda_GpuMat in and out)")
    args = p.parse_args(argv)

    root, fid = args.kitti_frame, args.id
    try:
        # The grey pair, the scan projected with calib.txt, the ground truth where disp_occ_0/ holds it.
        frame = cv.lidarsgm.loadKittiFrame(root, fid)
        left, right, sparse = frame.left, frame.right, frame.sparse
        sgm = cv.lidarsgm.StereoLidarSGM.load(args.params) if args.params else cv.lidarsgm.StereoLidarSGM.create()
        if args.num_disparities:
            sgm.setNumDisparities(args.num_disparities)
        sgm.setMode(MODES[args.mode])
        sgm.setConsistencyCheck(CHECKS[args.check])
        t0 = time.perf_counter()
        if args.cuda:
            g = cv.cuda.computeStereoLidarSGM(sgm, cv.cuda_GpuMat(left), cv.cuda_GpuMat(right), cv.cuda_GpuMat(sparse))
            disp16 = g.download()
        else:
            disp16 = sgm.compute(left, right, sparse)
        ms = 1000 * (time.perf_counter() - t0)
    except (IOError, OSError, KeyError, ValueError, cv.error) as e:
        print("lidarsgm_fuse.py: error: %s" % (e.err if isinstance(e, cv.error) else e), file=sys.stderr)
        return 1

    disp = disparity_to_float(disp16, sgm.getMinDisparity())
    line = "%s %-6s check %-12s %s %8.1f ms" % (fid, args.mode.upper(), args.check, "CUDA" if args.cuda else "CPU ", ms)
    if frame.groundTruth is not None and frame.groundTruth.size:
        e = cv.lidarsgm.evaluateDisparity(disp16, frame.groundTruth)  # KITTI D1
        line += "  coverage %6.2f %%  covered D1 %5.2f %%  total D1 %5.2f %%" % (
            e.coverage(), e.coveredError(), e.totalError())
    print(line)

    if args.out:
        os.makedirs(args.out, exist_ok=True)
        cv.imwrite(os.path.join(args.out, "disparity.png"), cv.lidarsgm.encodeKittiDisparity(disp))
        max_d = sgm.getMinDisparity() + sgm.getNumDisparities()
        cv.imwrite(os.path.join(args.out, "disparity_color.png"),
                   cv.lidarsgm.addDisparityLegend(cv.lidarsgm.colorizeDisparity(disp, max_d), max_d))
        points = cv.lidarsgm.drawSparseDisparity(left, sparse, max_d)
        cv.imwrite(os.path.join(args.out, "lidar_points.png"),
                   cv.lidarsgm.addDisparityLegend(points, max_d, title="LiDAR disparity (px)", showNone=False))
        print("wrote %s/disparity.png, disparity_color.png, lidar_points.png" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
