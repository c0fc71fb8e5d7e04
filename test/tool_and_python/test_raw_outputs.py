#!/usr/bin/env python3
"""KITTI raw drives in, metric depth and point clouds out: the tool's --kitti-raw and --format depth,ply, and the
module's disparityToDepth / disparityToPoints, checked as a robotics user would use them. The raw drive is made from
the shipped KITTI frames by tools/make_raw_drive.sh (the calibration in the raw files' format); the PLY is read with
plyfile.

Environment (set by ctest): LIDARSGM_TOOL (the tool binary), LIDARSGM_TESTDATA (testdata/), PYTHONPATH with cv2.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import cv2 as cv
from plyfile import PlyData

TOOL = os.environ.get("LIDARSGM_TOOL", "")
DATA = os.environ.get("LIDARSGM_TESTDATA", os.path.join(os.path.dirname(__file__), "..", "..", "testdata"))
KITTI = os.path.join(DATA, "kitti")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
FRAMES = {"0000000000": "000002", "0000000001": "000046"}   # raw frame name: KITTI 2015 frame (make_raw_drive.sh)


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, timeout=600)
    return p.returncode, p.stdout, p.stderr


def d1_outliers(d, gt):
    """KITTI D1: more than 3 px and more than 5 % off."""
    err = np.abs(d - gt)
    return (err > 3) & (err > 0.05 * gt)


class RawDriveTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="lidarsgm_raw_")
        calib = cv.lidarsgm.readKittiCalibration(os.path.join(KITTI, "calib.txt"))
        self.P2, self.fb = calib.projection, calib.focalBaseline
        # <date>/<date>_drive_0001_sync/{image_02,image_03,velodyne_points}/data, calibration files in <date>/,
        # made from testdata/kitti (the script reads the repository's testdata: the same frames as KITTI here).
        p = subprocess.run(["bash", os.path.join(ROOT, "tools", "make_raw_drive.sh"), self.tmp],
                           stdout=subprocess.PIPE, universal_newlines=True, check=True)
        self.drive = p.stdout.strip()
        self.date = os.path.dirname(self.drive)
        self.assertEqual(os.path.join(self.tmp, "2011_09_26", "2011_09_26_drive_0001_sync"), self.drive)
        # The ground truth as KITTI depth (metres x 256), the depth-completion set's format.
        self.gt_depth = os.path.join(self.tmp, "groundtruth")
        os.makedirs(self.gt_depth)
        for name, fid in FRAMES.items():
            gt = cv.imread(os.path.join(KITTI, "disp_occ_0", fid + "_10.png"), cv.IMREAD_UNCHANGED)
            depth = np.zeros(gt.shape, np.uint16)
            depth[gt > 0] = np.round(self.fb / (gt[gt > 0] / 256.0) * 256.0).astype(np.uint16)
            cv.imwrite(os.path.join(self.gt_depth, name + ".png"), depth)

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    @unittest.skipUnless(os.path.isfile(TOOL), "LIDARSGM_TOOL does not name the tool binary")
    def test_raw_drive_depth_and_ply(self):
        out = os.path.join(self.tmp, "out")
        rc, so, se = run([TOOL, "--kitti-raw", self.drive, "--out", out, "--modes", "sdsgm",
                          "--format", "kitti,depth,ply"])
        self.assertEqual(rc, 0, se)
        self.assertIn("[2/2] frames", se)
        self.assertIn("frames: 2 computed, 0 taken from earlier runs (--resume), 0 failed", so)
        self.assertRegex(so, r"KITTI raw .*: 2 frames, no ground truth")
        self.assertRegex(so, r"\| SDSGM \(stereo-lidar\) +\| +[\d.]+ \|")
        # The same frames as a KITTI-layout folder: the raw calibration gives the same disparity files, and the
        # table's covered D1 for the PLY check below.
        ref = os.path.join(self.tmp, "ref")
        rc, so_ref, se = run([TOOL, "--kitti", KITTI, "--out", ref, "--modes", "sdsgm"])
        self.assertEqual(rc, 0, se)
        covered = float(re.search(r"\| SDSGM \(stereo-lidar\) +\| +[\d.]+ % \| +([\d.]+) %", so_ref).group(1))
        f, cx, cy = self.P2[0, 0], self.P2[0, 2], self.P2[1, 2]
        outliers = estimated = 0
        for name, fid in FRAMES.items():
            with open(os.path.join(out, name, "disparity_sdsgm.png"), "rb") as a, \
                 open(os.path.join(ref, fid, "disparity_sdsgm.png"), "rb") as b:
                self.assertEqual(a.read(), b.read(), name)
            disp = cv.imread(os.path.join(out, name, "disparity_sdsgm.png"), cv.IMREAD_UNCHANGED) / 256.0
            valid = disp > 0
            # Depth PNG: metres x 256, 0 where the disparity is invalid; back to disparity within 1/16 px, or within
            # KITTI depth's own rounding (1/512 m) where that is coarser (disparities above ~111 px).
            depth = cv.imread(os.path.join(out, name, "depth_sdsgm.png"), cv.IMREAD_UNCHANGED)
            self.assertEqual(depth.dtype, np.uint16)
            # Depths beyond 65535 / 256 m (disparities below ~1.5 px here) do not fit and are written as none.
            fits = valid & (np.round(self.fb / np.where(valid, disp, 1) * 256) <= 65535)
            np.testing.assert_array_equal(depth > 0, fits)
            back = self.fb / (depth[fits] / 256.0)
            bound = np.maximum(1.0 / 16, disp[fits] ** 2 / (512 * self.fb) * 1.001)
            self.assertTrue(np.all(np.abs(back - disp[fits]) <= bound), np.max(np.abs(back - disp[fits]) - bound))
            # PLY: one vertex per valid pixel in row order, x y z in metres, the left image's colour.
            ply = PlyData.read(os.path.join(out, name, "points_sdsgm.ply"))
            v = ply["vertex"].data
            self.assertEqual(len(v), int(valid.sum()))
            ys, xs = np.nonzero(valid)
            d = disp[valid]
            z = self.fb / d
            np.testing.assert_allclose(v["z"], z, rtol=1e-5)
            np.testing.assert_allclose(v["x"], (xs - cx) * z / f, rtol=1e-5, atol=1e-5)
            np.testing.assert_allclose(v["y"], (ys - cy) * z / f, rtol=1e-5, atol=1e-5)
            bgr = cv.imread(os.path.join(KITTI, "image_2", fid + "_10.png"), cv.IMREAD_COLOR)
            np.testing.assert_array_equal(np.stack([v["blue"], v["green"], v["red"]], 1), bgr[valid])
            # The points of pixels with ground truth lie within D1 of its depth as often as the disparities do.
            gt = cv.imread(os.path.join(KITTI, "disp_occ_0", fid + "_10.png"), cv.IMREAD_UNCHANGED) / 256.0
            has = gt[valid] > 0
            back_d = np.round(self.fb / v["z"][has].astype(np.float64) * 16) / 16   # the 1/16-px grid of the output
            outliers += int(d1_outliers(back_d, gt[valid][has]).sum())
            estimated += int(has.sum())
        self.assertAlmostEqual(100.0 * outliers / estimated, covered, delta=0.005)

    @unittest.skipUnless(os.path.isfile(TOOL), "LIDARSGM_TOOL does not name the tool binary")
    def test_raw_drive_with_depth_ground_truth(self):
        rc, so, se = run([TOOL, "--kitti-raw", self.drive, "--gt-depth", self.gt_depth, "--modes", "sdsgm"])
        self.assertEqual(rc, 0, se)
        rc, so_ref, se = run([TOOL, "--kitti", KITTI, "--modes", "sdsgm"])
        self.assertEqual(rc, 0, se)
        row = r"\| SDSGM \(stereo-lidar\) +\| +([\d.]+) % \| +([\d.]+) % \| +([\d.]+) %"
        raw, ref = re.search(row, so), re.search(row, so_ref)
        self.assertIsNotNone(raw, so)
        # The same pixels carry ground truth (depth > 0 exactly where disparity > 0), so the coverage is the same.
        self.assertEqual(raw.group(1), ref.group(1))

    def test_raw_drive_calibration_refinement(self):
        # The drive pools its frames as the KITTI folder does: the same frames and calibration, the same correction.
        angles = r"pitch ([-+\d.]+) \+- [\d.]+, yaw ([-+\d.]+) \+- [\d.]+, roll ([-+\d.]+)"
        rc, so, se = run([TOOL, "--kitti-raw", self.drive, "--modes", "sdsgm", "--refine-calibration"])
        self.assertEqual(rc, 0, se)
        rc, so_ref, se = run([TOOL, "--kitti", KITTI, "--modes", "sdsgm", "--refine-calibration"])
        self.assertEqual(rc, 0, se)
        raw, ref = re.search(angles, so), re.search(angles, so_ref)
        self.assertIsNotNone(raw, so)
        self.assertIsNotNone(ref, so_ref)
        for k in (1, 2, 3):
            self.assertAlmostEqual(float(raw.group(k)), float(ref.group(k)), delta=0.002)
        self.assertIn("2 frames", so)

    @unittest.skipUnless(os.path.isfile(TOOL), "LIDARSGM_TOOL does not name the tool binary")
    def test_bad_raw_drives(self):
        out = os.path.join(self.tmp, "out")
        cmd = [TOOL, "--kitti-raw", self.drive, "--out", out, "--modes", "sdsgm", "--format", "depth,ply"]
        # A calibration key missing: the file and the key are named, nothing is computed.
        cam = os.path.join(self.date, "calib_cam_to_cam.txt")
        with open(cam) as fh:
            text = fh.read()
        with open(cam, "w") as fh:
            fh.write("\n".join(l for l in text.splitlines() if not l.startswith("R_rect_00")) + "\n")
        rc, so, se = run(cmd)
        self.assertEqual(rc, 1, se)
        self.assertIn("calibration file " + cam + " has no key R_rect_00", se)
        with open(cam, "w") as fh:
            fh.write(text)
        # An image missing and a scan that is not a whole number of points: those frames are skipped and listed,
        # the good frame's files are complete.
        second = os.path.join(self.drive, "image_03", "data", "0000000001.png")
        moved = second + ".away"
        os.rename(second, moved)
        rc, so, se = run(cmd)
        self.assertEqual(rc, 1, se)
        self.assertIn("frame 0000000001 skipped: cannot read image " + second, se)
        self.assertIn("frames: 1 computed, 0 taken from earlier runs (--resume), 1 failed", so)
        done = sorted(os.listdir(os.path.join(out, "0000000000")))
        self.assertIn("depth_sdsgm.png", done)
        self.assertIn("points_sdsgm.ply", done)
        self.assertIn("metrics.yml", done)
        os.rename(moved, second)
        scan = os.path.join(self.drive, "velodyne_points", "data", "0000000001.bin")
        with open(scan, "rb") as fh:
            whole = fh.read()
        with open(scan, "wb") as fh:
            fh.write(whole[:1001])
        rc, so, se = run(cmd + ["--resume"])
        self.assertEqual(rc, 1, se)
        self.assertIn("is not a whole number of 16-byte points", se)
        self.assertIn("frames: 0 computed, 1 taken from earlier runs (--resume), 1 failed", so)
        # Mended, --resume computes only the missing frame; nothing written earlier is lost or left partial.
        with open(scan, "wb") as fh:
            fh.write(whole)
        before = os.path.getmtime(os.path.join(out, "0000000000", "points_sdsgm.ply"))
        rc, so, se = run(cmd + ["--resume"])
        self.assertEqual(rc, 0, se)
        self.assertIn("frames: 1 computed, 1 taken from earlier runs (--resume), 0 failed", so)
        self.assertEqual(os.path.getmtime(os.path.join(out, "0000000000", "points_sdsgm.ply")), before)
        self.assertEqual([n for _, _, ns in os.walk(out) for n in ns if ".partial-" in n], [])
        # No drive at all, and depth asked of an input without calibration.
        rc, _, se = run([TOOL, "--kitti-raw", os.path.join(self.tmp, "nothing")])
        self.assertEqual(rc, 1)
        self.assertIn("calibration file", se)
        rc, _, se = run([TOOL, "--middlebury", DATA, "--format", "ply", "--out", os.path.join(self.tmp, "mb")])
        self.assertEqual(rc, 2)   # a bad command line
        self.assertIn("--format ply needs a calibration", se)
        # The consistency-check table needs ground truth: refused before any frame without --gt-depth.
        rc, _, se = run([TOOL, "--kitti-raw", self.drive, "--table5"])
        self.assertEqual(rc, 2)
        self.assertIn("--table5 scores each check against ground truth: with --kitti-raw give --gt-depth", se)


class DepthApiTest(unittest.TestCase):
    def test_depth_and_points_from_x16_disparity(self):
        fb = 389.0
        disp = np.array([[-16, 0, 16], [32 * 16, 1, 100 * 16 + 8]], np.int16)   # the matcher's x16 output
        depth = cv.lidarsgm.disparityToDepth(disp, fb)
        self.assertEqual(depth.dtype, np.float32)
        np.testing.assert_allclose(depth, [[0, 0, fb], [fb / 32, fb * 16, fb / 100.5]], rtol=1e-6)
        # minDisparity 2: its invalid code is 16; values below 2 px are invalid too.
        depth2 = cv.lidarsgm.disparityToDepth(disp, fb, minDisparity=2)
        np.testing.assert_allclose(depth2, [[0, 0, 0], [fb / 32, 0, fb / 100.5]], rtol=1e-6)
        P = np.array([[700.0, 0, 600, 45], [0, 700, 170, 0], [0, 0, 1, 0]])
        Q = cv.lidarsgm.reprojectionMatrix(P, fb)
        pts = cv.lidarsgm.disparityToPoints(disp, Q)
        self.assertEqual(pts.shape, (2, 3, 3))
        self.assertTrue(np.all(np.isnan(pts[0, :2])))
        z = fb / 100.5
        np.testing.assert_allclose(pts[1, 2], [(2 - 600) * z / 700, (1 - 170) * z / 700, z], rtol=1e-6)
        # cv::reprojectImageTo3D with the same Q on the disparity divided by 16 agrees on valid pixels.
        ref = cv.reprojectImageTo3D(disp.astype(np.float32) / 16, Q)
        np.testing.assert_allclose(pts[1, 2], ref[1, 2], rtol=1e-5)
        with self.assertRaisesRegex(cv.error, "focalBaseline must be positive"):
            cv.lidarsgm.disparityToDepth(disp, -1.0)
        with self.assertRaisesRegex(cv.error, "CV_16SC1 \\(x16\\) or CV_32FC1"):
            cv.lidarsgm.disparityToDepth(disp.astype(np.int32), fb)


if __name__ == "__main__":
    unittest.main()
