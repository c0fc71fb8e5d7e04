#!/usr/bin/env python3
"""Stereo-LiDAR fusion of one KITTI frame with cv2.lidarsgm and numpy: the Python twin of the C++ tool's
single-frame run (samples/lidarsgm_fuse.cpp).

  python3 lidarsgm_fuse.py --kitti-frame testdata/kitti --id 000002 [--mode sdsgm] [--out DIR] [--cuda]

Reads the stereo pair, the raw Velodyne scan and the KITTI calibration, projects the scan into a sparse disparity
map, fuses, and (with ground truth in disp_occ_0/) prints coverage, covered D1 and total D1 under the KITTI devkit's
rules, background interpolation included. With --out it writes disparity.png (KITTI 16-bit), disparity_color.png and
lidar_points.png. Exit codes: 0 done, 1 error (unreadable input, ...), 2 bad command line.
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


def interpolate_background(d):
    """The KITTI devkit's background interpolation (d < 0 = missing): in each row a gap with valid pixels on both
    sides takes the smaller of the two; row ends copy the nearest valid value; then columns are extrapolated to the
    top and bottom."""
    d = d.copy()
    H, W = d.shape
    for y in range(H):
        r = d[y]
        valid = np.flatnonzero(r >= 0)
        if valid.size == 0:
            continue
        for a, b in zip(valid[:-1], valid[1:]):
            if b > a + 1:
                r[a + 1:b] = min(r[a], r[b])
        r[:valid[0]] = r[valid[0]]
        r[valid[-1] + 1:] = r[valid[-1]]
    for x in range(W):
        c = d[:, x]
        valid = np.flatnonzero(c >= 0)
        if valid.size:
            c[:valid[0]] = c[valid[0]]
            c[valid[-1] + 1:] = c[valid[-1]]
    return d


def d1_outliers(est, gt):
    err = np.abs(est - gt)
    return (err > 3) & (err > 0.05 * gt)


def evaluate(est, gt):
    """Coverage, covered D1 and total D1 in percent (KITTI devkit rules); est and gt use -1 for "none"."""
    has_gt = gt >= 0
    has_est = has_gt & (est >= 0)
    n_gt, n_est = int(has_gt.sum()), int(has_est.sum())
    covered_bad = int((d1_outliers(est, gt) & has_est).sum())
    total_bad = int((d1_outliers(interpolate_background(est), gt) & has_gt).sum())
    return 100.0 * n_est / n_gt, 100.0 * covered_bad / max(n_est, 1), 100.0 * total_bad / n_gt


def kitti_colours(d, max_disp):
    """The KITTI devkit's disparity colour map; d < 0 is black. Returns BGR uint8."""
    ramp = np.array([[0, 0, 0, 114], [0, 0, 1, 185], [1, 0, 0, 114], [1, 0, 1, 174],
                     [0, 1, 0, 114], [0, 1, 1, 185], [1, 1, 0, 114], [1, 1, 1, 0]], np.float64)
    bounds = np.concatenate([[0], np.cumsum(ramp[:7, 3]) / ramp[:7, 3].sum()])
    v = np.clip(d / max_disp, 0, 1)
    i = np.clip(np.searchsorted(bounds, v, side="right") - 1, 0, 6)
    w = 1 - (v - bounds[i]) / (bounds[i + 1] - bounds[i])
    rgb = w[..., None] * ramp[i, :3] + (1 - w[..., None]) * ramp[i + 1, :3]
    out = np.clip(np.rint(rgb[..., ::-1] * 255), 0, 255).astype(np.uint8)
    out[~(d >= 0)] = 0
    return out


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--kitti-frame", required=True, help="KITTI-layout folder (image_2, image_3, velodyne, calib.txt)")
    p.add_argument("--id", default="000002")
    p.add_argument("--mode", choices=sorted(MODES), default="sdsgm")
    p.add_argument("--check", choices=sorted(CHECKS), default="stereo-lidar")
    p.add_argument("--num-disparities", type=int, default=128)
    p.add_argument("--out", help="folder for disparity.png, disparity_color.png, lidar_points.png")
    p.add_argument("--cuda", action="store_true", help="run on the GPU (cv2.cuda_GpuMat in and out)")
    args = p.parse_args(argv)

    root, fid = args.kitti_frame, args.id
    try:
        left = read_grey(os.path.join(root, "image_2", fid + "_10.png"))
        right = read_grey(os.path.join(root, "image_3", fid + "_10.png"))
        P2, lidar_to_cam, fb = read_calib(os.path.join(root, "calib.txt"))
        scan_path = os.path.join(root, "velodyne", fid + ".bin")
        if not os.path.isfile(scan_path):
            raise IOError("cannot open Velodyne scan " + scan_path)
        points = np.fromfile(scan_path, dtype=np.float32).reshape(-1, 4)
        h, w = left.shape
        sparse = cv.lidarsgm.projectPointsToDisparity(points, P2, lidar_to_cam, fb, (w, h))

        sgm = cv.lidarsgm.StereoLidarSGM.create(0, args.num_disparities, 10, 120, 5, 160, 0.7,
                                                MODES[args.mode], CHECKS[args.check])
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

    disp = disp16.astype(np.float32) / 16
    disp[disp16 <= -16] = -1  # invalid = (minDisparity - 1) * 16
    line = "%s %-6s check %-12s %s %8.1f ms" % (fid, args.mode.upper(), args.check, "CUDA" if args.cuda else "CPU ", ms)
    gt_png = cv.imread(os.path.join(root, "disp_occ_0", fid + "_10.png"), cv.IMREAD_UNCHANGED)
    if gt_png is not None:
        gt = gt_png.astype(np.float32) / 256
        gt[gt_png == 0] = -1
        cov, covered, total = evaluate(disp, gt)
        line += "  coverage %6.2f %%  covered D1 %5.2f %%  total D1 %5.2f %%" % (cov, covered, total)
    print(line)

    if args.out:
        os.makedirs(args.out, exist_ok=True)
        png = np.where(disp > 0, np.maximum(np.floor(disp * 256 + 0.5), 1), 0).astype(np.uint16)
        cv.imwrite(os.path.join(args.out, "disparity.png"), png)
        cv.imwrite(os.path.join(args.out, "disparity_color.png"), kitti_colours(disp, args.num_disparities))
        overlay = cv.cvtColor(left, cv.COLOR_GRAY2BGR)
        ys, xs = np.nonzero(sparse > 0)
        order = np.argsort(sparse[ys, xs])  # nearest points drawn last
        colours = kitti_colours(sparse[ys, xs][order][None, :], args.num_disparities)[0]
        for (y, x), c in zip(zip(ys[order], xs[order]), colours):
            overlay[max(y - 1, 0):y + 2, max(x - 1, 0):x + 2] = c
        cv.imwrite(os.path.join(args.out, "lidar_points.png"), overlay)
        print("wrote %s/disparity.png, disparity_color.png, lidar_points.png" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
