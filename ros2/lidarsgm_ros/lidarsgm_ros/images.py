"""sensor_msgs/Image to numpy: image_to_array reads an image of the encodings the node takes (mono8/16, bgr8, rgb8,
bgra8, rgba8, 32FC1) as an H x W (x C) array, to_grey makes the grey image the matcher takes and to_bgr the 8-bit BGR
image the point cloud's colour comes from (as cv2.cvtColor converts them).
"""
import numpy as np

from .conversions import ConversionError, _buffer, _int

__all__ = ["image_to_array", "to_grey", "to_bgr"]


_ENCODINGS = {  # encoding: (numpy dtype, channels)
    "mono8": (np.uint8, 1), "8UC1": (np.uint8, 1), "mono16": (np.uint16, 1), "16UC1": (np.uint16, 1),
    "bgr8": (np.uint8, 3), "rgb8": (np.uint8, 3), "bgra8": (np.uint8, 4), "rgba8": (np.uint8, 4),
    "32FC1": (np.float32, 1)}


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
