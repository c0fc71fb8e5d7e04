#!/usr/bin/env python3
"""The fail-safe for a LiDAR-to-camera transform that is off (cv2.lidarsgm.checkLidar), on the shared KITTI frames
(doc/benchmarks/fail_safe_kitti20.txt).

1. checkLidar on every frame under rotation errors of 0.5-2 degrees, at the frames' size and at twice it with JPEG
   compression (weaker matches: correct LiDAR maps whose residual lies above 1 px): how many frames it condemns, and
   the residual as given and moved.
2. The tool's folder run with kitti_best.yml under the error of 2 degrees (pitch 1.2, yaw -1.5, roll 0.8), its
   default (the fail-safe) against --trust-lidar, stereo alone and the exact calibration; then under single-axis
   errors (yaw 1, roll 1, roll 2). Stereo alone is kitti_best.yml in MODE_SGM with the left-right check on the pair
   alone (no LiDAR: its disparity windows come from the images), run here through cv2, not through the tool.
3. The bag command over a rosbag2 of the frames twice (40 sets) with the 2-degree mix and with a roll of 2 degrees
   given as --lidar-to-camera: sets fused as stereo alone, the switch to the recalibrated transform, and total D1
   over the last 20 sets against the exact calibration's.

    PYTHONPATH=<build>/python_loader <ros2 venv python> tools/fail_safe_benchmark.py --tool <build>/bin/lidarsgm_fuse
        --data ../shared/data/kitti2015_lidar [--threads 2]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
PACKAGE = os.path.join(ROOT, "ros2", "lidarsgm_ros")
sys.path.insert(0, HERE)
sys.path.insert(0, PACKAGE)
from calibration_benchmark import calib_transform as transform  # noqa: E402
from perturb_calibration import perturbed_calib, read_calib, rotation  # noqa: E402

PARAMS = os.path.join(ROOT, "doc", "params", "kitti_best.yml")
MIX2 = dict(pitch=1.2, yaw=-1.5, roll=0.8)
ROLL2 = dict(roll=2.0)
ERRORS = [("none", {}), ("pitch 0.5", dict(pitch=0.5)), ("yaw 1", dict(yaw=1)), ("roll 1", dict(roll=1)),
          ("roll 2", ROLL2), ("mix 1 deg (0.6, -0.7, 0.5)", dict(pitch=0.6, yaw=-0.7, roll=0.5)),
          ("mix 2 deg (1.2, -1.5, 0.8)", MIX2)]


def tool_row(args, folder, extra, label):
    cmd = [args.tool, "--kitti", folder, "--params", PARAMS, "--quiet", "--threads", str(args.threads)] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        sys.exit("%s failed:\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    m = re.search(r"\| %s\s*\|\s*([\d.]+) %%\s*\|\s*([\d.]+) %%\s*\|\s*([\d.]+) %%" % re.escape(label), p.stdout)
    alone = re.search(r"fused as stereo alone: (.*)", p.stdout)
    return float(m.group(1)), float(m.group(3)), (alone.group(1).count(" px,") if alone else 0)


def stereo_alone(cv2, data, ids):
    """(coverage %, total D1 %) over the frames of kitti_best.yml on the pair alone, with the fail-safe's stereo-alone
    matcher (MODE_SGM, the left-right check), as it fuses a condemned frame."""
    m = cv2.lidarsgm.LidarFailSafe.stereoAloneMatcher(cv2.lidarsgm.StereoLidarSGM.load(PARAMS))
    est = bad = gt = 0
    for i in ids:
        f = cv2.lidarsgm.loadKittiFrame(data, i)
        d = m.compute(f.left, f.right, np.zeros(f.left.shape, np.float32))
        e = cv2.lidarsgm.evaluateDisparity(d, f.groundTruth, cv2.lidarsgm.METRIC_KITTI_D1, 0, m.getMinDisparity())
        est, bad, gt = est + e.estimatedPixels, bad + e.totalOutliers, gt + e.groundTruthPixels
    return 100.0 * est / gt, 100.0 * bad / gt


def bag_d1(cv2, out, gts):
    """Total D1 (KITTI devkit) of each <ns>/disparity of an output folder, in stamp order: (outliers, gt pixels)."""
    from rosbags.highlevel import AnyReader
    got = {}
    with AnyReader(sorted(Path(out).glob("part_*"))) as reader:
        conns = [c for c in reader.connections if c.topic.endswith("/disparity")]
        for conn, _, raw in reader.messages(connections=conns):
            m = reader.deserialize(raw, conn.msgtype)
            d = np.frombuffer(m.image.data.tobytes(), np.float32).reshape(m.image.height, m.image.width)
            got[m.header.stamp.sec * 10**9 + m.header.stamp.nanosec] = np.round(d * 16).astype(np.int16)
    rows = []
    for (stamp, d16), gt in zip(sorted(got.items()), gts):
        e = cv2.lidarsgm.evaluateDisparity(d16, gt, cv2.lidarsgm.METRIC_KITTI_D1, 0, 0)
        rows.append((e.totalOutliers, e.groundTruthPixels))
    return rows


def run_bag(bag, out, extra):
    env = dict(os.environ, PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", ""))
    cmd = [sys.executable, "-m", "lidarsgm_ros.bag", bag, out, "--params-file", PARAMS] + extra
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode:
        sys.exit("%s failed:\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return p.stdout, time.time() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tool", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    import cv2
    cv2.setNumThreads(a.threads)
    entries, _ = read_calib(os.path.join(a.data, "calib.txt"))
    ids = open(os.path.join(a.data, "frames.txt")).read().split()
    P2 = np.array(entries["P2"]).reshape(3, 4)
    fB = P2[0, 3] - np.array(entries["P3"]).reshape(3, 4)[0, 3]
    frames = []
    for i in ids:
        f = cv2.lidarsgm.loadKittiFrame(a.data, i)
        left, right = f.left, f.right
        big = []
        for img in (left, right):
            b = cv2.resize(img, None, fx=2, fy=2, interpolation=cv2.INTER_CUBIC)
            big.append(cv2.imdecode(cv2.imencode(".jpg", b, [cv2.IMWRITE_JPEG_QUALITY, 75])[1], cv2.IMREAD_GRAYSCALE))
        pts = cv2.lidarsgm.readVelodyneScan(os.path.join(a.data, "velodyne", i + ".bin"))
        frames.append((left, right, big, pts))
    P2big = P2 * 2
    P2big[2] = P2[2]

    print("1. cv2.lidarsgm.checkLidar on %d frames of %s (maxResidual 1 px, maxShift a 32nd of the width)" % (len(ids), a.data))
    print("| error (degrees) | size | frames condemned | residual as given (median, range) | moved (median) "
          "| lowered by the best move (range over the frames) | ms a frame (median) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for name, err in ERRORS:
        T = transform(perturbed_calib(entries, err.get("pitch", 0), err.get("yaw", 0), err.get("roll", 0)))
        for size in ("1242x375", "2484x750 JPEG 75"):
            cond, r0, r1, ms = 0, [], [], []
            for left, right, big, pts in frames:
                if size.startswith("1242"):
                    l, r, sp = left, right, cv2.lidarsgm.projectPointsToDisparity(pts, P2, T, fB, (left.shape[1], left.shape[0]))
                else:
                    l, r = big
                    sp = cv2.lidarsgm.projectPointsToDisparity(pts, P2big, T, 2 * fB, (l.shape[1], l.shape[0]))
                t0 = time.perf_counter()
                c = cv2.lidarsgm.checkLidar(l, r, sp)
                ms.append(1000 * (time.perf_counter() - t0))
                cond += not c.trusted
                r0.append(c.residual)
                r1.append(c.shiftedResidual)
            gain = [100 * (1 - b / g) for g, b in zip(r0, r1)]
            print("| %s | %s | %d of %d | %.2f (%.2f-%.2f) | %.2f | %.0f-%.0f %% | %.1f |" % (
                name, size, cond, len(frames), np.median(r0), min(r0), max(r0), np.median(r1), min(gain), max(gain),
                np.median(ms)), flush=True)

    with tempfile.TemporaryDirectory() as tmp:
        wrong = os.path.join(tmp, "wrong")
        subprocess.run([sys.executable, os.path.join(HERE, "perturb_calibration.py"), a.data, wrong,
                        "--pitch", str(MIX2["pitch"]), "--yaw", str(MIX2["yaw"]), "--roll", str(MIX2["roll"])],
                       check=True)
        print("\n2. the tool, %d frames, kitti_best.yml, CPU %d threads, rotation error pitch 1.2, yaw -1.5, roll 0.8 "
              "degrees" % (len(ids), a.threads))
        print("| run | coverage | total D1 | frames fused as stereo alone |")
        print("| --- | --- | --- | --- |")
        for label, folder, extra, row in (
                ("exact calibration, default", a.data, ["--modes", "sdsgm"], "SDSGM (stereo-lidar)"),
                ("error, --trust-lidar", wrong, ["--modes", "sdsgm", "--trust-lidar"], "SDSGM (stereo-lidar)"),
                ("error, default (the fail-safe)", wrong, ["--modes", "sdsgm"], "SDSGM (stereo-lidar)")):
            cov, d1, alone = tool_row(a, folder, extra, row)
            print("| %s | %.2f %% | %.2f %% | %d |" % (label, cov, d1, alone), flush=True)
        cov, alone_d1 = stereo_alone(cv2, a.data, ids)
        print("| stereo alone (MODE_SGM, left-right check, no LiDAR; cv2) | %.2f %% | %.2f %% | %d |"
              % (cov, alone_d1, len(ids)), flush=True)
        print("\nthe same, SDSGM, under single-axis errors (stereo alone %.2f %%)" % alone_d1)
        print("| error | --trust-lidar: total D1 | default: total D1 | default - stereo alone | frames fused as stereo "
              "alone |")
        print("| --- | --- | --- | --- | --- |")
        for name, err in ERRORS:
            if name not in ("yaw 1", "roll 1", "roll 2"):
                continue
            folder = os.path.join(tmp, name.replace(" ", "_"))
            subprocess.run([sys.executable, os.path.join(HERE, "perturb_calibration.py"), a.data, folder] +
                           sum([["--" + k, str(v)] for k, v in err.items()], []), check=True)
            _, trusted, _ = tool_row(a, folder, ["--modes", "sdsgm", "--trust-lidar"], "SDSGM (stereo-lidar)")
            _, d1, alone = tool_row(a, folder, ["--modes", "sdsgm"], "SDSGM (stereo-lidar)")
            print("| %s | %.2f %% | %.2f %% | %+.2f pp | %d |" % (name, trusted, d1, d1 - alone_d1, alone), flush=True)

        from lidarsgm_ros import kitti
        bag = os.path.join(tmp, "bag")
        kitti.write_bag(a.data, bag, ids=ids + ids)
        calib = cv2.lidarsgm.readKittiCalibration(os.path.join(a.data, "calib.txt"))
        # ROS's transform (to the left optical frame) with the error applied in the rectified camera frame.
        exact = kitti.ros_calibration(calib)[3]
        shift = exact @ np.linalg.inv(transform(entries))
        def wrong_transform(err):
            motion = np.eye(4)
            motion[:3, :3] = np.array(rotation(err.get("pitch", 0), err.get("yaw", 0), err.get("roll", 0)))
            return shift @ motion @ transform(entries)
        gts = [cv2.imread(os.path.join(a.data, "disp_occ_0", i + "_10.png"), cv2.IMREAD_UNCHANGED)
               for i in ids + ids]
        print("\n3. the bag command (python3 -m lidarsgm_ros.bag, kitti_best.yml) over %d sets: the frames twice"
              % len(gts))
        print("| run | total D1, all sets | total D1, last 20 sets | sets fused as stereo alone | switch after set | s |")
        print("| --- | --- | --- | --- | --- | --- |")
        numbers = lambda m: ["%.9g" % v for v in m.ravel()]
        for label, T, extra in (("exact calibration", exact, []),
                                ("2-degree mix, --trust-lidar", wrong_transform(MIX2), ["--trust-lidar"]),
                                ("2-degree mix, default (fail-safe, recalibration)", wrong_transform(MIX2),
                                 ["--scan-rate", "10"]),
                                ("roll 2, --trust-lidar", wrong_transform(ROLL2), ["--trust-lidar"]),
                                ("roll 2, default (fail-safe, recalibration)", wrong_transform(ROLL2),
                                 ["--scan-rate", "10"])):
            out = os.path.join(tmp, "out_" + str(len(os.listdir(tmp))))
            so, secs = run_bag(bag, out, ["--lidar-to-camera"] + numbers(T) + extra)
            rows = bag_d1(cv2, out, gts)
            tot = lambda rs: 100.0 * sum(r[0] for r in rs) / sum(r[1] for r in rs)
            alone = re.search(r"(\d+) sets fused as stereo alone", so)
            switch = re.search(r"the corrected transform taken after set ([\d, ]+)", so)
            print("| %s | %.2f %% | %.2f %% | %s | %s | %.0f |" % (
                label, tot(rows), tot(rows[-20:]), alone.group(1) if alone else "0",
                switch.group(1) if switch else "-", secs), flush=True)
            for line in so.splitlines():
                if line.startswith("  "):
                    print("   " + line.strip())


if __name__ == "__main__":
    main()
