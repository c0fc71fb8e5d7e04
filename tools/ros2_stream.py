#!/usr/bin/env python3
"""KITTI sets streamed over DDS between processes of one machine: where megabyte messages are lost, and how many
sets the node answers (doc/benchmarks/ros2_stream_*.txt).

  python3 tools/ros2_stream.py probe [--sets 30] [--rate 5] [--only NAME ...] [--netns]
  python3 tools/ros2_stream.py node [--sets 100] [--rate 5] [--reliability best_effort|reliable] [--depth 10]
                                    [--size kitti|1080p] [--node-profile none|shipped]
                                    [--publisher-profile none|shipped] [--soak] [--param NAME:=VALUE ...] [--json]

probe: a publisher process sends sets of the node's five inputs at KITTI's sizes (a 1.4 MB bgr8 image, a 0.47 MB
mono8 image, two CameraInfo, the Velodyne scan as a 2.2 MB PointCloud2 with a ring field) to a probe subscriber in
another process, no node and no cv2 needed, under each configuration of a table: the Fast DDS transports of either
side (the pinned wheels' defaults, the package's profile config/fastdds_large_data.xml, UDP only,
FASTDDS_BUILTIN_TRANSPORTS=LARGE_DATA), the publisher's and the subscription's reliability and depth, and what the
subscriber does with a complete set (nothing; 75 ms of sleep or of CPU on two threads in the callback, blocking the
single-threaded executor; the same CPU in a worker thread that takes the newest set). Per configuration: messages
received per topic, complete sets (stamps with all five), the sets the node's ExactSync (queue 5) emits, the sets
worked on. --netns runs every pair in a fresh network namespace (loopback only).

node: python3 -m lidarsgm_ros.node with config/lidarsgm.yaml and the KITTI transform (as test/ros2/test_node.py
does), a publisher process of its own (best effort or reliable, --depth) sending N sets of the shipped KITTI frames
at --rate under new stamps (the wall clock), and a reliable subscription here timing each DisparityImage from its
stamp. --size 1080p scales the images to 1920 x 1080 (camera_info with them) and sends the scan twice, the copy
jittered by 1 cm (a 128-line LiDAR's 4.4 MB). --node-profile none launches the node as a user does (no
FASTDDS_DEFAULT_PROFILES_FILE); --publisher-profile none is a camera driver on the wheels' defaults. --soak: 2000 sets
at 10 Hz, the node's RSS at the start, after 100 sets and at the end. Prints the answered sets, latency median / p99 /
max and the node's summary line (at SIGINT). Needs cv2 with the module (PYTHONPATH=<build>/python_loader) and the ROS 2
environment's Python.
"""
import argparse
import atexit
import json
import os
import random
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
PACKAGE = os.path.abspath(os.path.join(ROOT, "ros2", "lidarsgm_ros"))
SHIPPED_PROFILE = os.path.join(PACKAGE, "config", "fastdds_large_data.xml")
KITTI = os.path.abspath(os.path.join(os.environ.get("LIDARSGM_TESTDATA", os.path.join(ROOT, "testdata")), "kitti"))
PARAMS = os.path.abspath(os.path.join(ROOT, "doc", "params", "kitti_best.yml"))
CONFIG = os.path.join(PACKAGE, "config", "lidarsgm.yaml")
FRAMES = ("000002", "000046")
sys.path.insert(0, PACKAGE)
sys.path.append(os.path.join(ROOT, "test", "ros2"))
from node_process import stop_node  # noqa: E402  (the stopping of the node, as the tests stop it)

# Fast DDS transport variants for the probe (written to a scratch folder); "shipped" is the package's profile.
UDP_ONLY = """<?xml version="1.0" encoding="UTF-8"?>
<profiles xmlns="http://www.eprosima.com">
  <transport_descriptors><transport_descriptor><transport_id>udp_large</transport_id><type>UDPv4</type>
    <sendBufferSize>4194304</sendBufferSize><receiveBufferSize>4194304</receiveBufferSize>
  </transport_descriptor></transport_descriptors>
  <participant profile_name="udp_only" is_default_profile="true"><rtps>
    <userTransports><transport_id>udp_large</transport_id></userTransports>
    <useBuiltinTransports>false</useBuiltinTransports></rtps></participant>
</profiles>
"""
SHM_ONLY = """<?xml version="1.0" encoding="UTF-8"?>
<profiles xmlns="http://www.eprosima.com">
  <transport_descriptors><transport_descriptor><transport_id>shm_large</transport_id><type>SHM</type>
    <segment_size>33554432</segment_size></transport_descriptor></transport_descriptors>
  <participant profile_name="shm_udp_default" is_default_profile="true"><rtps>
    <userTransports><transport_id>shm_large</transport_id></userTransports>
    <useBuiltinTransports>true</useBuiltinTransports></rtps></participant>
</profiles>
"""


def profile_env(name, scratch):
    """The environment a process gets for a transport variant (None: the wheels' defaults)."""
    env = {k: v for k, v in os.environ.items() if k not in ("FASTDDS_DEFAULT_PROFILES_FILE",
                                                             "FASTRTPS_DEFAULT_PROFILES_FILE",
                                                             "FASTDDS_BUILTIN_TRANSPORTS")}
    if name == "shipped":
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = SHIPPED_PROFILE
    elif name in ("udp_only", "shm32+udp"):
        path = os.path.join(scratch, name.replace("+", "_") + ".xml")
        with open(path, "w") as f:
            f.write(UDP_ONLY if name == "udp_only" else SHM_ONLY)
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = path
    elif name == "shipped_in_process":  # set by the process itself, after import rclpy, before rclpy.init
        env["LIDARSGM_STREAM_PROFILE_IN_PROCESS"] = SHIPPED_PROFILE
    elif name == "large_data":
        env["FASTDDS_BUILTIN_TRANSPORTS"] = "LARGE_DATA"
    elif name.startswith("file:"):
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = name[5:]
    elif name != "none":
        raise SystemExit("unknown transport variant " + name)
    return env


# -- the messages
def velodyne_points(fid):
    return np.fromfile(os.path.join(KITTI, "velodyne", fid + ".bin"), np.float32).reshape(-1, 4)


def kitti_sets(kit, size, synthetic):
    """[{topic: message}] of the shipped frames (stamps set when sent). synthetic: images of KITTI's size and
    the real scans, without cv2 (the probe: the sizes are what matter)."""
    from types import SimpleNamespace
    from lidarsgm_ros import kitti
    out = []
    for fid in FRAMES:
        points = velodyne_points(fid)
        if synthetic:
            rng = np.random.default_rng(int(fid))
            h, w = (375, 1242) if size == "kitti" else (1080, 1920)
            # outputs: the node's at 1080p (DisparityImage and depth 8.3 MB each, the organised cloud 33 MB)
            left = rng.integers(0, 255, (h, w, 4 if size == "outputs" else 3), np.uint8)
            right = rng.integers(0, 255, (h, w, 4) if size == "outputs" else (h, w), np.uint8)
            k = np.array([[721.5, 0, 609.6], [0, 721.5, 172.9], [0, 0, 1]])
            cal = SimpleNamespace(projection=np.hstack([k, [[44.9], [0.2], [0.003]]]), focalBaseline=387.6,
                                  lidarToCamera=np.eye(4))
            frame = SimpleNamespace(calibration=cal, left=right, leftImage=left, right=right)
        else:
            import cv2
            frame = cv2.lidarsgm.loadKittiFrame(KITTI, fid)
            if size == "1080p":
                sx, sy = 1920 / frame.left.shape[1], 1080 / frame.left.shape[0]
                s = np.diag([sx, sy, 1.0])
                cal = SimpleNamespace(projection=s @ np.asarray(frame.calibration.projection, np.float64),
                                      focalBaseline=frame.calibration.focalBaseline * sx,
                                      lidarToCamera=np.asarray(frame.calibration.lidarToCamera, np.float64))
                rs = lambda a: cv2.resize(a, (1920, 1080), interpolation=cv2.INTER_LINEAR)
                frame = SimpleNamespace(calibration=cal, left=rs(frame.left), leftImage=rs(frame.leftImage),
                                        right=rs(frame.right))
        if size == "outputs":
            out.append(kitti.frame_messages(kit, frame, points, 0))
            cloud = np.zeros((1080, 1920, 4), np.float32)
            out[-1]["points"] = kit.cloud(kit.header(0, "camera"), cloud, [(n, 4 * i, 7) for i, n in enumerate("xyzw")])
            continue
        if size == "1080p":  # a 128-line LiDAR: the scan and a copy 1 cm off
            copy = points.copy()
            copy[:, :3] += np.random.default_rng(1).normal(0, 0.01, (len(points), 3)).astype(np.float32)
            points = np.vstack([points, copy])
        out.append(kitti.frame_messages(kit, frame, points, 0))
    return out


def qos(reliability, depth):
    from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
    return QoSProfile(depth=depth, history=HistoryPolicy.KEEP_LAST,
                      reliability={"best_effort": ReliabilityPolicy.BEST_EFFORT, "reliable": ReliabilityPolicy.RELIABLE,
                                   "best_available": ReliabilityPolicy.BEST_AVAILABLE}[reliability])


def init_rclpy():
    """rclpy.init, the profile set first where the process is to set it itself (as the node's main() would)."""
    import rclpy
    if os.environ.get("LIDARSGM_STREAM_PROFILE_IN_PROCESS"):
        os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = os.environ["LIDARSGM_STREAM_PROFILE_IN_PROCESS"]
    rclpy.init()


def stamp_of(msg):
    return msg.header.stamp.sec * 1000000000 + msg.header.stamp.nanosec


# -- the publisher process
def publish_main(a):
    import rclpy
    from lidarsgm_ros.messages import INPUT_TYPES, MessageKit, rclpy_class
    kit = MessageKit.rclpy()
    sets = kitti_sets(kit, a.size, a.synthetic)
    init_rclpy()
    node = rclpy.create_node("stream_publisher_%d" % os.getpid())
    pubs = {t: node.create_publisher(rclpy_class(ty), t, qos(a.reliability, a.depth)) for t, ty in INPUT_TYPES.items()}
    end = time.monotonic() + a.match_timeout
    while not all(p.get_subscription_count() for p in pubs.values()):
        if time.monotonic() > end:
            print("NOMATCH %s" % {t: p.get_subscription_count() for t, p in pubs.items()}, flush=True)
            return 2
        time.sleep(0.05)
    time.sleep(a.settle)  # the reader's side of the match (a best-effort sample sent before it is lost)
    print("MATCHED", flush=True)
    period, start, cost = 1.0 / a.rate, time.monotonic(), []
    for i in range(a.sets):
        while time.monotonic() < start + i * period:
            time.sleep(min(0.005, max(0.0, start + i * period - time.monotonic())))
        stamp = time.time_ns()
        t0 = time.perf_counter()
        for topic, msg in sets[i % len(sets)].items():
            msg.header.stamp = kit.time(stamp)
            pubs[topic].publish(msg)
        cost.append(time.perf_counter() - t0)
        print("SENT %d %d" % (i, stamp), flush=True)
    time.sleep(a.linger)  # a reliable writer repairs what was lost while it lives
    print("DONE publish_ms_median %.1f max %.1f" % (1000 * statistics.median(cost), 1000 * max(cost)), flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


# -- the probe subscriber process
def burn(seconds, threads=2):
    """CPU on `threads` threads without the GIL (hashlib releases it), as a fusion's OpenCV threads use it."""
    import hashlib
    buf = b"\0" * (1 << 20)
    end = time.perf_counter() + seconds

    def spin():
        while time.perf_counter() < end:
            hashlib.sha256(buf).digest()
    ts = [threading.Thread(target=spin) for _ in range(threads - 1)]
    for t in ts:
        t.start()
    spin()
    for t in ts:
        t.join()


def probe_main(a):
    import rclpy
    from lidarsgm_ros.messages import INPUT_TYPES, rclpy_class
    from lidarsgm_ros.sync import ExactSync
    init_rclpy()
    node = rclpy.create_node("stream_probe")
    topics = list(INPUT_TYPES)
    stamps = {t: set() for t in topics}
    sync = ExactSync(len(topics), 5)
    state = {"emitted": 0, "worked": 0, "skipped": 0, "newest": None, "latency": []}
    cond = threading.Condition()

    def work(seconds):
        if a.work == "sleep":
            time.sleep(seconds)
        elif a.work == "burn":
            burn(seconds)

    def worker():
        while True:
            with cond:
                while state["newest"] is None:
                    cond.wait()
                s, state["newest"] = state["newest"], None
            work(a.work_ms / 1000)
            state["worked"] += 1
            state["latency"].append((time.time_ns() - s) / 1e6)
    if a.where == "worker":
        threading.Thread(target=worker, daemon=True).start()

    def callback(i):
        def on(msg):
            s = stamp_of(msg)
            stamps[topics[i]].add(s)
            for _ in sync.add(i, s, msg):
                state["emitted"] += 1
                if a.where == "worker":
                    with cond:
                        if state["newest"] is not None:
                            state["skipped"] += 1
                        state["newest"] = s
                        cond.notify()
                else:
                    work(a.work_ms / 1000)
                    state["worked"] += 1
                    state["latency"].append((time.time_ns() - s) / 1e6)
        return on
    subs = [node.create_subscription(rclpy_class(INPUT_TYPES[t]), t, callback(i), qos(a.reliability, a.depth))
            for i, t in enumerate(topics)]
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    print("READY", flush=True)
    while not stop.is_set():
        rclpy.spin_once(node, timeout_sec=0.05)
    complete = set.intersection(*stamps.values())
    print("RESULT " + json.dumps(dict(counts={t: len(v) for t, v in stamps.items()}, complete=len(complete),
                                      emitted=state["emitted"], worked=state["worked"], dropped=sync.dropped,
                                      skipped=state["skipped"], latency_ms=statistics.median(state["latency"])
                                      if state["latency"] else None)), flush=True)
    del subs
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


# -- a probe pair: the probe subscriber, then the publisher, in their own processes
def pair_main(a):  # noqa: C901
    scratch = tempfile.mkdtemp(prefix="lidarsgm_stream_")
    atexit.register(shutil.rmtree, scratch, True)
    me = [sys.executable, os.path.abspath(__file__)]
    probe = subprocess.Popen(me + ["_probe", "--reliability", a.sub_reliability, "--depth", str(a.sub_depth),
                                   "--work", a.work, "--where", a.where, "--work-ms", str(a.work_ms)],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             env=profile_env(a.sub_transport, scratch))
    assert probe.stdout.readline().strip() == "READY"
    pub = subprocess.run(me + ["_publish", "--reliability", a.pub_reliability, "--depth", str(a.pub_depth),
                               "--sets", str(a.sets), "--rate", str(a.rate), "--synthetic", "--match-timeout", "20",
                               "--size", a.size,
                               "--linger", "2"],
                         capture_output=True, text=True, env=profile_env(a.pub_transport, scratch))
    time.sleep(1.0)
    probe.send_signal(signal.SIGINT)
    out, _ = probe.communicate(timeout=60)
    res = next((json.loads(line[7:]) for line in out.splitlines() if line.startswith("RESULT ")), None)
    done = next((line for line in pub.stdout.splitlines() if line.startswith("DONE")), "")
    if res is None:
        print("PAIR " + json.dumps(dict(error=out[-2000:] + pub.stdout[-500:] + pub.stderr[-1000:])), flush=True)
        return 1
    res["publish_ms"] = float(done.split()[2]) if done else None
    res["matched"] = "MATCHED" in pub.stdout
    res["sent"] = pub.stdout.count("SENT ")
    print("PAIR " + json.dumps(res), flush=True)
    return 0


def row(name, pub, sub, work="none", where="callback", rate=None):
    """A probe: pub and sub "transport reliability" (the publisher depth 10, the subscription 5, sensor data's)."""
    (pt, pr), (st, sr) = pub.split(), sub.split()
    return name, (pt, pr, 10, st, sr, 5, work, where) + ((rate,) if rate else ())


BE, REL = "best_effort", "reliable"
PROBES = [
    row("defaults, BE pub -> BE sub (sensor data)", "none " + BE, "none " + BE),
    row("defaults, REL pub -> BE sub (sensor data)", "none " + REL, "none " + BE),
    row("defaults, REL pub -> REL sub depth 5", "none " + REL, "none " + REL),
    row("defaults, BE pub -> REL sub (incompatible)", "none " + BE, "none " + REL),
    row("shipped set in process, both, BE pub -> BE sub", "shipped_in_process " + BE, "shipped_in_process " + BE),
    row("shipped sub only, BE pub -> BE sub", "none " + BE, "shipped " + BE),
    row("shipped sub only, REL pub -> BE sub", "none " + REL, "shipped " + BE),
    row("shipped pub only, BE pub -> BE sub", "shipped " + BE, "none " + BE),
    row("shipped both, BE pub -> BE sub", "shipped " + BE, "shipped " + BE),
    row("shipped both, REL pub -> BE sub", "shipped " + REL, "shipped " + BE),
    row("shipped both, REL pub -> REL sub", "shipped " + REL, "shipped " + REL),
    row("udp_only both (4 MB buffers), BE -> BE", "udp_only " + BE, "udp_only " + BE),
    row("udp_only sub only, BE -> BE", "none " + BE, "udp_only " + BE),
    row("udp_only sub only, REL -> BE", "none " + REL, "udp_only " + BE),
    row("shm32+udp pub only, BE -> BE", "shm32+udp " + BE, "none " + BE),
    row("LARGE_DATA both, BE -> BE", "large_data " + BE, "large_data " + BE),
    row("LARGE_DATA sub only, BE -> BE", "none " + BE, "large_data " + BE),
    row("shipped both, BE, sleep 75 ms in callback", "shipped " + BE, "shipped " + BE, "sleep"),
    row("shipped both, BE, CPU 75 ms in callback", "shipped " + BE, "shipped " + BE, "burn"),
    row("shipped both, BE, CPU 75 ms in worker", "shipped " + BE, "shipped " + BE, "burn", "worker"),
    row("shipped both, REL, CPU 75 ms in callback", "shipped " + REL, "shipped " + BE, "burn"),
    row("shipped both, BE, CPU 150 ms in callback", "shipped " + BE, "shipped " + BE, "burn150"),
    row("shipped both, BE, CPU 150 ms in worker", "shipped " + BE, "shipped " + BE, "burn150", "worker"),
    row("shipped both, BE 10 Hz, CPU 150 ms in callback", "shipped " + BE, "shipped " + BE, "burn150", rate=10),
    row("shipped both, BE 10 Hz, CPU 150 ms in worker", "shipped " + BE, "shipped " + BE, "burn150", "worker", 10),
    row("shipped both, BE pub -> BEST_AVAILABLE sub made first", "shipped " + BE, "shipped best_available"),
    row("shipped both, REL pub -> BEST_AVAILABLE sub made first", "shipped " + REL, "shipped best_available"),
]


def probe_table(a):
    me = [sys.executable, os.path.abspath(__file__), "_pair"]
    print("| configuration | left img 1.4 MB | left info | right img 0.47 MB | right info | points 2.2 MB | complete "
          "sets | ExactSync(5) sets | worked | stamp to work done, median | publish ms |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    failures = 0
    for name, row in PROBES:
        if a.only and not any(o in name for o in a.only):
            continue
        (pt, pr, pd, st, sr, sd, work, where), rate = row[:8], (row[8] if len(row) > 8 else a.rate)
        ms = 150 if work == "burn150" else 75
        work = "burn" if work.startswith("burn") else work
        cmd = me + ["--pub-transport", pt, "--pub-reliability", pr, "--pub-depth", str(pd), "--sub-transport", st,
                    "--sub-reliability", sr, "--sub-depth", str(sd), "--work", work, "--where", where,
                    "--work-ms", str(ms), "--sets", str(a.sets), "--rate", str(rate), "--size", a.size]
        if a.netns:
            cmd = ["unshare", "-n", "sh", "-c", 'ip link set lo up && exec "$@"', "sh"] + cmd
        env = dict(os.environ, ROS_DOMAIN_ID=str(random.randint(151, 199)))
        out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600).stdout
        line = next((ln for ln in out.splitlines() if ln.startswith("PAIR ")), None)
        r = json.loads(line[5:]) if line else {"error": out[-1500:]}
        if "error" in r:
            failures += 1
            print("| %s | error: %s |" % (name, r["error"].replace("\n", " ")[-300:]))
            continue
        c = r["counts"]
        print("| %s | %s | %d / %d%s | %d | %d | %s | %s |" % (
            name, " | ".join(str(c[t]) for t in ("left/image_rect", "left/camera_info", "right/image_rect",
                                                 "right/camera_info", "points")),
            r["complete"], r["sent"], "" if r["matched"] else " (no match)", r["emitted"],
            r["worked"], "%.0f ms" % r["latency_ms"] if r["latency_ms"] is not None else "-",
            "%.1f" % r["publish_ms"] if r["publish_ms"] is not None else "-"), flush=True)
    return 1 if failures else 0


# -- the node, streamed to
def rss_kb(pid):
    try:
        with open("/proc/%d/status" % pid) as f:
            return int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))
    except (OSError, AttributeError):
        return None


def percentile(sorted_values, q):
    return sorted_values[min(len(sorted_values) - 1, int(round(q * (len(sorted_values) - 1))))]


def stream_to_node(a):
    """Returns a dict of the run (answered, latency, the node's summary...)."""
    import cv2
    from lidarsgm_ros import kitti
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ.setdefault("ROS_DOMAIN_ID", str(random.randint(151, 199)))
    work = tempfile.mkdtemp(prefix="lidarsgm_stream_")  # kept: the result names its node.log
    # This process reads the node's outputs (reliable, with the package's profile: its losses are not the node's).
    env_here = profile_env("shipped", work)
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = env_here["FASTDDS_DEFAULT_PROFILES_FILE"]
    import rclpy
    from lidarsgm_ros.messages import OUTPUT_TYPES, rclpy_class

    frame = cv2.lidarsgm.loadKittiFrame(KITTI, FRAMES[0])
    t = kitti.ros_calibration(frame.calibration)[3]
    overrides = os.path.join(work, "overrides.yaml")
    with open(overrides, "w") as f:
        f.write("lidarsgm:\n  ros__parameters:\n    params_file: %s\n    recalibration_sets: 0\n"
                "    lidar_to_camera: [%s]\n" % (PARAMS, ", ".join(repr(float(v)) for v in t.ravel())))
    extra = []
    for p in a.param:
        extra += ["-p", p]
    node_env = profile_env(a.node_profile, work)
    node_env.update(PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", ""), PYTHONUNBUFFERED="1",
                    RCUTILS_LOGGING_BUFFERED_STREAM="0")
    log = open(os.path.join(work, "node.log"), "w+")
    node_proc = subprocess.Popen([sys.executable, "-m", a.node_module, "--ros-args", "--params-file", CONFIG,
                                  "--params-file", overrides] + extra, stdout=log, stderr=subprocess.STDOUT,
                                 env=node_env)
    rclpy.init()
    node = rclpy.create_node("stream_receiver")
    got, lock = {}, threading.Lock()

    def on_disparity(msg):
        now = time.time_ns()
        with lock:
            got.setdefault(stamp_of(msg), now)
    node.create_subscription(rclpy_class(OUTPUT_TYPES["disparity"]), "disparity", on_disparity,
                             qos(a.receiver_reliability, 50))
    spinning = threading.Event()
    spinning.set()

    def spin():
        while spinning.is_set():
            rclpy.spin_once(node, timeout_sec=0.05)
    spinner = threading.Thread(target=spin, daemon=True)
    spinner.start()
    result = dict(sets=a.sets, rate=a.rate, reliability=a.reliability, depth=a.depth, size=a.size,
                  receiver=a.receiver_reliability,
                  node_profile=a.node_profile, publisher_profile=a.publisher_profile, log=log.name)
    try:
        end = time.monotonic() + 120
        while not node.count_publishers("disparity"):
            if time.monotonic() > end or node_proc.poll() is not None:
                raise RuntimeError("the node did not come up; its log:\n" + open(log.name).read()[-3000:])
            time.sleep(0.1)
        rss = {"start": rss_kb(node_proc.pid)}
        pub_env = profile_env(a.publisher_profile, work)
        pub_env["PYTHONPATH"] = os.environ.get("PYTHONPATH", "")
        pub = subprocess.Popen([sys.executable, os.path.abspath(__file__), "_publish", "--reliability",
                                a.reliability, "--depth", str(a.depth), "--sets", str(a.sets), "--rate", str(a.rate),
                                "--size", a.size, "--match-timeout", "60", "--linger", "1", "--settle", "2"],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=pub_env)
        sent, done = {}, ""
        for line in pub.stdout:
            if line.startswith("SENT "):
                i, stamp = (int(v) for v in line.split()[1:])
                sent[stamp] = i
                if i == 99:
                    rss["after 100 sets"] = rss_kb(node_proc.pid)
            elif line.startswith("DONE"):
                done = line.strip()
            elif line.startswith("NOMATCH"):
                raise RuntimeError("the publisher found no subscriptions: " + line)
        pub.wait()
        # The last answers: until none came for 3 s (a fusion takes 0.1-0.5 s), 30 s at most.
        end, last = time.monotonic() + 30, -1
        while time.monotonic() < end:
            with lock:
                n = len(got)
            if n == last:
                break
            last = n
            time.sleep(3)
        rss["end"] = rss_kb(node_proc.pid)
    finally:
        text = stop_node(node_proc, 30, log)
        spinning.clear()
        spinner.join()
        node.destroy_node()
        rclpy.try_shutdown()
    summary = [ln for ln in text.splitlines() if ln.startswith("lidarsgm_node: ")]
    lat = sorted((got[s] - s) / 1e6 for s in sent if s in got)
    result.update(sent=len(sent), answered=len(lat), stray=len(set(got) - set(sent)), rss_kb=rss,
                  publish=done, summary=summary[-1][len("lidarsgm_node: "):] if summary else "(no summary)",
                  latency_ms=dict(median=statistics.median(lat), p99=percentile(lat, 0.99), max=lat[-1])
                  if lat else None)
    return result


def node_main(a):
    if a.soak:
        a.sets, a.rate = 2000, 10.0
    r = stream_to_node(a)
    if a.json:
        print(json.dumps(r))
        return 0
    cpu = open("/proc/cpuinfo").read().split("model name")[1].split("\n")[0].strip(": \t")
    print("lidarsgm ROS 2 stream: %s, %d-core %s, load %.2f; tools/ros2_stream.py %s"
          % (time.strftime("%Y-%m-%d %H:%M"), os.cpu_count(), cpu, os.getloadavg()[0], " ".join(sys.argv[1:])))
    print("| sets | rate | publisher | node profile | publisher profile | size | answered | latency median / p99 / max "
          "| node RSS start / 100 / end |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    lat = r["latency_ms"]
    rss = r["rss_kb"]
    print("| %d | %.0f Hz | %s depth %d | %s | %s | %s | %d (%.1f %%) | %s | %s |" % (
        r["sent"], r["rate"], r["reliability"], r["depth"], r["node_profile"], r["publisher_profile"], r["size"],
        r["answered"], 100.0 * r["answered"] / max(r["sent"], 1),
        "%.0f / %.0f / %.0f ms" % (lat["median"], lat["p99"], lat["max"]) if lat else "-",
        " / ".join("%.0f MB" % (rss[k] / 1024) if rss.get(k) else "-" for k in ("start", "after 100 sets", "end"))))
    print("node: " + r["summary"])
    print("publisher: " + r["publish"])
    return 0


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    pr = sub.add_parser("probe", help="where messages are lost: a table of transports, QoS and executor load")
    pr.add_argument("--sets", type=int, default=30)
    pr.add_argument("--rate", type=float, default=5.0)
    pr.add_argument("--only", nargs="*", help="configurations whose names contain one of these")
    pr.add_argument("--netns", action="store_true", help="each pair in a fresh network namespace (unshare -n)")
    pr.add_argument("--size", choices=("kitti", "1080p", "outputs"), default="kitti",
                    help="1080p: the inputs at 1920 x 1080 and a 4.4 MB scan; outputs: the node's at 1080p")
    nd = sub.add_parser("node", help="stream KITTI sets to the node and count its answers")
    nd.add_argument("--sets", type=int, default=100)
    nd.add_argument("--rate", type=float, default=5.0)
    nd.add_argument("--reliability", choices=("best_effort", "reliable"), default="best_effort")
    nd.add_argument("--depth", type=int, default=10)
    nd.add_argument("--size", choices=("kitti", "1080p"), default="kitti")
    nd.add_argument("--node-profile", choices=("none", "shipped"), default="none",
                    help="none: as a user launches it (no FASTDDS_DEFAULT_PROFILES_FILE)")
    nd.add_argument("--publisher-profile", choices=("none", "shipped", "udp_only", "large_data"), default="none")
    nd.add_argument("--param", action="append", default=[], help="a node parameter, NAME:=VALUE")
    nd.add_argument("--soak", action="store_true", help="2000 sets at 10 Hz, the node's RSS")
    nd.add_argument("--receiver-reliability", choices=("best_effort", "reliable"), default="reliable",
                    help="this process's DisparityImage subscription (best_effort: as rviz takes images)")
    nd.add_argument("--node-module", default="lidarsgm_ros.node", help="python -m this (a wrapper to try)")
    nd.add_argument("--json", action="store_true")
    pu = sub.add_parser("_publish")
    pu.add_argument("--reliability", default="best_effort")
    pu.add_argument("--depth", type=int, default=10)
    pu.add_argument("--sets", type=int, default=30)
    pu.add_argument("--rate", type=float, default=5.0)
    pu.add_argument("--size", default="kitti")
    pu.add_argument("--synthetic", action="store_true")
    pu.add_argument("--match-timeout", type=float, default=30)
    pu.add_argument("--settle", type=float, default=1.0)
    pu.add_argument("--linger", type=float, default=2.0)
    ps = sub.add_parser("_probe")
    ps.add_argument("--reliability", default="best_effort")
    ps.add_argument("--depth", type=int, default=5)
    ps.add_argument("--work", choices=("none", "sleep", "burn"), default="none")
    ps.add_argument("--where", choices=("callback", "worker"), default="callback")
    ps.add_argument("--work-ms", type=float, default=75)
    pp = sub.add_parser("_pair")
    for n, d in (("pub-transport", "none"), ("pub-reliability", "best_effort"), ("sub-transport", "none"),
                 ("sub-reliability", "best_effort"), ("work", "none"), ("where", "callback")):
        pp.add_argument("--" + n, default=d)
    for n, d in (("pub-depth", 10), ("sub-depth", 5), ("sets", 30)):
        pp.add_argument("--" + n, type=int, default=d)
    pp.add_argument("--rate", type=float, default=5.0)
    pp.add_argument("--work-ms", type=float, default=75)
    pp.add_argument("--size", default="kitti")
    a = p.parse_args(argv)
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    return {"probe": probe_table, "node": node_main, "_publish": publish_main, "_probe": probe_main,
            "_pair": pair_main}[a.cmd](a)


if __name__ == "__main__":
    sys.exit(main())
