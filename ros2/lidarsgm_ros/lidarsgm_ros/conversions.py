"""ROS 2 message contents to and from the lidarsgm module's inputs and outputs, with numpy only.

Nothing here imports ROS: a message is read through its field names (rclpy's messages and rosbags' alike), and the
outputs are numpy arrays and plain values that lidarsgm_ros.messages puts into messages. Bad input raises
ConversionError with a message that says what was wrong.
"""
import math
from collections import namedtuple

import numpy as np

__all__ = ["ConversionError", "StereoGeometry", "stereo_geometry", "rectification_maps", "is_raw", "image_to_array",
           "to_grey", "to_bgr", "cloud_fields", "cloud_to_points", "transform_matrix", "rotation_quaternion",
           "chain_transform", "stamp_ns", "TransformBuffer", "disparity_image", "valid_window", "depth_image", "point_cloud_array", "POINT_FIELDS", "INVALID_DEPTH_MM"]


class ConversionError(ValueError):
    """A message that cannot be turned into the module's input (the text says why)."""


# ---------------------------------------------------------------------------------------------------------------
# CameraInfo pair -> the projection inputs

StereoGeometry = namedtuple("StereoGeometry", "projection focal_baseline size fx cx cy baseline frame_id rectification")
StereoGeometry.__doc__ = """A rectified pair's geometry: the left 3x4 projection (float64), f x baseline (px m), the
image size (width, height), the left focal length and principal point (px), the baseline (m), the left frame, and the
left rectification rotation R (3x3, the left camera's optical frame to the rectified one; identity where the
camera_info leaves it zero)."""

# camera_info distortion models the module can undo (cv2.initUndistortRectifyMap; equidistant: cv2.fisheye).
DISTORTION_MODELS = ("plumb_bob", "rational_polynomial", "equidistant")


def _matrix(values, rows, cols, what):
    m = np.asarray(values, dtype=np.float64)
    if m.size != rows * cols:
        raise ConversionError("%s has %d values, expected %d" % (what, m.size, rows * cols))
    return m.reshape(rows, cols)


def stereo_geometry(left_info, right_info, tolerance=1e-3):
    """The module's projection inputs from a rectified pair's CameraInfo messages.

    As ROS defines it (REP 104, sensor_msgs/CameraInfo), the right camera's P holds Tx = -fx * baseline in P[0,3]
    (relative to the left's P[0,3], which is 0 for a left camera), so f x baseline = left P[0,3] - right P[0,3].
    A rectified pair shares fx, fy, cx, cy and has no vertical offset (Ty); anything else is refused, since the
    module matches along rows of one camera matrix. tolerance: pixels (and px m for Ty).
    """
    lw, lh, rw, rh = int(left_info.width), int(left_info.height), int(right_info.width), int(right_info.height)
    if lw <= 0 or lh <= 0:
        raise ConversionError("left camera_info has no image size (%dx%d)" % (lw, lh))
    if (lw, lh) != (rw, rh):
        raise ConversionError("left camera_info is %dx%d, right %dx%d: not one rectified pair" % (lw, lh, rw, rh))
    pl = _matrix(left_info.p, 3, 4, "left camera_info P")
    pr = _matrix(right_info.p, 3, 4, "right camera_info P")
    for side, p in (("left", pl), ("right", pr)):
        if not np.all(np.isfinite(p)) or p[0, 0] <= 0 or p[1, 1] <= 0 or p[2, 2] == 0:
            raise ConversionError("%s camera_info has no projection matrix P (fx %g, fy %g): is the camera calibrated "
                                  "and the pair rectified?" % (side, p[0, 0], p[1, 1]))
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
    if values is None or not np.any(np.asarray(values, np.float64)):
        return np.eye(3)  # left zero: no rectification rotation
    r = _matrix(values, 3, 3, "%s camera_info R" % side)
    if not np.all(np.isfinite(r)) or np.abs(r @ r.T - np.eye(3)).max() > 1e-4 or np.linalg.det(r) < 0:
        raise ConversionError("%s camera_info R is not a rotation" % side)
    return r


def is_raw(info, side=""):
    """Whether images with this camera_info differ from their rectified view: distortion, a rectification rotation,
    or a camera matrix K other than P's."""
    d = np.asarray(info.d, np.float64)
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
    d = np.asarray(info.d, np.float64)
    size = (int(info.width), int(info.height))
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


def _buffer(data):
    return np.frombuffer(data, dtype=np.uint8) if not isinstance(data, np.ndarray) else data.view(np.uint8).ravel()


def image_to_array(msg):
    """A sensor_msgs/Image as an H x W (x C) numpy array (a view where the rows are contiguous)."""
    enc = msg.encoding
    if enc not in _ENCODINGS:
        raise ConversionError("image encoding '%s' is not supported (%s)" % (enc, ", ".join(sorted(_ENCODINGS))))
    dtype, ch = _ENCODINGS[enc]
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    row = w * ch * np.dtype(dtype).itemsize
    if h <= 0 or w <= 0:
        raise ConversionError("image is empty (%dx%d)" % (w, h))
    buf = _buffer(msg.data)
    if step < row or buf.size < step * (h - 1) + row:
        raise ConversionError("image data holds %d bytes, a %dx%d %s image with step %d needs %d"
                              % (buf.size, w, h, enc, step, step * (h - 1) + row))
    rows = np.lib.stride_tricks.as_strided(buf, shape=(h, row), strides=(step, 1))
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


def cloud_fields(cloud):
    """The cloud's records as a numpy structured array of height x width points (any field order and point step)."""
    fields = list(cloud.fields)
    step, h, w = int(cloud.point_step), int(cloud.height), int(cloud.width)
    if h * w == 0:
        raise ConversionError("the point cloud is empty")
    names, formats, offsets = [], [], []
    order = ">" if cloud.is_bigendian else "<"
    for f in fields:
        if f.datatype not in _POINT_TYPES:
            raise ConversionError("point field '%s' has an unknown datatype %d" % (f.name, f.datatype))
        if f.name in names or not f.name:
            continue  # nameless padding or a repeated name: not ours to read
        count = max(int(f.count), 1)
        t = np.dtype(_POINT_TYPES[f.datatype]).newbyteorder(order)
        if int(f.offset) + t.itemsize * count > step:
            raise ConversionError("point field '%s' (offset %d) does not fit the point step %d"
                                  % (f.name, f.offset, step))
        names.append(f.name)
        formats.append(t if count == 1 else (t, count))
        offsets.append(int(f.offset))
    dtype = np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": step})
    buf = _buffer(cloud.data)
    row_step = int(cloud.row_step) if int(cloud.row_step) else w * step
    if row_step < w * step or buf.size < row_step * (h - 1) + w * step:
        raise ConversionError("the point cloud's data holds %d bytes, %d x %d points of %d bytes (row step %d) need "
                              "%d" % (buf.size, h, w, step, row_step, row_step * (h - 1) + w * step))
    if row_step == w * step:
        return buf[:h * w * step].view(dtype)  # a view of the message's bytes: no copy
    rows = np.lib.stride_tricks.as_strided(buf, shape=(h, w * step), strides=(row_step, 1))
    return np.ascontiguousarray(rows).reshape(-1).view(dtype)


def cloud_to_points(cloud):
    """x, y, z (N x 3 float32, finite points only) and the ring index per point (N int32) where the cloud has a
    'ring' field, else None."""
    rec = cloud_fields(cloud)
    missing = [n for n in ("x", "y", "z") if n not in rec.dtype.names]
    if missing:
        raise ConversionError("the point cloud has no %s field (fields: %s)"
                              % ("/".join(missing), ", ".join(rec.dtype.names)))
    fields = rec.dtype.fields
    f32 = np.dtype("<f4")
    if all(fields[n][0] == f32 for n in "xyz") and fields["y"][1] == fields["x"][1] + 4 \
            and fields["z"][1] == fields["x"][1] + 8:
        # x, y, z side by side as float32 (every driver we know): one strided copy.
        xyz = np.ascontiguousarray(np.ndarray((rec.shape[0], 3), f32, buffer=rec, offset=fields["x"][1],
                                              strides=(rec.dtype.itemsize, 4))).astype(np.float32, copy=False)
    else:
        xyz = np.empty((rec.shape[0], 3), np.float32)
        for i, n in enumerate(("x", "y", "z")):
            xyz[:, i] = rec[n]
    ring = rec["ring"].astype(np.int32) if "ring" in rec.dtype.names else None
    if not np.isfinite(xyz).all():  # drivers mark missing returns with NaN
        keep = np.isfinite(xyz).all(axis=1)
        xyz = xyz[keep]
        ring = ring[keep] if ring is not None else None
    if xyz.shape[0] == 0:
        raise ConversionError("the point cloud has no finite point")
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


def valid_window(disp16, min_disparity):
    """(x_offset, y_offset, width, height): the smallest rectangle holding every valid disparity (0s if none)."""
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
        out[~(out > 0)] = np.nan
        return out
    if encoding == "16UC1":
        mm = np.rint(depth_m.astype(np.float64) * 1000.0)
        mm[~((mm > 0) & (mm <= 65535))] = INVALID_DEPTH_MM
        if out is None:
            return mm.astype(np.uint16)
        out[...] = mm
        return out
    raise ConversionError("depth encoding must be 32FC1 (metres) or 16UC1 (millimetres), not '%s'" % encoding)


POINT_FIELDS = (("x", 0), ("y", 4), ("z", 8), ("rgb", 12))  # all float32 (datatype 7), point step 16


def point_cloud_array(points, bgr, cv2, out=None):
    """An organised cloud's records (H x W x 4 float32: x y z rgb, 16 bytes a point; into out where given) from
    cv2.lidarsgm.disparityToPoints's H x W x 3 points (NaN = invalid) and the left image in BGR."""
    if points.shape[:2] != bgr.shape[:2]:
        raise ConversionError("points are %s, the colour image %s" % (points.shape[:2], bgr.shape[:2]))
    # PCL's and RViz's packed rgb is the float with the bits 0x00RRGGBB, whose little-endian bytes are B, G, R, 0:
    # BGRA with the alpha cleared, merged with the points by OpenCV in one pass.
    bgra = cv2.bitwise_and(cv2.cvtColor(bgr, cv2.COLOR_BGR2BGRA), (255, 255, 255, 0))
    return cv2.merge([points, bgra.view(np.float32)], out)
