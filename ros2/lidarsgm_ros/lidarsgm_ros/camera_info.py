"""A rectified pair's sensor_msgs/CameraInfo messages to the module's projection inputs: stereo_geometry gives the
left 3x4 projection, f x baseline, the image size and the left rectification rotation (StereoGeometry), and refuses a
pair that is not calibrated or not rectified to one camera matrix; is_raw says whether images of a camera_info differ
from their rectified view, and rectification_maps gives the cv2.remap maps that rectify them (image_proc's way).
"""
from collections import namedtuple

import numpy as np

from .conversions import ConversionError, _floats, _int, _matrix

__all__ = ["StereoGeometry", "stereo_geometry", "rectification_maps", "is_raw"]


StereoGeometry = namedtuple("StereoGeometry", "projection focal_baseline size fx cx cy baseline frame_id rectification")
StereoGeometry.__doc__ = """A rectified pair's geometry: the left 3x4 projection (float64), f x baseline (px m), the
image size (width, height), the left focal length and principal point (px), the baseline (m), the left frame, and the
left rectification rotation R (3x3, the left camera's optical frame to the rectified one; identity where the
camera_info leaves it zero)."""

# camera_info distortion models the module can undo (cv2.initUndistortRectifyMap; equidistant: cv2.fisheye).
DISTORTION_MODELS = ("plumb_bob", "rational_polynomial", "equidistant")


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
