#!/usr/bin/env python3
"""A user's own rig made from KITTI frames, and what the module makes of it (cv2.lidarsgm.StereoRig).

  PYTHONPATH=<opencv build>/python_loader python3 tools/unrectified_rig.py [--lines 64,16] [--keep DIR] [KITTI dir]

Each KITTI frame (default: the 20 shared frames) is un-rectified: both cameras are turned by about a degree (R1, R2)
and given radial / tangential distortion (k1 -0.2), so that StereoRig's rectification with those R1, R2, P1 = P2_kitti
and P2 (P1 shifted by f B) gives back KITTI's rectified view. Each raw pixel takes the KITTI image at the rectified
position cv2.undistortPoints gives it (bilinear). The rig is written as one cv::FileStorage file with OpenCV's
stereo_calib names (M1 D1 M2 D2 R T R1 R2 P1 P2, image_width, image_height, lidar_to_left: the LiDAR to the raw left
camera) and as ROS camera_calibration's two files; each frame's scan as PCD (pypcd4; ascii, binary and
binary_compressed in turn) and PLY (plyfile). The fusion then runs as a user would: StereoRig.fromFile or fromRos,
rectify, readPointCloud, projectCloud, compute (doc/params/kitti_best.yml, SDSGM) and is scored in the rectified view
against disp_occ_0, beside the KITTI frames themselves, and beside the KITTI frames passed through the un-rectification
and the rig's rectification alone (cv2.remap twice, KITTI's own sparse map): that last run measures what the two
resamplings of the images cost. --keep DIR leaves the rig folder (rig.yml, ros/, left/, right/, points/ with the
whole scans, gt/) there, as the tool's --rig-folder reads it.
"""
import os
import shutil
import sys
import tempfile

import numpy as np
import cv2 as cv

HERE = os.path.dirname(os.path.abspath(__file__))
BEST = os.path.join(HERE, "..", "doc", "params", "kitti_best.yml")


def rotation(rx, ry, rz):
    return cv.Rodrigues(np.array([rx, ry, rz], np.float64))[0]


def rig_of(calib, size):
    """The raw rig whose rectification gives KITTI's view: (M1, D1, M2, D2, R, T, R1, R2, P1, P2, lidar_to_left)."""
    P1 = np.asarray(calib.projection, np.float64)
    fB = calib.focalBaseline
    P2 = P1.copy()
    P2[0, 3] -= fB
    K = P1[:, :3].copy()
    M1, M2 = K.copy(), K.copy()
    M2[0, 2] += 3.0   # the right camera's own principal point
    D1 = np.array([[-0.2, 0.05, 0.001, -0.0005, 0.0]])
    D2 = np.array([[-0.18, 0.04, -0.001, 0.0005, 0.0]])
    R1 = rotation(0.012, -0.015, 0.008)    # about a degree in all
    R2 = rotation(-0.010, 0.012, -0.006)
    # Rectified right = rectified left + (-B, 0, 0); raw = R_i^T rectified.
    t = np.array([[-fB / K[0, 0]], [0.0], [0.0]])
    R = R2.T @ R1
    T = R2.T @ t
    lidar_to_left = np.eye(4)
    lidar_to_left[:3, :3] = R1.T
    lidar_to_left = lidar_to_left @ np.asarray(calib.lidarToCamera, np.float64)
    return M1, D1, M2, D2, R, T, R1, R2, P1, P2, lidar_to_left


def unrectify(img, M, D, Rr, P, size):
    """The raw image whose rectification (M, D, Rr, P) is img: each raw pixel samples img where it rectifies to."""
    w, h = size
    xs, ys = np.meshgrid(np.arange(w, dtype=np.float64), np.arange(h, dtype=np.float64))
    pts = np.stack([xs.ravel(), ys.ravel()], 1).reshape(-1, 1, 2)
    criteria = (cv.TERM_CRITERIA_COUNT | cv.TERM_CRITERIA_EPS, 50, 1e-9)
    if hasattr(cv, "undistortPointsIter"):   # OpenCV 4: the iterations' criteria are undistortPointsIter's
        rect = cv.undistortPointsIter(pts, M, D, Rr, P, criteria)
    else:
        rect = cv.undistortPoints(pts, M, D, R=Rr, P=P, criteria=criteria)
    rect = rect.reshape(h, w, 2).astype(np.float32)
    return cv.remap(img, rect[..., 0], rect[..., 1], cv.INTER_LINEAR, borderMode=cv.BORDER_CONSTANT)


def write_rig(path, rig, size):
    """rig_of's rig as one cv::FileStorage file: the stereo_calib sample's names, the image size, lidar_to_left."""
    fs = cv.FileStorage(path, cv.FILE_STORAGE_WRITE)
    fs.write("image_width", size[0])
    fs.write("image_height", size[1])
    for k, v in zip(("M1", "D1", "M2", "D2", "R", "T", "R1", "R2", "P1", "P2", "lidar_to_left"), rig):
        fs.write(k, np.asarray(v, np.float64))
    fs.release()


def write_ros(path, M, D, Rr, P, size):
    def data(m):
        return "[" + ", ".join("%.17g" % v for v in np.asarray(m, np.float64).ravel()) + "]"
    with open(path, "w") as f:
        f.write("image_width: %d\nimage_height: %d\ncamera_name: %s\n" % (size[0], size[1], os.path.basename(path)))
        f.write("camera_matrix:\n  rows: 3\n  cols: 3\n  data: %s\n" % data(M))
        f.write("distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: %s\n" % data(D))
        f.write("rectification_matrix:\n  rows: 3\n  cols: 3\n  data: %s\n" % data(Rr))
        f.write("projection_matrix:\n  rows: 3\n  cols: 4\n  data: %s\n" % data(P))


def write_cloud(points, stem, k):
    """points N x 4 float32 as PCD (the k-th DATA kind) and PLY; returns both paths."""
    import pypcd4
    import plyfile
    kinds = ["ascii", "binary", "binary_compressed"]
    pc = pypcd4.PointCloud.from_points(points.astype(np.float32), ["x", "y", "z", "intensity"],
                                       [np.float32] * 4)
    pc.save(stem + ".pcd", encoding=pypcd4.Encoding(kinds[k % 3]))
    v = np.empty(len(points), dtype=[("x", "f4"), ("y", "f4"), ("z", "f4"), ("intensity", "f4")])
    for i, n in enumerate(["x", "y", "z", "intensity"]):
        v[n] = points[:, i]
    plyfile.PlyData([plyfile.PlyElement.describe(v, "vertex")]).write(stem + ".ply")
    return stem + ".pcd", stem + ".ply"


def score(disp16, gt):
    """(total outliers, ground-truth pixels, estimated pixels): the KITTI devkit's D1 (evaluateDisparity), missing
    estimates filled by background interpolation, as the tool's folder runs score."""
    e = cv.lidarsgm.evaluateDisparity(disp16, gt)
    return e.totalOutliers, e.groundTruthPixels, e.estimatedPixels


def main():
    args = [a for a in sys.argv[1:]]
    lines = [64, 16]
    keep = None
    if "--lines" in args:
        i = args.index("--lines")
        lines = [int(v) for v in args[i + 1].split(",")]
        del args[i:i + 2]
    if "--keep" in args:
        i = args.index("--keep")
        keep = args[i + 1]
        del args[i:i + 2]
    kitti = args[0] if args else os.path.join(HERE, "..", "..", "shared", "data", "kitti2015_lidar")
    work = keep or tempfile.mkdtemp(prefix="lidarsgm_rig_")
    for sub in ("left", "right", "points", "gt", "ros"):
        os.makedirs(os.path.join(work, sub), exist_ok=True)
    cv.setNumThreads(2)
    ids = cv.lidarsgm.readKittiFrameIds(kitti)
    m = cv.lidarsgm.StereoLidarSGM.load(BEST)
    print("un-rectified rig from %d KITTI frames (%s), kitti_best.yml, SDSGM; total D1 (coverage) in the rectified "
          "left view against disp_occ_0" % (len(ids), kitti))
    print("| lines | KITTI frames | remap alone (two resamplings) | rig.yml + PCD | ROS files + PLY |")
    print("|---|---|---|---|---|")
    for nl in lines:
        every = 64 // nl
        sums = {k: [0, 0, 0] for k in ("kitti", "remap", "file", "ros")}
        for n, i in enumerate(ids):
            f = cv.lidarsgm.loadKittiFrame(kitti, i, every, 0)
            size = (f.left.shape[1], f.left.shape[0])
            M1, D1, M2, D2, R, T, R1, R2, P1, P2, l2l = rig_of(f.calibration, size)
            rawL = unrectify(f.left, M1, D1, R1, P1[:, :3], size)
            rawR = unrectify(f.right, M2, D2, R2, P2[:, :3], size)
            cv.imwrite(os.path.join(work, "left", i + ".png"), rawL)
            cv.imwrite(os.path.join(work, "right", i + ".png"), rawR)
            cv.imwrite(os.path.join(work, "gt", i + ".png"), cv.lidarsgm.encodeKittiDisparity(f.groundTruth))
            if n == 0:
                write_rig(os.path.join(work, "rig.yml"), (M1, D1, M2, D2, R, T, R1, R2, P1, P2, l2l), size)
                write_ros(os.path.join(work, "ros", "left.yaml"), M1, D1, R1, P1, size)
                write_ros(os.path.join(work, "ros", "right.yaml"), M2, D2, R2, P2, size)
                np.savetxt(os.path.join(work, "ros", "lidar_to_left.txt"), l2l)
            # The whole scan in the LiDAR's own frame and the driver's order; the rings are kept after reading, as the
            # tool's --rig-folder --lidar-lines does.
            scan = cv.lidarsgm.readVelodyneScan(os.path.join(kitti, "velodyne", i + ".bin"))
            pcd, ply = write_cloud(scan, os.path.join(work, "points", i), n)
            gt_back = cv.lidarsgm.readKittiDisparity(os.path.join(work, "gt", i + ".png"))
            runs = {"kitti": (f.left, f.right, f.sparse)}
            rig = cv.lidarsgm.StereoRig.fromFile(os.path.join(work, "rig.yml"))
            l, r = rig.rectify(cv.imread(os.path.join(work, "left", i + ".png"), cv.IMREAD_GRAYSCALE),
                               cv.imread(os.path.join(work, "right", i + ".png"), cv.IMREAD_GRAYSCALE))
            runs["remap"] = (l, r, f.sparse)
            runs["file"] = (l, r, rig.projectCloud(cv.lidarsgm.selectLidarRings(cv.lidarsgm.readPointCloud(pcd), every,
                                                                                 0)))
            ros = cv.lidarsgm.StereoRig.fromRos(os.path.join(work, "ros", "left.yaml"),
                                                os.path.join(work, "ros", "right.yaml"), l2l)
            l2, r2 = ros.rectify(cv.imread(os.path.join(work, "left", i + ".png"), cv.IMREAD_GRAYSCALE),
                                 cv.imread(os.path.join(work, "right", i + ".png"), cv.IMREAD_GRAYSCALE))
            runs["ros"] = (l2, r2, ros.projectCloud(cv.lidarsgm.selectLidarRings(cv.lidarsgm.readPointCloud(ply), every,
                                                                                0)))
            for k, (a, b, s) in runs.items():
                e, g, c = score(m.compute(a, b, s), gt_back)
                sums[k][0] += e
                sums[k][1] += g
                sums[k][2] += c
        cell = {k: "%.2f %% (%.2f %%)" % (100.0 * v[0] / v[1], 100.0 * v[2] / v[1]) for k, v in sums.items()}
        print("| %d | %s | %s | %s | %s |" % (nl, cell["kitti"], cell["remap"], cell["file"], cell["ros"]))
    if keep is None:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
