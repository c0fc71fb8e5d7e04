"""lidarsgm_node: stereo-LiDAR fusion as a ROS 2 node, launched like stereo_image_proc's disparity node.

Subscribes left/image_rect, left/camera_info, right/image_rect, right/camera_info and points (PointCloud2), time
synchronised (exact stamps, or approximately with approximate_sync); publishes disparity (stereo_msgs/
DisparityImage), depth (REP 118) and points2 (an organised x y z rgb PointCloud2 in the left optical frame), and
with publish_confidence the confidence (32FC1 in [0, 1]). Every check_calibration_every-th set it measures how far
the LiDAR lies from where the images match (cv2.lidarsgm.matchingResidual) and warns above 1 px: a calibration off.

The LiDAR-to-camera transform comes from tf: /tf_static and /tf, from the cloud's frame_id to the left camera_info's
frame_id (its optical frame), chained through the tree as the robot's URDF publishes it. A /tf edge is taken at the
cloud's stamp, interpolated between the samples around it, or the nearest sample within tf_tolerance_seconds where
none lies after (or before) it. While no chain links the two frames the node warns (every 5 s) and publishes
nothing. The lidar_to_camera parameter (16 numbers) overrides tf. The left camera_info's R then turns the transform
into the rectified frame. Raw images (left/image_rect remapped to an image_raw topic) are refused where their
camera_info has distortion or a rectification rotation, unless rectify rectifies them here.

The fail-safe: a set whose LiDAR lands misplaced on its images (cv2.lidarsgm.checkLidar, every set) is fused as
stereo alone, with a warning (trust_lidar fuses it anyway). Those sets are pooled, and in the background the node
refines the rotation from the last recalibration_sets of them (cv2.lidarsgm.LidarCalibration; scan_rate for scans
that are not motion-compensated); it switches to the corrected transform once that brings the residual under 1 px
and every pooled set's LiDAR is trusted under it, and logs the correction, its uncertainty and the new transform.

  python3 -m lidarsgm_ros.node --ros-args -p params_file:=doc/params/kitti_best.yml \
      -r left/image_rect:=/stereo/left/image_rect ...        # the transform from tf
  python3 -m lidarsgm_ros.node --ros-args -p lidar_to_camera:="[...16 numbers...]" ...  # or given

The node never goes dark for want of the LiDAR: an image pair that no cloud pairs with within lidar_timeout (the
LiDAR silent: a cable, a driver restart, a bag without the cloud) is fused as stereo alone, the fail-safe's path,
and published on the same topics; fusion with the LiDAR resumes with the next cloud that pairs. A cloud that cannot
be read, and a missing transform, give stereo alone too. Each set that goes out has its status on fusion_status
(diagnostic_msgs/DiagnosticArray, the images' header, latched: OK fused with the LiDAR, WARN stereo alone and why),
and /diagnostics has the node's state once a second (lidarsgm_ros.health gives the rules).

Messages are taken as they arrive and fused by a worker thread: when sets complete faster than they are fused,
the newest wins and the older ones waiting are skipped and counted, so no queue grows (the sets that one message
releases together, such as the pairs a returning cloud lets go, are fused in order). A stamp that repeats or goes
back (a bag played in a loop, a clock reset) restarts the synchroniser. A set whose images cannot be fused (a
camera_info of another size, an unknown encoding) is logged with the reason and skipped.

Every parameter but params_file can be changed while the node runs; a value the module refuses is refused with
its message and the old value stays.

Fast DDS: the node runs with the package's profile (config/fastdds_large_data.xml: 32 MiB shared-memory segments)
unless FASTDDS_DEFAULT_PROFILES_FILE or FASTDDS_BUILTIN_TRANSPORTS say otherwise. On the wheels' defaults a process
loses most messages of a megabyte and more that it publishes (a 512 KiB segment); the drivers that feed the node need
the profile too (doc/design.md, section 9).
"""
import os
import statistics
import sys
import threading
import time
from collections import deque

import cv2
import numpy as np
import rclpy
import rclpy.exceptions
from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from diagnostic_msgs.msg import DiagnosticArray
from tf2_msgs.msg import TFMessage

from . import health
from .conversions import ConversionError, stamp_ns
from .fusion import (ALONE_CLASSES, CALIBRATION, MATCHER_PARAMETERS, NO_CLOUD, Fusion,
                     residual_summary)
from .messages import INPUT_TYPES, OUTPUT_TYPES, MessageKit, output_messages, rclpy_class
from .recalibration import Recalibration
from .sync import ApproximateSync, ExactSync, LidarPairing
from .transforms import TransformBuffer

MATCHER = object()  # a parameter's default: the matcher's value, from the params file (or the module's)


def _matcher(node, p):
    if p.value != node.fusion.value(p.name):
        node.fusion.set(p.name, p.value)


def _use_cuda(node, p):
    node.fusion.set_use_cuda(p.value)


def _lidar_to_camera(node, p):
    if p.type_ != Parameter.Type.NOT_SET:
        node.fusion.set_lidar_to_camera(list(p.value))


def _flag(attribute):
    """Applies a parameter as the Fusion attribute of that name (True or False)."""
    def apply(node, p):
        setattr(node.fusion, attribute, bool(p.value))
    return apply


def _check(valid, refusal):
    """Refuses a value for which valid(value) is false, saying refusal % {"value": value}."""
    def apply(node, p):
        if not valid(p.value):
            raise ValueError(refusal % {"value": p.value})
    return apply


def _at_start(check=None):
    """A parameter read when the node starts: checked by `check` where given, and refused once the node runs."""
    def apply(node, p):
        if check is not None:
            check(node, p)
        if hasattr(node, "sync"):
            raise ValueError("%s is read when the node starts" % p.name)
    return apply


# The node's parameters but params_file (declared first: the matcher is made from it), in the order they are declared
# and applied: (name, default, description, apply). default: a value, whose type is the parameter's; a Parameter.Type
# for none (unset until given); or MATCHER. apply(node, parameter) sets the value or raises ValueError with the
# refusal the user sees; None where the value is read where it is used.
PARAMETERS = tuple((name, MATCHER, None, _matcher) for name in MATCHER_PARAMETERS) + (
    ("mode", MATCHER, "sgm, dsgm or sdsgm", _matcher),
    ("use_cuda", False, "fuse on the GPU (a CUDA build of cv2)", _use_cuda),
    ("lidar_to_camera", Parameter.Type.DOUBLE_ARRAY,
     "4x4 (or 3x4) transform from the points' frame to the left optical frame, row by row; unset: from tf",
     _lidar_to_camera),
    ("tf_tolerance_seconds", 0.1, "how far from the cloud's stamp the nearest /tf sample may lie where none "
     "lies on its other side (read when the node starts)",
     _at_start(_check(lambda v: v >= 0, "tf_tolerance_seconds must be >= 0"))),
    ("depth_encoding", "32FC1", "32FC1 (metres, NaN invalid) or 16UC1 (millimetres, 0 invalid)",
     _check(lambda v: v in ("32FC1", "16UC1"), "depth_encoding must be 32FC1 or 16UC1, not '%(value)s'")),
    ("publish_confidence", False, "publish each pixel's confidence (32FC1 in [0, 1]) on confidence", None),
    ("check_calibration_every", 10, "every n-th fused set, measure the LiDAR against the images "
     "(matchingResidual, about 3 % of a CPU fusion) and warn above 1 px; 0: never",
     _check(lambda v: v >= 0, "check_calibration_every must be >= 0 (0: never), not %(value)d")),
    ("rectify", False, "the images are raw (left/image_rect remapped to an image_raw topic): rectify them "
     "with their camera_info's K, D, R and P", _flag("rectify")),
    ("trust_lidar", False, "fuse every set with its LiDAR, also where it lands misplaced on the images",
     _flag("trust_lidar")),
    ("recalibration_sets", 8, "refine the rotation in the background from the last n sets fused as stereo "
     "alone, and switch to it once it fits (0: never)",
     _check(lambda v: not (v < 0 or v == 1), "recalibration_sets must be 0 (never) or at least 2, not %(value)d")),
    ("scan_rate", 0.0, "the recalibration's LiDAR sweep rate (Hz) for scans that are not motion-compensated",
     _check(lambda v: not v != v, "scan_rate must be a number of Hz")),
    ("approximate_sync", False, "match the five inputs by nearest stamps rather than equal ones", _at_start()),
    ("approximate_sync_tolerance_seconds", 0.05, "the widest spread of stamps in one approximate set", _at_start()),
    ("queue_size", 10, "messages kept per input while waiting for a set (and the subscriptions' depth)", _at_start()),
    ("use_system_default_qos", False, "subscribe with the system default QoS, not the sensor-data QoS", _at_start()),
    ("sync_warning_seconds", 5.0, "warn when messages arrive but no set is complete for this long", _at_start()),
    ("lidar_timeout", 0.5, "an image pair that no cloud pairs with for this long (s) is fused as stereo "
     "alone; while the LiDAR stays silent a pair then waits only for the next (read when the node starts)",
     _at_start(_check(lambda v: v > 0, "lidar_timeout must be > 0 seconds, not %(value)s"))),
)
APPLY = {name: apply for name, _, _, apply in PARAMETERS}


class StereoLidarNode(Node):
    def __init__(self, **kwargs):
        super().__init__("lidarsgm", **kwargs)
        self.fusion_lock = threading.Lock()  # the matcher's settings: parameter changes wait for a fusion to end
        # The transform: the parameter's where given, else tf's; the recalibration's correction on top of either.
        self.param_transform, self.correction = None, np.eye(4)
        try:
            self._declare()
        except (cv2.error, rclpy.exceptions.ParameterException) as e:
            raise SystemExit("lidarsgm_node: %s" % e)
        problems = self._apply(self._set_parameters())
        if problems:
            raise SystemExit("lidarsgm_node: " + "; ".join(problems))
        self.add_on_set_parameters_callback(self._on_set)

        approx = self.get_parameter("approximate_sync").value
        queue = self.get_parameter("queue_size").value
        tol = self.get_parameter("approximate_sync_tolerance_seconds").value
        n = len(INPUT_TYPES)
        self.lidar_timeout = self.get_parameter("lidar_timeout").value
        images = ApproximateSync(n - 1, queue, int(tol * 1e9)) if approx else ExactSync(n - 1, queue)
        self.sync = LidarPairing(images, int(tol * 1e9) if approx else 0, int(self.lidar_timeout * 1e9), queue)
        # The executor thread only takes messages; the worker fuses (cv2 lets go of the GIL while it computes).
        self.lock = threading.Condition()
        self.ready = deque()  # the sets released and not yet fused: (stamp, msgs, base transform or alone, t)
        self.fusing_since = None  # when the worker took the set it fuses (perf_counter), None while it is idle
        self.health = health.Health(self.fusion.max_residual)
        # Best effort, as camera drivers publish: it takes best-effort and reliable publishers alike (a reliable
        # subscription hears nothing from a best-effort one).
        qos = QoSProfile(depth=queue) if self.get_parameter("use_system_default_qos").value else QoSProfile(
            depth=max(queue, 5), history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.BEST_EFFORT,
            durability=DurabilityPolicy.VOLATILE)
        self.subs = [self.create_subscription(rclpy_class(t), topic, self._callback(i), qos)
                     for i, (topic, t) in enumerate(INPUT_TYPES.items())]
        # Images remapped to image_raw topics (fixed once subscribed): refused or rectified (Fusion.fuse).
        self.raw_images = any(self.subs[i].topic_name.endswith("image_raw") for i in (0, 2))
        self.pubs = {topic: self.create_publisher(rclpy_class(t), topic, 1) for topic, t in OUTPUT_TYPES.items()}
        self.status_pub = self.create_publisher(DiagnosticArray, health.FUSION_STATUS, QoSProfile(
            depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE))
        self.diagnostics_pub = self.create_publisher(DiagnosticArray, "/diagnostics", 10)
        self.points_topic = self.subs[4].topic_name
        # tf as tf2_ros's listener subscribes: /tf_static latched (transient local), /tf reliable, 100 deep.
        self.tf = TransformBuffer(int(self.get_parameter("tf_tolerance_seconds").value * 1e9))
        self.tf_subs = [
            self.create_subscription(TFMessage, "/tf_static", lambda m: self._on_tf(m, True), QoSProfile(
                depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)),
            self.create_subscription(TFMessage, "/tf", lambda m: self._on_tf(m, False), QoSProfile(depth=100))]
        self.kit = MessageKit.rclpy()
        self.fused, self.skipped, self.reported_drops = 0, 0, 0
        self.residuals = deque(maxlen=10000)  # the matching residuals measured (px), the newest
        self.latencies = deque(maxlen=10000)  # seconds from each output's stamp to its publication, the newest
        self.tf_received = None  # when the last /tf or /tf_static message came (the node's clock, s)
        self.recal, self.refining = None, None  # the pool and the background refinement (a thread)
        self.busy = 0.0  # seconds spent fusing and publishing
        # Messages that never make a set (a camera_info not published, stamps that never match) leave the node
        # silent: say so, with what arrived.
        self.received = [0] * n
        self.waiting = 0                        # messages received since the last complete set
        self.quiet_since = self._now()          # the last complete set, or the last warning
        self.create_timer(self.get_parameter("sync_warning_seconds").value / 4, self._check_sync)
        self.create_timer(min(self.lidar_timeout / 4, 0.1), self._poll)
        self.create_timer(self.health.period, self._report)
        self.running = True
        self.worker = threading.Thread(target=self._work, name="lidarsgm_fusion", daemon=True)
        self.worker.start()
        self.get_logger().info("fusing %s with %s sync (queue %d); stereo alone when no cloud pairs within %.2f s"
                               % (", ".join(INPUT_TYPES), "approximate" if approx else "exact", queue,
                                  self.lidar_timeout))

    # -- parameters
    def _declare(self):
        params_file = self.declare_parameter(
            "params_file", "", ParameterDescriptor(
                read_only=True, description="matcher parameters saved with StereoLidarSGM.save (e.g. kitti_best.yml); "
                "empty: the paper's")).value
        self.fusion = Fusion(cv2, params_file)
        # The matcher's parameters start from the params file's (or the module's) values; overrides go through the
        # same checks as later changes.
        for name, default, text, _ in PARAMETERS:
            default = self.fusion.value(name) if default is MATCHER else default
            self.declare_parameter(name, default, ParameterDescriptor(description=text or "see StereoLidarSGM"))
        self.declared = ["params_file"] + [name for name, _, _, _ in PARAMETERS]

    def _apply(self, params):
        """Applies the parameters to the matcher; returns the problems (nothing is changed where there is one)."""
        f = self.fusion
        saved = (f.sgm, f.use_cuda, f.lidar_to_camera, f.trust_lidar, f.rectify)
        problems = []
        for p in params:
            try:
                if APPLY.get(p.name) is not None:
                    APPLY[p.name](self, p)
            except ValueError as e:
                problems.append("%s: %s" % (p.name, e))
        if problems:
            f.sgm, f.use_cuda, f.lidar_to_camera, f.trust_lidar, f.rectify = saved
        elif any(p.name in ("recalibration_sets", "scan_rate", "lidar_to_camera") for p in params):
            self.recal = None  # a new pool, with the new settings or for the new transform
            if any(p.name == "lidar_to_camera" and p.type_ != Parameter.Type.NOT_SET for p in params):
                self.param_transform, self.correction = f.lidar_to_camera, np.eye(4)
        return problems

    def _set_parameters(self):
        """The declared parameters that have a value (lidar_to_camera has none until it is given)."""
        out = []
        for name in self.declared:
            try:
                out.append(self.get_parameter(name))
            except rclpy.exceptions.ParameterUninitializedException:
                pass
        return out

    def _on_set(self, params):
        with self.fusion_lock:
            problems = self._apply(params)
        for msg in problems:
            self.get_logger().warning("parameter refused, the old value stays: " + msg)
        return SetParametersResult(successful=not problems, reason="; ".join(problems))

    # -- frames
    def _now(self):
        return self.get_clock().now().nanoseconds * 1e-9

    def summary(self):
        t = self.health.totals
        alone = sum(t["alone:" + c] for c in ALONE_CLASSES)
        text = ("%d sets fused (%.1f ms each, conversions and publishing included), %d with the LiDAR, %d as stereo "
                "alone (%d no cloud, %d calibration, %d bad message); %d skipped (%d bad message, %d overload); %d %s "
                "dropped by the synchroniser, %d restarts" % (
                    self.fused, 1000 * self.busy / max(self.fused, 1), t["lidar"], alone, t["alone:" + NO_CLOUD],
                    t["alone:" + CALIBRATION], t["alone:bad message"], self.skipped + t["skipped:overload"],
                    self.skipped, t["skipped:overload"], self.sync.dropped, self.sync.unit, self.sync.restarts))
        if self.latencies:
            e2e = sorted(self.latencies)
            text += "; stamp to outputs median %.1f ms, p99 %.1f ms, max %.1f ms" % (
                1000 * statistics.median(e2e), 1000 * e2e[min(len(e2e) - 1, int(0.99 * len(e2e)))], 1000 * e2e[-1])
        if self.residuals:
            median, above = residual_summary(self.residuals, self.fusion.max_residual)
            text += "; matching residual median %.2f px over %d checks, %d above %.0f px" % (
                median, len(self.residuals), above, self.fusion.max_residual)
        return text

    def _check_calibration(self, result):
        every = self.get_parameter("check_calibration_every").value
        if every <= 0 or (self.fused - 1) % every:
            return
        r = self.fusion.matching_residual(result)
        if r is None:
            return
        self.residuals.append(r)
        self.health.residual = r
        if r > self.fusion.max_residual:
            self.get_logger().warning(
                "the LiDAR lies %.2f px (median) from where the images match, more than %.0f px: the fusion is pulled "
                "off the images; check lidar_to_camera (lidarsgm_fuse --refine-calibration, or "
                "cv2.lidarsgm.LidarCalibration)" % (r, self.fusion.max_residual), throttle_duration_sec=10.0)

    def _on_tf(self, msg, static):
        self.tf_received = self._now()
        try:
            self.tf.add(msg.transforms, static)
        except ConversionError as e:
            self.get_logger().warning("a transform on %s refused: %s" % ("/tf_static" if static else "/tf", e),
                                      throttle_duration_sec=5.0)

    def _transform(self, left_info, cloud):
        """The transform before the correction: the parameter's, or tf's at the cloud's stamp (ConversionError)."""
        if self.param_transform is not None:
            return self.param_transform
        target = left_info.header.frame_id
        if not target:
            raise ConversionError("the left camera_info has no frame_id to look the transform up for")
        return self.tf.lookup(cloud.header.frame_id, target, stamp_ns(cloud))

    def _fail_safe(self, result, base):
        verdict = self.fusion.verdict(result)
        if verdict:
            self.get_logger().warning(verdict + "; check lidar_to_camera", throttle_duration_sec=5.0)
        if result.stereo_alone != CALIBRATION or result.points is None:
            return
        sets = self.get_parameter("recalibration_sets").value
        if sets <= 0 or (self.refining is not None and self.refining.is_alive()):
            return
        if self.recal is not None and not np.array_equal(self.recal_base, base):
            self.recal = None  # the pool holds sets of another transform (tf changed it)
        if self.recal is None:
            self.recal, self.recal_base = Recalibration(cv2, self.get_parameter("scan_rate").value, sets), base
        self.recal.add(result)
        if not self.recal.due():
            return
        recal, start = self.recal, self.fusion.lidar_to_camera

        def refine():
            corrected, text = recal.refine(start, self.fusion.sgm.getNumDisparities())
            # Taken only if the pool is still the current one (no new transform meanwhile).
            if corrected is not None and recal is self.recal:
                self.correction = corrected @ np.linalg.inv(base)
                self.get_logger().warning("%s; switched to the corrected transform (%s): [%s]" % (
                    text, "set lidar_to_camera to keep it" if self.param_transform is not None else
                    "kept on top of tf's; set lidar_to_camera to it to keep it",
                    ", ".join("%.9g" % v for v in corrected.ravel())))
            else:
                self.get_logger().info(text)
        self.refining = threading.Thread(target=refine, name="lidarsgm_recalibration", daemon=True)
        self.refining.start()

    def _check_sync(self):
        period = self.get_parameter("sync_warning_seconds").value
        if self.waiting and self._now() - self.quiet_since >= period:
            self.quiet_since = self._now()
            self.get_logger().warning(
                "no complete set of inputs for %.0f s; received so far: %s (%s sync: %s)"
                % (period,
                   ", ".join("%s %d" % (t, n) for t, n in zip(INPUT_TYPES, self.received)),
                   "approximate" if isinstance(self.sync, ApproximateSync) else "exact",
                   "check the stamps and the tolerance" if isinstance(self.sync, ApproximateSync)
                   else "every input needs the same stamp; approximate_sync takes the nearest"))

    # -- sets: taken in the executor's thread, fused in the worker's
    def _callback(self, index):
        def on_message(msg):
            self.received[index] += 1
            self.waiting += 1
            now = self._now()
            self.health.message_in(now)
            restarts = self.sync.restarts
            released = self.sync.add(index, stamp_ns(msg), msg, int(now * 1e9))
            if self.sync.restarts > restarts:
                self.health.event(now, "restart", "stamp %.3f s on %s after %.3f s" % (
                    stamp_ns(msg) * 1e-9, self.subs[index].topic_name, (self.sync.last[index] or 0) * 1e-9))
                self.get_logger().warning("time went back on %s (a bag loop or a clock reset): the synchroniser "
                                          "starts over" % self.subs[index].topic_name, throttle_duration_sec=5.0)
            self._offer(released)
        return on_message

    def _poll(self):
        self._offer(self.sync.poll(int(self._now() * 1e9)))

    def _offer(self, released):
        """Hands released sets to the worker: the newest win over sets still waiting from before."""
        if not released:
            return
        self.waiting, self.quiet_since = 0, self._now()
        items = [(stamp, msgs, self._lidar_for(msgs), time.perf_counter()) for stamp, msgs in released]
        with self.lock:
            # Overload is a fusion still running when newer sets come; sets the idle worker has yet to wake up for
            # are not skipped.
            if self.ready and self.fusing_since is not None:
                for _ in self.ready:
                    self.health.event(self._now(), "skipped:overload", "input faster than the fusion")
                self.ready.clear()
            self.ready.extend(items)
            self.lock.notify()

    def _lidar_for(self, msgs):
        """The transform (before the correction) for a set's cloud, or (class, reason) to fuse it as stereo alone."""
        left_info, cloud = msgs[1], msgs[4]
        if cloud is None:
            return NO_CLOUD, "no cloud on %s within %.2f s" % (self.points_topic, self.lidar_timeout)
        try:
            return self._transform(left_info, cloud)
        except ConversionError as e:
            return CALIBRATION, "no transform from the cloud's frame '%s' to the left camera's '%s' (%s): tf has " \
                "none yet (/tf_static, /tf), or set lidar_to_camera" % (cloud.header.frame_id,
                                                                       left_info.header.frame_id, e)

    def _work(self):
        while True:
            with self.lock:
                self.fusing_since = None
                while self.running and not self.ready:
                    self.lock.wait()
                if not self.running:
                    return
                stamp, msgs, lidar, since = self.ready.popleft()
                self.fusing_since = time.perf_counter()
            try:
                with self.fusion_lock:
                    self._fuse(stamp, msgs, lidar, since)
            except Exception as e:  # never let one set stop the depth: log it and go on with the next
                self.skipped += 1
                self.get_logger().error("set at %d.%09d failed: %r" % (stamp // 1000000000, stamp % 1000000000, e))

    def stop(self):
        with self.lock:
            self.running = False
            self.lock.notify()
        self.worker.join(30)

    def _fuse(self, stamp, msgs, lidar, since):
        left = msgs[0]
        t0 = time.perf_counter()
        alone = lidar if isinstance(lidar, tuple) else None
        if alone is None:
            self.fusion.lidar_to_camera = self.correction @ lidar
        try:
            result = self.fusion.fuse(*msgs, confidence=self.get_parameter("publish_confidence").value,
                                      raw=self.raw_images, alone=alone)
            out = output_messages(self.kit, self.fusion, result, left.header.frame_id, stamp_ns(left),
                                  self.get_parameter("depth_encoding").value)
        except ConversionError as e:
            self.skipped += 1
            self.health.event(self._now(), "skipped:bad message", str(e))
            self.get_logger().warning("frame at %d.%09d skipped: %s (%d skipped, %d fused)"
                                      % (stamp // 1000000000, stamp % 1000000000, e, self.skipped, self.fused))
            return
        level, text = health.set_status(result)
        status = health.diagnostic_array(self.kit._new, out[0][1].header, level, text,
                                         [("source", "stereo alone" if result.stereo_alone else "lidar"),
                                          ("class", result.stereo_alone)], level_of=lambda v: bytes([v]))
        for topic, msg in out:
            self.pubs[topic].publish(msg)
        self.status_pub.publish(status)
        self.fused += 1
        if result.check is None and result.stereo_alone:  # the fail-safe's verdict has its own line
            self.get_logger().warning("fused as stereo alone: " + result.reason, throttle_duration_sec=5.0)
        if result.check is not None:
            self._check_calibration(result)
        self._fail_safe(result, lidar if alone is None else None)
        done = time.perf_counter()
        self.busy += done - t0
        now = self._now()
        self.latencies.append(now - stamp * 1e-9)
        self.health.output(now, result, done - since, now - stamp * 1e-9)
        if self.sync.dropped > self.reported_drops:
            self.get_logger().warning("%d incomplete message sets dropped so far (a topic missing or late: check the "
                                      "stamps, or set approximate_sync)" % self.sync.dropped,
                                      throttle_duration_sec=5.0)
            self.reported_drops = self.sync.dropped

    def _report(self):
        now = self._now()
        level, text = self.health.level(now)
        source = "parameter" if self.param_transform is not None else "tf"
        age = now - self.tf_received if source == "tf" and self.tf_received is not None else None
        with self.lock:
            since, waiting = self.fusing_since, len(self.ready)
        # What came in and where the sets are: a set that never goes out was either never complete (a message lost)
        # or waits behind a fusion.
        worker = "idle" if since is None else "fusing for %.1f s" % (time.perf_counter() - since)
        extra = [("transform source", source), ("transform message age s", "-" if age is None else "%.1f" % age),
                 ("lidar timeout s", "%.2f" % self.lidar_timeout),
                 ("messages received", ", ".join("%s %d" % (t, n) for t, n in zip(INPUT_TYPES, self.received))),
                 ("worker", "%s, %d set%s waiting" % (worker, waiting, "" if waiting == 1 else "s"))]
        self.diagnostics_pub.publish(health.diagnostic_array(
            self.kit._new, self.kit.header(int(now * 1e9), ""), level, text, self.health.values(now, extra),
            level_of=lambda v: bytes([v])))


def large_data_profile():
    """The package's Fast DDS profile: installed (pip: <prefix>/share, colcon: the package's share folder) or in the
    source tree; None where there is none."""
    places = [os.path.join(sys.prefix, "share", "lidarsgm_ros", "config")]
    try:
        from ament_index_python.packages import get_package_share_directory
        places.append(os.path.join(get_package_share_directory("lidarsgm_ros"), "config"))
    except (ImportError, LookupError, OSError):  # a pip environment has no ament index
        pass
    places.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config"))
    return next((os.path.abspath(os.path.join(p, "fastdds_large_data.xml")) for p in places
                 if os.path.isfile(os.path.join(p, "fastdds_large_data.xml"))), None)


def apply_large_data_profile(environ=os.environ):
    """Points Fast DDS at the package's profile before rclpy.init (it is read when the participant is made), unless
    the user chose the transports (FASTDDS_DEFAULT_PROFILES_FILE, FASTDDS_BUILTIN_TRANSPORTS, a
    DEFAULT_FASTDDS_PROFILES.xml here) or another middleware. Returns the profile applied, or None."""
    if any(k in environ for k in ("FASTDDS_DEFAULT_PROFILES_FILE", "FASTDDS_BUILTIN_TRANSPORTS")) \
            or environ.get("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp") != "rmw_fastrtps_cpp" \
            or os.path.exists("DEFAULT_FASTDDS_PROFILES.xml"):
        return None
    path = large_data_profile()
    if path:
        environ["FASTDDS_DEFAULT_PROFILES_FILE"] = path
    return path


def main(argv=None):
    apply_large_data_profile()
    rclpy.init(args=argv if argv is not None else sys.argv)
    try:
        node = StereoLidarNode()
    except SystemExit as e:
        print(e, file=sys.stderr)
        rclpy.try_shutdown()
        return 1
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass
    finally:
        node.stop()
        print("lidarsgm_node: " + node.summary(), flush=True)  # the logger may be gone after a signal
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
