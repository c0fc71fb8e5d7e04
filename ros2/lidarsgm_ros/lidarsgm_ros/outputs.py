"""The matcher's outputs to the contents of the node's messages: the float32 pixels and valid window of a
stereo_msgs/DisparityImage (disparity_image, valid_window), REP 118 depth (depth_image) and the organised x y z rgb
PointCloud2's records (point_cloud_array, POINT_FIELDS), and the bands of rows Fusion.outputs converts at once
(output_bands, row_bands, band_reprojection).
"""
from fractions import Fraction

import numpy as np

from .conversions import ConversionError

__all__ = ["disparity_image", "valid_window", "depth_image", "output_bands", "row_bands", "band_reprojection",
           "point_cloud_array", "POINT_FIELDS", "INVALID_DEPTH_MM"]


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
    """How many bands of rows to convert at once (Fusion.outputs): one where OpenCV's threads take half the cores
    or more (its own parallel loops keep them busy; the node's default, a thread a core) or on two cores; else
    about as many as leave the cores busy beside OpenCV's threads, 2 to 4. Measured on a 16-core host at KITTI size
    (tools/ros2_latency.py --cuda, median ms of the outputs): 16 OpenCV threads 1.36-1.72 in one band against
    1.76-2.24 in two; 2 OpenCV threads, in 1 / 2 / 4 / 8 bands, 6.3 / 5.1 / 3.4 / 3.5."""
    if cpus <= 2 or 2 * opencv_threads >= cpus:
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


def point_cloud_array(disp16, q, bgr, min_disparity, cv2, out=None):
    """An organised cloud's records (H x W x 4 float32: x y z rgb, 16 bytes a point; into out where given) of the
    matcher's CV_16S output, its Q and the left image in BGR: cv2.lidarsgm.disparityToColoredPoints, one pass (the
    points of disparityToPoints, NaN = invalid, and PCL's and RViz's packed rgb: the float with the bits 0x00RRGGBB,
    whose little-endian bytes are B, G, R, 0)."""
    if disp16.shape[:2] != bgr.shape[:2]:
        raise ConversionError("points are %s, the colour image %s" % (disp16.shape[:2], bgr.shape[:2]))
    return cv2.lidarsgm.disparityToColoredPoints(disp16, q, bgr, out, minDisparity=min_disparity)
