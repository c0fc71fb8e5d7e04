"""ROS 2 message contents to and from the lidarsgm module's inputs and outputs, with numpy only.

Nothing here imports ROS: a message is read through its field names (rclpy's messages and rosbags' alike), and the
outputs are numpy arrays and plain values that lidarsgm_ros.messages puts into messages. Bad input raises
ConversionError with a message that says what was wrong.
"""
import math
from collections import namedtuple
from fractions import Fraction

import numpy as np

__all__ = ["ConversionError", "StereoGeometry", "stereo_geometry", "rectification_maps", "is_raw", "image_to_array",
           "to_grey", "to_bgr", "cloud_fields", "cloud_points", "cloud_to_points", "transform_matrix",
           "rotation_quaternion", "chain_transform", "stamp_ns", "TransformBuffer", "disparity_image", "valid_window",
           "depth_image", "output_bands", "row_bands", "band_reprojection", "point_cloud_array", "POINT_FIELDS",
           "INVALID_DEPTH_MM"]


class ConversionError(ValueError):
    """A message that cannot be turned into the module's input (the text says why)."""


def _int(value, what):
    """A message's integer field as a Python int (ConversionError where it is none: a hand-built message)."""
    try:
        i = int(value)
    except (TypeError, ValueError, OverflowError):
        raise ConversionError("%s is %r, expected an integer" % (what, value)) from None
    if i != value:
        raise ConversionError("%s is %r, expected an integer" % (what, value))
    return i


# ---------------------------------------------------------------------------------------------------------------
# CameraInfo pair -> the projection inputs

StereoGeometry = namedtuple("StereoGeometry", "projection focal_baseline size fx cx cy baseline frame_id rectification")
StereoGeometry.__doc__ = """A rectified pair's geometry: the left 3x4 projection (float64), f x baseline (px m), the
image size (width, height), the left focal length and principal point (px), the baseline (m), the left frame, and the
left rectification rotation R (3x3, the left camera's optical frame to the rectified one; identity where the
camera_info leaves it zero)."""

# camera_info distortion models the module can undo (cv2.initUndistortRectifyMap; equidistant: cv2.fisheye).
DISTORTION_MODELS = ("plumb_bob", "rational_polynomial", "equidistant")


def _floats(values, what):
    try:
        return np.asarray(values if values is not None else (), dtype=np.float64).ravel()
    except (TypeError, ValueError, OverflowError):
        raise ConversionError("%s is not a list of numbers (%.60r)" % (what, values)) from None


def _matrix(values, rows, cols, what, finite=False):
    m = _floats(values, what)
    if m.size != rows * cols:
        raise ConversionError("%s has %d values, expected %d (%d x %d, row by row)"
                              % (what, m.size, rows * cols, rows, cols))
    if finite and not np.all(np.isfinite(m)):
        raise ConversionError("%s holds NaN or infinite values (%s): is the camera calibrated?"
                              % (what, ", ".join("%g" % v for v in m)))
    return m.reshape(rows, cols)


def _info_key(info):
    """The values of a CameraInfo that stereo_geometry reads, as a key to compare (None where one is not plain)."""
    try:
        w, h = info.width, info.height
        frame = getattr(getattr(info, "header", None), "frame_id", "")
        if not (isinstance(w, (int, np.integer)) and isinstance(h, (int, np.integer)) and isinstance(frame, str)):
            return None
        return (int(w), int(h), frame) + tuple(
            None if getattr(info, n, None) is None else np.asarray(getattr(info, n), np.float64).tobytes()
            for n in ("k", "p", "r"))
    except (TypeError, ValueError, OverflowError):
        return None


_last_geometry = [None, None]  # [key, StereoGeometry] of the last pair: camera_info rarely changes


def stereo_geometry(left_info, right_info, tolerance=1e-3):
    """The module's projection inputs from a rectified pair's CameraInfo messages.

    As ROS defines it (REP 104, sensor_msgs/CameraInfo), the right camera's P holds Tx = -fx * baseline in P[0,3]
    (relative to the left's P[0,3], which is 0 for a left camera), so f x baseline = left P[0,3] - right P[0,3].
    A rectified pair shares fx, fy, cx, cy and has no vertical offset (Ty); anything else is refused, since the
    module matches along rows of one camera matrix. tolerance: pixels (and px m for Ty). The pair's values the same
    as the last call's: the last call's StereoGeometry (its arrays are not to be written).
    """
    key = (_info_key(left_info), _info_key(right_info), tolerance)
    if None not in key[:2] and key == _last_geometry[0]:
        return _last_geometry[1]
    g = _stereo_geometry(left_info, right_info, tolerance)
    _last_geometry[:] = [key if None not in key[:2] else None, g]
    return g


def _stereo_geometry(left_info, right_info, tolerance):
    sizes = {}
    for side, info in (("left", left_info), ("right", right_info)):
        w, h = (_int(getattr(info, n, None), "%s camera_info %s" % (side, n)) for n in ("width", "height"))
        if w <= 0 or h <= 0:
            raise ConversionError("%s camera_info has no image size (%dx%d): expected the calibrated image's width "
                                  "and height" % (side, w, h))
        sizes[side] = (w, h)
    (lw, lh), (rw, rh) = sizes["left"], sizes["right"]
    if (lw, lh) != (rw, rh):
        raise ConversionError("left camera_info is %dx%d, right %dx%d: not one rectified pair" % (lw, lh, rw, rh))
    for side, info in (("left", left_info), ("right", right_info)):
        if getattr(info, "k", None) is not None:  # not read here, but a K of the wrong size is a broken message
            _matrix(info.k, 3, 3, "%s camera_info K" % side, finite=True)
    pl = _matrix(getattr(left_info, "p", None), 3, 4, "left camera_info P", finite=True)
    pr = _matrix(getattr(right_info, "p", None), 3, 4, "right camera_info P", finite=True)
    for side, p in (("left", pl), ("right", pr)):
        if p[0, 0] <= 0 or p[1, 1] <= 0 or p[2, 2] == 0:
            raise ConversionError("%s camera_info has no projection matrix P (fx %g, fy %g, P[2,2] %g; expected fx, "
                                  "fy > 0 and P[2,2] = 1): is the camera calibrated and the pair rectified?"
                                  % (side, p[0, 0], p[1, 1], p[2, 2]))
    names = ("fx", "fy", "cx", "cy")
    lk = (pl[0, 0], pl[1, 1], pl[0, 2], pl[1, 2])
    rk = (pr[0, 0], pr[1, 1], pr[0, 2], pr[1, 2])
    for name, a, b in zip(names, lk, rk):
        if abs(a - b) > tolerance:
            raise ConversionError("the pair is not rectified to one camera matrix: left P %s %g, right P %s %g "
                                  "(rectify both images with the stereo calibration's P, e.g. image_proc)"
                                  % (name, a, name, b))
    if abs(pl[1, 3] - pr[1, 3]) > tolerance:
        raise ConversionError("the right camera is offset vertically (P[1,3] %g against the left's %g): only "
                              "horizontal pairs, left camera on the left, are supported" % (pr[1, 3], pl[1, 3]))
    fb = float(pl[0, 3] - pr[0, 3])
    if not fb > 0:
        raise ConversionError("right camera_info P[0,3] (Tx = -fx * baseline) is %g against the left's %g: f x "
                              "baseline must be > 0 (left and right swapped?)" % (pr[0, 3], pl[0, 3]))
    frame = getattr(getattr(left_info, "header", None), "frame_id", "") or ""
    return StereoGeometry(pl, fb, (lw, lh), float(pl[0, 0]), float(pl[0, 2]), float(pl[1, 2]), fb / float(pl[0, 0]),
                          frame, _rotation(left_info, "left"))


def _rotation(info, side):
    values = getattr(info, "r", None)
    if values is None or not np.any(_floats(values, "%s camera_info R" % side)):
        return np.eye(3)  # left zero: no rectification rotation
    r = _matrix(values, 3, 3, "%s camera_info R" % side)
    if not np.all(np.isfinite(r)) or np.abs(r @ r.T - np.eye(3)).max() > 1e-4 or np.linalg.det(r) < 0:
        raise ConversionError("%s camera_info R is not a rotation" % side)
    return r


def is_raw(info, side=""):
    """Whether images with this camera_info differ from their rectified view: distortion, a rectification rotation,
    or a camera matrix K other than P's."""
    d = _floats(info.d, "%s camera_info D" % side)
    k = _matrix(info.k, 3, 3, "%s camera_info K" % side)
    p = _matrix(info.p, 3, 4, "%s camera_info P" % side)
    return bool(np.any(d != 0) or np.abs(_rotation(info, side) - np.eye(3)).max() > 1e-9 or
                np.abs(k - p[:, :3]).max() > 1e-9)


def rectification_maps(cv2, info, side):
    """(map x, map y) float32 of cv2.remap that rectify a raw image of this camera_info: its K and D undone, turned by
    R and projected with P's camera matrix (image_proc's rectification)."""
    model = info.distortion_model or "plumb_bob"
    if model not in DISTORTION_MODELS:
        raise ConversionError("the %s camera_info's distortion model '%s' is not one of %s: rectify the images "
                              "first (image_proc)" % (side, model, ", ".join(DISTORTION_MODELS)))
    k = _matrix(info.k, 3, 3, "%s camera_info K" % side)
    p = _matrix(info.p, 3, 4, "%s camera_info P" % side)
    if not np.all(np.isfinite(k)) or k[0, 0] <= 0 or k[1, 1] <= 0:
        raise ConversionError("the %s camera_info has no camera matrix K: is the camera calibrated?" % side)
    d = _floats(info.d, "%s camera_info D" % side)
    if not np.all(np.isfinite(d)):
        raise ConversionError("the %s camera_info's distortion coefficients hold NaN or infinite values" % side)
    size = (_int(info.width, "%s camera_info width" % side), _int(info.height, "%s camera_info height" % side))
    if size[0] <= 0 or size[1] <= 0:
        raise ConversionError("the %s camera_info has no image size (%dx%d)" % (side, size[0], size[1]))
    if model == "equidistant":
        if d.size != 4:
            raise ConversionError("the %s camera_info's equidistant model needs 4 coefficients, got %d"
                                  % (side, d.size))
        return cv2.fisheye.initUndistortRectifyMap(k, d, _rotation(info, side), p[:, :3], size, cv2.CV_32FC1)
    if d.size not in (0, 4, 5, 8, 12, 14):
        raise ConversionError("the %s camera_info has %d distortion coefficients (plumb_bob: 5, rational_polynomial: "
                              "8)" % (side, d.size))
    return cv2.initUndistortRectifyMap(k, d if d.size else None, _rotation(info, side), p[:, :3], size, cv2.CV_32FC1)


# ---------------------------------------------------------------------------------------------------------------
# Image -> numpy

_ENCODINGS = {  # encoding: (numpy dtype, channels)
    "mono8": (np.uint8, 1), "8UC1": (np.uint8, 1), "mono16": (np.uint16, 1), "16UC1": (np.uint16, 1),
    "bgr8": (np.uint8, 3), "rgb8": (np.uint8, 3), "bgra8": (np.uint8, 4), "rgba8": (np.uint8, 4),
    "32FC1": (np.float32, 1)}


def _buffer(data, what="the message"):
    """A message's byte array (bytes, array.array, numpy uint8, memoryview; a list of byte values) as uint8."""
    if isinstance(data, np.ndarray):
        if data.dtype.kind in "biuf":  # its bytes, as the message holds them
            return np.ascontiguousarray(data).reshape(-1).view(np.uint8)
        raise ConversionError("%s's data is a %s array, expected bytes (uint8)" % (what, data.dtype))
    try:
        return np.frombuffer(data, dtype=np.uint8)
    except (TypeError, ValueError, BufferError):
        pass
    try:
        a = np.asarray(data)
        if a.ndim == 1 and a.dtype.kind in "iu" and (a.size == 0 or (a.min() >= 0 and a.max() <= 255)):
            return a.astype(np.uint8)
    except (TypeError, ValueError, OverflowError):
        pass
    raise ConversionError("%s's data is %s, expected bytes" % (what, type(data).__name__))


def image_to_array(msg):
    """A sensor_msgs/Image as an H x W (x C) numpy array (a view where the rows are contiguous)."""
    enc = msg.encoding
    if enc not in _ENCODINGS:
        raise ConversionError("image encoding '%s' is not supported (%s)" % (enc, ", ".join(sorted(_ENCODINGS))))
    dtype, ch = _ENCODINGS[enc]
    h, w, step = _int(msg.height, "image height"), _int(msg.width, "image width"), _int(msg.step, "image step")
    row = w * ch * np.dtype(dtype).itemsize
    if h <= 0 or w <= 0:
        raise ConversionError("image is empty (%dx%d): expected width and height > 0" % (w, h))
    if step < row:
        raise ConversionError("image step %d is less than a row of the %dx%d %s image (%d bytes): expected step >= "
                              "width x %d" % (step, w, h, enc, row, row // w))
    buf = _buffer(msg.data, "the image")
    if buf.size != step * h:
        raise ConversionError("image data holds %d bytes, a %dx%d %s image with step %d needs step x height = %d"
                              % (buf.size, w, h, enc, step, step * h))
    rows = buf.reshape(h, step)[:, :row]  # a view; contiguous where step == row
    a = np.ascontiguousarray(rows).view(np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<"))
    a = a.astype(dtype, copy=False)
    return a.reshape(h, w, ch) if ch > 1 else a.reshape(h, w)


COLOUR_ENCODINGS = ("bgr8", "rgb8", "bgra8", "rgba8")


def to_grey(msg, cv2):
    """The grey image the matcher takes (8 or 16 bits, one channel): colour converted as cv2.cvtColor does."""
    a = image_to_array(msg)
    codes = {"bgr8": cv2.COLOR_BGR2GRAY, "rgb8": cv2.COLOR_RGB2GRAY, "bgra8": cv2.COLOR_BGRA2GRAY,
             "rgba8": cv2.COLOR_RGBA2GRAY}
    if msg.encoding in codes:
        return cv2.cvtColor(a, codes[msg.encoding])
    if a.dtype == np.float32:
        raise ConversionError("a 32FC1 image cannot be matched: send mono8 or mono16")
    return a


def to_bgr(msg, cv2):
    """The image as 8-bit BGR, for the point cloud's colour (grey and 16-bit images are scaled and replicated)."""
    a = image_to_array(msg)
    if msg.encoding == "bgr8":
        return a
    if msg.encoding == "rgb8":
        return cv2.cvtColor(a, cv2.COLOR_RGB2BGR)
    if msg.encoding == "bgra8":
        return cv2.cvtColor(a, cv2.COLOR_BGRA2BGR)
    if msg.encoding == "rgba8":
        return cv2.cvtColor(a, cv2.COLOR_RGBA2BGR)
    if a.dtype == np.uint16:
        a = (a >> 8).astype(np.uint8)
    elif a.dtype != np.uint8:
        a = np.clip(a, 0, 255).astype(np.uint8)
    return cv2.cvtColor(a, cv2.COLOR_GRAY2BGR)


# ---------------------------------------------------------------------------------------------------------------
# PointCloud2 -> points

# sensor_msgs/PointField datatypes
_POINT_TYPES = {1: np.int8, 2: np.uint8, 3: np.int16, 4: np.uint16, 5: np.int32, 6: np.uint32, 7: np.float32,
                8: np.float64}


_POINT_TYPE_NAMES = "1 INT8, 2 UINT8, 3 INT16, 4 UINT16, 5 INT32, 6 UINT32, 7 FLOAT32, 8 FLOAT64"
_READ_FIELDS = ("x", "y", "z", "ring")  # the fields cloud_points reads: each must be there once, one value a point


def cloud_fields(cloud):
    """The cloud's records as a numpy structured array of height x width points (any field order and point step).

    The message is checked as sensor_msgs/PointCloud2 defines it: point_step > 0 holds every field, the fields do
    not overlap, row_step >= width x point_step and the data is row_step x height bytes; ConversionError otherwise."""
    h, w = _int(cloud.height, "the point cloud's height"), _int(cloud.width, "the point cloud's width")
    step, row_step = _int(cloud.point_step, "point_step"), _int(cloud.row_step, "row_step")
    if h < 0 or w < 0:
        raise ConversionError("the point cloud is %d x %d points: expected height and width >= 1" % (h, w))
    if h * w == 0:
        raise ConversionError("the point cloud is empty (%d x %d points)" % (h, w))
    if step <= 0:
        raise ConversionError("the point cloud's point_step is %d: expected the bytes of one point (> 0)" % step)
    try:
        fields = list(cloud.fields)
    except TypeError:
        raise ConversionError("the point cloud's fields are %r, expected a list of PointField" % cloud.fields) from None
    if not fields:
        raise ConversionError("the point cloud has no fields: expected at least x, y, z (sensor_msgs/PointField)")
    order = ">" if cloud.is_bigendian else "<"
    spans, kept = [], {}
    for f in fields:
        name = f.name
        if not isinstance(name, str):
            raise ConversionError("a point field's name is %r, expected a string" % (name,))
        datatype = _int(f.datatype, "point field '%s' datatype" % name)
        offset = _int(f.offset, "point field '%s' offset" % name)
        count = _int(f.count, "point field '%s' count" % name)
        if datatype not in _POINT_TYPES:
            raise ConversionError("point field '%s' has an unknown datatype %d: expected one of sensor_msgs/"
                                  "PointField's (%s)" % (name, datatype, _POINT_TYPE_NAMES))
        if offset < 0 or count < 0:
            raise ConversionError("point field '%s' has offset %d and count %d: expected both >= 0"
                                  % (name, offset, count))
        if count == 0:
            if name not in _READ_FIELDS:
                continue  # holds nothing
            count = 1  # a PointField made without count=1 (its default is 0): one value, as drivers mean it
        t = np.dtype(_POINT_TYPES[datatype]).newbyteorder(order)
        end = offset + t.itemsize * count
        if end > step:
            raise ConversionError("point field '%s' (offset %d, %d x %d bytes) does not fit the point step %d: "
                                  "expected offset + size x count <= point_step" % (name, offset, count, t.itemsize,
                                                                                     step))
        spans.append((offset, end, name))
        if not name:
            continue  # nameless padding: not ours to read
        if name in kept:
            if name in _READ_FIELDS:
                raise ConversionError("point field '%s' appears twice (offsets %d and %d): expected it once"
                                      % (name, kept[name][1], offset))
            continue  # a repeated name we do not read
        kept[name] = (t if count == 1 else (t, count), offset)
    spans.sort()
    for (o0, e0, n0), (o1, e1, n1) in zip(spans, spans[1:]):
        if o1 < e0:
            raise ConversionError("point fields '%s' (bytes %d-%d) and '%s' (bytes %d-%d) overlap: expected each "
                                  "field its own bytes of the point" % (n0, o0, e0 - 1, n1, o1, e1 - 1))
    buf = _buffer(cloud.data, "the point cloud")
    if row_step == 0 and buf.size == w * h * step:
        row_step = w * step  # left unset by its publisher, and the data says it: rows of width x point_step
    if row_step < w * step:
        raise ConversionError("the point cloud's row_step %d is less than width x point_step = %d x %d = %d"
                              % (row_step, w, step, w * step))
    if buf.size != row_step * h:
        raise ConversionError("the point cloud's data holds %d bytes, expected row_step x height = %d x %d = %d "
                              "(%d x %d points of %d bytes)" % (buf.size, row_step, h, row_step * h, h, w, step))
    dtype = np.dtype({"names": list(kept), "formats": [v[0] for v in kept.values()],
                      "offsets": [v[1] for v in kept.values()], "itemsize": step})
    if row_step == w * step:
        return buf.view(dtype)  # a view of the message's bytes: no copy
    return np.ascontiguousarray(buf.reshape(h, row_step)[:, :w * step]).reshape(-1).view(dtype)


def cloud_points(cloud):
    """(x y z, ring, dropped) of a PointCloud2: x, y, z as N x 3 float32 of the finite points only (any numeric
    datatype read as float32), the ring index per point (N int32) where the cloud has a 'ring' field, else None, and
    the number of points dropped for a NaN or infinite coordinate (drivers mark missing returns with NaN)."""
    rec = cloud_fields(cloud)
    names = rec.dtype.names
    missing = [n for n in ("x", "y", "z") if n not in names]
    if missing:
        raise ConversionError("the point cloud has no %s field (fields: %s)"
                              % ("/".join(missing), ", ".join(names)))
    fields = rec.dtype.fields
    for n in ("x", "y", "z", "ring"):
        if n in names and fields[n][0].shape:
            raise ConversionError("point field '%s' has count %d: expected 1 (one value a point)"
                                  % (n, fields[n][0].shape[0]))
    f32 = np.dtype("<f4")
    if all(fields[n][0] == f32 for n in "xyz") and fields["y"][1] == fields["x"][1] + 4 \
            and fields["z"][1] == fields["x"][1] + 8:
        # x, y, z side by side as float32 (every driver we know): one strided copy of their 12 bytes a point, as
        # one 12-byte item (twice as fast as numpy's copy of 3 floats a point at an odd stride; the same bytes).
        block = np.dtype({"names": ["xyz"], "formats": ["V12"], "offsets": [fields["x"][1]],
                          "itemsize": rec.dtype.itemsize})
        xyz = np.ascontiguousarray(rec.view(block)["xyz"]).view(np.float32).reshape(-1, 3)
    else:
        xyz = np.empty((rec.shape[0], 3), np.float32)
        with np.errstate(over="ignore", invalid="ignore"):  # float64 beyond float32's range: inf, dropped below
            for i, n in enumerate(("x", "y", "z")):
                xyz[:, i] = rec[n]
    ring = rec["ring"] if "ring" in names else None
    dropped = 0
    if not np.isfinite(xyz).all():  # one pass over the whole array where every point is finite
        finite = np.isfinite(xyz).all(axis=1)
        dropped = int(finite.size - np.count_nonzero(finite))
        xyz = xyz[finite]
        ring = ring[finite] if ring is not None else None
    if xyz.shape[0] == 0:
        raise ConversionError("the point cloud has no finite point (%d points, all with a NaN or infinite "
                              "coordinate)" % dropped)
    if ring is not None:
        if ring.dtype.kind == "f":
            ok = np.isfinite(ring).all() and (ring == np.round(ring)).all() and np.abs(ring).max() < 2**31
        else:  # (u)int8, (u)int16, int32 fit int32 as they are
            ok = ring.dtype.itemsize < 4 or ring.dtype.kind == "i" or ring.max() < 2**31
        if not ok:
            raise ConversionError("point field 'ring' holds values that are not laser indices (whole numbers within "
                                  "int32): expected the laser's ring per point")
        ring = ring.astype(np.int32)
    return xyz, ring, dropped


def cloud_to_points(cloud):
    """x, y, z (N x 3 float32, finite points only) and the ring index per point (N int32) where the cloud has a
    'ring' field, else None: cloud_points without the count of dropped points."""
    xyz, ring, _ = cloud_points(cloud)
    return xyz, ring


# ---------------------------------------------------------------------------------------------------------------
# Transforms (geometry_msgs/Transform and tf trees) -> 4 x 4 matrices

def transform_matrix(translation, rotation):
    """4x4 float64 from a translation (x, y, z) and a unit quaternion (x, y, z, w), as geometry_msgs/Transform."""
    x, y, z, w = (float(v) for v in rotation)
    n = math.sqrt(x * x + y * y + z * z + w * w)
    if not n > 0 or abs(n - 1) > 1e-3:
        raise ConversionError("rotation quaternion (%g, %g, %g, %g) is not a unit quaternion" % (x, y, z, w))
    x, y, z, w = x / n, y / n, z / n, w / n
    m = np.eye(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = [float(v) for v in translation]
    return m


def rotation_quaternion(r):
    """The unit quaternion (x, y, z, w) of a 3x3 rotation matrix."""
    r = np.asarray(r, np.float64)
    w = math.sqrt(max(0.0, 1 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + r[0, 0] - r[1, 1] - r[2, 2])) / 2, r[2, 1] - r[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - r[0, 0] + r[1, 1] - r[2, 2])) / 2, r[0, 2] - r[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - r[0, 0] - r[1, 1] + r[2, 2])) / 2, r[1, 0] - r[0, 1])
    return x, y, z, w


def chain_transform(edges, source, target):
    """The 4x4 matrix taking points in frame `source` to frame `target`, through a tree of transforms.

    edges: (parent, child, matrix) triples where matrix takes child coordinates to parent coordinates (a tf
    TransformStamped: header.frame_id = parent, child_frame_id = child). Raises ConversionError where no chain links
    the two frames.
    """
    to_root = {}
    for parent, child, m in edges:
        to_root[child.lstrip("/")] = (parent.lstrip("/"), np.asarray(m, dtype=np.float64))

    def path(frame):  # frame -> [(frame, matrix to its parent), ...] up to the root
        out, seen = [], set()
        while frame in to_root and frame not in seen:
            seen.add(frame)
            parent, m = to_root[frame]
            out.append((frame, parent, m))
            frame = parent
        return out, frame

    source, target = source.lstrip("/"), target.lstrip("/")
    sp, sroot = path(source)
    tp, troot = path(target)
    if sroot != troot:
        raise ConversionError("no transform links frame '%s' to '%s' (known frames: %s)"
                              % (source, target, ", ".join(sorted(set(to_root) | {p for p, _ in to_root.values()}))))
    # Drop the common part of both paths, then source -> common ancestor -> target.
    s_nodes = [source] + [p for _, p, _ in sp]
    t_nodes = [target] + [p for _, p, _ in tp]
    common = next(n for n in s_nodes if n in t_nodes)
    up = np.eye(4)
    for child, parent, m in sp:
        if child == common:
            break
        up = m @ up
    down = np.eye(4)
    for child, parent, m in tp:
        if child == common:
            break
        down = m @ down
    return np.linalg.inv(down) @ up


def stamp_ns(msg):
    """A message's header stamp in nanoseconds."""
    return int(msg.header.stamp.sec) * 1000000000 + int(msg.header.stamp.nanosec)


def _slerp(q0, q1, t):
    """The unit quaternion a fraction t of the way from q0 to q1 (the shorter arc)."""
    q0, q1 = np.asarray(q0, np.float64), np.asarray(q1, np.float64)
    q0, q1 = q0 / np.linalg.norm(q0), q1 / np.linalg.norm(q1)
    dot = float(q0 @ q1)
    if dot < 0:
        q1, dot = -q1, -dot
    if dot > 0.9995:  # nearly equal: the linear blend, normalised, is as exact
        q = q0 + t * (q1 - q0)
        return q / np.linalg.norm(q)
    a = math.acos(dot)
    return (math.sin((1 - t) * a) * q0 + math.sin(t * a) * q1) / math.sin(a)


class TransformBuffer:
    """The transforms of /tf_static and /tf (tf2_msgs/TFMessage contents), for chain_transform at a stamp.

    A static transform holds until another one for the same child replaces it; a /tf transform of a child replaces
    its static one (the latest message decides, as in tf2). A /tf transform is taken at the stamp asked for:
    interpolated between the two samples around it (translation linearly, rotation along the shorter arc), or the
    nearest sample where the stamp lies outside them by at most `tolerance_ns` (a transform published a little after
    the cloud it applies to). Samples older than `history_ns` behind the newest are dropped.
    """

    def __init__(self, tolerance_ns=100000000, history_ns=10000000000):
        self.tolerance_ns, self.history_ns = int(tolerance_ns), int(history_ns)
        self.static = {}   # child -> (parent, 4x4)
        self.dynamic = {}  # child -> (parent, [(stamp, translation, quaternion), ...] in stamp order)

    def add(self, transforms, static):
        """Takes the TransformStamped items of one TFMessage (from /tf_static when static)."""
        for t in transforms:
            parent, child = t.header.frame_id.lstrip("/"), t.child_frame_id.lstrip("/")
            tr, rot = t.transform.translation, t.transform.rotation
            trans, quat = (float(tr.x), float(tr.y), float(tr.z)), (float(rot.x), float(rot.y), float(rot.z),
                                                                     float(rot.w))
            m = transform_matrix(trans, quat)  # refuses a quaternion that is not a unit one
            if static:
                self.static[child] = (parent, m)
                self.dynamic.pop(child, None)
                continue
            self.static.pop(child, None)
            stamp = stamp_ns(t)
            old_parent, samples = self.dynamic.get(child, (parent, []))
            if old_parent != parent:
                samples = []  # re-parented: the old history describes another edge
            samples = [s for s in samples if s[0] != stamp] + [(stamp, trans, quat)]
            samples.sort(key=lambda s: s[0])
            self.dynamic[child] = (parent, [s for s in samples if s[0] >= samples[-1][0] - self.history_ns])

    def edges(self, at_ns):
        """(parent, child, 4x4 child -> parent) of every edge known at at_ns, and a line on each /tf edge that
        is not (for the error message)."""
        out, missing = [], []
        for child, (parent, m) in self.static.items():
            out.append((parent, child, m))
        for child, (parent, samples) in self.dynamic.items():
            stamps = [s[0] for s in samples]
            k = int(np.searchsorted(stamps, at_ns))
            if k < len(samples) and stamps[k] == at_ns:
                s = samples[k]
                out.append((parent, child, transform_matrix(s[1], s[2])))
            elif 0 < k < len(samples):
                (t0, a0, q0), (t1, a1, q1) = samples[k - 1], samples[k]
                f = (at_ns - t0) / (t1 - t0)
                trans = [a + f * (b - a) for a, b in zip(a0, a1)]
                out.append((parent, child, transform_matrix(trans, _slerp(q0, q1, f))))
            else:
                near = samples[0] if k == 0 else samples[-1]
                if abs(near[0] - at_ns) <= self.tolerance_ns:
                    out.append((parent, child, transform_matrix(near[1], near[2])))
                else:
                    missing.append("/tf has %s -> %s from %.3f to %.3f s, not at %.3f s" % (
                        parent, child, stamps[0] * 1e-9, stamps[-1] * 1e-9, at_ns * 1e-9))
        return out, missing

    def lookup(self, source, target, at_ns):
        """The 4x4 taking points in `source` to `target` at at_ns; raises ConversionError (why) where no chain of
        known transforms links them."""
        edges, missing = self.edges(at_ns)
        if not edges and not missing:
            raise ConversionError("nothing received on /tf_static or /tf yet")
        try:
            return chain_transform(edges, source, target)
        except ConversionError as e:
            raise ConversionError("%s%s" % (e, "; " + "; ".join(missing) if missing else ""))


# ---------------------------------------------------------------------------------------------------------------
# Outputs

INVALID_DEPTH_MM = 0


def disparity_image(disp16, out=None):
    """The matcher's CV_16S output (disparity x 16) as the float32 pixels of a stereo_msgs/DisparityImage (into out,
    an H x W float32 array, where given).

    Invalid pixels keep the matcher's value (minDisparity - 1), below DisparityImage.min_disparity, as
    stereo_image_proc's disparity node leaves them."""
    if disp16.dtype != np.int16:
        raise ConversionError("expected the matcher's int16 output, got %s" % disp16.dtype)
    out = np.empty(disp16.shape, np.float32) if out is None else out
    np.multiply(disp16, np.float32(1.0 / 16), out=out, dtype=np.float32)  # exact: x16 values are small integers
    return out


def valid_window(disp16, min_disparity, cv2=None):
    """(x_offset, y_offset, width, height): the smallest rectangle holding every valid disparity (0s if none). With
    cv2: one comparison and cv2.boundingRect of its mask, the same rectangle."""
    if cv2 is not None and disp16.dtype == np.int16:
        return tuple(int(v) for v in cv2.boundingRect(cv2.compare(disp16, int(min_disparity) * 16, cv2.CMP_GE)))
    valid = disp16 >= min_disparity * 16
    rows, cols = np.flatnonzero(valid.any(axis=1)), np.flatnonzero(valid.any(axis=0))
    if rows.size == 0:
        return 0, 0, 0, 0
    return int(cols[0]), int(rows[0]), int(cols[-1] - cols[0] + 1), int(rows[-1] - rows[0] + 1)


def depth_image(depth_m, encoding, out=None):
    """REP 118 depth from metres (0 = invalid, as cv2.lidarsgm.disparityToDepth gives it): '32FC1' metres with NaN
    where invalid, or '16UC1' millimetres with 0 where invalid (and beyond 65.535 m, which 16 bits cannot hold).
    out: where to write it (H x W float32 or uint16; for 32FC1 it may be depth_m itself)."""
    if encoding == "32FC1":
        if out is None:
            out = depth_m.astype(np.float32, copy=True)
        elif out is not depth_m:
            out[...] = depth_m
        # numpy's masked store: faster on real maps, whose invalid pixels lie together, than cv2's compare and
        # masked bit operations (0.26 against 0.38 ms at KITTI size)
        out[~(out > 0)] = np.nan
        return out
    if encoding == "16UC1":
        mm = np.multiply(depth_m, 1000.0, dtype=np.float64)
        np.rint(mm, out=mm)
        mm[~((mm > 0) & (mm <= 65535))] = INVALID_DEPTH_MM
        if out is None:
            return mm.astype(np.uint16)
        out[...] = mm
        return out
    raise ConversionError("depth encoding must be 32FC1 (metres) or 16UC1 (millimetres), not '%s'" % encoding)


def output_bands(cpus, opencv_threads):
    """How many bands of rows to convert at once (Fusion.outputs): none on two cores or fewer; else about as many as
    leave the cores busy beside OpenCV's own threads, 2 to 4. Measured on a 16-core host at KITTI size (median
    ms of the outputs in 1 / 2 / 4 / 8 bands): 2 OpenCV threads 6.3 / 5.1 / 3.4 / 3.5, 16 threads 3.9 / 3.3 / 4.0
    / 5.3 (bands that each start OpenCV's parallel loops oversubscribe the cores)."""
    if cpus <= 2:
        return 1
    return max(2, min(4, cpus // max(1, opencv_threads)))


def row_bands(height, bands):
    """[(first row, end row)] of about `bands` horizontal bands of a map (one where it has fewer than 32 rows a
    band), for converting them at the same time."""
    n = max(1, min(int(bands), height // 32))
    return [(height * i // n, height * (i + 1) // n) for i in range(n)]


def band_reprojection(q, first_row):
    """The Q that gives cv2.lidarsgm.disparityToPoints the points of the rows from first_row on as those of a map of
    their own, bit for bit the full map's: Q's y column (0, 1, 0, 0) as reprojectionMatrix makes it, and its -cy
    moved by first_row, where that is exact in double (y - cy is then rounded once from the same value); else None."""
    q = np.asarray(q, np.float64)
    if q.shape != (4, 4) or list(q[:, 1]) != [0, 1, 0, 0]:
        return None
    qb = q.copy()
    qb[1, 3] = q[1, 3] + first_row
    return qb if Fraction(float(qb[1, 3])) == Fraction(float(q[1, 3])) + first_row else None


POINT_FIELDS = (("x", 0), ("y", 4), ("z", 8), ("rgb", 12))  # all float32 (datatype 7), point step 16


def point_cloud_array(points, bgr, cv2, out=None, bgra=None):
    """An organised cloud's records (H x W x 4 float32: x y z rgb, 16 bytes a point; into out where given) from
    cv2.lidarsgm.disparityToPoints's H x W x 3 points (NaN = invalid) and the left image in BGR. bgra: an H x W x 4
    uint8 array for the colour on its way (a fresh one where not given)."""
    if points.shape[:2] != bgr.shape[:2]:
        raise ConversionError("points are %s, the colour image %s" % (points.shape[:2], bgr.shape[:2]))
    # PCL's and RViz's packed rgb is the float with the bits 0x00RRGGBB, whose little-endian bytes are B, G, R, 0:
    # BGRA with the alpha cleared, merged with the points by OpenCV in one pass.
    bgra = cv2.cvtColor(bgr, cv2.COLOR_BGR2BGRA, bgra)
    cv2.bitwise_and(bgra, (255, 255, 255, 0), bgra)
    return cv2.merge([points, bgra.view(np.float32)], out)
