"""The ROS 2 node, run as a user runs it (python3 -m lidarsgm_ros.node with the shipped parameters file), fed by a
real rclpy publisher that replays the shipped KITTI frames as Image, CameraInfo and PointCloud2 (the Velodyne scan
with a ring field). Discovery stays on this machine (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, a domain of its own); both sides use the
package's Fast DDS profile for megabyte messages (config/fastdds_large_data.xml).

Checks: the DisparityImage equals the tool's output for the frame pixel for pixel (and the same call through cv2);
its D1 against the ground truth; depth and points against cv2.lidarsgm.disparityToDepth / disparityToPoints; a frame
whose cloud has no x/y/z is fused as stereo alone with the reason logged; a value the module refuses is refused at
run time with its message, the old value kept. A second node takes the transform from tf instead (a /tf_static and a
/tf publisher): stereo alone with a warning before tf has it, then the same DisparityImages, and a change on /tf taken.
(test_node_faults.py drives a node through the faults a robot meets.)
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import cv2
import numpy as np

from ros_env import HERE, PACKAGE  # noqa: E402  (before rclpy: the environment the tests run in)
from node_process import log_text, stop_node  # noqa: E402

import rclpy  # noqa: E402
from rcl_interfaces.srv import GetParameters, SetParameters  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray  # noqa: E402
from tf2_msgs.msg import TFMessage  # noqa: E402
from geometry_msgs.msg import TransformStamped  # noqa: E402

from lidarsgm_ros import kitti  # noqa: E402
from lidarsgm_ros.conversions import stamp_ns  # noqa: E402
from lidarsgm_ros.messages import INPUT_TYPES, OUTPUT_TYPES, MessageKit, rclpy_class  # noqa: E402
from lidarsgm_ros.transforms import rotation_quaternion, transform_matrix  # noqa: E402

TESTDATA = os.environ["LIDARSGM_TESTDATA"]
TOOL = os.environ["LIDARSGM_TOOL"]
PARAMS = os.path.join(HERE, "..", "..", "doc", "params", "kitti_best.yml")
CONFIG = os.path.join(PACKAGE, "config", "lidarsgm.yaml")
FRAMES = ("000002", "000046")
KITTI = os.path.join(TESTDATA, "kitti")

def wait_for(node, condition, seconds, what):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
        if condition():
            return
    raise AssertionError("timed out after %d s waiting for %s" % (seconds, what))


def array_of(img):
    dt = {"32FC1": np.float32, "16UC1": np.uint16}[img.encoding]
    return np.frombuffer(bytes(img.data), dt).reshape(img.height, img.width)


def pitched(degrees, m):
    """m with a rotation about the camera's x axis before it."""
    a = np.radians(degrees)
    pitch = np.eye(4)
    pitch[1:3, 1:3] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    return pitch @ m


class NodeRun(unittest.TestCase):
    """The node in its own process, fed and read by a replay node here (USE_TF: no lidar_to_camera parameter)."""
    USE_TF = False

    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="lidarsgm_ros_")
        cls.addClassCleanup(shutil.rmtree, cls.work, True)
        frame = cv2.lidarsgm.loadKittiFrame(KITTI, FRAMES[0])
        t = kitti.ros_calibration(frame.calibration)[3]
        overrides = os.path.join(cls.work, "overrides.yaml")
        with open(overrides, "w") as f:  # what a user adds for their robot: the calibration and the params file
            f.write("lidarsgm:\n  ros__parameters:\n    params_file: %s\n    publish_confidence: true\n"
                    "    sync_warning_seconds: 1.0\n    check_calibration_every: 1\n" % os.path.abspath(PARAMS))
            # No recalibration until a test turns it on: on a loaded machine a set sent again while the node is busy
            # adds to the pool, and a default pool of 8 could fill before the test sets its own size.
            f.write("    recalibration_sets: 0\n")
            if not cls.USE_TF:
                f.write("    lidar_to_camera: [%s]\n" % ", ".join(repr(float(v)) for v in t.ravel()))
        cls.lidar_to_camera = t
        cls.log = open(os.path.join(cls.work, "node.log"), "w+")
        cls.proc = subprocess.Popen(
            [sys.executable, "-m", "lidarsgm_ros.node", "--ros-args", "--params-file", CONFIG,
             "--params-file", overrides], stdout=cls.log, stderr=subprocess.STDOUT,
            env=dict(os.environ, PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", ""),
                     PYTHONUNBUFFERED="1", RCUTILS_LOGGING_BUFFERED_STREAM="0"))
        rclpy.init()
        cls.node = rclpy.create_node("kitti_replay")
        cls.pubs = {topic: cls.node.create_publisher(rclpy_class(t), topic, 10)
                    for topic, t in INPUT_TYPES.items()}
        cls.got = {topic: {} for topic in OUTPUT_TYPES}  # topic -> {stamp: message}
        for topic, t in OUTPUT_TYPES.items():
            cls.node.create_subscription(rclpy_class(t), topic, lambda m, topic=topic: cls.got[topic].__setitem__(
                stamp_ns(m), m), 10)
        cls.status = {}  # stamp -> fusion_status's source ("lidar" or "stereo alone") and class
        cls.node.create_subscription(DiagnosticArray, "fusion_status", lambda m: cls.status.__setitem__(
            stamp_ns(m), tuple(kv.value for kv in m.status[0].values)), QoSProfile(depth=10))
        cls.kit = MessageKit.rclpy()
        wait_for(cls.node, lambda: all(p.get_subscription_count() for p in cls.pubs.values()), 60,
                 "the node's subscriptions")

    @classmethod
    def tearDownClass(cls):
        stop_node(cls.proc, 20)
        cls.node.destroy_node()
        rclpy.shutdown()

    def node_log(self):
        return log_text(self.log)

    def publish(self, fid, stamp, break_cloud=False):
        frame = cv2.lidarsgm.loadKittiFrame(KITTI, fid)
        points = cv2.lidarsgm.readVelodyneScan(os.path.join(KITTI, "velodyne", fid + ".bin"))
        msgs = kitti.frame_messages(self.kit, frame, points, stamp)
        if break_cloud:
            for f in msgs["points"].fields:
                f.name = {"x": "a", "y": "b", "z": "c"}.get(f.name, f.name)
        for topic, msg in msgs.items():
            self.pubs[topic].publish(msg)
        return frame

    def wait(self, condition, seconds, what):
        try:
            wait_for(self.node, condition, seconds, what)
        except AssertionError as e:
            raise AssertionError("%s; outputs received %s; the node's log:\n%s"
                                 % (e, {k: len(v) for k, v in self.got.items()}, self.node_log()))

    def expect_outputs(self, stamp, seconds=120):
        self.wait(lambda: all(stamp in v for v in self.got.values()), seconds, "the outputs of %d" % stamp)

    def publish_until_fused(self, fid, stamp, before=None, lidar=True):
        """Publishes the frame, again under a later stamp every 3 s until its outputs come (fused with its LiDAR
        unless lidar is False: a transform the test made wrong): a best-effort message sent before the node's
        subscription has matched the publisher is lost, as on a robot (a lost cloud gives stereo alone).
        before(stamp) runs ahead of each attempt. The outputs of any stamp sent count (under load a fusion may take
        longer than the 3 s). Returns the frame and the stamp whose outputs came."""
        sent = []
        done = lambda: next((s for s in sent if all(s in v for v in self.got.values()) and
                             (not lidar or self.status.get(s, ("",))[0] == "lidar")), None)
        for attempt in range(40):
            if before:
                before(stamp)
                rclpy.spin_once(self.node, timeout_sec=0.05)
            frame = self.publish(fid, stamp)
            sent.append(stamp)
            try:
                wait_for(self.node, lambda: done() is not None, 3, "outputs")
                return frame, done()
            except AssertionError:
                stamp += 10**7
        self.expect_outputs(stamp, 0)

    def tool_disparity(self, fid):
        out = os.path.join(self.work, "tool_" + fid)
        subprocess.run([TOOL, "--kitti-frame", KITTI, "--id", fid, "--params", PARAMS, "--modes", "sdsgm",
                        "--out", out], check=True, stdout=subprocess.DEVNULL)
        return cv2.imread(os.path.join(out, "disparity.png"), cv2.IMREAD_UNCHANGED)

    def check_frame(self, stamp, fid, frame, sparse=None):
        """The outputs of one set against the tool's and cv2's (with the frame's sparse map, or `sparse`: a
        transform other than KITTI's, where only the cv2 call can follow)."""
        d = self.got["disparity"][stamp]
        disp = np.frombuffer(bytes(d.image.data), np.float32).reshape(d.image.height, d.image.width)
        disp16 = np.rint(disp * 16).astype(np.int16)
        np.testing.assert_array_equal(disp16.astype(np.float32) / 16, disp)  # 1/16 px steps, as delta_d says
        # Pixel for pixel the tool's output (its KITTI PNG) and the same call through cv2.
        if sparse is None:
            np.testing.assert_array_equal(cv2.lidarsgm.encodeKittiDisparity(disp), self.tool_disparity(fid))
            sparse = frame.sparse
        sgm = cv2.lidarsgm.StereoLidarSGM.load(PARAMS)
        np.testing.assert_array_equal(disp16, sgm.compute(frame.left, frame.right, sparse))
        e = cv2.lidarsgm.evaluateDisparity(disp16, frame.groundTruth)
        print("%s: coverage %.2f %%, total D1 %.2f %% (DisparityImage against the ground truth)"
              % (fid, e.coverage(), e.totalError()))
        self.assertGreater(e.coverage(), 99.0)
        self.assertLess(e.totalError(), 3.0)
        fb = frame.calibration.focalBaseline
        f = frame.calibration.projection[0, 0]  # f and t are float32 in the message
        self.assertEqual(d.f, float(np.float32(f)))
        self.assertEqual(d.t, float(np.float32(fb / f)))
        self.assertEqual((d.min_disparity, d.max_disparity, d.delta_d), (0.0, 127.0, 1 / 16))
        self.assertEqual(d.header.frame_id, kitti.LEFT_FRAME)
        valid = np.argwhere(disp16 >= 0)
        w = d.valid_window
        self.assertEqual((w.y_offset, w.x_offset), tuple(valid.min(axis=0)))
        self.assertEqual((w.y_offset + w.height - 1, w.x_offset + w.width - 1), tuple(valid.max(axis=0)))
        self.assertTrue(np.all(disp[disp16 < 0] < d.min_disparity))  # invalid below min_disparity
        # REP 118 depth (32FC1, metres, NaN invalid) and the organised cloud against the library's conversions.
        depth = array_of(self.got["depth"][stamp])
        ref = cv2.lidarsgm.disparityToDepth(disp16, fb)
        np.testing.assert_array_equal(np.isnan(depth), ref == 0)
        np.testing.assert_array_equal(depth[ref > 0], ref[ref > 0])
        c = self.got["points2"][stamp]
        self.assertEqual((c.height, c.width, c.point_step, c.is_dense), (d.image.height, d.image.width, 16, False))
        self.assertEqual([(f.name, f.offset, f.datatype) for f in c.fields],
                         [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("rgb", 12, 7)])
        rec = np.frombuffer(bytes(c.data), np.float32).reshape(c.height, c.width, 4)
        q = cv2.lidarsgm.reprojectionMatrix(frame.calibration.projection, fb)
        np.testing.assert_array_equal(rec[..., :3], cv2.lidarsgm.disparityToPoints(disp16, q))
        bgr = frame.leftImage.astype(np.uint32)
        np.testing.assert_array_equal(rec[..., 3].view(np.uint32), (bgr[..., 2] << 16) | (bgr[..., 1] << 8) | bgr[..., 0])
        conf = array_of(self.got["confidence"][stamp])
        _, ref_conf = sgm.computeWithConfidence(frame.left, frame.right, sparse)
        np.testing.assert_array_equal(conf, ref_conf)

    def call(self, srv_type, name, request, seconds=30):
        client = self.node.create_client(srv_type, "/lidarsgm/" + name)
        self.assertTrue(client.wait_for_service(timeout_sec=seconds), name)
        future = client.call_async(request)
        wait_for(self.node, future.done, seconds, name)
        return future.result()



class NodeTest(NodeRun):
    def test_frames_bad_frame_and_parameters(self):
        f0, stamp = self.publish_until_fused(FRAMES[0], 10**9)
        self.check_frame(stamp, FRAMES[0], f0)

        # A broken cloud: its images fused as stereo alone (the matcher in MODE_SGM without a sparse map), the
        # reason in the log and on fusion_status; the next set fused with its LiDAR. (The sensor-data QoS is best
        # effort, as on a robot: a message may be lost under load, so each is sent again under a later stamp until
        # its effect shows.)
        broken = 2 * 10**9
        for attempt in range(40):
            self.publish(FRAMES[0], broken, break_cloud=True)
            try:
                wait_for(self.node, lambda: self.status.get(broken) == ("stereo alone", "bad message"), 3, "")
                break
            except AssertionError:
                broken += 10**7
        f1, stamp = self.publish_until_fused(FRAMES[1], 3 * 10**9)
        self.check_frame(stamp, FRAMES[1], f1)
        self.assertIn("fused as stereo alone: the cloud: the point cloud has no x/y/z field (fields: a, b, c, "
                      "intensity, ring)", self.node_log())
        sgm = cv2.lidarsgm.StereoLidarSGM.load(PARAMS)
        sgm.setMode(cv2.lidarsgm.StereoLidarSGM_MODE_SGM)
        sgm.setConsistencyCheck(cv2.lidarsgm.StereoLidarSGM_CHECK_STEREO)
        d = self.got["disparity"][broken]
        disp = np.frombuffer(bytes(d.image.data), np.float32).reshape(d.image.height, d.image.width)
        np.testing.assert_array_equal(np.rint(disp * 16).astype(np.int16),
                                      sgm.compute(f0.left, f0.right, np.zeros(f0.sparse.shape, np.float32)))

        # Images without their camera_info never make a set: the node says so, with what it received. (Its warnings
        # repeat while inputs wait; one may also come at the start, before discovery lets every topic through: the
        # counts are those of the warnings after these messages. A message lost on the way, here or at the start,
        # is made up for by sending the set again under a later stamp until the left images lead their
        # camera_info.)
        mark = len(self.node_log())
        scan = cv2.lidarsgm.readVelodyneScan(os.path.join(KITTI, "velodyne", FRAMES[1] + ".bin"))

        def counts():
            warnings = self.node_log()[mark:].split("received so far: ")
            return {t: int(n) for t, n in re.findall(r"(\S+) (\d+)[,(]", warnings[-1])} if len(warnings) > 1 else {}
        ahead = lambda: counts().get("left/image_rect", -1) > counts().get("left/camera_info", 10**9)
        for attempt in range(10):
            for topic, msg in kitti.frame_messages(self.kit, f1, scan, 4 * 10**9 + attempt * 10**7).items():
                if "camera_info" not in topic:
                    self.pubs[topic].publish(msg)
            try:
                wait_for(self.node, ahead, 3, "")
                break
            except AssertionError:
                pass
        self.wait(ahead, 10, "the sync warning with the left images ahead of their camera_info")
        self.assertIn("(exact sync: every input needs the same stamp; approximate_sync takes the nearest)",
                      self.node_log())

        # At run time: a value the module refuses is refused with its message; a good one is taken.
        req = SetParameters.Request(parameters=[Parameter("P1", value=5000).to_parameter_msg()])
        res = self.call(SetParameters, "set_parameters", req).results[0]
        self.assertFalse(res.successful)
        self.assertIn("P1 (the penalty of a disparity step of 1) must be in [0, 1000]; got 5000", res.reason)
        req = SetParameters.Request(parameters=[Parameter("P2", value=5).to_parameter_msg()])  # P1 10 > P2 5
        res = self.call(SetParameters, "set_parameters", req).results[0]
        self.assertFalse(res.successful)
        self.assertIn("P1 (10) must not exceed P2 (5)", res.reason)
        req = SetParameters.Request(parameters=[Parameter("mode", value="dsgm").to_parameter_msg(),
                                                Parameter("P1", value=8).to_parameter_msg()])
        self.assertTrue(all(r.successful for r in self.call(SetParameters, "set_parameters", req).results))
        values = self.call(GetParameters, "get_parameters", GetParameters.Request(names=["P1", "P2", "mode"])).values
        self.assertEqual((values[0].integer_value, values[1].integer_value, values[2].string_value),
                         (8, 120, "dsgm"))
        self.assertIn("parameter refused, the old value stays: P1:", self.node_log())

        # Every set is checked against its images (check_calibration_every 1): KITTI's calibration passes; with a
        # degree of pitch added at run time the next set draws the warning.
        self.assertNotIn("from where the images match", self.node_log())
        wrong = [float(v) for v in pitched(1.0, self.lidar_to_camera).ravel()]
        req = SetParameters.Request(parameters=[Parameter("lidar_to_camera", value=wrong).to_parameter_msg()])
        self.assertTrue(self.call(SetParameters, "set_parameters", req).results[0].successful)
        self.publish_until_fused(FRAMES[1], 5 * 10**9, lidar=False)
        self.wait(lambda: "from where the images match" in self.node_log(), 10, "the calibration warning")
        r = float(re.search(r"the LiDAR lies ([\d.]+) px \(median\) from where the images match, more than 1 px",
                            self.node_log()).group(1))
        self.assertGreater(r, 1.0)
        # The fail-safe: that set was fused as stereo alone. With a pool of two sets, the next two are too, the
        # rotation is refined from them in the background, and the node switches to the corrected transform.
        self.wait(lambda: "fused as stereo alone; check lidar_to_camera" in self.node_log(), 10, "the fail-safe")
        req = SetParameters.Request(parameters=[Parameter("recalibration_sets", value=2).to_parameter_msg(),
                                                Parameter("scan_rate", value=10.0).to_parameter_msg()])
        self.assertTrue(all(r.successful for r in self.call(SetParameters, "set_parameters", req).results))
        for k, fid in enumerate(FRAMES):
            self.publish_until_fused(fid, (6 + k) * 10**9, lidar=False)
        self.wait(lambda: "switched to the corrected transform" in self.node_log(), 120, "the recalibration")
        m = re.search(r"correction from 2 sets: pitch ([-+\d.]+) \+- [\d.]+, .* calibration residual [\d.]+ -> "
                      r"([\d.]+) px; switched", self.node_log())
        self.assertIsNotNone(m, self.node_log())
        self.assertLess(abs(float(m.group(1)) + 1.0), 0.2)   # the degree of pitch undone
        self.assertLessEqual(float(m.group(2)), 1.0)


def transform_stamped(parent, child, m, stamp):
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.header.stamp.sec, t.header.stamp.nanosec = stamp // 10**9, stamp % 10**9
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = (float(v) for v in m[:3, 3])
    q = rotation_quaternion(m[:3, :3])
    t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w = q
    return t


class NodeTfTest(NodeRun):
    """The transform from tf, as a robot publishes it from its URDF: base_link -> camera_left_optical and base_link ->
    velodyne on /tf_static; then the LiDAR's link changed on /tf."""
    USE_TF = True

    def publish_tf(self, base_to_lidar, stamp):
        self.tf_pub.publish(TFMessage(transforms=[transform_stamped("base_link", kitti.LIDAR_FRAME, base_to_lidar,
                                                                    stamp)]))

    def fuse_with_tf(self, fid, stamp, base_to_lidar, lidar=True):
        """As publish_until_fused, the /tf sample of each stamp sent before its set."""
        return self.publish_until_fused(fid, stamp, lambda t: self.publish_tf(base_to_lidar, t), lidar)

    def test_transform_from_tf(self):
        # Without tf: stereo alone, with a warning.
        stamp = 10**9
        for attempt in range(40):
            self.publish(FRAMES[0], stamp + attempt * 10**7)
            try:
                wait_for(self.node, lambda: "no transform from the cloud's frame 'velodyne' to the left camera's "
                         "'camera_left_optical'" in self.node_log(), 3, "")
                break
            except AssertionError:
                pass
        self.wait(lambda: "tf has none yet (/tf_static, /tf), or set lidar_to_camera" in self.node_log(), 10,
                  "the missing-tf warning")
        self.wait(lambda: self.status, 10, "a fusion_status")
        self.assertEqual(set(self.status.values()), {("stereo alone", "calibration")})

        # The body frame: 1.2 m behind and 0.3 m left of the camera, x forward, z up (REP 103), the camera's optical
        # frame x right, y down, z forward (REP 105); the LiDAR from the KITTI calibration through it. tf carries
        # rotations as unit quaternions, so KITTI's calibration (orthonormal to about 1e-6 only) arrives as the
        # nearest rotation: the reference is the parameter's result for that rigid transform.
        base_to_camera = np.array([[0, 0, 1, -1.2], [-1, 0, 0, 0.3], [0, -1, 0, 1.65], [0, 0, 0, 1]], np.float64)
        t = self.lidar_to_camera
        rigid = transform_matrix(t[:3, 3], rotation_quaternion(t[:3, :3]))
        base_to_lidar = base_to_camera @ rigid
        static_qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                                reliability=ReliabilityPolicy.RELIABLE)
        static = self.node.create_publisher(TFMessage, "/tf_static", static_qos)
        static.publish(TFMessage(transforms=[transform_stamped("base_link", kitti.LEFT_FRAME, base_to_camera, 0),
                                             transform_stamped("base_link", kitti.LIDAR_FRAME, base_to_lidar, 0)]))
        self.tf_pub = self.node.create_publisher(TFMessage, "/tf", QoSProfile(depth=100))
        self.wait(lambda: self.tf_pub.get_subscription_count() > 0, 30, "the node's /tf subscription")
        # The generated tf2_msgs (ros2/tf2_msgs) has the official type hash, as rosbags computes it.
        from rosbags.typesys import Stores, get_typestore
        info = [i for i in self.node.get_subscriptions_info_by_topic("/tf") if i.node_name == "lidarsgm"]
        self.assertEqual(str(info[0].topic_type_hash),
                         get_typestore(Stores.ROS2_KILTED).hash_rihs01("tf2_msgs/msg/TFMessage"))

        # Pixel for pixel what the parameter gives with that transform (cv2's call on the same projection).
        for k, fid in enumerate(FRAMES):
            f, stamp = self.publish_until_fused(fid, (2 + k) * 10**9)
            points = cv2.lidarsgm.readVelodyneScan(os.path.join(KITTI, "velodyne", fid + ".bin"))[:, :3].copy()
            left_p = kitti.ros_calibration(f.calibration)[1]
            sparse = cv2.lidarsgm.projectPointsToDisparity(points, left_p, rigid, f.calibration.focalBaseline,
                                                           (f.left.shape[1], f.left.shape[0]))
            self.assertGreater(cv2.countNonZero(sparse), 10000)
            self.check_frame(stamp, fid, f, sparse)
        self.assertNotIn("from where the images match", self.node_log())

        # The LiDAR's link pitched by a degree on /tf at run time (a knocked mount, as a calibration node would
        # publish it): the next set is checked under it (the matching residual warning and the fail-safe).
        self.fuse_with_tf(FRAMES[1], 4 * 10**9, base_to_camera @ pitched(1.0, rigid), lidar=False)
        self.wait(lambda: "from where the images match" in self.node_log(), 10, "the calibration warning")
        self.wait(lambda: "fused as stereo alone; check lidar_to_camera" in self.node_log(), 10, "the fail-safe")


if __name__ == "__main__":
    unittest.main()
