#!/usr/bin/env python3
"""What the ROS 2 node adds to a fusion, and whether it keeps up with a 10 Hz LiDAR (doc/perf.md, "ROS 2 node").

  python3 tools/ros2_latency.py --kitti testdata/kitti --params doc/params/kitti_best.yml [--cuda] [--rounds 20]
                                [--node-frames 100] [--threads 2]

1. In one process, per frame of the KITTI folder as ROS messages (lidarsgm_ros.kitti): the node's conversions in
   (CameraInfo pair, images to grey, PointCloud2 to points), the projection, the bare compute call (cv2, or GpuMat
   upload, compute and download with --cuda), and the conversions out (DisparityImage pixels and window, REP 118 depth,
   the organised cloud, the three messages built), median over --rounds rounds. Target: conversions <= 10 % of the
   compute on the CPU path at KITTI size.
2. With rclpy (the ROS 2 environment): the node as a process (python3 -m lidarsgm_ros.node), a publisher sending the
   frames at 10 Hz under new stamps, and a subscriber timing each output from its publication; the node keeps up when
   every frame published after the first output is fused.
"""
import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
PACKAGE = os.path.join(ROOT, "ros2", "lidarsgm_ros")
sys.path.insert(0, PACKAGE)
from lidarsgm_ros import conversions as cr  # noqa: E402
from lidarsgm_ros import kitti  # noqa: E402
from lidarsgm_ros.fusion import Fusion, Result  # noqa: E402
from lidarsgm_ros.messages import INPUT_TYPES, OUTPUT_TYPES, MessageKit, output_messages, rclpy_class  # noqa: E402

try:
    import rclpy
    HAVE_RCLPY = True
except ImportError:
    HAVE_RCLPY = False


def frames(args, kit):
    out = []
    for fid in cv2.lidarsgm.readKittiFrameIds(args.kitti):
        frame = cv2.lidarsgm.loadKittiFrame(args.kitti, fid)
        points = cv2.lidarsgm.readVelodyneScan(os.path.join(args.kitti, "velodyne", fid + ".bin"))
        out.append((fid, frame, kitti.frame_messages(kit, frame, points, 10**9)))
    return out


def in_process(args):
    kit = MessageKit.rclpy() if HAVE_RCLPY else MessageKit(
        lambda type_name, **f: type("Msg", (), f)(), lambda a: np.ascontiguousarray(a).tobytes(),
        lambda a: np.asarray(a, np.float64).ravel())
    print("1. per frame, median of %d rounds (%s messages, %s, %d OpenCV threads)"
          % (args.rounds, "rclpy" if HAVE_RCLPY else "plain", "CUDA" if args.cuda else "CPU", cv2.getNumThreads()))
    print("| frame | conversions in | projection | compute | conversions out | conversions / compute |")
    print("| --- | --- | --- | --- | --- | --- |")
    for fid, frame, m in frames(args, kit):
        fusion = Fusion(cv2, args.params, args.cuda, kitti.ros_calibration(frame.calibration)[3])
        t = {k: [] for k in ("in", "proj", "compute", "out")}
        for r in range(args.rounds + 1):
            t0 = time.perf_counter()
            g = cr.stereo_geometry(m["left/camera_info"], m["right/camera_info"])
            grey_l, grey_r = cr.to_grey(m["left/image_rect"], cv2), cr.to_grey(m["right/image_rect"], cv2)
            bgr = cr.to_bgr(m["left/image_rect"], cv2)
            points, _ = cr.cloud_to_points(m["points"])
            t1 = time.perf_counter()
            sparse = fusion.project(g, points)
            t2 = time.perf_counter()
            if args.cuda:
                disp = cv2.cuda.computeStereoLidarSGM(fusion.sgm, cv2.cuda_GpuMat(grey_l), cv2.cuda_GpuMat(grey_r),
                                                      cv2.cuda_GpuMat(sparse)).download()
            else:
                disp = fusion.sgm.compute(grey_l, grey_r, sparse)
            t3 = time.perf_counter()
            output_messages(kit, fusion, Result(disp, None, g, bgr, sparse, grey_l, grey_r), "camera", 10**9,
                            "32FC1")
            t4 = time.perf_counter()
            if r == 0:
                continue  # warm-up
            t["in"].append(t1 - t0)
            t["proj"].append(t2 - t1)
            t["compute"].append(t3 - t2)
            t["out"].append(t4 - t3)
        med = {k: 1000 * statistics.median(v) for k, v in t.items()}
        print("| %s | %.2f ms | %.2f ms | %.2f ms | %.2f ms | %.1f %% |"
              % (fid, med["in"], med["proj"], med["compute"], med["out"],
                 100 * (med["in"] + med["out"]) / med["compute"]))


def node_rate(args):
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = os.path.join(PACKAGE, "config", "fastdds_large_data.xml")
    os.environ.setdefault("ROS_DOMAIN_ID", "77")
    kit = MessageKit.rclpy()
    data = frames(args, kit)
    work = tempfile.mkdtemp(prefix="lidarsgm_latency_")
    t = kitti.ros_calibration(data[0][1].calibration)[3]
    cfg = os.path.join(work, "params.yaml")
    with open(cfg, "w") as f:
        f.write("lidarsgm:\n  ros__parameters:\n    params_file: %s\n    use_cuda: %s\n    lidar_to_camera: [%s]\n"
                % (os.path.abspath(args.params), "true" if args.cuda else "false",
                   ", ".join(repr(float(v)) for v in t.ravel())))
    log = open(os.path.join(work, "node.log"), "w")
    env = dict(os.environ, PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", ""),
               OPENCV_FOR_THREADS_NUM=str(args.threads))
    node_proc = subprocess.Popen([sys.executable, "-m", "lidarsgm_ros.node", "--ros-args", "--params-file", cfg],
                                 stdout=log, stderr=subprocess.STDOUT, env=env)
    rclpy.init()
    node = rclpy.create_node("latency_replay")
    pubs = {k: node.create_publisher(rclpy_class(v), k, 10) for k, v in INPUT_TYPES.items()}
    sent, got = {}, {}
    node.create_subscription(rclpy_class(OUTPUT_TYPES["disparity"]), "disparity",
                             lambda msg: got.setdefault(cr.stamp_ns(msg), time.perf_counter()), 10)
    end = time.monotonic() + 60
    while time.monotonic() < end and not all(p.get_subscription_count() for p in pubs.values()):
        rclpy.spin_once(node, timeout_sec=0.05)
    period = 0.1
    start = time.perf_counter()
    for i in range(args.node_frames):
        stamp = (i + 1) * 10**8
        _, _, msgs = data[i % len(data)]
        for topic, msg in msgs.items():
            msg.header.stamp = kit.time(stamp)
            pubs[topic].publish(msg)
        sent[stamp] = time.perf_counter()
        while time.perf_counter() < start + (i + 1) * period:
            rclpy.spin_once(node, timeout_sec=max(0.0, start + (i + 1) * period - time.perf_counter()))
    end = time.perf_counter() + 5
    while time.perf_counter() < end and len(got) < len(sent):
        rclpy.spin_once(node, timeout_sec=0.05)
    node_proc.send_signal(signal.SIGINT)
    node_proc.wait(20)
    log.close()
    summary = [line for line in open(log.name) if line.startswith("lidarsgm_node: ")]
    node.destroy_node()
    rclpy.shutdown()
    first = min(got) if got else None
    after = [s for s in sent if first is not None and s >= first]
    lat = sorted(1000 * (got[s] - sent[s]) for s in after if s in got)
    print("2. the node as a process, %d frames published at 10 Hz (%s, %d OpenCV threads)"
          % (len(sent), "CUDA" if args.cuda else "CPU", args.threads))
    if not lat:
        print("no output came (the node's log: %s)" % log.name)
        return 1
    print("   fused %d of the %d frames published from the first output on (%d before it, lost to discovery); "
          "publication to DisparityImage: median %.0f ms, 90th percentile %.0f ms, max %.0f ms; %s"
          % (len(lat), len(after), len(sent) - len(after), statistics.median(lat), lat[int(0.9 * (len(lat) - 1))],
             lat[-1], "keeps up" if len(lat) == len(after) else "falls behind (frames dropped)"))
    print("   the node: %s" % (summary[-1].strip()[len("lidarsgm_node: "):] if summary else "(no summary in its log)"))
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--kitti", default=os.path.join(ROOT, "testdata", "kitti"))
    p.add_argument("--params", default=os.path.join(ROOT, "doc", "params", "kitti_best.yml"))
    p.add_argument("--cuda", action="store_true")
    p.add_argument("--rounds", type=int, default=20)
    p.add_argument("--node-frames", type=int, default=100)
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args()
    cv2.setNumThreads(args.threads)
    cpu = ""
    if os.path.exists("/proc/cpuinfo"):
        cpu = open("/proc/cpuinfo").read().split("model name")[1].split("\n")[0].strip(": \t")
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    print("lidarsgm ROS 2 latency: %s, commit %s, %d-core %s; python3 tools/ros2_latency.py %s"
          % (time.strftime("%Y-%m-%d"), commit, os.cpu_count(), cpu, " ".join(sys.argv[1:])))
    in_process(args)
    if not args.node_frames:
        return 0
    if HAVE_RCLPY:
        return node_rate(args)
    print("2. skipped: no rclpy in this Python (run it with the ROS 2 environment's)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
