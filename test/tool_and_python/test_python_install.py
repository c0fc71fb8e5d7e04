#!/usr/bin/env python3
"""`cmake --build build --target python_install` as a Python user runs it: into a fresh virtual environment, then
that environment's python alone (no PYTHONPATH) imports cv2.lidarsgm, fuses a frame with the Python sample, shows
the parameters in help() and the typing stubs, and `pip uninstall opencv-lidarsgm` removes it again.

Environment (set by ctest): LIDARSGM_SUPERBUILD (the build folder), LIDARSGM_WORK (scratch), LIDARSGM_TESTDATA.
"""
import os
import re
import shutil
import subprocess
import sys
import unittest

BUILD = os.environ.get("LIDARSGM_SUPERBUILD", "")
WORK = os.environ.get("LIDARSGM_WORK", "")
TARGET = os.environ.get("LIDARSGM_INSTALL_TARGET", "python_install")   # python_install_opencv<version>: another build
DATA = os.environ.get("LIDARSGM_TESTDATA", "")
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
SAMPLE = os.path.join(ROOT, "samples", "python", "lidarsgm_fuse.py")


def run(cmd, env):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, env=env,
                       timeout=900)
    return p.returncode, p.stdout


@unittest.skipUnless(BUILD and WORK, "run by ctest (LIDARSGM_SUPERBUILD, LIDARSGM_WORK)")
class PythonInstallTest(unittest.TestCase):
    def test_install_use_uninstall(self):
        shutil.rmtree(WORK, ignore_errors=True)
        venv = os.path.join(WORK, "venv")
        rc, out = run([sys.executable, "-m", "venv", venv], dict(os.environ))
        self.assertEqual(rc, 0, out)
        py = os.path.join(venv, "bin", "python")
        # The user's shell: the environment activated, nothing pointing at the build.
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH", "PYTHONHOME")}
        env["VIRTUAL_ENV"] = venv
        env["PATH"] = os.path.join(venv, "bin") + os.pathsep + env.get("PATH", "")
        rc, out = run(["cmake", "--build", BUILD, "--target", TARGET], env)
        self.assertEqual(rc, 0, out)
        self.assertIn("with lidarsgm installed into " + venv, out)

        rc, out = run([py, "-c", "import cv2; print(cv2.__file__); print(cv2.lidarsgm.StereoLidarSGM.create().getP2())"],
                      env)
        self.assertEqual(rc, 0, out)
        self.assertTrue(out.startswith(os.path.join(venv, "lib")), out)
        self.assertEqual(out.split()[-1], "120")
        rc, out = run([py, SAMPLE, "--kitti-frame", os.path.join(DATA, "kitti"), "--id", "000002"], env)
        self.assertEqual(rc, 0, out)
        self.assertRegex(out, r"coverage +[\d.]+ %  covered D1 +[\d.]+ %  total D1 +[\d.]+ %")
        rc, out = run([py, "-c", "import cv2; help(cv2.lidarsgm.StereoLidarSGM)"], env)
        self.assertEqual(rc, 0, out)
        for name in ("setNumDisparities", "setP1", "setAlpha", "setSemidenseThreshold", "compute", "semidensify"):
            self.assertIn(name, out)
        stubs = os.path.join(venv, "lib", "python%d.%d" % sys.version_info[:2], "site-packages", "cv2", "lidarsgm",
                             "__init__.pyi")
        with open(stubs) as f:
            pyi = f.read()
        self.assertIn("class StereoLidarSGM(cv2.Algorithm)", pyi)
        self.assertRegex(pyi, r"def setP1\(self, [^)]*\) -> None")
        self.assertIn("def evaluateDisparity(", pyi)
        rc, out = run([py, "-m", "pip", "list"], env)
        self.assertRegex(out, r"opencv-lidarsgm +\d+\.\d+\.\d+")

        rc, out = run([py, "-m", "pip", "uninstall", "--yes", "opencv-lidarsgm"], env)
        self.assertEqual(rc, 0, out)
        rc, out = run([py, "-c", "import cv2"], env)
        self.assertNotEqual(rc, 0, out)
        left = [n for n in os.listdir(os.path.join(venv, "lib")) if re.match(r"libopencv_", n)]
        self.assertEqual(left, [])

    def test_refuses_without_an_environment(self):
        env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "CONDA_PREFIX")}
        rc, out = run(["cmake", "--build", BUILD, "--target", TARGET], env)
        self.assertNotEqual(rc, 0)
        self.assertIn("no Python environment to install into", out)


if __name__ == "__main__":
    unittest.main()
