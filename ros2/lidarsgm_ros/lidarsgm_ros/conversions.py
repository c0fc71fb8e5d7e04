"""ROS 2 message contents to and from the lidarsgm module's inputs and outputs, with numpy only: the common base.

The conversions are lidarsgm_ros.images, .clouds, .camera_info, .transforms and .outputs; this module holds what they
share: ConversionError and the small readers of a message's fields (an integer, a list of numbers, a matrix, a byte
array, a header stamp). Nothing in them imports ROS: a message is read through its field names (rclpy's messages and
rosbags' alike), and the outputs are numpy arrays and plain values that lidarsgm_ros.messages puts into messages. Bad
input raises ConversionError with a message that says what was wrong.
"""
import numpy as np

__all__ = ["ConversionError", "stamp_ns"]


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


def stamp_ns(msg):
    """A message's header stamp in nanoseconds."""
    return int(msg.header.stamp.sec) * 1000000000 + int(msg.header.stamp.nanosec)
