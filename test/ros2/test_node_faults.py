"""The node through what a running robot meets, scripted: a LiDAR gap of seconds, corrupt clouds, clouds with NaN
points, a camera_info of the wrong size (once, then for seconds: the depth dark), an unknown encoding, a repeated
stamp and a jump back in time, and a burst faster than the fusion. The node runs as a user runs it (python3 -m
lidarsgm_ros.node), fed by a publisher here (another process) with the shipped KITTI frames.

Checks: the node is alive at the end; every set outside the burst that the rules say to publish has its outputs,
fused with the LiDAR where a good cloud paired and as stereo alone in the gap and for the corrupt clouds, each
DisparityImage equal to the matcher's own result for that mode on the same images (cv2, not the package); the
skipped sets have none; fusion_status says how each set went; /diagnostics reports each fault class with its level;
fusion resumes after the gap. The same script written to a bag and fused by the bag command gives the same outputs.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

import cv2
import numpy as np

from ros_env import HERE, PACKAGE  # noqa: E402  (before rclpy: the environment the tests run in)
from node_process import log_text, stop_node  # noqa: E402

import rclpy  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray  # noqa: E402
from rclpy.qos import QoSProfile, ReliabilityPolicy  # noqa: E402

from lidarsgm_ros import kitti  # noqa: E402
from lidarsgm_ros.conversions import stamp_ns  # noqa: E402
from lidarsgm_ros.messages import INPUT_TYPES, MessageKit, rclpy_class  # noqa: E402

TESTDATA = os.environ["LIDARSGM_TESTDATA"]
PARAMS = os.path.abspath(os.path.join(HERE, "..", "..", "doc", "params", "kitti_best.yml"))
CONFIG = os.path.join(PACKAGE, "config", "lidarsgm.yaml")
KITTI = os.path.join(TESTDATA, "kitti")
FRAMES = ("000002", "000046")
PERIOD = 10**8  # stamps 0.1 s apart: a 10 Hz rig


def script():
    """The steps: dict(fid, stamp, cloud, info, encoding, pace, expect). cloud: good, none, nan (points behind the
    LiDAR made NaN), point_step, truncated, no_xyz; info: good or wrong_size; pace: step (the next set once this
    one's outputs came), sleep (0.3 s, no output expected), burst (1/100 s); expect: lidar, 'no cloud',
    'bad message' (stereo alone), skip, or None (the burst: any)."""
    steps, t = [], 100 * 10**9

    def add(n, expect, pace="step", **kw):
        nonlocal t
        for _ in range(n):
            step = dict(fid=FRAMES[len(steps) % 2], stamp=t, cloud="good", info="good", encoding=None, pace=pace,
                        expect=expect)
            step.update(kw)
            steps.append(step)
            t += PERIOD
    add(10, "lidar")
    add(32, "no cloud", cloud="none")           # 3.2 s without the LiDAR
    add(6, "lidar")                             # it resumes
    add(1, "bad message", cloud="point_step")
    add(1, "lidar", cloud="nan")
    add(1, "bad message", cloud="truncated")
    add(1, "lidar")
    add(1, "bad message", cloud="no_xyz")
    add(2, "lidar")
    add(1, "skip", info="wrong_size")
    add(1, "skip", encoding="yuv422")
    add(2, "lidar")
    steps.append(dict(steps[-1]))               # the same stamp again
    t -= 20 * 10**9                             # a jump back (a bag loop)
    add(4, "lidar")
    add(14, "skip", pace="sleep", info="wrong_size")  # 4 s of nothing fusable: dark
    add(2, "lidar")
    add(10, None, pace="burst")
    add(4, "lidar")
    return steps


def set_messages(kit, frames, scans, step):
    """[(topic, message)] of one step, in the order a driver set publishes them."""
    points = scans[step["fid"]].copy()
    msgs = kitti.frame_messages(kit, frames[step["fid"]], points, step["stamp"])
    c = msgs["points"]
    if step["cloud"] == "nan":
        raw = np.frombuffer(c.data, np.uint8).reshape(-1, 18)
        xyz = raw[:, :12].copy().view("<f4")
        xyz[xyz[:, 0] < 0] = np.nan        # behind the LiDAR: none of them projects into the image anyway
        raw[:, :12] = xyz.view(np.uint8)
    elif step["cloud"] == "point_step":
        c.point_step += 4
    elif step["cloud"] == "truncated":
        c.data = c.data[:len(c.data) // 2]
    elif step["cloud"] == "no_xyz":
        for f in c.fields:
            f.name = {"x": "a", "y": "b", "z": "c"}.get(f.name, f.name)
    if step["info"] == "wrong_size":
        msgs["left/camera_info"].width = 1000
        msgs["right/camera_info"].width = 1000
    if step["encoding"]:
        msgs["left/image_rect"].encoding = step["encoding"]
    return [(topic, msgs[topic]) for topic in INPUT_TYPES if not (topic == "points" and step["cloud"] == "none")]


def expected(frames):
    """{(fid, 'lidar' | 'alone'): int16 disparity} from cv2 directly: the params file's matcher with the frame's
    sparse map, and the same settings in MODE_SGM with the left-right check without one (the fail-safe's stereo
    alone)."""
    out = {}
    for fid, f in frames.items():
        sgm = cv2.lidarsgm.StereoLidarSGM.load(PARAMS)
        out[fid, "lidar"] = sgm.compute(f.left, f.right, f.sparse)
        sgm.setMode(cv2.lidarsgm.StereoLidarSGM_MODE_SGM)
        sgm.setConsistencyCheck(cv2.lidarsgm.StereoLidarSGM_CHECK_STEREO)
        out[fid, "alone"] = sgm.compute(f.left, f.right, np.zeros(f.sparse.shape, np.float32))
    return out


def disparity16(msg):
    img = msg.image
    data = img.data.tobytes() if hasattr(img.data, "tobytes") else bytes(img.data)
    return np.rint(np.frombuffer(data, np.float32).reshape(img.height, img.width) * 16).astype(np.int16)


def diagnostic_values(msg):
    """{key: value} of a DiagnosticArray's status."""
    return {kv.key: kv.value for kv in msg.status[0].values}


def status_class(msg):
    values = diagnostic_values(msg)
    return "lidar" if values["source"] == "lidar" else values["class"]


class FaultRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="lidarsgm_faults_")
        cls.addClassCleanup(shutil.rmtree, cls.work, True)  # bags of 1.1 GB a run
        cls.frames = {fid: cv2.lidarsgm.loadKittiFrame(KITTI, fid) for fid in FRAMES}
        cls.scans = {fid: cv2.lidarsgm.readVelodyneScan(os.path.join(KITTI, "velodyne", fid + ".bin"))
                     for fid in FRAMES}
        cls.want = expected(cls.frames)
        cls.transform = kitti.ros_calibration(cls.frames[FRAMES[0]].calibration)[3]
        cls.steps = script()

    def check_outputs(self, got, where):
        """got: {stamp: [(class, int16 disparity)]} against the script; returns the classes of the sets fused."""
        burst = {s["stamp"] for s in self.steps if s["expect"] is None}
        by_stamp = {}
        for s in self.steps:
            by_stamp.setdefault(s["stamp"], []).append(s)
        for stamp, steps in by_stamp.items():
            outs = got.get(stamp, [])
            if stamp in burst:
                continue
            want = [s for s in steps if s["expect"] != "skip"]
            self.assertEqual(len(outs), len(want), "%s: set at %d: %d outputs, the script says %d"
                             % (where, stamp, len(outs), len(want)))
            for s, (cls, d16) in zip(want, outs):
                self.assertEqual(cls, s["expect"], "%s: set at %d (%s)" % (where, stamp, s))
                mode = "lidar" if s["expect"] == "lidar" else "alone"
                np.testing.assert_array_equal(d16, self.want[s["fid"], mode],
                                              "%s: set at %d (%s)" % (where, stamp, s))


class NodeFaults(FaultRun):
    def test_node_through_faults_and_the_bag_command_alike(self):
        overrides = os.path.join(self.work, "overrides.yaml")
        with open(overrides, "w") as f:
            f.write("lidarsgm:\n  ros__parameters:\n    params_file: %s\n    recalibration_sets: 0\n"
                    "    lidar_timeout: 0.5\n    lidar_to_camera: [%s]\n"
                    % (PARAMS, ", ".join(repr(float(v)) for v in self.transform.ravel())))
        log = open(os.path.join(self.work, "node.log"), "w+")
        proc = subprocess.Popen(
            [sys.executable, "-m", "lidarsgm_ros.node", "--ros-args", "--params-file", CONFIG,
             "--params-file", overrides], stdout=log, stderr=subprocess.STDOUT,
            env=dict(os.environ, PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", ""),
                     PYTHONUNBUFFERED="1", RCUTILS_LOGGING_BUFFERED_STREAM="0"))
        rclpy.init()
        node = rclpy.create_node("fault_script")
        try:
            pubs = {t: node.create_publisher(rclpy_class(ty), t, 10) for t, ty in INPUT_TYPES.items()}
            disparity, status, reports = {}, {}, []
            node.create_subscription(rclpy_class("stereo_msgs/msg/DisparityImage"), "disparity",
                                     lambda m: disparity.setdefault(stamp_ns(m), []).append(disparity16(m)), 50)
            node.create_subscription(DiagnosticArray, "fusion_status", lambda m: status.setdefault(
                stamp_ns(m), []).append(status_class(m)), QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE))
            report_at = []  # when each /diagnostics report came (the node's executor alive)

            def on_report(m):
                reports.append(m)
                report_at.append(time.monotonic())

            def settled(since):
                # Two reports after `since`, the last with the worker idle and nothing waiting, and no message taken
                # between them: the node has taken and fused (or skipped) everything sent before.
                if len(reports) < 2 or report_at[-2] < since:
                    return False
                a, b = diagnostic_values(reports[-2]), diagnostic_values(reports[-1])
                return b["worker"] == "idle, 0 sets waiting" and a["messages received"] == b["messages received"]
            node.create_subscription(DiagnosticArray, "/diagnostics", on_report, 50)
            kit = MessageKit.rclpy()

            def spin_until(cond, seconds, what):
                end = time.monotonic() + seconds
                while time.monotonic() < end:
                    rclpy.spin_once(node, timeout_sec=0.02)
                    if cond():
                        return
                spy = os.path.join(os.path.dirname(sys.executable), "py-spy")  # where installed: the threads
                dump = subprocess.run([spy, "dump", "--pid", str(proc.pid)], capture_output=True,
                                      text=True).stdout if what and os.path.exists(spy) else ""
                last = "none" if not reports else "%.1f s ago: %s" % (time.monotonic() - report_at[-1], "; ".join(
                    "%s = %s" % kv for kv in diagnostic_values(reports[-1]).items()))
                raise AssertionError("timed out after %d s waiting for %s; the node's last /diagnostics report: %s; "
                                     "its log:\n%s\n%s" % (seconds, what, last, log_text(log), dump))
            spin_until(lambda: all(p.get_subscription_count() for p in pubs.values()), 60, "the node's subscriptions")
            # Warm-up sets, stamped before the script, until one comes back: a best-effort message sent before the
            # node has matched the publisher is lost, as on a robot.
            warm = 50 * 10**9
            for attempt in range(30):
                for topic, msg in set_messages(kit, self.frames, self.scans, dict(self.steps[0], stamp=warm)):
                    pubs[topic].publish(msg)
                try:
                    spin_until(lambda: warm in status, 3, "")
                    break
                except AssertionError:
                    warm += PERIOD
            spin_until(lambda: warm in status, 60, "a warm-up set's outputs")
            # Each set goes once this one's predecessor has its outputs (the script's pace, not a race with the
            # fusion): a set of the gap goes out when the next set comes, as on a rig streaming at its rate.
            pending = None
            count = lambda s: len(status.get(s["stamp"], []))
            need = {}
            for k, s in enumerate(self.steps):
                need[s["stamp"]] = need.get(s["stamp"], 0) + (s["expect"] not in ("skip", None))
                if k and self.steps[k - 1]["pace"] == "burst" and s["pace"] != "burst":
                    # After the burst, what it left is done before the next set goes (else that set, waiting behind
                    # a fusion of the burst's, would be skipped when the one after it comes): the node says so.
                    spin_until(lambda t=time.monotonic(): settled(t), 60, "the node idle after the burst")
                for topic, msg in set_messages(kit, self.frames, self.scans, s):
                    pubs[topic].publish(msg)
                if pending is not None:
                    p = pending
                    spin_until(lambda: count(p) >= need[p["stamp"]], 60, "the outputs of step %d (%s)" % (k - 1, p))
                    pending = None
                if s["pace"] == "step" and s["expect"] != "skip":
                    pending = s
                elif s["pace"] in ("sleep", "burst"):
                    # 0.3 s; a burst at 100 Hz: two sets or more arrive during each fusion (58-80 ms a set on 2
                    # cores), so that the newest wins over one still waiting; at 30 Hz a fusion under 67 ms keeps
                    # up with a set at a time
                    end = time.monotonic() + (0.3 if s["pace"] == "sleep" else 1 / 100)
                    while time.monotonic() < end:
                        rclpy.spin_once(node, timeout_sec=0.02)
            last = self.steps[-1]
            spin_until(lambda: count(last) >= need[last["stamp"]], 60, "the last outputs")
            n = len(reports)
            spin_until(lambda: len(reports) > n + 1, 10, "two reports after the last set")
            self.assertIsNone(proc.poll(), "the node died:\n" + log_text(log))
        finally:
            text = stop_node(proc, 30, log)
            node.destroy_node()
            rclpy.shutdown()
        self.assertEqual(proc.returncode, 0, text)
        got = {st: list(zip(status.get(st, []), disparity.get(st, []))) for st in set(status) | set(disparity)}
        self.check_outputs(got, "node")

        # /diagnostics: each fault class with its level (WARN for what the node rides through, ERROR for the 4 s
        # without a fusable set), and the counts at the end.
        seen = [(r.status[0].level[0] if isinstance(r.status[0].level, bytes) else r.status[0].level,
                 r.status[0].message) for r in reports]
        for level, text_part in ((1, "stereo alone (no cloud): no cloud on /points within 0.50 s"),
                                 (1, "stereo alone (bad message): the cloud: "),
                                 (1, "a set skipped (bad message)"),
                                 (1, "time went back"),
                                 (1, "input faster than the fusion"),
                                 (2, "no output for "),
                                 (0, "fused with the LiDAR")):
            self.assertTrue(any(lv == level and text_part in m for lv, m in seen),
                            "no report at level %d with '%s' among:\n%s" % (level, text_part, "\n".join(
                                "%d %s" % x for x in seen)))
        values = diagnostic_values(reports[-1])
        # (a cloud lost on the way in the burst or the warm-up would add one there)
        self.assertGreaterEqual(int(values["stereo alone: no cloud"]), 32)
        self.assertEqual(values["stereo alone: bad message"], "3")
        self.assertEqual(values["skipped: bad message"], "16")
        self.assertEqual(values["synchroniser restarts (time went back)"], "2")
        self.assertGreater(int(values["skipped: overload"]), 0)
        self.assertGreater(int(values["non-finite points dropped"]), 0)
        self.assertIn("lidarsgm_node: ", text)

        # The bag command on the same script, written as a rosbag2 in the order it was published.
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
        ts = get_typestore(Stores.ROS2_JAZZY)
        bkit = MessageKit.rosbags(ts)
        bag = os.path.join(self.work, "script_bag")
        with Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP) as w:
            conns = {n: w.add_connection("/" + n, t, typestore=ts) for n, t in INPUT_TYPES.items()}
            t_rec = 10**9
            for s in self.steps:
                for topic, msg in set_messages(bkit, self.frames, self.scans, s):
                    t_rec += 1000
                    w.write(conns[topic], t_rec, ts.serialize_cdr(msg, INPUT_TYPES[topic]))
        out = os.path.join(self.work, "script_out")
        r = subprocess.run([sys.executable, "-m", "lidarsgm_ros.bag", bag, out, "--params-file", PARAMS,
                            "--lidar-timeout", "0.5", "--recalibration-sets", "0", "--lidar-to-camera"] +
                           [repr(float(v)) for v in self.transform.ravel()], capture_output=True, text=True,
                           env=dict(os.environ, PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", "")))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        bag_got = {}
        with AnyReader(sorted(Path(out).glob("part_*"))) as reader:
            disp_b, status_b = {}, {}
            for conn, _, raw in reader.messages():
                m = reader.deserialize(raw, conn.msgtype)
                if conn.topic == "/disparity":
                    disp_b.setdefault(stamp_ns(m), []).append(disparity16(m))
                elif conn.topic == "/fusion_status":
                    status_b.setdefault(stamp_ns(m), []).append(status_class(m))
            bag_got = {st: list(zip(status_b.get(st, []), disp_b.get(st, []))) for st in set(status_b) | set(disp_b)}
        self.check_outputs(bag_got, "bag")
        self.assertIn("sets fused as stereo alone (32 no cloud, 0 calibration, 3 bad message)", r.stdout)


if __name__ == "__main__":
    unittest.main()
