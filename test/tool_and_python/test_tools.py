#!/usr/bin/env python3
"""The command-line tool (lidarsgm_fuse) and the Python sample (samples/python/lidarsgm_fuse.py), run as a
user runs them: outputs, formats, summary tables, progress, exit codes and messages on bad input.

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

TOOL = os.environ.get("LIDARSGM_TOOL", "")
DATA = os.environ.get("LIDARSGM_TESTDATA", os.path.join(os.path.dirname(__file__), "..", "..", "testdata"))
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SAMPLE = os.path.join(ROOT, "samples", "python", "lidarsgm_fuse.py")
BEST = os.path.join(ROOT, "doc", "params", "kitti_best.yml")
KITTI = os.path.join(DATA, "kitti")
METRICS = re.compile(r"coverage +([\d.]+) %  covered D1 +([\d.]+) %  total D1 +([\d.]+) %")


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, timeout=600)
    return p.returncode, p.stdout, p.stderr


@unittest.skipUnless(os.path.isfile(TOOL), "LIDARSGM_TOOL does not name the tool binary")
class ToolTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="lidarsgm_tool_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def kitti_folder(self, frames):
        """A copy of the test frames' KITTI folder whose frames.txt lists frames."""
        kitti = os.path.join(self.tmp, "kitti")
        shutil.copytree(KITTI, kitti)
        with open(os.path.join(kitti, "frames.txt"), "w") as f:
            f.write(frames)
        return kitti

    def test_frame_outputs_and_formats(self):
        out = os.path.join(self.tmp, "out")
        rc, so, se = run([TOOL, "--kitti-frame", KITTI, "--id", "000002", "--out", out, "--format", "kitti,pfm,s16"])
        self.assertEqual(rc, 0, se)
        m = METRICS.search(so)
        self.assertIsNotNone(m, so)
        for name in ["disparity.png", "disparity.pfm", "disparity.s16", "disparity_color.png", "error.png",
                     "lidar_points.png", "semidense.png", "semidense_color.png"]:
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
        png = cv.imread(os.path.join(out, "disparity.png"), cv.IMREAD_UNCHANGED)
        pfm = cv.imread(os.path.join(out, "disparity.pfm"), cv.IMREAD_UNCHANGED)
        s16 = np.fromfile(os.path.join(out, "disparity.s16"), dtype="<i2").reshape(png.shape)
        self.assertEqual(png.dtype, np.uint16)
        self.assertEqual(pfm.dtype, np.float32)
        valid = s16 > -16
        # The three formats hold the same map: x16 integers, pixels, x256 (0 and inf = invalid).
        np.testing.assert_array_equal(png[valid], s16[valid].astype(np.uint16) * 16 * (s16[valid] > 0))
        np.testing.assert_array_equal(pfm[valid], s16[valid] / 16.0)
        self.assertTrue(np.all(np.isinf(pfm[~valid])))
        self.assertTrue(np.all(png[~valid] == 0))
        # The error picture is black exactly where there is no ground truth.
        gt = cv.imread(os.path.join(KITTI, "disp_occ_0", "000002_10.png"), cv.IMREAD_UNCHANGED)
        err = cv.imread(os.path.join(out, "error.png"))[:gt.shape[0]]   # the frame, above its legend
        self.assertTrue(np.all(err[gt == 0] == 0))
        self.assertTrue(np.all(err[gt > 0].max(axis=1) > 0))

    def test_confidence_format(self):
        # The confidence map as a 16-bit PNG beside the disparity, in single-frame and folder runs: 0 exactly where
        # the disparity has none; the disparity itself the same as without it.
        out, plain = os.path.join(self.tmp, "conf"), os.path.join(self.tmp, "plain")
        rc, so, se = run([TOOL, "--kitti-frame", KITTI, "--id", "000046", "--out", out, "--format",
                          "kitti,pfm,confidence"])
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"confidence of SDSGM \(stereo-lidar\), frame 000046: the 10 % least confident hold "
                             r"[\d.]+ % of the D1 outliers; AUC [\d.]+ \(oracle [\d.]+")
        rc, _, se = run([TOOL, "--kitti-frame", KITTI, "--id", "000046", "--out", plain])
        self.assertEqual(rc, 0, se)
        conf = cv.imread(os.path.join(out, "confidence.png"), cv.IMREAD_UNCHANGED)
        disp = cv.imread(os.path.join(out, "disparity.png"), cv.IMREAD_UNCHANGED)
        self.assertEqual(conf.dtype, np.uint16)
        np.testing.assert_array_equal(disp, cv.imread(os.path.join(plain, "disparity.png"), cv.IMREAD_UNCHANGED))
        pfm = cv.imread(os.path.join(out, "disparity.pfm"), cv.IMREAD_UNCHANGED)   # inf = no disparity
        np.testing.assert_array_equal(conf == 0, np.isinf(pfm))
        self.assertEqual(conf.max(), 65535)   # both tests confirm most pixels, on flat ground
        kitti = self.kitti_folder("000002\n")
        folder = os.path.join(self.tmp, "folder")
        rc, so, se = run([TOOL, "--kitti", kitti, "--out", folder, "--modes", "sdsgm", "--format", "confidence"])
        self.assertEqual(rc, 0, se)
        self.assertIn("confidence of SDSGM (stereo-lidar), 1 computed frames", so)
        self.assertTrue(os.path.isfile(os.path.join(folder, "000002", "confidence_sdsgm.png")))

    def test_folder_summary_and_progress(self):
        kitti = self.kitti_folder("000002\n000046\n")
        out = os.path.join(self.tmp, "out")
        rc, so, se = run([TOOL, "--kitti", kitti, "--out", out, "--modes", "dsgm,sdsgm"])
        self.assertEqual(rc, 0, se)
        self.assertIn("[2/2] frames", se)
        self.assertRegex(so, r"\| DSGM \(stereo-lidar\) +\| +[\d.]+ % \| +[\d.]+ % \| +[\d.]+ % \| +[\d.]+ \|")
        self.assertRegex(so, r"\| SDSGM \(stereo-lidar\) +\| +[\d.]+ % \| +[\d.]+ % \| +[\d.]+ % \| +[\d.]+ \|")
        for fid in ["000002", "000046"]:
            for name in ["disparity_dsgm.png", "disparity_sdsgm_color.png", "error_sdsgm.png", "lidar_points.png",
                         "semidense_color.png"]:
                self.assertTrue(os.path.isfile(os.path.join(out, fid, name)), fid + "/" + name)
        # A one-frame folder gives the single-frame run's numbers (same matcher, same evaluator).
        with open(os.path.join(kitti, "frames.txt"), "w") as f:
            f.write("000046\n")
        rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sdsgm", "--quiet"])
        self.assertEqual(rc, 0, se)
        row = re.search(r"\| SDSGM \(stereo-lidar\) +\| +([\d.]+) % \| +([\d.]+) % \| +([\d.]+) %", so)
        rc, so1, _ = run([TOOL, "--kitti-frame", KITTI, "--id", "000046"])
        self.assertEqual(rc, 0)
        self.assertEqual(row.groups(), METRICS.search(so1).groups())

    def test_folder_workers(self):
        # --streams 3: three workers on their own threads (more than frames); the same files and table as one.
        kitti = self.kitti_folder("000002\n000046\n")
        outs, tables = [], []
        rows = r"\| ([A-Za-z][^|]*?) +\| +([\d.]+) % \| +([\d.]+) % \| +([\d.]+|-) %?"
        for streams in ["1", "3"]:
            outs.append(os.path.join(self.tmp, "out" + streams))
            rc, so, se = run([TOOL, "--kitti", kitti, "--out", outs[-1], "--modes", "sgm,sdsgm", "--table5",
                              "--streams", streams, "--threads", "1"])
            self.assertEqual(rc, 0, se)
            self.assertIn("[2/2] frames", se)
            self.assertIn("frames: 2 computed, 0 taken from earlier runs (--resume), 0 failed", so)
            tables.append(re.findall(rows, so))
        self.assertEqual(len(tables[0]), 8)
        self.assertEqual(tables[0], tables[1])
        for fid in ["000002", "000046"]:
            names = sorted(os.listdir(os.path.join(outs[0], fid)))
            self.assertEqual(names, sorted(os.listdir(os.path.join(outs[1], fid))))
            for name in names:
                if name != "metrics.yml":
                    with open(os.path.join(outs[0], fid, name), "rb") as a, \
                         open(os.path.join(outs[1], fid, name), "rb") as b:
                        self.assertEqual(a.read(), b.read(), fid + "/" + name)
        rc, _, se = run([TOOL, "--kitti", kitti, "--streams", "0"])
        self.assertEqual(rc, 2)
        self.assertIn("--streams takes 1 to 64 workers, got 0", se)
        # GPU workers: the same table where there is a CUDA device; without one, the reason and exit 1, no abort.
        rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sgm,sdsgm", "--table5", "--cuda", "--streams", "2",
                          "--quiet"])
        if rc == 0:
            self.assertEqual(re.findall(rows, so), tables[0])
        else:
            self.assertEqual(rc, 1, se)
            self.assertIn("lidarsgm_fuse: error: ", se)

    def test_folder_bad_frame_partial_files_and_resume(self):
        kitti = self.kitti_folder("000002\n000046\n")
        scan = os.path.join(kitti, "velodyne", "000046.bin")
        with open(scan, "rb") as f:
            whole = f.read()
        with open(scan, "wb") as f:
            f.write(whole[:1000])  # a truncated scan
        out = os.path.join(self.tmp, "out")
        cmd = [TOOL, "--kitti", kitti, "--out", out, "--modes", "sdsgm"]
        # The bad frame is reported with its file and reason, skipped; the run goes on and ends with 1 and the list.
        rc, so, se = run(cmd)
        self.assertEqual(rc, 1, se)
        self.assertIn("frame 000046 skipped: Velodyne scan " + scan + " is not a whole number of 16-byte points", se)
        self.assertIn("1 frame(s) failed:\n  000046: Velodyne scan", se)
        self.assertIn("frames: 1 computed, 0 taken from earlier runs (--resume), 1 failed", so)
        self.assertIn(": 1 frames,", so)
        self.assertTrue(os.path.isfile(os.path.join(out, "000002", "metrics.yml")))
        self.assertFalse(os.path.exists(os.path.join(out, "000046", "metrics.yml")))
        # A run killed mid-frame: a truncated output under its final name and a partial file, no metrics.yml.
        with open(scan, "wb") as f:
            f.write(whole)
        os.makedirs(os.path.join(out, "000046"), exist_ok=True)
        with open(os.path.join(out, "000046", "disparity_sdsgm.png"), "wb") as f:
            f.write(b"\x89PNG\r\n")
        with open(os.path.join(out, "000046", ".semidense.partial-1234.png"), "wb") as f:
            f.write(b"\x89PNG")
        done_before = os.path.getmtime(os.path.join(out, "000002", "metrics.yml"))
        rc, so, se = run(cmd + ["--resume"])
        self.assertEqual(rc, 0, se)
        self.assertIn("frames: 1 computed, 1 taken from earlier runs (--resume), 0 failed", so)
        self.assertEqual(os.path.getmtime(os.path.join(out, "000002", "metrics.yml")), done_before)
        leftovers = [n for _, _, names in os.walk(out) for n in names if ".partial-" in n]
        self.assertEqual(leftovers, [])
        # The resumed run's table and files equal a run from scratch.
        fresh = os.path.join(self.tmp, "fresh")
        rc, so_fresh, se = run([TOOL, "--kitti", kitti, "--out", fresh, "--modes", "sdsgm"])
        self.assertEqual(rc, 0, se)
        rows = r"\| (SDSGM \(stereo-lidar\)|LiDAR points alone|semidense map[^|]*) +\| +([\d.]+) % \| +([\d.]+) %"
        self.assertEqual(re.findall(rows, so), re.findall(rows, so_fresh))
        for fid in ["000002", "000046"]:
            for name in sorted(os.listdir(os.path.join(fresh, fid))):
                if name != "metrics.yml":
                    with open(os.path.join(out, fid, name), "rb") as a, open(os.path.join(fresh, fid, name), "rb") as b:
                        self.assertEqual(a.read(), b.read(), fid + "/" + name)
        # Frames finished with other options are not taken.
        rc, so, se = run([TOOL, "--kitti", kitti, "--out", out, "--modes", "dsgm", "--resume"])
        self.assertEqual(rc, 1)
        self.assertIn("metrics.yml was written with other options", se)
        # A frame of an earlier version of the tool, without the frame's LiDAR check: not taken, and said so.
        metrics = os.path.join(out, "000002", "metrics.yml")
        with open(metrics) as f:
            text = f.read()
        with open(metrics, "w") as f:
            f.write("".join(l for l in text.splitlines(True) if not l.startswith(("misplaced", "stereoAlone"))))
        rc, so, se = run(cmd + ["--resume"])
        self.assertEqual(rc, 1)
        self.assertIn("000002/metrics.yml was written by an earlier version of the tool, without the frame's LiDAR "
                      "check (rerun without --resume", se)

    def test_middlebury_folder(self):
        rc, so, se = run([TOOL, "--middlebury", os.path.join(DATA, "middlebury"), "--modes", "sgm,sdsgm", "--quiet"])
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"\| cone +\| +\d+ \| SDSGM ")
        self.assertRegex(so, r"\| SDSGM \(stereo-lidar\) +\| +[\d.]+ % \| +[\d.]+ % \| +[\d.]+ % \| +[\d.]+ \|")
        self.assertNotIn("frames/s", se)

    def test_params_file_and_overrides(self):
        # --params loads a saved matcher; options given beside it override its values.
        frame = [TOOL, "--kitti-frame", KITTI, "--id", "000046"]
        rc, best, se = run(frame + ["--params", BEST])
        self.assertEqual(rc, 0, se)
        rc, same, se = run(frame + ["--visibility-rx", "2", "--visibility-ry", "4", "--visibility-parallax", "0.18",
                                    "--edge-threshold", "32", "--ring-gap-factor", "2", "--semidense-weight", "0.5",
                                    "--search-window", "4"])
        self.assertEqual(rc, 0, se)
        self.assertEqual(METRICS.search(best).groups(), METRICS.search(same).groups())
        rc, over, se = run(frame + ["--params", BEST, "--edge-threshold", "0"])
        self.assertEqual(rc, 0, se)
        rc, ref, se = run(frame + ["--visibility-rx", "2", "--visibility-ry", "4", "--visibility-parallax", "0.18",
                                   "--ring-gap-factor", "2", "--semidense-weight", "0.5", "--search-window", "4"])
        self.assertEqual(METRICS.search(over).groups(), METRICS.search(ref).groups())
        self.assertNotEqual(METRICS.search(over).groups(), METRICS.search(best).groups())
        # A value out of range in the file is refused with the parameter's name.
        bad = os.path.join(self.tmp, "bad.yml")
        with open(BEST) as f, open(bad, "w") as g:
            g.write(f.read().replace("numPaths: 8", "numPaths: 6"))
        rc, so, se = run(frame + ["--params", bad])
        self.assertEqual(rc, 1)
        self.assertIn("numPaths", se)

    def test_lidar_lines(self):
        # Fewer LiDAR lines: a table per line count, fewer LiDAR points, and the 64-line table as without the option.
        kitti = self.kitti_folder("000046\n")
        rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sdsgm", "--quiet", "--lidar-lines", "64,32,16"])
        self.assertEqual(rc, 0, se)
        cov = [float(c) for c in re.findall(r"\| LiDAR points alone +\| +([\d.]+) %", so)]
        self.assertEqual(len(cov), 3, so)
        self.assertGreater(cov[0], cov[1])
        self.assertGreater(cov[1], cov[2])
        for n in (64, 32, 16):
            self.assertIn("%d LiDAR lines" % n, so)
        rc, so64, se = run([TOOL, "--kitti", kitti, "--modes", "sdsgm", "--quiet"])
        row = r"\| SDSGM \(stereo-lidar\) +\| +([\d.]+) % \| +([\d.]+) % \| +([\d.]+) %"
        self.assertEqual(re.search(row, so64).groups(), re.search(row, so).groups())
        # Another ring offset keeps other rings at 16 lines (other LiDAR points); offset 4 is offset 0 again.
        lines16 = [TOOL, "--kitti", kitti, "--modes", "sdsgm", "--quiet", "--lidar-lines", "16"]
        lidar = r"\| LiDAR points alone +\| +([\d.]+) % \| +([\d.]+) %"
        outs = []
        for k in ("0", "3", "4"):
            rc, o, se = run(lines16 + ["--lidar-ring-offset", k])
            self.assertEqual(rc, 0, se)
            outs.append(re.search(lidar, o).groups())
        self.assertNotEqual(outs[0], outs[1])
        self.assertEqual(outs[0], outs[2])

    def test_car_split_matches_the_tool(self):
        """tools/car_split.py: its total D1 over the test frames is the tool's at 64 and 16 lines, the cars and the
        rest add up to it, and the LiDAR points on cars are far more often wrong than elsewhere (on these frames
        12.3 % against 0.5 % at 64 lines). A folder without obj_map is refused with the reason."""
        split = os.path.join(ROOT, "tools", "car_split.py")
        p = subprocess.run([sys.executable, split, "--data", KITTI, "--params", BEST, "--lidar-lines", "64,16"],
                           capture_output=True, text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stderr)
        rc, so, se = run([TOOL, "--kitti", KITTI, "--modes", "sdsgm", "--params", BEST, "--quiet",
                          "--lidar-lines", "64,16"])
        self.assertEqual(rc, 0, se)
        tool = re.findall(r"\| SDSGM \(stereo-lidar\) +\| +[\d.]+ % \| +[\d.]+ % \| +([\d.]+) %", so)
        blocks = p.stdout.split("LiDAR lines: SDSGM total D1")[1:]
        self.assertEqual(len(blocks), 2, p.stdout)
        for total, block in zip(tool, blocks):
            rows = dict(re.findall(r"\| (cars \(obj_map > 0\)|elsewhere|all) \| [\d.]+ % \| ([\d.]+) %", block))
            self.assertEqual(set(rows), {"cars (obj_map > 0)", "elsewhere", "all"}, block)
            self.assertEqual(total, rows["all"], block)
            points = dict(re.findall(r"\| (on cars|elsewhere) \| \d+ \| ([\d.]+) %", block))
            self.assertGreater(float(points["on cars"]), 5 * float(points["elsewhere"]), block)
        bare = self.kitti_folder("000046\n")
        shutil.rmtree(os.path.join(bare, "obj_map"))
        p = subprocess.run([sys.executable, split, "--data", bare], capture_output=True, text=True, timeout=600)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("has no obj_map/ folder", p.stderr)

    def test_calibration_check_and_refinement(self):
        rc, so, se = run([TOOL, "--kitti", KITTI, "--modes", "sdsgm", "--quiet", "--refine-calibration"])
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"calibration residual: [\d.]+ px \(median \|LiDAR - stereo disparity\|, 2 frames\)")
        m = re.search(r"pitch ([-+\d.]+) \+- ([\d.]+), yaw ([-+\d.]+) \+- ([\d.]+), roll ([-+\d.]+) \+- ([\d.]+)", so)
        self.assertIsNotNone(m, so)
        for k in (1, 3, 5):
            self.assertLessEqual(abs(float(m.group(k))), 0.2, so)   # calib.txt is close to right
        self.assertRegex(so, r"after the correction: [\d.]+ px \(\d+ points, 2 frames")
        rc, so, se = run([TOOL, "--kitti", KITTI, "--modes", "sdsgm", "--quiet", "--check-calibration"])
        self.assertEqual(rc, 0, se)
        self.assertIn("calibration residual:", so)
        self.assertNotIn("calibration correction", so)
        # Every run measures its frames' LiDAR against their images (matchingResidual); calib.txt is within 1 px.
        m = re.search(r"matching residual \(.*\): median ([\d.]+) px over 2 frame\(s\)", so)
        self.assertIsNotNone(m, so)
        self.assertLessEqual(float(m.group(1)), 1.0, so)
        self.assertNotIn("above 1 px", so)
        # Scans swapped between the two frames (a synchronisation error): no rotation repairs that, and the run
        # gives stereo alone instead of a fusion with the wrong scans.
        kitti = self.kitti_folder("000002\n000046\n")
        scans = os.path.join(kitti, "velodyne")
        os.rename(os.path.join(scans, "000002.bin"), os.path.join(scans, "tmp.bin"))
        os.rename(os.path.join(scans, "000046.bin"), os.path.join(scans, "000002.bin"))
        os.rename(os.path.join(scans, "tmp.bin"), os.path.join(scans, "000046.bin"))
        rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sdsgm", "--quiet", "--refine-calibration"])
        self.assertEqual(rc, 0, se)
        self.assertIn("the LiDAR is left out: stereo alone (SGM, left-right check)", so)
        self.assertRegex(so, r"above 1 px, where the LiDAR pulls the fusion off the images .*: 000002, 000046")
        self.assertIn("| SGM (stereo) ", so)
        self.assertNotIn("| SDSGM", so)
        # Left out means left out: with kitti_best.yml the scans would still draw MODE_SGM's disparity windows. Each
        # map is cv2's plain SGM, left-right checked, given no sparse map.
        out = os.path.join(self.tmp, "left_out")
        rc, so, se = run([TOOL, "--kitti", kitti, "--params", BEST, "--quiet", "--refine-calibration", "--out",
                          out])
        self.assertEqual(rc, 0, se)
        self.assertIn("the LiDAR is left out", so)
        stereo = cv.lidarsgm.StereoLidarSGM.load(BEST)
        stereo.setMode(cv.lidarsgm.StereoLidarSGM_MODE_SGM)
        stereo.setConsistencyCheck(cv.lidarsgm.StereoLidarSGM_CHECK_STEREO)
        for fid in ("000002", "000046"):
            f = cv.lidarsgm.loadKittiFrame(kitti, fid)
            alone = stereo.compute(f.left, f.right, np.zeros_like(f.sparse))
            self.assertFalse(np.array_equal(alone, stereo.compute(f.left, f.right, f.sparse)))   # the windows
            np.testing.assert_array_equal(cv.lidarsgm.encodeKittiDisparity(alone.astype(np.float32) / 16),
                                          cv.imread(os.path.join(out, fid, "disparity_sgm.png"), cv.IMREAD_UNCHANGED))
        for args, message in ((["--kitti-frame", KITTI, "--refine-calibration"],
                               "--refine-calibration does nothing with --kitti-frame (it goes with --kitti or "
                               "--kitti-raw)"),
                              (["--kitti", KITTI, "--refine-translation"],
                               "--refine-translation does nothing without --refine-calibration")):
            rc, so, se = run([TOOL] + args)
            self.assertEqual(rc, 2, se)
            self.assertIn(message, se)

    def test_fail_safe_for_a_wrong_calibration(self):
        """A LiDAR-to-camera rotation off by 2 degrees (tools/perturb_calibration.py): by default each frame is fused
        as stereo alone and the run says so per frame; --trust-lidar fuses it anyway, and worse."""
        wrong = os.path.join(self.tmp, "wrong")
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "perturb_calibration.py"), KITTI, wrong,
                        "--pitch", "1.2", "--yaw", "-1.5", "--roll", "0.8"], check=True)
        row = r"\| %s \(%s\)\s*\|\s*([\d.]+) %%\s*\|\s*([\d.]+) %%\s*\|\s*([\d.]+) %%"
        base = [TOOL, "--kitti", wrong, "--quiet", "--params", BEST]
        rc, so, se = run(base + ["--modes", "sgm,sdsgm"])
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"the LiDAR misplaced on the images .*, fused as stereo alone: 000002 \([\d.]+ px, "
                             r"[\d.]+ moved by \(-?\d+, -?\d+\)\), 000046 \(")
        sdsgm = re.search(row % ("SDSGM", "stereo-lidar"), so).groups()
        self.assertEqual(sdsgm, re.search(row % ("SGM", "stereo-lidar"), so).groups())
        rc, so, se = run(base + ["--modes", "sgm", "--check", "stereo"])
        self.assertEqual(rc, 0, se)
        self.assertEqual(sdsgm, re.search(row % ("SGM", "stereo"), so).groups())   # stereo alone
        rc, so, se = run(base + ["--modes", "sdsgm", "--trust-lidar"])
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"fused anyway \(--trust-lidar\): 000002 \(")
        trusted = re.search(row % ("SDSGM", "stereo-lidar"), so).groups()
        self.assertGreater(float(trusted[2]), 3 * float(sdsgm[2]), so)
        # One frame: the same rule, and the same map as stereo alone's.
        rc, so, se = run([TOOL, "--kitti-frame", wrong, "--id", "000002", "--params", BEST])
        self.assertEqual(rc, 0, se)
        self.assertIn("fused as stereo alone: 000002", so)
        alone = METRICS.search(so).groups()
        rc, so, se = run([TOOL, "--kitti-frame", wrong, "--id", "000002", "--params", BEST, "--modes", "sgm", "--check",
                          "stereo"])
        self.assertEqual(rc, 0, se)
        self.assertEqual(alone, METRICS.search(so).groups())
        # The exact calibration: every frame fused with its LiDAR.
        rc, so, se = run([TOOL, "--kitti", KITTI, "--quiet", "--params", BEST, "--modes", "sdsgm"])
        self.assertEqual(rc, 0, se)
        self.assertNotIn("misplaced", so)

    def test_own_rig(self):
        """--rig: a raw pair of the test frame un-rectified (tools/unrectified_rig.py), its scan as PCD, fused as the
        KITTI frame is, within what the images' two resamplings cost; depth written; bad combinations refused."""
        rig = os.path.join(self.tmp, "rig")
        p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "unrectified_rig.py"), "--lines", "64",
                            "--keep", rig, KITTI], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           universal_newlines=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stderr)
        rc, so, se = run([TOOL, "--kitti-frame", KITTI, "--id", "000002", "--params", BEST])
        self.assertEqual(rc, 0, se)
        ref = float(METRICS.search(so).group(3))
        out = os.path.join(self.tmp, "out")
        args = [TOOL, "--rig", os.path.join(rig, "rig.yml"), "--left", os.path.join(rig, "left", "000002.png"),
                "--right", os.path.join(rig, "right", "000002.png"), "--gt", os.path.join(rig, "gt", "000002.png"),
                "--params", BEST]
        rc, so, se = run(args + ["--points", os.path.join(rig, "points", "000002.pcd"), "--out", out,
                                 "--format", "kitti,depth"])
        self.assertEqual(rc, 0, se)
        total = float(METRICS.search(so).group(3))
        self.assertLess(abs(total - ref), 0.3, so)
        self.assertTrue(os.path.isfile(os.path.join(out, "depth.png")))
        rc, so2, se = run(args + ["--points", os.path.join(rig, "points", "000002.ply")])
        self.assertEqual(rc, 0, se)
        self.assertEqual(METRICS.search(so).group(0), METRICS.search(so2).group(0))
        # The whole recording: --rig-folder as the KITTI folder run, resumable.
        table = re.compile(r"\| SDSGM \(stereo-lidar\) +\| +([\d.]+) % \| +([\d.]+) % \| +([\d.]+) %")
        rc, so_k, se = run([TOOL, "--kitti", KITTI, "--params", BEST, "--modes", "sdsgm", "--quiet"])
        self.assertEqual(rc, 0, se)
        folder_out = os.path.join(self.tmp, "folder_out")
        rc, so_r, se = run([TOOL, "--rig-folder", rig, "--params", BEST, "--modes", "sdsgm", "--quiet",
                            "--out", folder_out])
        self.assertEqual(rc, 0, se)
        self.assertLess(abs(float(table.search(so_r).group(3)) - float(table.search(so_k).group(3))), 0.3, so_r)
        self.assertIn("2 computed", so_r)
        rc, so_r2, se = run([TOOL, "--rig-folder", rig, "--params", BEST, "--modes", "sdsgm", "--quiet",
                             "--out", folder_out, "--resume"])
        self.assertEqual(rc, 0, se)
        self.assertIn("2 taken from earlier runs", so_r2)
        self.assertEqual(table.search(so_r).group(0), table.search(so_r2).group(0))
        rc, so, se = run(args)
        self.assertEqual(rc, 2)
        self.assertIn("--rig needs --points", se)
        rc, so, se = run(args + ["--points", os.path.join(rig, "points", "000002.pcd"), "--calib",
                                 os.path.join(KITTI, "calib.txt")])
        self.assertEqual(rc, 2)
        self.assertIn("--calib does nothing with --rig (the rig file holds the calibration)", se)

    def test_exit_codes_and_messages(self):
        cases = [
            (["--kitti-frame", os.path.join(self.tmp, "missing"), "--id", "000002"], 1,
             "cannot read image " + os.path.join(self.tmp, "missing", "image_2", "000002_10.png") +
             ": no such file, or not readable"),
            (["--kitti", os.path.join(self.tmp, "missing")], 1, "frames.txt"),
            (["--middlebury", self.tmp], 1, "no Middlebury scene"),
            (["--left", os.path.join(KITTI, "image_2", "000002_10.png"), "--right",
              os.path.join(KITTI, "image_3", "000002_10.png"), "--sparse", os.path.join(self.tmp, "none.png")],
             1, "cannot read sparse disparity"),
            (["--kitti-frame", KITTI, "--id", "000002", "--num-disparities", "100"], 2,
             "--num-disparities 100 is refused: numDisparities"),
            (["--kitti-frame", KITTI, "--id", "000002", "--num-disparities", "abc"], 2, "takes an integer"),
            (["--kitti-frame", KITTI, "--id", "000002", "--alpha", "1.5"], 2, "--alpha 1.5 is refused: alpha"),
            (["--kitti-frame", KITTI, "--id", "000002", "--modes", "fast"], 2, "unknown mode"),
            (["--kitti-frame", KITTI, "--id", "000002", "--out", self.tmp, "--format", "jpg"], 2, "unknown --format"),
            (["--middlebury", self.tmp, "--out", self.tmp, "--format", "confidence"], 2,
             "--format confidence is written for KITTI inputs"),
            (["--kitti-frame", KITTI, "--id", "000002", "--colour", "1"], 2, "unknown option --colour"),
            (["--kitti-frame", KITTI, "--serch-window", "4"], 2,
             "unknown option --serch-window (did you mean --search-window? see --help)"),
            (["--kitti-frame", KITTI, "--id", "000002", "--lidar-lines", "48"], 2, "--lidar-lines takes 64, 32 or 16"),
            (["--kitti-frame", KITTI, "--id", "000002", "--lidar-ring-offset", "-1"], 2, "--lidar-ring-offset takes"),
            (["--kitti-frame", KITTI, "--id", "000002", "--params", os.path.join(self.tmp, "none.yml")], 1,
             "cannot open --params"),
            (["--kitti-frame", KITTI, "--id", "000002", "--resize", "10x"], 2, "--resize takes"),
            (["--kitti-frame", KITTI, "--id", "000002", "--resume"], 2,
             "--resume does nothing with --kitti-frame (it goes with --kitti, --kitti-raw or --rig-folder)"),
            (["--kitti", KITTI, "--resume"], 2, "--resume needs --out"),
            (["--kitti-frame"], 2, "needs a value"),
            (["stray"], 2, "unexpected argument"),
            ([], 2, "give --kitti-frame"),
        ]
        for args, code, message in cases:
            rc, so, se = run([TOOL] + args)
            self.assertEqual(rc, code, " ".join(args) + "\n" + se)
            self.assertIn(message, se, " ".join(args))
            self.assertNotIn("WARN", se, " ".join(args))   # the tool's message alone, no OpenCV log line before it

    def test_conflicting_and_idle_options_exit_2_naming_both(self):
        """Two inputs, an option that does nothing with the input, two LiDARs, an option without its companion: refused
        before any work with 2 and a message that names both options."""
        left, right = os.path.join(KITTI, "image_2", "000002_10.png"), os.path.join(KITTI, "image_3", "000002_10.png")
        sparse = os.path.join(self.tmp, "sparse.png")
        cv.imwrite(sparse, np.zeros((375, 1242), np.uint16))
        calib, scan = os.path.join(KITTI, "calib.txt"), os.path.join(KITTI, "velodyne", "000002.bin")
        frame, pair = ["--kitti-frame", KITTI], ["--left", left, "--right", right]
        out = ["--out", self.tmp]
        cases = [
            (frame + ["--sparse", sparse], "--sparse does nothing with --kitti-frame (the frame's velodyne scan is "
                                           "its LiDAR); drop one of them"),
            (frame + ["--velodyne", scan], "--velodyne does nothing with --kitti-frame"),
            (frame + ["--calib", calib], "--calib does nothing with --kitti-frame (calib.txt is the calibration)"),
            (frame + ["--gt", left], "--gt does nothing with --kitti-frame (disp_occ_0/ is the ground truth)"),
            (frame + pair, "--kitti-frame and --left/--right are two inputs: give one of them"),
            (frame + ["--left", left], "--kitti-frame and --left/--right are two inputs"),
            (["--kitti", KITTI, "--middlebury", DATA], "--kitti and --middlebury are two inputs"),
            (frame + ["--table5"], "--table5 does nothing with --kitti-frame (it goes with --kitti, --kitti-raw or "
                                   "--rig-folder)"),
            (pair + ["--sparse", sparse, "--table5"], "--table5 does nothing with --left/--right"),
            (frame + ["--streams", "2"], "--streams does nothing with --kitti-frame"),
            (frame + ["--quiet"], "--quiet does nothing with --kitti-frame"),
            (frame + ["--seed", "3"], "--seed does nothing with --kitti-frame (it goes with --middlebury)"),
            (["--kitti", KITTI, "--id", "000002"], "--id does nothing with --kitti (it goes with --kitti-frame)"),
            (["--kitti", KITTI, "--sparse", sparse], "--sparse does nothing with --kitti (each frame's velodyne scan"),
            (["--kitti", KITTI, "--timing", "5"], "--timing does nothing with --kitti"),
            (["--kitti", KITTI, "--gt-depth", self.tmp], "--gt-depth does nothing with --kitti"),
            (["--middlebury", DATA, "--cuda"], "--cuda does nothing with --middlebury"),
            (["--middlebury", DATA, "--trust-lidar"], "--trust-lidar does nothing with --middlebury"),
            (["--middlebury", DATA, "--table5"], "--table5 does nothing with --middlebury"),
            (pair + ["--sparse", sparse, "--resize", "621x188"], "--resize does nothing with --left/--right"),
            (pair + ["--sparse", sparse, "--velodyne", scan, "--calib", calib],
             "--sparse and --velodyne are two LiDAR inputs: give one of them"),
            (pair + ["--velodyne", scan], "--velodyne needs the calibration that projects it: add --calib"),
            (pair + ["--sparse", sparse, "--calib", calib], "--calib does nothing with --sparse"),
            (pair + ["--sparse", sparse, "--lidar-lines", "16"], "--lidar-lines does nothing with --sparse"),
            (["--left", left, "--sparse", sparse], "--left goes with --right"),
            (["--right", right, "--sparse", sparse], "--right goes with --left"),
            (frame + ["--lidar-lines", "64,16"], "one frame takes one --lidar-lines count, got 64,16"),
            (frame + ["--lidar-ring-offset", "1"], "--lidar-ring-offset does nothing without --lidar-lines 32 or 16"),
            (frame + ["--format", "pfm"], "--format does nothing without --out"),
            (frame + ["--rounds", "3"], "--rounds does nothing without --timing and --cuda"),
            (frame + ["--sm-count", "8"], "--sm-count does nothing without --timing and --cuda"),
            (frame + ["--timing", "2", "--cuda", "--sm-count", "0"], "--sm-count takes 1 or more SMs"),
            (["--kitti", KITTI, "--scan-rate", "0"], "--scan-rate does nothing without --refine-calibration"),
            (pair + ["--sparse", sparse, "--format", "depth"] + out, "--format depth needs the calibration: give "
                                                                     "--calib or --rig"),
            (["--middlebury", DATA, "--format", "ply"] + out, "--format ply needs a calibration"),
        ]
        for args, message in cases:   # each message names both options
            rc, so, se = run([TOOL] + args)
            self.assertEqual(rc, 2, " ".join(args) + "\n" + se)
            self.assertIn("lidarsgm_fuse: " + message, se, " ".join(args))
            self.assertEqual(so, "", " ".join(args))   # nothing was run

    def test_a_pair_without_lidar_says_what_gives_one(self):
        """--left/--right alone: refused before computing (2), with the options that give a LiDAR and the stereo-alone
        command; which then runs."""
        pair = [TOOL, "--left", os.path.join(KITTI, "image_2", "000002_10.png"), "--right",
                os.path.join(KITTI, "image_3", "000002_10.png")]
        for extra in ([], ["--modes", "sgm"], ["--check", "stereo"], ["--modes", "sgm", "--check", "camera-lidar"]):
            rc, so, se = run(pair + extra)
            self.assertEqual(rc, 2, se)
            self.assertIn("--left/--right give no LiDAR", se)
            for option in ("--sparse", "--points P with --calib C or --rig", "--velodyne V with --calib",
                           "--modes sgm --check stereo"):
                self.assertIn(option, se)
            self.assertNotIn("sparse disparity map is empty", se)
        rc, so, se = run(pair + ["--modes", "sgm", "--check", "stereo"])
        self.assertEqual(rc, 0, se)
        self.assertIn("SGM    check stereo", so)

    def test_help(self):
        rc, so, se = run([TOOL, "--help"])
        self.assertEqual(rc, 0)
        lines = so.splitlines()
        self.assertRegex(lines[0], r"^Usage: lidarsgm_fuse INPUT \[OPTION\]")
        examples = so.split("Examples:\n")[1].split("\n\n")[0]
        self.assertEqual(len(re.findall(r"^  lidarsgm_fuse --", examples, re.M)), 3, examples)
        for group in ("Input (give one):", "Output:", "Method:", "Matcher parameters"):
            self.assertIn("\n" + group, so)
        # One entry per option: "  --name VALUE  help", continued on lines indented further.
        entries = {}
        for line in lines:
            if line.startswith("  --"):
                name = line.split()[0]
                entries[name] = line.strip()
            elif line.startswith(" " * 24) and entries:
                entries[name] += " " + line.strip()
        entries = {k: " ".join(v.split()) for k, v in entries.items()}
        self.assertGreater(len(entries), 60)
        # The matcher's defaults are the library's (create()), the threads OpenCV's, the rest the tool's.
        m = cv.lidarsgm.StereoLidarSGM.create()
        for option, value in (("--num-disparities", m.getNumDisparities()), ("--P1", m.getP1()), ("--P2", m.getP2()),
                              ("--paths", m.getNumPaths()), ("--Q2", m.getQ2()), ("--alpha", "%g" % m.getAlpha()),
                              ("--Tc", "%g" % m.getCheckThreshold()), ("--search-window", m.getSearchWindow()),
                              ("--threads", "%d, OpenCV's" % cv.getNumThreads()), ("--streams", 1),
                              ("--id", "000002"), ("--check", "stereo-lidar"), ("--format", "kitti")):
            self.assertTrue(entries[option].endswith("(default %s)" % value), entries[option])
        self.assertTrue(entries["--num-disparities"].startswith("--num-disparities N numDisparities"))
        self.assertTrue(entries["--num-disparities"].endswith("(default 128)"))
        self.assertTrue(entries["--P1"].endswith("(default 10)"))
        for switch in ("--cuda", "--quiet", "--resume", "--table5"):   # no value
            self.assertNotRegex(entries[switch].split()[1], r"^([A-Z]+|\d)$", entries[switch])

    def test_switches_with_and_without_a_value(self):
        kitti = self.kitti_folder("000046\n")
        for args, progress in ((["--quiet"], False), (["--quiet", "1"], False), (["--quiet", "0"], True), ([], True)):
            rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sgm"] + args)
            self.assertEqual(rc, 0, se)
            self.assertEqual("[1/1] frames" in se, progress, args)
        # --cuda 0 is the CPU; --cuda and --cuda 1 the GPU (or, without a device, a failed run with the reason).
        frame = [TOOL, "--kitti-frame", KITTI, "--id", "000046", "--modes", "sgm"]
        rc, so, se = run(frame + ["--cuda", "0"])
        self.assertEqual(rc, 0, se)
        self.assertIn("stereo-lidar CPU ", so)
        results = [run(frame + a) for a in (["--cuda"], ["--cuda", "1"])]
        self.assertEqual(results[0][0], results[1][0])
        for rc, so, se in results:
            if rc == 0:
                self.assertIn("stereo-lidar CUDA", so)
            else:
                self.assertEqual(rc, 1, se)
                self.assertIn("lidarsgm_fuse: error: ", se)
        # A switch before another option, and the older value form of --resume.
        out = os.path.join(self.tmp, "out")
        rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sgm", "--quiet", "--out", out])
        self.assertEqual(rc, 0, se)
        rc, so, se = run([TOOL, "--kitti", kitti, "--modes", "sgm", "--quiet", "--out", out, "--resume", "1"])
        self.assertEqual(rc, 0, se)
        self.assertIn("frames: 0 computed, 1 taken from earlier runs (--resume), 0 failed", so)

    def test_bad_values_exit_2(self):
        frame = ["--kitti-frame", KITTI, "--id", "000002"]
        cases = [
            (["--num-disparities", "abc"], "--num-disparities takes an integer, got 'abc'"),
            (["--num-disparities", "100"], "--num-disparities 100 is refused: numDisparities"),
            (["--P1", "200"], "--P1 200 is refused: P1 (200) must not exceed P2"),
            (["--alpha", "x"], "--alpha takes a number, got 'x'"),
            (["--paths", "6"], "--paths 6 is refused: numPaths"),
            (["--resize", "100"], "--resize takes WIDTHxHEIGHT"),
            (["--timing", "0"], "--timing takes 1 or more runs"),
            (["--threads", "0"], "--threads takes 1 or more"),
            (["--check", "lidar"], "unknown check 'lidar'"),
            (["--modes", "sgm,fast"], "unknown mode 'fast'"),
            (["--lidar-lines", "8"], "--lidar-lines takes 64, 32 or 16"),
            (["--id"], "option --id needs a value"),
            (["--id", "--out", self.tmp], "option --id needs a value"),
        ]
        for args, message in cases:
            rc, so, se = run([TOOL] + frame + args)
            self.assertEqual(rc, 2, " ".join(args) + "\n" + se)
            self.assertIn("lidarsgm_fuse: " + message, se, " ".join(args))
        for args, message in ((["--middlebury", DATA, "--bad", "0"], "--bad takes a threshold above 0"),
                              (["--kitti", KITTI, "--streams", "65"], "--streams takes 1 to 64 workers, got 65")):
            rc, so, se = run([TOOL] + args)
            self.assertEqual(rc, 2, se)
            self.assertIn(message, se)
        # A failed run is 1: a file that cannot be read, a --params file with a bad value.
        rc, so, se = run([TOOL, "--kitti-frame", os.path.join(self.tmp, "none")])
        self.assertEqual(rc, 1, se)

    def test_resume_summaries_print_no_rate_for_frames_not_computed(self):
        kitti = self.kitti_folder("000002\n000046\n")
        out = os.path.join(self.tmp, "out")
        cmd = [TOOL, "--kitti", kitti, "--out", out, "--modes", "sgm"]
        rc, so, se = run(cmd)
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"frames: 2 computed, 0 taken from earlier runs \(--resume\), 0 failed; [\d.]+ frames/s")
        self.assertRegex(so, r"\| SGM \(stereo-lidar\) +\|.*\| +[\d.]+ \|")
        # Everything taken: no rate, no times.
        rc, so, se = run(cmd + ["--resume"])
        self.assertEqual(rc, 0, se)
        self.assertIn("frames: 0 computed, 2 taken from earlier runs (--resume), 0 failed\n", so)
        self.assertNotIn("frames/s", so + se)
        self.assertRegex(so, r"\| SGM \(stereo-lidar\) +\|.*\| +- \|")
        self.assertIn("[2/2] frames, none computed", se)
        # Refused for other options: every frame failed, no table, no rate.
        rc, so, se = run(cmd[:-1] + ["dsgm", "--resume"])
        self.assertEqual(rc, 1, se)
        self.assertIn("no frame to sum, every frame failed", so)
        self.assertIn("frames: 0 computed, 0 taken from earlier runs (--resume), 2 failed\n", so)
        self.assertNotIn("frames/s", so + se)
        self.assertNotIn("ms/frame", so)
        self.assertNotIn(": 0 frames", so)
        # One computed, one taken: the rate of the one.
        shutil.rmtree(os.path.join(out, "000046"))
        rc, so, se = run(cmd + ["--resume"])
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"frames: 1 computed, 1 taken from earlier runs \(--resume\), 0 failed; [\d.]+ frames/s "
                             r"computed")

    def test_pictures_have_a_legend(self):
        """Each picture is the library's drawing of the frame above a legend band: colour bar with disparity ticks, or
        the ten D1 error bands in colorizeDisparityError's colours."""
        out = os.path.join(self.tmp, "out")
        rc, so, se = run([TOOL, "--kitti-frame", KITTI, "--id", "000002", "--out", out, "--format", "pfm"])
        self.assertEqual(rc, 0, se)
        f = cv.lidarsgm.loadKittiFrame(KITTI, "000002")
        h, w = f.left.shape
        m = cv.lidarsgm.StereoLidarSGM.create()
        max_d = m.getMinDisparity() + m.getNumDisparities()
        disp = cv.imread(os.path.join(out, "disparity.pfm"), cv.IMREAD_UNCHANGED)
        disp[~np.isfinite(disp)] = -1
        gt = f.groundTruth
        if gt.dtype == np.uint16:
            gt = np.where(gt > 0, gt / 256.0, -1).astype(np.float32)
        expected = {"disparity_color.png": cv.lidarsgm.colorizeDisparity(disp, max_d),
                    "error.png": cv.lidarsgm.colorizeDisparityError(cv.lidarsgm.interpolateBackground(disp), gt)}
        # Every colour colorizeDisparity gives over [0, max_d]: the disparity legends' bars are drawn with it.
        ramp = cv.lidarsgm.colorizeDisparity(np.linspace(0, max_d, 200000, dtype=np.float32).reshape(1, -1), max_d)
        ramp_colours = {tuple(c) for c in ramp.reshape(-1, 3) if not c[0] == c[1] == c[2]}
        for name in ("disparity_color.png", "error.png", "semidense_color.png", "lidar_points.png"):
            img = cv.imread(os.path.join(out, name))
            self.assertEqual(img.shape[1], w, name)
            self.assertGreater(img.shape[0], h + 20, name)
            band = img[h:]
            self.assertGreater(np.mean(band == 255), 0.3, name)    # a white band ...
            self.assertGreater(len(np.unique(band.reshape(-1, 3), axis=0)), 20, name)   # ... with a legend on it
            if name in expected:
                np.testing.assert_array_equal(img[:h], expected[name], name)
            if name != "error.png":
                drawn = [tuple(c) in ramp_colours for c in band.reshape(-1, 3)]
                self.assertGreater(sum(drawn), w * 5, name)   # a bar of colorizeDisparity's ramp, 5 px at least
                self.assertGreater(len({tuple(c) for c in band.reshape(-1, 3)} & ramp_colours), 300, name)
        # The error legend shows the ten bands of colorizeDisparityError: errors of 1/32 .. 32 thresholds (5 px).
        band = cv.imread(os.path.join(out, "error.png"))[h:]
        colours = cv.lidarsgm.colorizeDisparityError(
            (100 + 5 * 2.0 ** (np.arange(10) - 4.5)).astype(np.float32).reshape(1, 10),
            np.full((1, 10), 100, np.float32))
        present = {tuple(c) for c in band.reshape(-1, 3)}
        self.assertEqual(len({tuple(c) for c in colours.reshape(-1, 3)}), 10)
        for c in colours.reshape(-1, 3):
            self.assertIn(tuple(c), present)


class PythonSampleTest(unittest.TestCase):
    def test_sample_matches_the_tool(self):
        tmp = tempfile.mkdtemp(prefix="lidarsgm_pysample_")
        try:
            rc, so, se = run([sys.executable, SAMPLE, "--kitti-frame", KITTI, "--id", "000002", "--out", tmp])
            self.assertEqual(rc, 0, se)
            m = METRICS.search(so)
            self.assertIsNotNone(m, so)
            for name in ["disparity.png", "disparity_color.png", "lidar_points.png"]:
                self.assertTrue(os.path.isfile(os.path.join(tmp, name)), name)
            if os.path.isfile(TOOL):
                out2 = os.path.join(tmp, "tool")
                rc, so2, se2 = run([TOOL, "--kitti-frame", KITTI, "--id", "000002", "--out", out2])
                self.assertEqual(rc, 0, se2)
                # numpy evaluator == C++ evaluator, and the same disparity file.
                self.assertEqual(m.groups(), METRICS.search(so2).groups())
                a = cv.imread(os.path.join(tmp, "disparity.png"), cv.IMREAD_UNCHANGED)
                b = cv.imread(os.path.join(out2, "disparity.png"), cv.IMREAD_UNCHANGED)
                np.testing.assert_array_equal(a, b)
                for name in ["disparity_color.png", "lidar_points.png"]:  # the same pictures, legends included
                    pa, pb = cv.imread(os.path.join(tmp, name)), cv.imread(os.path.join(out2, name))
                    np.testing.assert_array_equal(pa, pb, name)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)

    def test_sample_bad_input(self):
        rc, so, se = run([sys.executable, SAMPLE, "--kitti-frame", "/nonexistent", "--id", "000002"])
        self.assertEqual(rc, 1)
        self.assertIn("cannot read image", se)
        rc, so, se = run([sys.executable, SAMPLE, "--id", "000002"])
        self.assertEqual(rc, 2)


def heading_anchors(path):
    """The anchors GitHub gives a Markdown file's headings: lower case, punctuation but '-' and '_' dropped, spaces
    to '-', repeats numbered."""
    anchors, seen, fence = set(), {}, False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fence = not fence
            m = None if fence else re.match(r"#{1,6} +(.*?) *#* *$", line)
            if m:
                a = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
                n = seen.get(a, 0)
                seen[a] = n + 1
                anchors.add(a if n == 0 else "%s-%d" % (a, n))
    return anchors


class DocLinks(unittest.TestCase):
    def test_every_link_resolves(self):
        """Every relative link of README.md and doc/*.md names a file of the repository, and its #anchor a heading
        there (web links are not followed: no network)."""
        docs = [os.path.join(ROOT, "README.md")] + sorted(
            os.path.join(ROOT, "doc", n) for n in os.listdir(os.path.join(ROOT, "doc")) if n.endswith(".md"))
        checked, broken = 0, []
        for doc in docs:
            with open(doc, encoding="utf-8") as f:
                text = re.sub(r"```.*?```", "", f.read(), flags=re.S)
            for target in re.findall(r"\]\(([^)\s]+)\)", text):
                if re.match(r"[a-z]+:", target):
                    continue
                path, _, anchor = target.partition("#")
                full = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
                checked += 1
                if not os.path.exists(full):
                    broken.append("%s: %s (no such file)" % (os.path.relpath(doc, ROOT), target))
                elif anchor and full.endswith(".md") and anchor not in heading_anchors(full):
                    broken.append("%s: %s (no such heading)" % (os.path.relpath(doc, ROOT), target))
        print("%d relative links checked in %d files" % (checked, len(docs)))
        self.assertGreater(checked, 50)
        self.assertEqual(broken, [])

    def test_readme_is_short(self):
        with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
            self.assertLessEqual(len(f.read().splitlines()), 160, "README.md: keep the detail in doc/")


if __name__ == "__main__":
    unittest.main()
