"""The bag command on rosbag2 bags of the shipped KITTI frames (written by lidarsgm_kitti_to_bag, MCAP and sqlite3):
outputs read back with rosbags and with the mcap library's own ROS 2 decoder, pixel for pixel the tool's disparity;
the transform from /tf_static or the command line; approximate sync of late scans; resume after an interruption;
errors with their exit codes."""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import cv2
import numpy as np
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = os.path.join(HERE, "..", "..", "ros2", "lidarsgm_ros")
sys.path.insert(0, PACKAGE)
from lidarsgm_ros import kitti  # noqa: E402

TESTDATA = os.environ["LIDARSGM_TESTDATA"]
TOOL = os.environ["LIDARSGM_TOOL"]
PARAMS = os.path.abspath(os.path.join(HERE, "..", "..", "doc", "params", "kitti_best.yml"))
KITTI = os.path.join(TESTDATA, "kitti")
FRAMES = ("000002", "000046")


def run(module, *args):
    env = dict(os.environ, PYTHONPATH=PACKAGE + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", module] + list(args), capture_output=True, text=True, env=env)


def disparities(out):
    """{stamp: float32 disparity} of every <ns>/disparity in an output folder's segments, read with rosbags."""
    parts = sorted(Path(out).glob("part_*"))
    got = {}
    with AnyReader(parts) as reader:
        conns = [c for c in reader.connections if c.topic.endswith("/disparity")]
        for conn, _, raw in reader.messages(connections=conns):
            m = reader.deserialize(raw, conn.msgtype)
            got[m.header.stamp.sec * 10**9 + m.header.stamp.nanosec] = \
                np.frombuffer(m.image.data.tobytes(), np.float32).reshape(m.image.height, m.image.width)
    return got


class BagTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = tempfile.mkdtemp(prefix="lidarsgm_bag_")
        cls.addClassCleanup(shutil.rmtree, cls.work, True)  # bags of 0.4 GB a run
        cls.tool = {}
        for fid in FRAMES:
            out = os.path.join(cls.work, "tool_" + fid)
            subprocess.run([TOOL, "--kitti-frame", KITTI, "--id", fid, "--params", PARAMS, "--modes", "sdsgm",
                            "--out", out], check=True, stdout=subprocess.DEVNULL)
            cls.tool[fid] = cv2.imread(os.path.join(out, "disparity.png"), cv2.IMREAD_UNCHANGED)
        cls.mcap_in = os.path.join(cls.work, "kitti_mcap")
        r = run("lidarsgm_ros.kitti", KITTI, cls.mcap_in, "--namespace", "/stereo")
        assert r.returncode == 0, r.stderr

    def expect_tool_output(self, out, stamps=(100000000, 200000000)):
        got = disparities(out)
        self.assertEqual(sorted(got), list(stamps))
        for stamp, fid in zip(stamps, FRAMES):
            np.testing.assert_array_equal(cv2.lidarsgm.encodeKittiDisparity(got[stamp]), self.tool[fid])

    def test_mcap_in_outputs_out_readable_by_mcap(self):
        out = os.path.join(self.work, "out_mcap")
        r = run("lidarsgm_ros.bag", self.mcap_in, out, "--namespace", "/stereo", "--params-file", PARAMS,
                "--with-inputs", "--confidence")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("set 2 of ~2 fused", r.stdout)
        self.assertIn("2 sets fused, 0 skipped", r.stdout)
        # Each set's LiDAR against its images: the shipped frames' 1.00 and 0.62 px, none above 1 px.
        self.assertIn("matching residual 1.00 px", r.stdout)
        self.assertIn("matching residual 0.62 px", r.stdout)
        self.assertIn("matching residual (the LiDAR against the images): median 1.00 px over 2 sets, 0 above 1 px\n",
                      r.stdout)
        self.expect_tool_output(out)   # the transform came from the bag's /tf_static
        # The mcap library's own ROS 2 decoder (what Foxglove's and rerun's importers build on) reads every topic.
        topics = {}
        with open(os.path.join(out, "part_0000", "part_0000.mcap"), "rb") as f:
            for _, channel, _, msg in make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages():
                topics.setdefault(channel.topic, []).append(msg)
        self.assertEqual(sorted(topics), sorted("/stereo/" + t for t in (
            "disparity", "depth", "points2", "confidence", "fusion_status", "left/image_rect", "left/camera_info",
            "right/image_rect", "right/camera_info", "points")))
        self.assertTrue(all(len(v) == 2 for v in topics.values()))
        self.assertEqual([(s.status[0].level, s.status[0].message) for s in topics["/stereo/fusion_status"]],
                         [(0, "fused with the LiDAR")] * 2)
        d = topics["/stereo/disparity"][1]
        self.assertEqual((d.image.encoding, d.delta_d, d.min_disparity, d.max_disparity), ("32FC1", 1 / 16, 0, 127))
        disp = np.frombuffer(bytes(d.image.data), np.float32).reshape(d.image.height, d.image.width)
        np.testing.assert_array_equal(cv2.lidarsgm.encodeKittiDisparity(disp), self.tool[FRAMES[1]])
        depth = topics["/stereo/depth"][1]
        self.assertEqual(depth.encoding, "32FC1")
        cloud = topics["/stereo/points2"][1]
        self.assertEqual((cloud.height, cloud.width, cloud.point_step), (d.image.height, d.image.width, 16))

    def test_sqlite3_with_the_transform_given_and_16_bit_depth(self):
        bag = os.path.join(self.work, "kitti_db3")
        self.assertEqual(run("lidarsgm_ros.kitti", KITTI, bag, "--storage", "sqlite3").returncode, 0)
        frame = cv2.lidarsgm.loadKittiFrame(KITTI, FRAMES[0])
        t = kitti.ros_calibration(frame.calibration)[3]
        out = os.path.join(self.work, "out_db3")
        r = run("lidarsgm_ros.bag", bag, out, "--params-file", PARAMS, "--depth-encoding", "16UC1",
                "--lidar-to-camera", *[repr(float(v)) for v in t.ravel()])
        self.assertEqual(r.returncode, 0, r.stderr)
        self.expect_tool_output(out)
        # A degree of pitch: fused, and the residual says the LiDAR has left the images.
        a = np.radians(1.0)
        pitch = np.eye(4)
        pitch[1:3, 1:3] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
        r = run("lidarsgm_ros.bag", bag, os.path.join(self.work, "out_db3_pitch"), "--params-file", PARAMS,
                "--lidar-to-camera", *[repr(float(v)) for v in (pitch @ t).ravel()])
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("over 2 sets, 2 above 1 px: the LiDAR pulls the fusion off the images there", r.stdout)
        # A transform that puts the scan 1 km behind the camera: every set fused as stereo alone, with the reason.
        flip = t.copy()
        flip[2, 3] -= 1000
        out = os.path.join(self.work, "out_db3_flipped")
        r = run("lidarsgm_ros.bag", bag, out, "--params-file", PARAMS,
                "--lidar-to-camera", *[repr(float(v)) for v in flip.ravel()])
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("set 1 of ~2 fused in ", r.stdout)
        self.assertIn("stereo alone: none of the cloud's 123223 points projects into the left image", r.stdout)
        self.assertIn("2 sets fused as stereo alone (0 no cloud, 2 calibration, 0 bad message)", r.stdout)
        sgm = cv2.lidarsgm.StereoLidarSGM.load(PARAMS)
        sgm.setMode(cv2.lidarsgm.StereoLidarSGM_MODE_SGM)
        sgm.setConsistencyCheck(cv2.lidarsgm.StereoLidarSGM_CHECK_STEREO)
        np.testing.assert_array_equal(np.round(disparities(out)[10**8] * 16).astype(np.int16),
                                      sgm.compute(frame.left, frame.right, np.zeros(frame.sparse.shape, np.float32)))

    def test_fail_safe_and_recalibration(self):
        """A 2-degree rotation error: the sets are fused as stereo alone (pixel for pixel the tool's SGM with the
        left-right check on the pair alone), the rotation is refined from them, and the command switches to the
        corrected transform."""
        bag = os.path.join(self.work, "kitti_three_times")
        kitti.write_bag(KITTI, bag, ids=list(FRAMES) * 3)
        frame = cv2.lidarsgm.loadKittiFrame(KITTI, FRAMES[0])
        t = kitti.ros_calibration(frame.calibration)[3]
        wrong = np.eye(4)
        wrong[:3, :3] = cv2.Rodrigues(np.radians([1.2, -1.5, 0.8]))[0]
        args = ["--params-file", PARAMS, "--lidar-to-camera"] + [repr(float(v)) for v in (wrong @ t).ravel()]
        out = os.path.join(self.work, "out_fail_safe")
        r = run("lidarsgm_ros.bag", bag, out, "--recalibration-sets", "4", "--scan-rate", "10", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        for k in range(1, 5):
            self.assertRegex(r.stdout, r"set %d of ~6 fused in \d+ ms, matching residual [\d.]+ px; the LiDAR "
                                       r"misplaced on the images \([\d.]+ px, [\d.]+ moved by \(-?\d+, -?\d+\)\): "
                                       r"fused as stereo alone" % k)
        self.assertRegex(r.stdout, r"correction from 4 sets: pitch [-+\d.]+ \+- [\d.]+, yaw .* calibration residual "
                                   r"[\d.]+ -> 0\.\d+ px")
        self.assertIn("switched to the corrected transform from set 5 on", r.stdout)
        self.assertIn("4 sets fused as stereo alone (0 no cloud, 4 calibration, 0 bad message); the corrected "
                      "transform taken after set 4", r.stdout)
        for k in (5, 6):
            m = re.search(r"set %d of ~6 fused in \d+ ms, matching residual ([\d.]+) px\n" % k, r.stdout)
            self.assertIsNotNone(m, r.stdout)
            self.assertLessEqual(float(m.group(1)), 1.0)
        got = disparities(out)
        stamps = sorted(got)
        for k, fid in enumerate(FRAMES):
            tool = os.path.join(self.work, "tool_sgm_" + fid)
            # The pair alone, no LiDAR: kitti_best.yml's disparity windows then come from the images, as the bag's.
            subprocess.run([TOOL, "--left", os.path.join(KITTI, "image_2", fid + "_10.png"),
                            "--right", os.path.join(KITTI, "image_3", fid + "_10.png"), "--params", PARAMS,
                            "--modes", "sgm", "--check", "stereo", "--out", tool], check=True,
                           stdout=subprocess.DEVNULL)
            sgm = cv2.imread(os.path.join(tool, "disparity.png"), cv2.IMREAD_UNCHANGED)
            np.testing.assert_array_equal(cv2.lidarsgm.encodeKittiDisparity(got[stamps[k]]), sgm)
        # --trust-lidar: every set fused with the LiDAR, and said to be misplaced.
        r = run("lidarsgm_ros.bag", bag, out + "_trusted", "--trust-lidar", *args)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(6, r.stdout.count("fused anyway (trust_lidar)"))
        self.assertNotIn("stereo alone", r.stdout)

    def test_raw_images_refused_or_rectified(self):
        """An un-rectified rig (tools/unrectified_rig.py: each camera turned by about a degree, k1 -0.2), its
        camera_info with D, R and P as a calibrated camera publishes them. Raw images (image_raw): refused with the
        reason, and with --rectify fused pixel for pixel as StereoRig rectifies the pair and projects the scan (the
        transform ending in the raw left camera's frame, camera_info's R after it). The rectified pair on image_rect
        topics with the same camera_info: fused, the same. Raw images with a rotation error: the recalibration's
        correction (found in the rectified frame) is taken back to the optical frame, and the LiDAR fits again."""
        sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
        from unrectified_rig import rig_of, unrectify, write_rig
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.typesys import Stores, get_typestore
        from lidarsgm_ros.messages import INPUT_TYPES, MessageKit
        ts = get_typestore(Stores.ROS2_JAZZY)
        kit = MessageKit.rosbags(ts)
        frame = cv2.lidarsgm.loadKittiFrame(KITTI, FRAMES[0])
        size = (frame.left.shape[1], frame.left.shape[0])
        rig = rig_of(frame.calibration, size)
        M1, D1, M2, D2, R, T, R1, R2, P1, P2, l2l = rig
        raw_l = unrectify(frame.left, M1, D1, R1, P1[:, :3], size)
        raw_r = unrectify(frame.right, M2, D2, R2, P2[:, :3], size)
        scan = cv2.lidarsgm.readVelodyneScan(os.path.join(KITTI, "velodyne", FRAMES[0] + ".bin"))
        records, fields = kitti.velodyne_records(scan)
        rig_file = os.path.join(self.work, "rig.yml")
        write_rig(rig_file, rig, size)
        stereo_rig = cv2.lidarsgm.StereoRig.fromFile(rig_file)
        rect_l, rect_r = stereo_rig.rectify(raw_l, raw_r)
        sgm = cv2.lidarsgm.StereoLidarSGM.load(PARAMS)
        want = sgm.compute(rect_l, rect_r, stereo_rig.projectCloud(scan))
        self.assertLess(cv2.lidarsgm.evaluateDisparity(want, frame.groundTruth).totalError(), 3.0)

        def bag_of(name, left, right, kind, sets=1):
            """A bag of the pair on /cam/{left,right}/<kind> with the rig's camera_info and the scan, sets times."""
            bag = os.path.join(self.work, name)
            topics = {"left/image_rect": "/cam/left/" + kind, "right/image_rect": "/cam/right/" + kind,
                      "left/camera_info": "/cam/left/camera_info", "right/camera_info": "/cam/right/camera_info",
                      "points": "/points"}
            with Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP) as w:
                conns = {n: w.add_connection(t, INPUT_TYPES[n], typestore=ts) for n, t in topics.items()}
                for k in range(sets):
                    stamp = (k + 1) * 10**8
                    lh, rh = kit.header(stamp, "left_optical"), kit.header(stamp, "right_optical")
                    msgs = {"left/image_rect": kit.image(lh, left, "mono8"),
                            "right/image_rect": kit.image(rh, right, "mono8"),
                            "left/camera_info": kit.camera_info(lh, size[0], size[1], M1, P1, D1.ravel(), R1),
                            "right/camera_info": kit.camera_info(rh, size[0], size[1], M2, P2, D2.ravel(), R2),
                            "points": kit.cloud(kit.header(stamp, "velodyne"), records, fields)}
                    for n, msg in msgs.items():
                        w.write(conns[n], stamp, ts.serialize_cdr(msg, INPUT_TYPES[n]))
            return bag, sum((["--topic", "%s=%s" % nt] for nt in topics.items()), [])

        def args_with(transform):
            return ["--params-file", PARAMS, "--lidar-to-camera"] + [repr(float(v)) for v in transform.ravel()]

        raw_bag, topics = bag_of("raw_bag", raw_l, raw_r, "image_raw")
        r = run("lidarsgm_ros.bag", raw_bag, os.path.join(self.work, "out_raw_refused"), *topics, *args_with(l2l))
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
        self.assertIn("skipped: the images come on image_raw and their camera_info has distortion (or a "
                      "rectification): rectify them first (image_proc), or set rectify", r.stdout)
        out = os.path.join(self.work, "out_raw")
        r = run("lidarsgm_ros.bag", raw_bag, out, "--rectify", *topics, *args_with(l2l))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        np.testing.assert_array_equal(np.round(disparities(out)[10**8] * 16).astype(np.int16), want)
        exact = float(re.search(r"set 1 of ~1 fused in \d+ ms, matching residual ([\d.]+) px\n", r.stdout).group(1))
        rect_bag, topics = bag_of("rect_bag", rect_l, rect_r, "image_rect")
        out = os.path.join(self.work, "out_rect")
        r = run("lidarsgm_ros.bag", rect_bag, out, *topics, *args_with(l2l))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        np.testing.assert_array_equal(np.round(disparities(out)[10**8] * 16).astype(np.int16), want)
        # A rotation error of the LiDAR in the raw left camera's frame, three sets: the first two fused as stereo
        # alone and pooled, the correction taken after the second, the third fused with its LiDAR again, as close to
        # the images as with the exact transform.
        wrong = np.eye(4)
        wrong[:3, :3] = cv2.Rodrigues(np.radians([1.2, -1.5, 0.8]))[0]
        raw3, topics = bag_of("raw_bag_3", raw_l, raw_r, "image_raw", sets=3)
        r = run("lidarsgm_ros.bag", raw3, os.path.join(self.work, "out_raw_3"), "--rectify", "--recalibration-sets",
                "2", "--scan-rate", "10", *topics, *args_with(wrong @ l2l))
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("switched to the corrected transform from set 3 on", r.stdout)
        m = re.search(r"set 3 of ~3 fused in \d+ ms, matching residual ([\d.]+) px\n", r.stdout)
        self.assertIsNotNone(m, r.stdout)   # no verdict after the residual: trusted
        self.assertLessEqual(float(m.group(1)), exact + 0.1, r.stdout)

    def test_late_scans_need_approximate_sync(self):
        bag = os.path.join(self.work, "kitti_late")
        self.assertEqual(run("lidarsgm_ros.kitti", KITTI, bag, "--lidar-offset-ms", "30").returncode, 0)
        # Exact sync: no scan shares the images' stamps; the pairs go as stereo alone, and the command says why.
        r = run("lidarsgm_ros.bag", bag, os.path.join(self.work, "out_exact"), "--params-file", PARAMS)
        self.assertEqual(r.returncode, 0, r.stdout)
        self.assertIn("2 sets fused, 0 skipped, 0 kept from before, 2 messages dropped", r.stdout)
        self.assertIn("2 sets fused as stereo alone (2 no cloud, 0 calibration, 0 bad message)", r.stdout)
        self.assertIn("no scan shares a stamp with the images: if the LiDAR is not triggered by the cameras, pass "
                      "--approximate-sync", r.stderr)
        out = os.path.join(self.work, "out_approx")
        r = run("lidarsgm_ros.bag", bag, out, "--params-file", PARAMS, "--approximate-sync", "--tolerance", "0.05")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.expect_tool_output(out)
        r = run("lidarsgm_ros.bag", bag, os.path.join(self.work, "out_tight"), "--params-file", PARAMS,
                "--approximate-sync", "--tolerance", "0.02")
        self.assertEqual(r.returncode, 0)
        self.assertIn("2 sets fused as stereo alone (2 no cloud, 0 calibration, 0 bad message)", r.stdout)

    def test_resume_after_an_interruption(self):
        out = os.path.join(self.work, "out_resume")
        args = [self.mcap_in, out, "--namespace", "/stereo", "--params-file", PARAMS, "--segment-frames", "1"]
        self.assertEqual(run("lidarsgm_ros.bag", *args).returncode, 0)
        # As a run killed while writing the second segment leaves it: the first complete, the second partial.
        shutil.rmtree(os.path.join(out, "part_0001"))
        os.makedirs(os.path.join(out, ".partial", "part_0001"))
        with open(os.path.join(out, ".partial", "part_0001", "part_0001.mcap"), "wb") as f:
            f.write(b"\x89MCAP0\r\n")
        before = os.stat(os.path.join(out, "part_0000", "part_0000.mcap")).st_mtime_ns
        r = run("lidarsgm_ros.bag", *args)
        self.assertEqual(r.returncode, 2)
        self.assertIn("exists and is not empty: pass --resume", r.stderr)
        r = run("lidarsgm_ros.bag", *args, "--resume")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("resuming: 1 complete segment(s) of 1 sets kept", r.stdout)
        self.assertIn("1 sets fused, 0 skipped, 1 kept from before", r.stdout)
        self.assertNotIn("set 1 of", r.stdout)
        self.assertEqual(os.stat(os.path.join(out, "part_0000", "part_0000.mcap")).st_mtime_ns, before)
        self.assertFalse(os.path.exists(os.path.join(out, ".partial")))
        self.expect_tool_output(out)

    def test_errors(self):
        out = os.path.join(self.work, "out_err")
        r = run("lidarsgm_ros.bag", os.path.join(self.work, "no_such_bag"), out)
        self.assertEqual(r.returncode, 1)
        self.assertIn("cannot read", r.stderr)
        r = run("lidarsgm_ros.bag", self.mcap_in, out)  # the topics are under /stereo
        self.assertEqual(r.returncode, 1)
        self.assertIn("has no topic /left/image_rect", r.stderr)
        self.assertIn("/stereo/left/image_rect", r.stderr)
        r = run("lidarsgm_ros.bag", self.mcap_in, out, "--topic", "left=/x")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--topic takes NAME=TOPIC", r.stderr)
        r = run("lidarsgm_ros.bag", self.mcap_in, out, "--P1", "5000")
        self.assertEqual(r.returncode, 2)
        self.assertIn("P1 (the penalty of a disparity step of 1) must be in [0, 1000]", r.stderr)
        r = run("lidarsgm_ros.bag", self.mcap_in, out, "--lidar-to-camera", "1", "2", "3")
        self.assertEqual(r.returncode, 2)
        self.assertIn("lidar_to_camera takes 12 or 16 numbers", r.stderr)
        self.assertFalse(os.path.exists(out))


if __name__ == "__main__":
    unittest.main()
