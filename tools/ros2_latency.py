#!/usr/bin/env python3
"""What the ROS 2 node adds to a fusion, and whether it keeps up with a 10 Hz LiDAR (doc/perf.md, "ROS 2 node").

  python3 tools/ros2_latency.py --kitti testdata/kitti --params doc/params/kitti_best.yml [--cuda] [--rounds 20]
                                [--node-frames 100] [--threads N] [--bands N]

1. In one process, per frame of the KITTI folder as ROS messages (lidarsgm_ros.kitti): the node's conversions in
   (CameraInfo pair, images to grey, PointCloud2 to points), the projection, the fail-safe's check of the projected
   scan (Fusion.check, as the node runs it on every set), the bare compute call (cv2, or GpuMat
   upload, compute and download with --cuda), and the conversions out (DisparityImage pixels and window, REP 118 depth,
   the organised cloud, the three messages built), median over --rounds rounds; then the node's own call
   (Fusion.fuse: all of it in, with --cuda the GPU's fusion beside the CPU's check) and its overhead, Fusion.fuse and
   the conversions out less the bare compute. Targets at KITTI size: conversions <= 10 % of the compute on the CPU
   path, node overhead <= 5 ms on the GPU host. Then each conversion's sub-steps (median ms, minor page faults, MB written
   and the GB/s that makes), and the host's memory for reference (NUMA nodes, transparent huge pages, a copy of the
   cloud's size into a reused buffer and into a fresh one): a host where fresh memory costs page faults, or whose
   memory bandwidth is low, shows it there. Without rclpy the messages are plain objects that keep their arrays as
   they are (as the rclpy kit and rosbags' do: the node and the bag command copy nothing into a message).
2. With rclpy (the ROS 2 environment): the node as a process (python3 -m lidarsgm_ros.node), a publisher sending the
   frames at 10 Hz under new stamps, and a subscriber timing each output from its publication; the node keeps up when
   every frame published after the first output is fused.
"""
import argparse
import atexit
import glob
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from types import SimpleNamespace

import cv2
import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
PACKAGE = os.path.join(ROOT, "ros2", "lidarsgm_ros")
sys.path.insert(0, PACKAGE)
from lidarsgm_ros import camera_info, clouds, images, kitti  # noqa: E402
from lidarsgm_ros.conversions import stamp_ns  # noqa: E402
from lidarsgm_ros.fusion import Fusion, Result  # noqa: E402
from lidarsgm_ros.messages import INPUT_TYPES, OUTPUT_TYPES, MessageKit, output_messages, rclpy_class  # noqa: E402
sys.path.append(os.path.join(ROOT, "test", "ros2"))
from node_process import stop_node  # noqa: E402  (the stopping of the node, as the tests stop it)

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


def minor_faults():
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


class Steps:
    """Wall time and minor page faults of named steps, one round at a time (mark(name) ends a step)."""

    def __init__(self):
        self.rounds = []

    def start(self):
        self.round = {}
        self.rounds.append(self.round)
        self._t, self._f = time.perf_counter(), minor_faults()

    def mark(self, name):
        t, f = time.perf_counter(), minor_faults()
        dt, df = self.round.get(name, (0.0, 0))
        self.round[name] = (dt + t - self._t, df + f - self._f)
        self._t, self._f = time.perf_counter(), minor_faults()  # the getrusage call itself not counted

    def median(self, name, skip=1):
        rows = [r[name] for r in self.rounds[skip:] if name in r]
        return 1000 * statistics.median(t for t, _ in rows), statistics.median(f for _, f in rows)

    def names(self):
        return list(self.rounds[0]) if self.rounds else []


# sub-steps: (part, step names) in the order they run; the bytes each writes per pixel (32FC1 depth) for its GB/s
IN_STEPS = ("camera_info pair", "images to grey", "left image to BGR", "PointCloud2 to points")
OUT_BYTES = {"disparity image": 4, "disparityToDepth": 4, "depth image": 4, "x y z rgb cloud": 16}


def plain_kit():
    """Messages as plain objects that keep their arrays (no ROS): as MessageKit.rosbags, the node's rclpy kit."""
    return MessageKit(lambda type_name, **f: SimpleNamespace(**f),
                      lambda a: np.ascontiguousarray(a).reshape(-1).view(np.uint8),
                      lambda a: np.asarray(a, np.float64).ravel())


def memory_reference(nbytes, rounds):
    """A line on the host's memory: NUMA nodes, transparent huge pages, and a copy of nbytes into a reused buffer
    against one into a fresh buffer each time (the difference: page faults), median of rounds."""
    nodes = len(glob.glob("/sys/devices/system/node/node[0-9]*"))
    thp = "?"
    if os.path.exists("/sys/kernel/mm/transparent_hugepage/enabled"):
        thp = open("/sys/kernel/mm/transparent_hugepage/enabled").read().strip()
    src = np.ones(nbytes, np.uint8)
    dst = np.empty_like(src)
    dst[...] = 0
    reused, fresh, faults, tobytes = [], [], [], []
    for _ in range(rounds + 1):
        t = time.perf_counter()
        np.copyto(dst, src)
        reused.append(time.perf_counter() - t)
        f, t = minor_faults(), time.perf_counter()
        new = np.empty_like(src)
        np.copyto(new, src)
        fresh.append(time.perf_counter() - t)
        faults.append(minor_faults() - f)
        del new
        t = time.perf_counter()
        b = src.tobytes()
        tobytes.append(time.perf_counter() - t)
        del b
    r, fr, fa, tb = (statistics.median(v[1:]) for v in (reused, fresh, faults, tobytes))
    return ("memory: %s NUMA node%s, transparent huge pages %s, %d CPUs for this process; a %.1f MB copy: %.2f ms "
            "(%.1f GB/s) into a reused buffer, %.2f ms (%.1f GB/s, %d minor page faults, %.2f us each over the "
            "reused copy) into a fresh one, %.2f ms as bytes (tobytes)"
            % (nodes or "?", "" if nodes == 1 else "s", thp, len(os.sched_getaffinity(0)), nbytes / 1e6, 1000 * r,
               nbytes / r / 1e9, 1000 * fr, nbytes / fr / 1e9, fa, 1e6 * (fr - r) / fa if fa else 0.0,
               1000 * tb))


def in_process(args):
    kit = MessageKit.rclpy() if HAVE_RCLPY else plain_kit()
    print("1. per frame, median of %d rounds (%s messages, %s, %d OpenCV threads)"
          % (args.rounds, "rclpy" if HAVE_RCLPY else "plain", "CUDA" if args.cuda else "CPU", cv2.getNumThreads()))
    print("| frame | conversions in | projection | check | compute | conversions out | conversions / compute "
          "| in + out | all but compute, in turn | the node's Fusion.fuse | node overhead |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    breakdown = []
    for fid, frame, m in frames(args, kit):
        fusion = Fusion(cv2, args.params, args.cuda, kitti.ros_calibration(frame.calibration)[3])
        t = {k: [] for k in ("in", "proj", "check", "compute", "out", "fuse")}
        steps, serial = Steps(), Steps()
        for r in range(args.rounds + 1):
            steps.start()
            t0 = time.perf_counter()
            g = camera_info.stereo_geometry(m["left/camera_info"], m["right/camera_info"])
            steps.mark("camera_info pair")
            grey_l, grey_r = images.to_grey(m["left/image_rect"], cv2), images.to_grey(m["right/image_rect"], cv2)
            steps.mark("images to grey")
            bgr = images.to_bgr(m["left/image_rect"], cv2)
            steps.mark("left image to BGR")
            points, _, _ = clouds.cloud_points(m["points"])
            steps.mark("PointCloud2 to points")
            t1 = time.perf_counter()
            sparse = fusion.project(g, points)
            t1b = time.perf_counter()
            fusion.check(grey_l, grey_r, sparse)
            t2 = time.perf_counter()
            if args.cuda:
                disp = cv2.cuda.computeStereoLidarSGM(fusion.sgm, cv2.cuda_GpuMat(grey_l), cv2.cuda_GpuMat(grey_r),
                                                      cv2.cuda_GpuMat(sparse)).download()
            else:
                disp = fusion.sgm.compute(grey_l, grey_r, sparse)
            t3 = time.perf_counter()
            steps.mark("(projection, check and compute)")
            result = Result(**dict(dict.fromkeys(Result._fields), disparity16=disp, geometry=g, left_bgr=bgr,
                                   sparse=sparse, left_grey=grey_l, right_grey=grey_r, points=points))
            output_messages(kit, fusion, result, "camera", 10**9, "32FC1", steps.mark, bands=args.bands or None)
            t4 = time.perf_counter()
            # The node's own call on the same messages: with --cuda the GPU fuses while the CPU checks.
            t5 = time.perf_counter()
            fusion.fuse(m["left/image_rect"], m["left/camera_info"], m["right/image_rect"], m["right/camera_info"],
                        m["points"])
            t6 = time.perf_counter()
            # The same outputs once more in one band, each step timed on its own (not in the totals above).
            serial.start()
            output_messages(kit, fusion, result, "camera", 10**9, "32FC1", serial.mark, bands=1)
            if r == 0:
                continue  # warm-up
            t["in"].append(t1 - t0)
            t["proj"].append(t1b - t1)
            t["check"].append(t2 - t1b)
            t["compute"].append(t3 - t2)
            t["out"].append(t4 - t3)
            t["fuse"].append(t6 - t5)
        med = {k: 1000 * statistics.median(v) for k, v in t.items()}
        print("| %s | %.2f ms | %.2f ms | %.2f ms | %.2f ms | %.2f ms | %.1f %% | %.2f ms | %.2f ms | %.2f ms "
              "| %.2f ms |"
              % (fid, med["in"], med["proj"], med["check"], med["compute"], med["out"],
                 100 * (med["in"] + med["out"]) / med["compute"], med["in"] + med["out"],
                 med["in"] + med["proj"] + med["check"] + med["out"], med["fuse"],
                 med["fuse"] + med["out"] - med["compute"]))
        breakdown.append((fid, frame.left.shape[0] * frame.left.shape[1], steps, serial))
    print("\n1b. the conversions by sub-step, median of the same rounds: ms, minor page faults, and for the outputs "
          "the MB each writes and the GB/s that makes; 'out, one band' is each output step on its own, the outputs "
          "made once more in one band (Fusion.outputs bands=1) after each round's")
    print("| sub-step | %s |" % " | ".join(b[0] for b in breakdown))
    print("| --- |%s" % (" --- |" * len(breakdown)))
    names = [n for n in breakdown[0][2].names() if not n.startswith("(")]
    for part, chosen, which in (("in", [n for n in names if n in IN_STEPS], 2),
                                ("out", [n for n in names if n not in IN_STEPS], 2),
                                ("out, one band", breakdown[0][3].names(), 3)):
        tot = [[0.0, 0] for _ in breakdown]
        for n in chosen:
            cells = []
            for i, b in enumerate(breakdown):
                pixels, steps = b[1], b[which]
                ms, faults = steps.median(n)
                tot[i][0] += ms
                tot[i][1] += faults
                cell = "%.2f ms, %d faults" % (ms, faults)
                if n in OUT_BYTES:
                    mb = OUT_BYTES[n] * pixels / 1e6
                    cell += ", %.1f MB, %.1f GB/s" % (mb, mb / ms if ms > 0 else 0.0)
                cells.append(cell)
            print("| %s: %s | %s |" % (part, n, " | ".join(cells)))
        print("| %s: sum of the medians | %s |" % (part, " | ".join("%.2f ms, %d faults" % (ms, f) for ms, f in tot)))
    print(memory_reference(16 * breakdown[0][1], args.rounds))


def node_rate(args):
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = os.path.join(PACKAGE, "config", "fastdds_large_data.xml")
    os.environ.setdefault("ROS_DOMAIN_ID", "77")
    kit = MessageKit.rclpy()
    data = frames(args, kit)
    work = tempfile.mkdtemp(prefix="lidarsgm_latency_")
    atexit.register(shutil.rmtree, work, True)
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
                             lambda msg: got.setdefault(stamp_ns(msg), time.perf_counter()), 10)
    end = time.monotonic() + 60
    while time.monotonic() < end and not all(p.get_subscription_count() for p in pubs.values()):
        rclpy.spin_once(node, timeout_sec=0.05)
    period = 0.1
    start = time.perf_counter()
    for i in range(args.node_frames):
        stamp = node.get_clock().now().nanoseconds  # the node's clock: its stamp-to-outputs latency is real
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
    stop_node(node_proc, 20)
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
    p.add_argument("--threads", type=int, default=0,
                   help="OpenCV threads; 0 (default): cv2's own, one a CPU, as the node runs")
    p.add_argument("--bands", type=int, default=0,
                   help="bands of rows the outputs are made in at once; 0 (default): the node's rule "
                        "(lidarsgm_ros.outputs.output_bands)")
    args = p.parse_args()
    if args.threads > 0:
        cv2.setNumThreads(args.threads)
    args.threads = cv2.getNumThreads()
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
