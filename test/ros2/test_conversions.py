"""lidarsgm_ros's conversions (.camera_info, .images, .clouds, .transforms, .outputs) and .sync on their own: numpy
and cv2 only, no ROS installation needed.

Messages are plain objects with the fields of sensor_msgs' (the conversions read fields by name, as they do from
rclpy's and rosbags' messages); the KITTI frame's are built by lidarsgm_ros.kitti as the node's tests publish them.
"""
import os
import struct
import sys
import unittest
from types import SimpleNamespace as Msg

import cv2
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "ros2", "lidarsgm_ros"))
from lidarsgm_ros import camera_info, clouds, images, outputs, transforms  # noqa: E402
from lidarsgm_ros import kitti  # noqa: E402
from lidarsgm_ros.conversions import ConversionError  # noqa: E402
from lidarsgm_ros.fusion import Fusion  # noqa: E402
from lidarsgm_ros import fusion as fusion_module  # noqa: E402
from lidarsgm_ros.messages import MessageKit  # noqa: E402
from lidarsgm_ros.sync import ApproximateSync, ExactSync  # noqa: E402

TESTDATA = os.environ.get("LIDARSGM_TESTDATA", os.path.join(os.path.dirname(__file__), "..", "..", "testdata"))


def info(p, w=1242, h=375, frame="cam"):
    return Msg(width=w, height=h, p=list(np.ravel(p)), header=Msg(frame_id=frame))


def field(name, offset, datatype, count=1):
    return Msg(name=name, offset=offset, datatype=datatype, count=count)


def cloud(records, fields, height=1, bigendian=False, row_step=None):
    records = np.ascontiguousarray(records)
    n = records.shape[0]
    step = records.nbytes // n
    w = n // height
    return Msg(height=height, width=w, fields=fields, point_step=step, row_step=row_step or step * w,
               data=records.tobytes(), is_bigendian=bigendian)


class StereoGeometry(unittest.TestCase):
    K = np.array([[700.0, 0, 600], [0, 700, 180], [0, 0, 1]])

    def pair(self):
        left = np.hstack([self.K, np.zeros((3, 1))])
        right = left.copy()
        right[0, 3] = -700 * 0.54
        return left, right

    def test_focal_baseline_from_the_right_tx(self):
        left, right = self.pair()
        g = camera_info.stereo_geometry(info(left, frame="left_optical"), info(right))
        self.assertAlmostEqual(g.focal_baseline, 378.0)
        self.assertAlmostEqual(g.baseline, 0.54)
        self.assertEqual(g.size, (1242, 375))
        self.assertEqual(g.frame_id, "left_optical")
        np.testing.assert_array_equal(g.projection, left)

    def test_rectification_and_raw_images(self):
        left, right = self.pair()
        r = cv2.Rodrigues(np.array([0.01, -0.02, 0.005]))[0]
        li = info(left)
        li.r = list(r.ravel())
        np.testing.assert_array_equal(camera_info.stereo_geometry(li, info(right)).rectification, r)
        np.testing.assert_array_equal(camera_info.stereo_geometry(info(left), info(right)).rectification, np.eye(3))
        li.r = list((2 * r).ravel())
        with self.assertRaises(ConversionError) as e:
            camera_info.stereo_geometry(li, info(right))
        self.assertIn("left camera_info R is not a rotation", str(e.exception))
        # Raw: distortion, a rotation or K other than P's; the rectification maps of each distortion model.
        rect = Msg(width=64, height=48, d=[0.0] * 5, k=list(self.K.ravel()), r=list(np.eye(3).ravel()),
                   p=list(left.ravel()), distortion_model="plumb_bob")
        self.assertFalse(camera_info.is_raw(rect))
        for change in (dict(d=[-0.2, 0, 0, 0, 0]), dict(r=list(r.ravel())), dict(k=list((self.K * 1.01).ravel()))):
            self.assertTrue(camera_info.is_raw(Msg(**dict(vars(rect), **change))))
        mx, my = camera_info.rectification_maps(cv2, rect, "left")
        self.assertEqual(mx.shape, (48, 64))
        self.assertAlmostEqual(float(mx[10, 20]), 20.0, places=3)   # nothing to undo: the identity map
        fisheye = Msg(**dict(vars(rect), distortion_model="equidistant", d=[0.1, 0.0, 0.0, 0.0]))
        self.assertEqual(camera_info.rectification_maps(cv2, fisheye, "left")[0].shape, (48, 64))
        for change, text in ((dict(distortion_model="kannala"), "distortion model 'kannala' is not one of"),
                             (dict(distortion_model="equidistant"), "equidistant model needs 4 coefficients, got 5"),
                             (dict(d=[0.1, 0.2]), "has 2 distortion coefficients"),
                             (dict(k=[0.0] * 9), "has no camera matrix K")):
            with self.assertRaises(ConversionError) as e:
                camera_info.rectification_maps(cv2, Msg(**dict(vars(rect), **change)), "right")
            self.assertIn(text, str(e.exception))

    def test_refusals_say_what_is_wrong(self):
        left, right = self.pair()
        cases = []
        other = right.copy()
        other[0, 2] += 5
        cases.append(((info(left), info(other)), "not rectified to one camera matrix: left P cx 600"))
        cases.append(((info(left), info(right, w=1240)), "left camera_info is 1242x375, right 1240x375"))
        cases.append(((info(np.zeros((3, 4))), info(right)), "left camera_info has no projection matrix P"))
        cases.append(((info(right), info(left)), "f x baseline must be > 0 (left and right swapped?)"))
        ty = right.copy()
        ty[1, 3] = 30
        cases.append(((info(left), info(ty)), "offset vertically"))
        cases.append(((info(left[:2]), info(right)), "left camera_info P has 8 values, expected 12"))
        cases.append(((info(left, w=0), info(right, w=0)), "no image size"))
        for (l, r), text in cases:
            with self.assertRaises(ConversionError) as e:
                camera_info.stereo_geometry(l, r)
            self.assertIn(text, str(e.exception))

    def test_the_last_pair_is_kept(self):
        """The same pair's values again: the same StereoGeometry back, without the checks; any value changed, or a
        broken pair after a good one: worked out (or refused) anew."""
        left, right = self.pair()
        g = camera_info.stereo_geometry(info(left), info(right))
        self.assertIs(camera_info.stereo_geometry(info(left), info(right)), g)
        other = right.copy()
        other[0, 3] = -700 * 0.5
        self.assertAlmostEqual(camera_info.stereo_geometry(info(left), info(other)).baseline, 0.5)
        self.assertAlmostEqual(camera_info.stereo_geometry(info(left), info(right, frame="x")).baseline, 0.54)
        with self.assertRaisesRegex(ConversionError, "no image size"):
            camera_info.stereo_geometry(info(left, w=0), info(right, w=0))
        self.assertIsNot(camera_info.stereo_geometry(info(left), info(right)), g)
        self.assertEqual(camera_info.stereo_geometry(info(left), info(right)).focal_baseline, g.focal_baseline)

    def test_broken_camera_info(self):
        """K or P of the wrong size, fx 0, NaN, no image size, values that are no numbers: each refused, saying what
        is wrong and what was expected."""
        left, right = self.pair()
        k = list(self.K.ravel())

        def with_k(m, kv, **kw):
            i = info(m, **kw)
            i.k = kv
            return i
        fx0 = left.copy()
        fx0[0, 0] = 0
        nan = right.copy()
        nan[0, 3] = np.nan
        inf = left.copy()
        inf[1, 2] = np.inf
        cases = [
            ((with_k(left, k[:8]), with_k(right, k)), "left camera_info K has 8 values, expected 9 (3 x 3"),
            ((with_k(left, k), with_k(right, k + [1.0])), "right camera_info K has 10 values, expected 9"),
            ((with_k(left, k[:3] + [np.nan] + k[4:]), info(right)), "left camera_info K holds NaN or infinite"),
            ((info(left), info(right[:, :3])), "right camera_info P has 9 values, expected 12 (3 x 4, row by row)"),
            ((info(fx0), info(right)), "left camera_info has no projection matrix P (fx 0, fy 700, P[2,2] 1; "
                                       "expected fx, fy > 0"),
            ((info(left), info(nan)), "right camera_info P holds NaN or infinite values"),
            ((info(inf), info(right)), "left camera_info P holds NaN or infinite values"),
            ((info(left), info(right, w=0)), "right camera_info has no image size (0x375): expected the calibrated"),
            ((info(left, h=0), info(right, h=0)), "left camera_info has no image size (1242x0)"),
            ((info(left, w=-4), info(right)), "left camera_info has no image size (-4x375)"),
            ((info(left, w=12.5), info(right)), "left camera_info width is 12.5, expected an integer"),
            ((Msg(width=1242, height=375, p=["a"] * 12, header=Msg(frame_id="")), info(right)),
             "left camera_info P is not a list of numbers"),
        ]
        for (l, r), text in cases:
            with self.assertRaises(ConversionError, msg=text) as e:
                camera_info.stereo_geometry(l, r)
            self.assertIn(text, str(e.exception))
        # The rectification maps refuse NaN distortion and a camera_info without an image size.
        rect = Msg(width=64, height=48, d=[0.0] * 5, k=k, r=list(np.eye(3).ravel()), p=list(left.ravel()),
                   distortion_model="plumb_bob")
        for change, text in ((dict(d=[np.nan, 0, 0, 0, 0]), "distortion coefficients hold NaN"),
                             (dict(width=0), "the left camera_info has no image size (0x48)")):
            with self.assertRaises(ConversionError) as e:
                camera_info.rectification_maps(cv2, Msg(**dict(vars(rect), **change)), "left")
            self.assertIn(text, str(e.exception))


class Images(unittest.TestCase):
    def test_padded_rows_and_encodings(self):
        rng = np.random.default_rng(1)
        a = rng.integers(0, 255, (5, 7, 3), dtype=np.uint8)
        padded = np.zeros((5, 24), np.uint8)
        padded[:, :21] = a.reshape(5, 21)
        msg = Msg(height=5, width=7, step=24, encoding="rgb8", is_bigendian=0, data=padded.tobytes())
        np.testing.assert_array_equal(images.image_to_array(msg), a)
        np.testing.assert_array_equal(images.to_grey(msg, cv2), cv2.cvtColor(a, cv2.COLOR_RGB2GRAY))
        np.testing.assert_array_equal(images.to_bgr(msg, cv2), a[..., ::-1])
        b16 = rng.integers(0, 65535, (4, 3), dtype=np.uint16)
        big = Msg(height=4, width=3, step=6, encoding="mono16", is_bigendian=1, data=b16.astype(">u2").tobytes())
        np.testing.assert_array_equal(images.to_grey(big, cv2), b16)

    def test_bad_images(self):
        short = Msg(height=5, width=7, step=7, encoding="mono8", is_bigendian=0, data=bytes(30))
        with self.assertRaisesRegex(ConversionError, "image data holds 30 bytes"):
            images.image_to_array(short)
        with self.assertRaisesRegex(ConversionError, "encoding 'yuv422' is not supported"):
            images.image_to_array(Msg(height=1, width=1, step=2, encoding="yuv422", is_bigendian=0, data=bytes(2)))
        with self.assertRaisesRegex(ConversionError, "32FC1 image cannot be matched"):
            images.to_grey(Msg(height=1, width=1, step=4, encoding="32FC1", is_bigendian=0, data=bytes(4)), cv2)

    def test_image_size_step_and_data_must_agree(self):
        """len(data) = step x height exactly, step >= a row, width and height > 0; data of any buffer type."""
        def img(**kw):
            m = dict(height=5, width=7, step=8, encoding="mono8", is_bigendian=0, data=bytes(40))
            m.update(kw)
            return Msg(**m)
        self.assertEqual(images.image_to_array(img()).shape, (5, 7))
        self.assertEqual(images.image_to_array(img(data=list(range(40)))).tolist()[1][:2], [8, 9])
        self.assertEqual(images.image_to_array(img(data=np.zeros(40, np.uint8))).shape, (5, 7))
        for msg, text in (
                (img(data=bytes(41)), "image data holds 41 bytes, a 7x5 mono8 image with step 8 needs step x height "
                                      "= 40"),
                (img(data=bytes(39)), "image data holds 39 bytes"),
                (img(step=6, data=bytes(30)), "image step 6 is less than a row of the 7x5 mono8 image (7 bytes)"),
                (img(encoding="bgr8", step=20, data=bytes(100)), "image step 20 is less than a row of the 7x5 bgr8 "
                                                                 "image (21 bytes): expected step >= width x 3"),
                (img(width=0, step=0, data=b""), "image is empty (0x5): expected width and height > 0"),
                (img(height=0, data=b""), "image is empty (7x0)"),
                (img(height=-1), "image is empty (7x-1)"),
                (img(step=None), "image step is None, expected an integer"),
                (img(data=None), "the image's data is NoneType, expected bytes"),
                (img(data=[300] * 40), "the image's data is list, expected bytes"),
                (img(encoding="mono10"), "image encoding 'mono10' is not supported (16UC1, 32FC1, 8UC1, bgr8")):
            with self.assertRaises(ConversionError, msg=text) as e:
                images.to_grey(msg, cv2)
            self.assertIn(text, str(e.exception))


class Clouds(unittest.TestCase):
    def setUp(self):
        self.xyz = np.array([[1, 2, 3], [4, 5, 6], [np.nan, 0, 1], [7, 8, 9]], np.float32)

    def test_any_field_order_step_and_type(self):
        # z first, float64 x, 3 padding bytes, a ring, 32-byte points, big endian
        dt = np.dtype({"names": ["z", "ring", "x", "y"], "formats": [">f4", ">u2", ">f8", ">f4"],
                       "offsets": [0, 4, 8, 20], "itemsize": 32})
        rec = np.zeros(4, dt)
        rec["x"], rec["y"], rec["z"], rec["ring"] = self.xyz[:, 0], self.xyz[:, 1], self.xyz[:, 2], [3, 4, 5, 6]
        fields = [field("z", 0, 7), field("ring", 4, 4), field("x", 8, 8), field("y", 20, 7)]
        xyz, ring = clouds.cloud_to_points(cloud(rec.view(np.uint8).reshape(4, 32), fields, bigendian=True))
        np.testing.assert_array_equal(xyz, self.xyz[[0, 1, 3]])
        np.testing.assert_array_equal(ring, [3, 4, 6])

    def test_organised_cloud_with_row_padding(self):
        rec = np.zeros((2, 2, 4), np.float32)
        rec[..., :3] = self.xyz.reshape(2, 2, 3)
        rows = np.zeros((2, 40), np.uint8)  # 2 points of 16 bytes + 8 bytes of padding per row
        rows[:, :32] = rec.view(np.uint8).reshape(2, 32)
        msg = Msg(height=2, width=2, fields=[field("x", 0, 7), field("y", 4, 7), field("z", 8, 7)], point_step=16,
                  row_step=40, data=rows.tobytes(), is_bigendian=False)
        xyz, ring = clouds.cloud_to_points(msg)
        self.assertIsNone(ring)
        np.testing.assert_array_equal(xyz, self.xyz[[0, 1, 3]])

    def test_bad_clouds(self):
        rec = np.zeros((3, 3), np.float32)
        cases = [
            (cloud(rec, [field("a", 0, 7), field("b", 4, 7), field("c", 8, 7)]), "no x/y/z field (fields: a, b, c)"),
            (cloud(rec, [field("x", 0, 7), field("y", 4, 7)]), "no z field"),
            (Msg(height=1, width=0, fields=[], point_step=12, row_step=0, data=b"", is_bigendian=False),
             "the point cloud is empty"),
            (cloud(rec, [field("x", 0, 7), field("y", 4, 7), field("z", 8, 8)]), "does not fit the point step 12"),
            (cloud(rec, [field("x", 0, 7), field("y", 4, 7), field("z", 8, 9)]), "unknown datatype 9"),
            (cloud(np.full((2, 3), np.nan, np.float32), [field("x", 0, 7), field("y", 4, 7), field("z", 8, 7)]),
             "no finite point"),
        ]
        short = cloud(rec, [field("x", 0, 7), field("y", 4, 7), field("z", 8, 7)])
        short.data = short.data[:-1]
        cases.append((short, "data holds 35 bytes"))
        for msg, text in cases:
            with self.assertRaises(ConversionError) as e:
                clouds.cloud_to_points(msg)
            self.assertIn(text, str(e.exception))

    XYZ = [field("x", 0, 7), field("y", 4, 7), field("z", 8, 7)]

    def test_non_finite_points_dropped_and_counted(self):
        xyz = np.array([[1, 2, 3], [np.nan, 0, 1], [4, np.inf, 6], [7, 8, -np.inf], [9, 9, 9]], np.float32)
        rec = np.zeros((5, 4), np.float32)
        rec[:, :3] = xyz
        rec[:, 3].view(np.uint32)[:] = [0, 1, 2, 3, 4]
        points, ring, dropped = clouds.cloud_points(cloud(rec, self.XYZ + [field("ring", 12, 6)]))
        np.testing.assert_array_equal(points, xyz[[0, 4]])
        np.testing.assert_array_equal(ring, [0, 4])
        self.assertEqual(dropped, 3)
        points, ring, dropped = clouds.cloud_points(cloud(rec, self.XYZ))
        self.assertEqual((points.shape, ring, dropped), ((2, 3), None, 3))
        self.assertEqual(clouds.cloud_points(cloud(rec[[0, 4]], self.XYZ))[2], 0)
        # float64 beyond float32's range: infinite as float32, dropped and counted, no warning
        big = np.array([[1, 2, 3], [1e300, 0, 0]], np.float64)
        f64 = [field("x", 0, 8), field("y", 8, 8), field("z", 16, 8)]
        with np.errstate(all="raise"):
            points, _, dropped = clouds.cloud_points(cloud(big, f64))
        np.testing.assert_array_equal(points, [[1, 2, 3]])
        self.assertEqual(dropped, 1)
        np.testing.assert_array_equal(clouds.cloud_to_points(cloud(rec, self.XYZ))[0], xyz[[0, 4]])  # the old call
        with self.assertRaisesRegex(ConversionError, r"no finite point \(5 points, all with a NaN or infinite"):
            clouds.cloud_points(cloud(np.full((5, 3), np.nan, np.float32), self.XYZ))

    def test_aligned_records_are_viewed_not_copied(self):
        """x y z intensity as float32, 16 bytes a point: the points are a view of the message's data; a NaN
        intensity drops nothing, a NaN coordinate its point."""
        rec = np.arange(20, dtype=np.float32).reshape(5, 4)
        rec[1, 3] = np.nan
        fields = self.XYZ + [field("intensity", 12, 7)]
        msg = cloud(rec, fields)
        points, _, dropped = clouds.cloud_points(msg)
        np.testing.assert_array_equal(points, rec[:, :3])
        self.assertEqual(dropped, 0)
        self.assertTrue(np.shares_memory(points, clouds.cloud_fields(msg)))
        # cv2 takes the pitched rows as they are: the projection of the view is that of a copy
        P, T = np.array([[2.0, 0, 2, 0], [0, 2, 2, 0], [0, 0, 1, 0]]), np.eye(4)
        view = cv2.lidarsgm.projectPointsToDisparity(points, P, T, 8.0, (5, 5))
        np.testing.assert_array_equal(view, cv2.lidarsgm.projectPointsToDisparity(points.copy(), P, T, 8.0, (5, 5)))
        self.assertGreater(np.count_nonzero(view), 0)
        rec[2, 0] = np.nan
        points, _, dropped = clouds.cloud_points(cloud(rec, fields))
        np.testing.assert_array_equal(points, rec[[0, 1, 3, 4], :3])
        self.assertEqual(dropped, 1)

    def test_numeric_coordinates_of_any_datatype(self):
        """x y z as int16 (a driver's millimetres, say) are read as their numbers, as float32."""
        rec = np.array([[1, -2, 3], [-300, 5, 32767]], np.int16)
        points, _, dropped = clouds.cloud_points(cloud(rec, [field("x", 0, 3), field("y", 2, 3), field("z", 4, 3)]))
        np.testing.assert_array_equal(points, rec.astype(np.float32))
        self.assertEqual((points.dtype, dropped), (np.float32, 0))

    def test_header_and_data_must_agree(self):
        """The rules of sensor_msgs/PointCloud2: each refused with what is wrong and what was expected."""
        rec = np.zeros((6, 4), np.float32)  # 6 points of 16 bytes: x y z and 4 bytes free

        def c(fields=None, **kw):
            m = cloud(rec, self.XYZ if fields is None else fields, height=2)
            for k, v in kw.items():
                setattr(m, k, v)
            return m
        self.assertEqual(clouds.cloud_points(c())[0].shape, (6, 3))
        self.assertEqual(clouds.cloud_points(c(data=list(c().data)))[0].shape, (6, 3))  # a list of byte values
        # Left unset where the rest says it (drivers that make fields and clouds by hand): count 0 on x is one value,
        # row_step 0 with rows of width x point_step.
        for lenient in (c([field("x", 0, 7, count=0), field("y", 4, 7), field("z", 8, 7)]), c(row_step=0)):
            np.testing.assert_array_equal(clouds.cloud_points(lenient)[0], clouds.cloud_points(c())[0])
        cases = [
            (c(point_step=0), "point_step is 0: expected the bytes of one point (> 0)"),
            (c(point_step=-16), "point_step is -16"),
            (c(point_step=8), "point field 'z' (offset 8, 1 x 4 bytes) does not fit the point step 8: expected "
                              "offset + size x count <= point_step"),
            (c(row_step=40), "row_step 40 is less than width x point_step = 3 x 16 = 48"),
            (c(row_step=0, data=c().data[:-16]), "row_step 0 is less than width x point_step"),
            (c(data=c().data + bytes(16)), "data holds 112 bytes, expected row_step x height = 48 x 2 = 96"),
            (c(data=c().data[:-16]), "data holds 80 bytes, expected row_step x height = 48 x 2 = 96"),
            (c(row_step=64), "data holds 96 bytes, expected row_step x height = 64 x 2 = 128"),
            (c(width=0), "the point cloud is empty (2 x 0 points)"),
            (c(height=0), "the point cloud is empty (0 x 3 points)"),
            (c(width=-3, height=-2), "the point cloud is -2 x -3 points: expected height and width >= 1"),
            (c(width=2.5), "the point cloud's width is 2.5, expected an integer"),
            (c([field("x", 0, 7), field("y", 2, 7), field("z", 8, 7)]),
             "point fields 'x' (bytes 0-3) and 'y' (bytes 2-5) overlap"),
            (c(self.XYZ + [field("", 10, 2)]), "point fields 'z' (bytes 8-11) and '' (bytes 10-10) overlap"),
            (c(self.XYZ + [field("intensity", 0, 8)]), "point fields 'x' (bytes 0-3) and 'intensity' (bytes 0-7) "
                                                       "overlap"),
            (c([]), "the point cloud has no fields: expected at least x, y, z"),
            (c([field("x", 0, 7, count=2), field("y", 8, 7), field("z", 12, 7)]),
             "point field 'x' has count 2: expected 1 (one value a point)"),
            (c(self.XYZ + [field("ring", 12, 4, count=2)]), "point field 'ring' has count 2: expected 1"),
            (c(self.XYZ + [field("x", 12, 7)]), "point field 'x' appears twice (offsets 0 and 12): expected it once"),
            (c([field("x", -4, 7), field("y", 4, 7), field("z", 8, 7)]),
             "point field 'x' has offset -4 and count 1: expected both >= 0"),
            (c([field("x", 2**40, 7), field("y", 4, 7), field("z", 8, 7)]), "point field 'x' (offset 1099511627776"),
            (c([field("x", 0, 7, count=2**62), field("y", 4, 7), field("z", 8, 7)]), "does not fit the point step 16"),
            (c([field("x", 0, "float32"), field("y", 4, 7), field("z", 8, 7)]),
             "point field 'x' datatype is 'float32', expected an integer"),
            (c([field("x", 0, 0), field("y", 4, 7), field("z", 8, 7)]),
             "point field 'x' has an unknown datatype 0: expected one of sensor_msgs/PointField's (1 INT8"),
            (c(self.XYZ + [field(None, 12, 7)]), "a point field's name is None, expected a string"),
            (c(data=None), "the point cloud's data is NoneType, expected bytes"),
            (Msg(**dict(vars(c()), fields=None)), "the point cloud's fields are None, expected a list of PointField"),
        ]
        for msg, text in cases:
            with self.assertRaises(ConversionError, msg=text) as e:
                clouds.cloud_points(msg)
            self.assertIn(text, str(e.exception))
        bad_ring = rec.copy()
        bad_ring[1, 3] = np.nan
        with self.assertRaisesRegex(ConversionError, "point field 'ring' holds values that are not laser indices"):
            clouds.cloud_points(cloud(bad_ring, self.XYZ + [field("ring", 12, 7)]))
        # Padding fields without a name, repeated names we do not read and count-0 fields we do not read: allowed.
        ok = c(self.XYZ + [field("", 12, 2, count=4), field("t", 12, 7, count=0)])
        self.assertEqual(clouds.cloud_points(ok)[0].shape, (6, 3))

    def test_fuzz_every_outcome_is_a_result_or_a_refusal(self):
        """A good cloud's point_step, row_step, width, height, fields and data length mutated at random: every
        outcome is either the points an independent reader (struct, point by point) finds, or a ConversionError."""
        rng = np.random.default_rng(20261127)
        types = {1: "b", 2: "B", 3: "h", 4: "H", 5: "i", 6: "I", 7: "f", 8: "d"}
        base_rec = rng.normal(scale=10, size=(12, 5)).astype(np.float32)
        base_rec[3, 1] = np.nan
        base_rec[:, 4].view(np.uint32)[:] = rng.integers(0, 64, 12)
        fields0 = [("x", 0, 7, 1), ("y", 4, 7, 1), ("z", 8, 7, 1), ("intensity", 12, 7, 1), ("ring", 16, 6, 1)]
        outcomes = {"result": 0, "refused": 0}

        def reference(m):
            """The finite points (float32) and rings the message's own definition gives, read point by point (a
            row_step of 0 taken as width x point_step)."""
            f = {fd.name: fd for fd in m.fields}
            order = ">" if m.is_bigendian else "<"
            pts, rings = [], []
            row_step = m.row_step or m.width * m.point_step
            for r in range(m.height):
                for col in range(m.width):
                    base = r * row_step + col * m.point_step
                    p = [struct.unpack_from(order + types[f[n].datatype], m.data, base + f[n].offset)[0]
                         for n in "xyz"]
                    p = np.array(p, np.float64)
                    with np.errstate(over="ignore"):
                        p32 = p.astype(np.float32)
                    if np.isfinite(p32).all():
                        pts.append(p32)
                        if "ring" in f:
                            rings.append(struct.unpack_from(order + types[f["ring"].datatype], m.data,
                                                            base + f["ring"].offset)[0])
            return np.array(pts, np.float32).reshape(-1, 3), rings
        for case in range(400):
            height = int(rng.choice([1, 2, 3, 4]))
            rec = base_rec[:12 // height * height]
            m = cloud(rec, [field(*f) for f in fields0], height=height)
            for _ in range(int(rng.integers(1, 4))):
                what = rng.integers(0, 7)
                if what == 0:
                    m.point_step = int(rng.choice([0, 1, 4, 12, 16, 19, 20, 24, 40, -20, 2**33]))
                elif what == 1:
                    m.row_step = int(rng.choice([0, m.row_step - 4, m.row_step, m.row_step + 4, 2 * m.row_step,
                                                 -m.row_step, m.width * m.point_step]))
                elif what == 2:
                    m.width = int(rng.choice([0, 1, m.width - 1, m.width + 1, 2 * m.width, -1]))
                elif what == 3:
                    m.height = int(rng.choice([0, 1, m.height - 1, m.height + 1, -1]))
                elif what == 4:
                    d = int(rng.choice([-20, -1, 1, 4, 20, -len(m.data)]))
                    m.data = m.data[:len(m.data) + d] if d < 0 else m.data + bytes(d)
                elif what == 5:
                    i = int(rng.integers(0, len(m.fields)))
                    fd = m.fields[i]
                    attr = ["offset", "datatype", "count", "name"][int(rng.integers(0, 4))]
                    value = {"offset": [0, 2, 4, 15, 16, 17, -4, 2**31], "datatype": [0, 1, 3, 5, 7, 8, 9],
                             "count": [0, 1, 2, 3], "name": ["", "x", "y", "ring", "w"]}[attr]
                    m.fields[i] = field(**dict(vars(fd), **{attr: value[int(rng.integers(0, len(value)))]}))
                else:
                    if rng.random() < 0.5 and len(m.fields) > 1:
                        m.fields = [f for j, f in enumerate(m.fields) if j != int(rng.integers(0, len(m.fields)))]
                    else:
                        m.fields = m.fields + [field(str(rng.choice(["pad", "", "x"])), int(rng.integers(0, 24)),
                                                     int(rng.choice([2, 4, 7, 8])))]
                # keep the data consistent with the header half of the time: the mutation then reaches the fields
                if rng.random() < 0.5 and m.height > 0 and m.row_step > 0 and m.row_step * m.height < 10**6:
                    need = m.row_step * m.height
                    m.data = (m.data * (need // max(len(m.data), 1) + 1))[:need]
            try:
                points, ring, dropped = clouds.cloud_points(m)
            except ConversionError:
                outcomes["refused"] += 1
                continue
            outcomes["result"] += 1
            want, rings = reference(m)
            np.testing.assert_array_equal(points, want, err_msg="case %d" % case)
            self.assertEqual(dropped, m.width * m.height - len(want), "case %d" % case)
            if ring is not None:
                self.assertEqual(ring.tolist(), rings, "case %d" % case)
        self.assertGreater(outcomes["result"], 40, outcomes)  # the fuzz reaches both outcomes
        self.assertGreater(outcomes["refused"], 100, outcomes)


class Transforms(unittest.TestCase):
    def test_quaternion_round_trip(self):
        r = cv2.Rodrigues(np.array([0.3, -1.2, 2.0]))[0]
        m = transforms.transform_matrix((1, 2, 3), transforms.rotation_quaternion(r))
        np.testing.assert_allclose(m[:3, :3], r, atol=1e-12)
        np.testing.assert_array_equal(m[:3, 3], [1, 2, 3])
        with self.assertRaisesRegex(ConversionError, "not a unit quaternion"):
            transforms.transform_matrix((0, 0, 0), (0, 0, 0, 0))

    def test_chain_through_a_tree(self):
        rng = np.random.default_rng(2)

        def rigid():
            return transforms.transform_matrix(rng.normal(size=3), transforms.rotation_quaternion(
                cv2.Rodrigues(rng.normal(size=3))[0]))
        base_cam, cam_opt, base_lidar = rigid(), rigid(), rigid()  # child -> parent
        edges = [("base_link", "camera", base_cam), ("camera", "camera_optical", cam_opt),
                 ("/base_link", "velodyne", base_lidar)]
        m = transforms.chain_transform(edges, "velodyne", "camera_optical")
        np.testing.assert_allclose(m, np.linalg.inv(base_cam @ cam_opt) @ base_lidar, atol=1e-12)
        np.testing.assert_allclose(transforms.chain_transform(edges, "camera_optical", "base_link"), base_cam @ cam_opt,
                                   atol=1e-12)
        np.testing.assert_allclose(transforms.chain_transform(edges, "camera", "camera"), np.eye(4))
        with self.assertRaisesRegex(ConversionError, "no transform links frame 'velodyne' to 'map'"):
            transforms.chain_transform(edges, "velodyne", "map")

    def test_transform_buffer_at_a_stamp(self):
        """/tf samples interpolated at the cloud's stamp (the rotation checked with cv2.Rodrigues: a turn about one
        axis, a fraction of the way), the nearest within the tolerance beyond them, /tf_static as it came."""
        def stamped(parent, child, m, stamp):
            q = transforms.rotation_quaternion(m[:3, :3])
            return Msg(header=Msg(frame_id=parent, stamp=Msg(sec=stamp // 10**9, nanosec=stamp % 10**9)),
                       child_frame_id=child, transform=Msg(translation=Msg(x=m[0, 3], y=m[1, 3], z=m[2, 3]),
                                                           rotation=Msg(x=q[0], y=q[1], z=q[2], w=q[3])))
        r0 = cv2.Rodrigues(np.array([0.2, -0.4, 0.1]))[0]
        axis = np.array([0.6, 0.0, 0.8])
        def lidar(t):  # base_link -> velodyne at t in [0, 1]: turned about axis by 0.3 t rad, moved 0.5 t m in x
            m = np.eye(4)
            m[:3, :3] = r0 @ cv2.Rodrigues(axis * 0.3 * t)[0]
            m[:3, 3] = [1.0 + 0.5 * t, 0.2, 1.5]
            return m
        cam = np.eye(4)
        cam[:3, :3] = [[0, 0, 1], [-1, 0, 0], [0, -1, 0]]
        buf = transforms.TransformBuffer(tolerance_ns=10**8)
        with self.assertRaisesRegex(ConversionError, "nothing received on /tf_static or /tf yet"):
            buf.lookup("velodyne", "camera_optical", 0)
        buf.add([stamped("base_link", "camera_optical", cam, 0)], static=True)
        t0, t1 = 10 * 10**9, 11 * 10**9
        buf.add([stamped("base_link", "velodyne", lidar(1), t1)], static=False)
        buf.add([stamped("/base_link", "velodyne", lidar(0), t0)], static=False)  # out of order
        for f in (0.0, 0.25, 0.5, 1.0):
            m = buf.lookup("velodyne", "camera_optical", t0 + int(f * 10**9))
            np.testing.assert_allclose(m, np.linalg.inv(cam) @ lidar(f), atol=1e-12)
        np.testing.assert_allclose(buf.lookup("velodyne", "camera_optical", t1 + 10**8),
                                   np.linalg.inv(cam) @ lidar(1), atol=1e-12)
        np.testing.assert_allclose(buf.lookup("velodyne", "camera_optical", t0 - 10**8),
                                   np.linalg.inv(cam) @ lidar(0), atol=1e-12)
        with self.assertRaisesRegex(ConversionError, r"no transform links frame 'velodyne' to 'camera_optical'.*"
                                    r"/tf has base_link -> velodyne from 10.000 to 11.000 s, not at 11.200 s"):
            buf.lookup("velodyne", "camera_optical", t1 + 2 * 10**8)
        # The latest message decides: a static transform of the child replaces its /tf history, a /tf one its static.
        buf.add([stamped("base_link", "velodyne", lidar(0.5), 0)], static=True)
        np.testing.assert_allclose(buf.lookup("velodyne", "camera_optical", 5 * 10**9),
                                   np.linalg.inv(cam) @ lidar(0.5), atol=1e-12)
        buf.add([stamped("base_link", "velodyne", lidar(0.75), t1)], static=False)
        np.testing.assert_allclose(buf.lookup("velodyne", "camera_optical", t1),
                                   np.linalg.inv(cam) @ lidar(0.75), atol=1e-12)
        with self.assertRaisesRegex(ConversionError, "not at 5.000 s"):
            buf.lookup("velodyne", "camera_optical", 5 * 10**9)
        with self.assertRaisesRegex(ConversionError, "not a unit quaternion"):
            bad = stamped("base_link", "x", np.eye(4), 0)
            bad.transform.rotation.w = 2.0
            buf.add([bad], static=True)


def pack_rgb(bgr):
    """Colours (..., 3 uint8 BGR) packed as PCL and RViz read them: the bits of 0x00RRGGBB as float32."""
    bgr = bgr.astype(np.uint32)
    return ((bgr[..., 2] << 16) | (bgr[..., 1] << 8) | bgr[..., 0]).view(np.float32)


class Outputs(unittest.TestCase):
    def test_disparity_depth_points(self):
        d16 = np.array([[-16, 0, 16], [160, 17, -16]], np.int16)
        np.testing.assert_array_equal(outputs.disparity_image(d16), [[-1, 0, 1], [10, 17 / 16, -1]])
        self.assertEqual(outputs.valid_window(d16, 0), (0, 0, 3, 2))
        self.assertEqual(outputs.valid_window(np.full((3, 4), -16, np.int16), 0), (0, 0, 0, 0))
        self.assertEqual(outputs.valid_window(np.array([[-16, -16], [-16, 32]], np.int16), 0), (1, 1, 1, 1))
        depth = cv2.lidarsgm.disparityToDepth(d16, 100.0)  # 0 where invalid or d = 0
        f32 = outputs.depth_image(depth, "32FC1")
        self.assertTrue(np.isnan(f32[0, 0]) and np.isnan(f32[0, 1]) and np.isnan(f32[1, 2]))
        self.assertAlmostEqual(float(f32[1, 0]), 10.0, places=5)
        # What Fusion.outputs writes for 32FC1: the NaN set by the conversion, the same array
        np.testing.assert_array_equal(cv2.lidarsgm.disparityToDepth(d16, 100.0, invalidDepth=np.nan), f32)
        mm = outputs.depth_image(depth, "16UC1")
        self.assertEqual(mm.dtype, np.uint16)
        self.assertEqual(mm[1, 0], 10000)
        self.assertEqual(mm[0, 2], 0)  # 100 m does not fit 16 bits of millimetres: invalid, not wrapped
        self.assertEqual(mm[0, 0], 0)
        with self.assertRaisesRegex(ConversionError, "depth encoding must be 32FC1"):
            outputs.depth_image(depth, "mono8")

    def test_cv2_window_is_the_same(self):
        """valid_window with cv2 (cv2.boundingRect of a comparison, what Fusion.outputs calls) against its numpy
        path, and on a map without a valid pixel."""
        rng = np.random.default_rng(4)
        d16 = rng.integers(-40, 2000, (37, 53)).astype(np.int16)
        for mind in (-2, 0, 3, 200):
            self.assertEqual(outputs.valid_window(d16, mind, cv2), outputs.valid_window(d16, mind))
        sub = np.full((6, 9), -16, np.int16)
        sub[2:4, 5] = 40
        self.assertEqual(outputs.valid_window(sub, 0, cv2), (5, 2, 1, 2))
        self.assertEqual(outputs.valid_window(np.full((3, 4), -16, np.int16), 0, cv2), (0, 0, 0, 0))

    def test_packed_colour(self):
        bgr = np.array([[[1, 2, 3]]], np.uint8)
        packed = pack_rgb(bgr).view(np.uint32)
        self.assertEqual(int(packed[0, 0]), 0x030201)
        rng = np.random.default_rng(3)
        bgr = rng.integers(0, 256, (5, 7, 3), dtype=np.uint8)
        d16 = rng.integers(-16, 128 * 16, (5, 7)).astype(np.int16)
        d16[1, 2] = -16
        q = cv2.lidarsgm.reprojectionMatrix(np.array([[721.5, 0, 3.5, 0], [0, 721.5, 2.5, 0], [0, 0, 1, 0]]), 384.4)
        for mind in (0, 5):
            rec = outputs.point_cloud_array(d16, q, bgr, mind, cv2)
            self.assertEqual((rec.shape, rec.dtype), ((5, 7, 4), np.float32))
            np.testing.assert_array_equal(rec[..., :3], cv2.lidarsgm.disparityToPoints(d16, q, minDisparity=mind))
            self.assertTrue(np.isnan(rec[1, 2, :3]).all())
            np.testing.assert_array_equal(rec[..., 3].view(np.uint32), pack_rgb(bgr).view(np.uint32))
        out = np.zeros((5, 7, 4), np.float32)  # written in place: the node's message array
        self.assertIs(outputs.point_cloud_array(d16, q, bgr, 0, cv2, out), out)
        np.testing.assert_array_equal(out.view(np.uint32),
                                      outputs.point_cloud_array(d16, q, bgr, 0, cv2).view(np.uint32))
        with self.assertRaises(ConversionError):
            outputs.point_cloud_array(d16[:4], q, bgr, 0, cv2)
        self.assertEqual(struct.unpack("<I", pack_rgb(bgr)[0, 0].tobytes())[0],
                         (int(bgr[0, 0, 2]) << 16) | (int(bgr[0, 0, 1]) << 8) | int(bgr[0, 0, 0]))


class KittiMessages(unittest.TestCase):
    """The shipped frames in ROS's convention project to the same sparse map as KITTI's own calibration."""

    def test_ros_convention_projects_the_same(self):
        kit = MessageKit(lambda type_name, **f: Msg(**f), lambda a: np.ascontiguousarray(a).tobytes(),
                         lambda a: np.asarray(a, np.float64).ravel())  # plain objects: no ROS needed
        for fid in ("000002", "000046"):
            frame = cv2.lidarsgm.loadKittiFrame(os.path.join(TESTDATA, "kitti"), fid)
            points = cv2.lidarsgm.readVelodyneScan(os.path.join(TESTDATA, "kitti", "velodyne", fid + ".bin"))
            msgs = kitti.frame_messages(kit, frame, points, 10**9)
            g = camera_info.stereo_geometry(msgs["left/camera_info"], msgs["right/camera_info"])
            self.assertAlmostEqual(g.focal_baseline, frame.calibration.focalBaseline, places=9)
            xyz, ring = clouds.cloud_to_points(msgs["points"])
            np.testing.assert_array_equal(xyz, points[:, :3])
            self.assertEqual(len(np.unique(ring)), cv2.lidarsgm.countLidarRings(points))
            t = kitti.ros_calibration(frame.calibration)[3]
            sparse = cv2.lidarsgm.projectPointsToDisparity(xyz, g.projection, t, g.focal_baseline, g.size)
            np.testing.assert_array_equal(sparse, frame.sparse)


class FusionOfMessages(unittest.TestCase):
    """lidarsgm_ros.fusion, what the node and the bag command call, on the KITTI frames as plain messages."""

    def setUp(self):
        self.kit = MessageKit(lambda type_name, **f: Msg(**f), lambda a: np.ascontiguousarray(a).tobytes(),
                              lambda a: np.asarray(a, np.float64).ravel())
        self.frame = cv2.lidarsgm.loadKittiFrame(os.path.join(TESTDATA, "kitti"), "000002")
        points = cv2.lidarsgm.readVelodyneScan(os.path.join(TESTDATA, "kitti", "velodyne", "000002.bin"))
        self.msgs = kitti.frame_messages(self.kit, self.frame, points, 10**9)
        self.params = os.path.join(os.path.dirname(__file__), "..", "..", "doc", "params", "kitti_best.yml")

    def inputs(self, **replace):
        m = dict(self.msgs, **replace)
        return m["left/image_rect"], m["left/camera_info"], m["right/image_rect"], m["right/camera_info"], m["points"]

    def fusion(self, use_cuda=False):
        return Fusion(cv2, self.params, use_cuda, kitti.ros_calibration(self.frame.calibration)[3])

    def test_outputs_in_bands_are_the_same_bytes(self):
        """Fusion.outputs in 1, 3 and 8 bands of rows at once (on threads): every array byte for byte the same, in
        32FC1 and 16UC1, fresh arrays and a kit's reused ones; a Q whose -cy moved by a band's first row is not exact
        in double is not split."""
        f = self.fusion()
        r = f.fuse(*self.inputs())
        d16 = r.disparity16.copy()
        d16[::7, ::5] = -16  # invalid pixels scattered too
        r = r._replace(disparity16=d16)
        for enc in ("32FC1", "16UC1"):
            want = [np.array(a) for a in f.outputs(r, enc, bands=1)]
            for bands in (3, 8):
                for alloc in (None, self.kit.alloc, self.kit.alloc):
                    got = f.outputs(r, enc, alloc, bands=bands)
                    for a, b in zip(want, got):
                        self.assertEqual(np.array(b).tobytes(), a.tobytes(), (enc, bands))
        self.assertEqual(outputs.row_bands(375, 8), [(0, 46), (46, 93), (93, 140), (140, 187), (187, 234), (234, 281),
                                                     (281, 328), (328, 375)])
        self.assertEqual(outputs.row_bands(40, 8), [(0, 40)])
        # one band where OpenCV's threads fill half the cores or more (a thread a core: the node's default)
        self.assertEqual([outputs.output_bands(c, t) for c, t in ((16, 16), (16, 8), (2, 1), (16, 2), (16, 6), (64, 8))],
                         [1, 1, 1, 4, 2, 4])
        q = cv2.lidarsgm.reprojectionMatrix(r.geometry.projection, r.geometry.focal_baseline)
        self.assertEqual(outputs.band_reprojection(q, 46)[1, 3], q[1, 3] + 46)
        q[1, 3] = -0.1  # -0.1 + 3 is not exact
        self.assertIsNone(outputs.band_reprojection(q, 3))
        q[3, 1] = 1e-3  # y in the fourth row: not a shift of cy alone
        self.assertIsNone(outputs.band_reprojection(q, 0))

    def test_same_as_the_module_call(self):
        r = self.fusion().fuse(*self.inputs(), confidence=True)
        sgm = cv2.lidarsgm.StereoLidarSGM.load(self.params)
        np.testing.assert_array_equal(r.sparse, self.frame.sparse)
        disp, conf = sgm.computeWithConfidence(self.frame.left, self.frame.right, self.frame.sparse)
        np.testing.assert_array_equal(r.disparity16, disp)
        np.testing.assert_array_equal(r.confidence, conf)

    @unittest.skipIf(cv2.cuda.getCudaEnabledDeviceCount() < 1, "no CUDA device")
    def test_cuda_same_as_cpu(self):
        cpu = self.fusion().fuse(*self.inputs(), confidence=True)
        gpu = self.fusion(use_cuda=True).fuse(*self.inputs(), confidence=True)
        np.testing.assert_array_equal(gpu.disparity16, cpu.disparity16)
        np.testing.assert_array_equal(gpu.confidence, cpu.confidence)

    def test_misplaced_lidar_goes_stereo_alone(self):
        """The LiDAR turned by 1.5 degrees about the camera's vertical: the fail-safe's stereo alone, the stereo-alone
        matcher's output; on the GPU (which fuses with the LiDAR while the CPU checks, then computes again) the
        same."""
        a = np.radians(1.5)
        turn = np.eye(4)
        turn[0, 0] = turn[2, 2] = np.cos(a)
        turn[0, 2], turn[2, 0] = np.sin(a), -np.sin(a)
        wrong = (turn @ kitti.ros_calibration(self.frame.calibration)[3]).ravel()
        f = self.fusion()
        f.set_lidar_to_camera(wrong)
        cpu = f.fuse(*self.inputs())
        self.assertEqual(cpu.stereo_alone, fusion_module.CALIBRATION)
        self.assertIn("the LiDAR misplaced on the images", cpu.reason)
        alone = cv2.lidarsgm.LidarFailSafe.stereoAloneMatcher(cv2.lidarsgm.StereoLidarSGM.load(self.params))
        np.testing.assert_array_equal(cpu.disparity16, alone.compute(
            self.frame.left, self.frame.right, np.zeros(self.frame.left.shape, np.float32)))
        if cv2.cuda.getCudaEnabledDeviceCount() > 0:
            g = self.fusion(use_cuda=True)
            g.set_lidar_to_camera(wrong)
            gpu = g.fuse(*self.inputs())
            self.assertEqual(gpu.stereo_alone, fusion_module.CALIBRATION)
            np.testing.assert_array_equal(gpu.disparity16, cpu.disparity16)

    def test_sets_that_cannot_be_fused(self):
        f = self.fusion()
        small = self.kit.image(self.kit.header(0, ""), self.frame.right[:, :-2], "mono8")
        with self.assertRaisesRegex(ConversionError, "the right image is 1240x375, its camera_info 1242x375"):
            f.fuse(*self.inputs(**{"right/image_rect": small}))
        deep = self.kit.image(self.kit.header(0, ""), self.frame.right.astype(np.uint16) * 256, "mono16")
        with self.assertRaisesRegex(ConversionError, "the left image is bgr8, the right mono16"):
            f.fuse(*self.inputs(**{"right/image_rect": deep}))
        uncalibrated = self.kit.camera_info(self.kit.header(0, ""), 1242, 375, np.eye(3), np.zeros((3, 4)))
        with self.assertRaisesRegex(ConversionError, "right camera_info has no projection matrix P"):
            f.fuse(*self.inputs(**{"right/camera_info": uncalibrated}))
        f.lidar_to_camera = None  # no transform: the images fused as stereo alone, saying why (Fusion.fuse)
        r = f.fuse(*self.inputs())
        self.assertEqual(r.stereo_alone, fusion_module.CALIBRATION)
        self.assertIn("no LiDAR-to-camera transform: set the lidar_to_camera", r.reason)

    def test_settings_checked_by_the_module(self):
        f = self.fusion()
        sgm = f.sgm
        for name, value, text in (("P1", 5000, "must be in [0, 1000]; got 5000"), ("P2", 5, "P1 (10) must not exceed "
                                  "P2 (5)"), ("disparity_range", 100, "multiple of 16"), ("mode", "bm", "mode must be")):
            with self.assertRaises(ValueError) as e:
                f.set(name, value)
            self.assertIn(text, str(e.exception))
            self.assertIs(f.sgm, sgm)   # the matcher as it was
        f.set("disparity_range", 192)
        f.set("mode", "dsgm")
        self.assertEqual((f.sgm.getNumDisparities(), f.value("mode"), f.value("P2")), (192, "dsgm", 120))
        with self.assertRaisesRegex(ValueError, "not a rigid transform"):
            f.set_lidar_to_camera(np.ones(16))
        with self.assertRaisesRegex(ValueError, "takes 12 or 16 numbers"):
            f.set_lidar_to_camera([1, 2])
        if cv2.cuda.getCudaEnabledDeviceCount() < 1:
            with self.assertRaisesRegex(ValueError, "use_cuda: this cv2 has no CUDA device"):
                f.set_use_cuda(True)


class Sync(unittest.TestCase):
    def test_exact(self):
        s = ExactSync(3, queue_size=2)
        self.assertEqual(s.add(0, 10, "a0"), [])
        self.assertEqual(s.add(1, 10, "b0"), [])
        self.assertEqual(s.add(0, 20, "a1"), [])
        self.assertEqual(s.add(2, 10, "c0"), [(10, ["a0", "b0", "c0"])])
        self.assertEqual(s.add(1, 20, "b1"), [])
        self.assertEqual(s.add(0, 30, "a2"), [])
        self.assertEqual(s.add(2, 30, "c2"), [])     # 20 still incomplete, 30 waits for stream 1
        self.assertEqual(s.add(1, 30, "b2"), [(30, ["a2", "b2", "c2"])])
        self.assertEqual(s.dropped, 1)                # the set at 20 can no longer complete
        self.assertEqual(s.pending, {})

    def test_approximate(self):
        ms = 1000000
        s = ApproximateSync(2, queue_size=5, max_interval_ns=20 * ms)
        out = []
        for i, t in [(0, 100), (1, 130), (0, 200), (1, 195), (0, 300), (1, 310), (1, 330), (0, 400)]:
            out += s.add(i, t * ms, "%d@%d" % (i, t))
        # 130 has no partner within 20 ms (100 is 30 ms off): dropped; 100, older than the next set, goes too
        self.assertEqual([m for _, m in out], [["0@200", "1@195"], ["0@300", "1@310"]])
        self.assertEqual(s.add(1, 405 * ms, "1@405"), [(400 * ms, ["0@400", "1@405"])])
        self.assertGreaterEqual(s.dropped, 2)
        self.assertEqual(s.add(0, 390 * ms, "old"), [])  # back in time: dropped, not emitted
        # At the end of the input the last set is final without a later message; what is left counts as dropped.
        self.assertEqual(s.add(0, 500 * ms, "0@500"), [])
        self.assertEqual(s.add(1, 510 * ms, "1@510"), [])   # waits: stream 0 might still send one nearer 510
        dropped = s.dropped
        self.assertEqual(s.finish(), [(510 * ms, ["0@500", "1@510"])])
        self.assertEqual(s.dropped, dropped)
        e = ExactSync(2)
        e.add(0, 1, "a")
        self.assertEqual(e.finish(), [])
        self.assertEqual(e.dropped, 1)


if __name__ == "__main__":
    unittest.main()
