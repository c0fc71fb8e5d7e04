#!/usr/bin/env python3
"""The Ray sample (samples/python/lidarsgm_ray.py) on a local Ray instance with 2 CPUs: its outputs equal the C++
tool's folder run byte for byte, and a worker killed mid-run loses nothing (the run, or a rerun with --resume,
completes every frame with complete files).

Environment (set by ctest): LIDARSGM_TOOL (the tool binary), LIDARSGM_TESTDATA (testdata/), PYTHONPATH with cv2.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import cv2 as cv
import ray  # noqa: F401  (the test needs Ray itself: a missing Ray fails here, it does not skip)

TOOL = os.environ.get("LIDARSGM_TOOL", "")
DATA = os.environ.get("LIDARSGM_TESTDATA", os.path.join(os.path.dirname(__file__), "..", "..", "testdata"))
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SAMPLE = os.path.join(ROOT, "samples", "python", "lidarsgm_ray.py")
KITTI = os.path.join(DATA, "kitti")
ROWS = re.compile(r"^\| ([A-Za-z][^|]*?) +\| +([\d.]+) % \| +([\d.]+) % \| +([\d.-]+)", re.M)


def run(cmd, timeout=600):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def ray_cmd(kitti, out, *extra):
    return [sys.executable, SAMPLE, "--kitti", kitti, "--out", out, "--num-cpus", "2", "--quiet"] + list(extra)


def files(folder):
    return sorted(os.path.relpath(os.path.join(d, n), folder) for d, _, names in os.walk(folder) for n in names)


def metrics(path):
    """metrics.yml without the times: the options key, each row's counts and the frame's LiDAR check."""
    fs = cv.FileStorage(path, cv.FILE_STORAGE_READ)
    rows = fs.getNode("rows")
    shift = fs.getNode("shift")
    check = [fs.getNode(k).real() for k in ("matchingResidual", "shiftedResidual", "misplaced", "stereoAlone")]
    return fs.getNode("options").string(), [
        tuple([rows.at(i).getNode("label").string()] +
              [rows.at(i).getNode(k).real() for k in ("gt", "est", "estBad", "totalBad")])
        for i in range(rows.size())], check, [shift.at(i).real() for i in range(shift.size())]


def ray_workers():
    """PIDs of the sample's Ray workers (Ray names their processes ray::FrameFuser...)."""
    pids = []
    for p in os.listdir("/proc"):
        if p.isdigit():
            try:
                with open("/proc/%s/cmdline" % p, "rb") as f:
                    if f.read().startswith(b"ray::FrameFuser"):
                        pids.append(int(p))
            except OSError:
                pass
    return pids


@unittest.skipUnless(os.path.isfile(TOOL), "LIDARSGM_TOOL does not name the tool binary")
class RaySampleTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="lidarsgm_ray_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def assertSameOutputs(self, a, b):
        self.assertEqual(files(a), files(b))
        for name in files(a):
            if os.path.basename(name) == "metrics.yml":
                self.assertEqual(metrics(os.path.join(a, name)), metrics(os.path.join(b, name)), name)
            else:
                with open(os.path.join(a, name), "rb") as fa, open(os.path.join(b, name), "rb") as fb:
                    self.assertEqual(fa.read(), fb.read(), name)

    def test_outputs_equal_the_tool(self):
        tool_out, ray_out = os.path.join(self.tmp, "tool"), os.path.join(self.tmp, "ray")
        rc, so_tool, se = run([TOOL, "--kitti", KITTI, "--out", tool_out, "--quiet", "1"])
        self.assertEqual(rc, 0, se)
        rc, so_ray, se = run(ray_cmd(KITTI, ray_out))
        self.assertEqual(rc, 0, se)
        self.assertIn("2 Ray workers (CPU)", so_ray)
        self.assertIn("frames: 2 computed, 0 taken from earlier runs (--resume), 0 failed", so_ray)
        self.assertSameOutputs(tool_out, ray_out)
        # The same summary table (the figures; the times differ).
        self.assertEqual(ROWS.findall(so_tool), ROWS.findall(so_ray))
        self.assertEqual(len(ROWS.findall(so_ray)), 5)
        # The tool resumes the Ray run: every frame taken, none computed.
        rc, so, se = run([TOOL, "--kitti", KITTI, "--out", ray_out, "--quiet", "1", "--resume"])
        self.assertEqual(rc, 0, se)
        self.assertIn("frames: 0 computed, 2 taken from earlier runs (--resume), 0 failed", so)

    def test_wrong_calibration_as_the_tool(self):
        """A 2-degree rotation error: the sample fuses the frames as stereo alone, as the tool does, byte for byte."""
        wrong = os.path.join(self.tmp, "wrong")
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "perturb_calibration.py"), KITTI, wrong,
                        "--pitch", "1.2", "--yaw", "-1.5", "--roll", "0.8"], check=True)
        tool_out, ray_out = os.path.join(self.tmp, "tool"), os.path.join(self.tmp, "ray")
        rc, so_tool, se = run([TOOL, "--kitti", wrong, "--out", tool_out, "--quiet", "1", "--modes", "sgm,sdsgm"])
        self.assertEqual(rc, 0, se)
        rc, so_ray, se = run(ray_cmd(wrong, ray_out, "--modes", "sgm,sdsgm"))
        self.assertEqual(rc, 0, se)
        self.assertIn("fused as stereo alone: 000002, 000046", so_ray)
        self.assertSameOutputs(tool_out, ray_out)
        self.assertEqual(ROWS.findall(so_tool), ROWS.findall(so_ray))
        self.assertEqual(metrics(os.path.join(ray_out, "000002", "metrics.yml"))[2][2:], [1.0, 1.0])

    def test_worker_killed_mid_run(self):
        # Six frames (the two shipped ones under three ids each), two workers.
        kitti = os.path.join(self.tmp, "kitti")
        shutil.copytree(KITTI, kitti)
        ids = []
        for n, fid in enumerate(["000002", "000046"] * 3):
            new = "%06d" % (int(fid) + 100000 * (n // 2))
            for sub, suffix in [("image_2", "_10.png"), ("image_3", "_10.png"), ("velodyne", ".bin"),
                                ("disp_occ_0", "_10.png")]:
                if new != fid:
                    shutil.copy(os.path.join(kitti, sub, fid + suffix), os.path.join(kitti, sub, new + suffix))
            ids.append(new)
        with open(os.path.join(kitti, "frames.txt"), "w") as f:
            f.write("\n".join(ids) + "\n")
        out = os.path.join(self.tmp, "ray")
        p = subprocess.Popen(ray_cmd(kitti, out, "--modes", "sdsgm"), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             universal_newlines=True)
        killed = None
        deadline = time.time() + 300
        while killed is None and p.poll() is None and time.time() < deadline:
            finished = [i for i in ids if os.path.isfile(os.path.join(out, i, "metrics.yml"))]
            busy = ray_workers()
            if finished and busy and len(finished) < len(ids) - 2:
                killed = busy[0]
                os.kill(killed, signal.SIGKILL)
            time.sleep(0.05)
        so, se = p.communicate(timeout=600)
        self.assertIsNotNone(killed, "no worker was killed mid-run:\n" + so + se)
        # Ray restarts the worker and computes its frame again; a frame it could not finish is listed as failed.
        self.assertIn(p.returncode, (0, 1), se)
        summary = [l for l in so.splitlines() if l.startswith("frames:")]
        sys.stderr.write("\n  killed worker %d; the run exited %d: %s\n" % (killed, p.returncode, summary))
        rc, so, se = run(ray_cmd(kitti, out, "--modes", "sdsgm", "--resume"))
        self.assertEqual(rc, 0, se)
        self.assertRegex(so, r"frames: \d+ computed, \d+ taken from earlier runs \(--resume\), 0 failed")
        self.assertEqual([n for n in files(out) if ".partial-" in n], [])
        tool_out = os.path.join(self.tmp, "tool")
        rc, so_tool, se = run([TOOL, "--kitti", kitti, "--out", tool_out, "--modes", "sdsgm", "--quiet", "1"])
        self.assertEqual(rc, 0, se)
        self.assertSameOutputs(tool_out, out)
        self.assertEqual(ROWS.findall(so_tool), ROWS.findall(so))

    def test_bad_frame_and_bad_input(self):
        kitti = os.path.join(self.tmp, "kitti")
        shutil.copytree(KITTI, kitti)
        scan = os.path.join(kitti, "velodyne", "000046.bin")
        with open(scan, "r+b") as f:
            f.truncate(1000)
        rc, so, se = run(ray_cmd(kitti, os.path.join(self.tmp, "out"), "--modes", "dsgm"))
        self.assertEqual(rc, 1)
        self.assertIn("000046: Velodyne scan " + scan + " is not a whole number of 16-byte points", se)
        self.assertIn("frames: 1 computed, 0 taken from earlier runs (--resume), 1 failed", so)
        rc, so, se = run(ray_cmd(os.path.join(self.tmp, "missing"), os.path.join(self.tmp, "out")))
        self.assertEqual(rc, 1)
        self.assertIn("frames.txt", se)
        rc, so, se = run(ray_cmd(KITTI, os.path.join(self.tmp, "out"), "--modes", "fast"))
        self.assertEqual(rc, 2)
        self.assertIn("unknown mode", se)


if __name__ == "__main__":
    unittest.main()
