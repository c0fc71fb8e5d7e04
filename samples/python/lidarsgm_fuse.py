#!/usr/bin/env python3
"""Stereo-LiDAR fusion of one KITTI frame with cv2.lidarsgm and numpy: the Python twin of the C++ tool's
single-frame run (samples/fuse/).

  python3 lidarsgm_fuse.py --kitti-frame testdata/kitti --id 000002 [--mode sdsgm] [--out DIR] [--cuda]

Reads the stereo pair, the raw Velodyne scan and the KITTI calibration, projects the scan into a sparse disparity
map, fuses, and (with ground truth in disp_occ_0/) prints coverage, covered D1 and total D1 under the KITTI devkit's
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


def read_calib(path):
    """KITTI calibration: P2, the LiDAR-to-rectified-camera transform R0_rect * Tr_velo_to_cam, and f * baseline."""
    entries = {}
    with open(path) as f:
        for line in f:
            if ":" in line:
                name, values = line.split(":", 1)
                entries[name.strip()] = np.array([float(v) for v in values.split()])
    P2 = entries["P2"].reshape(3, 4)
    P3 = entries["P3"].reshape(3, 4)
    R0 = np.eye(4)
    R0[:3, :3] = entries["R0_rect"].reshape(3, 3)
    Tr = np.eye(4)
    Tr[:3, :] = entries["Tr_velo_to_cam"].reshape(3, 4)
    return P2, R0 @ Tr, P2[0, 3] - P3[0, 3]


def read_grey(path):
    """As the C++ tool: decode as stored, then cv.cvtColor (imread's own grey conversion rounds differently)."""
    img = cv.imread(path, cv.IMREAD_UNCHANGED)
    if img is None:
        raise IOError("cannot read image " + path)
    if img.ndim == 3:
        img = cv.cvtColor(img, cv.COLOR_BGRA2GRAY if img.shape[2] == 4 else cv.COLOR_BGR2GRAY)
    return img


def load_kitti_frame(root, fid):
    """Frame fid of a KITTI-layout folder as the C++ tool reads it: the grey pair, the full scan projected into a sparse
    disparity map (CV_32F, 0 = none), and the ground truth PNG as stored (None where there is none)."""
    left = read_grey(os.path.join(root, "image_2", fid + "_10.png"))
    right = read_grey(os.path.join(root, "image_3", fid + "_10.png"))
    P2, lidar_to_cam, fb = read_calib(os.path.join(root, "calib.txt"))
    scan_path = os.path.join(root, "velodyne", fid + ".bin")
    if not os.path.isfile(scan_path):
        raise IOError("cannot open Velodyne scan " + scan_path)
    if os.path.getsize(scan_path) % 16:
        raise IOError("Velodyne scan %s is not a whole number of 16-byte points" % scan_path)
    raw = np.fromfile(scan_path, dtype=np.float32)
    h, w = left.shape
    sparse = cv.lidarsgm.projectPointsToDisparity(raw.reshape(-1, 4), P2, lidar_to_cam, fb, (w, h))
    gt_png = cv.imread(os.path.join(root, "disp_occ_0", fid + "_10.png"), cv.IMREAD_UNCHANGED)
    return left, right, sparse, gt_png


def disparity_to_float(disp16, min_disparity=0):
    """A matcher's CV_16S (x16) output as float32 pixels, -1 = invalid ((minDisparity - 1) * 16 or below)."""
    disp = disp16.astype(np.float32) / np.float32(16)
    disp[disp16 <= (min_disparity - 1) * 16] = -1
    return disp


def to_kitti_png(disp):
    """KITTI 16-bit PNG encoding: round(d * 256), 0 = invalid."""
    return np.where(disp > 0, np.clip(np.floor(disp.astype(np.float64) * 256 + 0.5), 1, 65535), 0).astype(np.uint16)


def draw_lidar_points(grey, sparse, max_disparity):
    """The LiDAR points over the image as 3x3 dots in the KITTI disparity colours, nearest points on top."""
    overlay = cv.cvtColor(grey, cv.COLOR_GRAY2BGR)
    ys, xs = np.nonzero(sparse > 0)
    order = np.argsort(sparse[ys, xs], kind="stable")  # nearest points drawn last
    colours = cv.lidarsgm.colorizeDisparity(sparse[ys, xs][order][None, :].astype(np.float32), max_disparity)[0]
    h, w = grey.shape
    for (y, x), c in zip(zip(ys[order], xs[order]), colours):
        overlay[max(y - 1, 0):min(y + 2, h), max(x - 1, 0):min(x + 2, w)] = c
    return overlay


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
        left, right, sparse, gt_png = load_kitti_frame(root, fid)
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
        print("lidarsgm_fuse.py: error: %s" % e, file=sys.stderr)
        return 1

    disp = disparity_to_float(disp16, sgm.getMinDisparity())
    line = "%s %-6s check %-12s %s %8.1f ms" % (fid, args.mode.upper(), args.check, "CUDA" if args.cuda else "CPU ", ms)
    if gt_png is not None:
        e = cv.lidarsgm.evaluateDisparity(disp16, gt_png)  # KITTI D1, both in their stored encodings
        line += "  coverage %6.2f %%  covered D1 %5.2f %%  total D1 %5.2f %%" % (
            e.coverage(), e.coveredError(), e.totalError())
    print(line)

    if args.out:
        os.makedirs(args.out, exist_ok=True)
        cv.imwrite(os.path.join(args.out, "disparity.png"), to_kitti_png(disp))
        cv.imwrite(os.path.join(args.out, "disparity_color.png"),
                   cv.lidarsgm.colorizeDisparity(disp, sgm.getNumDisparities()))
        cv.imwrite(os.path.join(args.out, "lidar_points.png"), draw_lidar_points(left, sparse, sgm.getNumDisparities()))
        print("wrote %s/disparity.png, disparity_color.png, lidar_points.png" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
