"""Messages built from numpy arrays, for rclpy (a live node) or rosbags (bag files) alike.

A MessageKit makes the same messages from the same arrays for either library: rclpy's generated classes want
uint8 arrays as array.array (checked element by element otherwise, seconds per image), rosbags' dataclasses want
numpy arrays and every field.
"""
import array
import importlib

import numpy as np

from .outputs import POINT_FIELDS

FLOAT32 = 7  # sensor_msgs/PointField.FLOAT32

# The node's inputs and outputs, in the order the synchroniser and the fusion take them: topic -> message type.
INPUT_TYPES = {"left/image_rect": "sensor_msgs/msg/Image", "left/camera_info": "sensor_msgs/msg/CameraInfo",
               "right/image_rect": "sensor_msgs/msg/Image", "right/camera_info": "sensor_msgs/msg/CameraInfo",
               "points": "sensor_msgs/msg/PointCloud2"}
OUTPUT_TYPES = {"disparity": "stereo_msgs/msg/DisparityImage", "depth": "sensor_msgs/msg/Image",
                "points2": "sensor_msgs/msg/PointCloud2", "confidence": "sensor_msgs/msg/Image"}


def rclpy_class(type_name):
    """rclpy's generated class of a type name such as sensor_msgs/msg/Image."""
    pkg, _, typ = type_name.split("/")
    return getattr(importlib.import_module(pkg + ".msg"), typ)


def output_messages(kit, fusion, result, header_frame, stamp, depth_encoding, mark=None, bands=None):
    """[(output topic, message)] of one fused set: disparity, depth, points2, and confidence where the Result has
    it; the arrays come from kit.alloc, so the messages must go out before the next call. mark(step): called after
    each step (Fusion.outputs's, then 'messages'); bands: Fusion.outputs's."""
    disp, window, depth, records = fusion.outputs(result, depth_encoding, kit.alloc, mark, bands)
    g, sgm = result.geometry, fusion.sgm
    header = kit.header(stamp, header_frame or g.frame_id)
    out = [("disparity", kit.disparity(header, disp, g.fx, g.baseline, sgm.getMinDisparity(),
                                       sgm.getNumDisparities(), window)),
           ("depth", kit.image(header, depth, depth_encoding)),
           ("points2", kit.organised_cloud(header, records))]
    if result.confidence is not None:
        out.append(("confidence", kit.image(header, result.confidence, "32FC1")))
    if mark is not None:
        mark("messages")
    return out


class MessageKit:
    """Builds sensor_msgs / stereo_msgs / std_msgs messages for one library (MessageKit.rclpy() or
    MessageKit.rosbags(typestore))."""

    def __init__(self, new, bytes_of, floats, alloc=np.empty):
        self._new, self._bytes, self._floats, self._alloc = new, bytes_of, floats, alloc
        self._pool = {}

    def alloc(self, shape, dtype, name=None):
        """An array a message can take without a copy. With a name, the array of the last call with that name, shape
        and dtype comes back: fresh megabytes cost page faults (about as much as the conversions themselves), and a
        published or serialised message no longer needs its array (rclpy and rosbags copy it as they serialise)."""
        if name is None:
            return self._alloc(shape, dtype)
        key = (name, tuple(shape), np.dtype(dtype).str)
        if key not in self._pool:
            self._pool = {k: v for k, v in self._pool.items() if k[0] != name}
            self._pool[key] = self._alloc(shape, dtype)
        return self._pool[key]

    @classmethod
    def rclpy(cls):
        def new(type_name, **fields):
            # The generated constructors copy an array.array field (array.array('B', value)), and so do the setters
            # unless the message checks its fields, when they keep an array.array of type 'B' as it is.
            arrays = {k: fields.pop(k) for k in [k for k, v in fields.items() if isinstance(v, array.array)]}
            if arrays:
                fields["check_fields"] = True
            msg = rclpy_class(type_name)(**fields)
            for k, v in arrays.items():
                setattr(msg, k, v)
            return msg

        def alloc(shape, dtype):  # a numpy view of an array.array the message can keep
            buf = array.array("B", [0]) * (int(np.prod(shape)) * np.dtype(dtype).itemsize)
            return np.frombuffer(buf, dtype).reshape(shape)

        def bytes_of(a):  # alloc's array.array as it is, anything else copied once into one
            base = a
            while isinstance(base, (np.ndarray, memoryview)):
                base = base.base if isinstance(base, np.ndarray) else base.obj
            if isinstance(base, array.array) and a.flags.c_contiguous and a.nbytes == len(base) \
                    and a.__array_interface__["data"][0] == base.buffer_info()[0]:
                return base
            out = array.array("B")
            out.frombytes(memoryview(np.ascontiguousarray(a)).cast("B"))
            return out
        return cls(new, bytes_of, lambda a: [float(v) for v in np.ravel(a)], alloc)

    @classmethod
    def rosbags(cls, typestore):
        def new(type_name, **fields):
            return typestore.types[type_name](**fields)
        return cls(new, lambda a: np.ascontiguousarray(a).reshape(-1).view(np.uint8),
                   lambda a: np.asarray(a, np.float64).ravel())

    def time(self, nanoseconds):
        return self._new("builtin_interfaces/msg/Time", sec=int(nanoseconds // 1000000000),
                         nanosec=int(nanoseconds % 1000000000))

    def header(self, nanoseconds, frame_id):
        return self._new("std_msgs/msg/Header", stamp=self.time(nanoseconds), frame_id=frame_id)

    def roi(self, x=0, y=0, width=0, height=0):
        return self._new("sensor_msgs/msg/RegionOfInterest", x_offset=x, y_offset=y, width=width, height=height,
                         do_rectify=False)

    def image(self, header, a, encoding):
        """sensor_msgs/Image of an H x W (x C) array (little endian, rows contiguous)."""
        a = np.ascontiguousarray(a)
        return self._new("sensor_msgs/msg/Image", header=header, height=a.shape[0], width=a.shape[1],
                         encoding=encoding, is_bigendian=0, step=a.strides[0], data=self._bytes(a))

    def camera_info(self, header, width, height, K, P, D=(), R=np.eye(3), distortion_model="plumb_bob"):
        return self._new("sensor_msgs/msg/CameraInfo", header=header, height=height, width=width,
                         distortion_model=distortion_model, d=self._floats(D), k=self._floats(K),
                         r=self._floats(R), p=self._floats(P), binning_x=0, binning_y=0, roi=self.roi())

    def field(self, name, offset, datatype, count=1):
        return self._new("sensor_msgs/msg/PointField", name=name, offset=offset, datatype=datatype, count=count)

    def cloud(self, header, records, fields):
        """sensor_msgs/PointCloud2 of records (H x W x K or N x K numeric array, or structured), fields
        [(name, offset, datatype)]; is_dense False (NaN points may be in it)."""
        records = np.ascontiguousarray(records)
        h, w = (records.shape[0], records.shape[1]) if records.ndim == 3 else (1, records.shape[0])
        step = records.nbytes // (h * w)
        return self._new("sensor_msgs/msg/PointCloud2", header=header, height=h, width=w,
                         fields=[self.field(n, o, t) for n, o, t in fields], is_bigendian=False,
                         point_step=step, row_step=step * w, data=self._bytes(records), is_dense=False)

    def organised_cloud(self, header, records):
        """The x y z rgb cloud of outputs.point_cloud_array."""
        return self.cloud(header, records, [(n, o, FLOAT32) for n, o in POINT_FIELDS])

    def disparity(self, header, disparity, f, baseline, min_disparity, num_disparities, window):
        """stereo_msgs/DisparityImage: float32 pixels, the module's range, delta_d 1/16 (4 fractional bits)."""
        return self._new("stereo_msgs/msg/DisparityImage", header=header,
                         image=self.image(header, disparity, "32FC1"), f=float(f), t=float(baseline),
                         valid_window=self.roi(*window), min_disparity=float(min_disparity),
                         max_disparity=float(min_disparity + num_disparities - 1), delta_d=1.0 / 16)
