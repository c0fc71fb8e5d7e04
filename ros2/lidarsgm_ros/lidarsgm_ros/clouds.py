"""sensor_msgs/PointCloud2 to the module's LiDAR input: cloud_fields reads a cloud's records in any field order and
point step (checked as PointCloud2 defines it), cloud_points and cloud_to_points take its finite x, y, z as N x 3
float32 and the ring index per point where the cloud has a 'ring' field; a malformed cloud raises ConversionError.
"""
import numpy as np

from .conversions import ConversionError, _buffer, _int

__all__ = ["cloud_fields", "cloud_points", "cloud_to_points"]


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
    step, ox = rec.dtype.itemsize, fields["x"][1]
    side_by_side = all(fields[n][0] == f32 for n in "xyz") and fields["y"][1] == ox + 4 and fields["z"][1] == ox + 8
    known_finite = False
    if side_by_side and ox % 4 == 0 and step % 4 == 0 and rec.flags.c_contiguous:
        # x, y, z side by side as float32 (every driver we know): an N x 3 view of the records, no copy (the
        # projection reads pitched rows). Finite where the sum of every float of the records is; the sum is the
        # cheap test (one contiguous pass), taken only where every 4 bytes of a record hold a float32 field, since
        # integers read as floats are denormals, slow to add.
        rows = rec.view(np.uint8).view(f32).reshape(rec.shape[0], step // 4)
        xyz = rows[:, ox // 4:ox // 4 + 3]
        all_floats = sorted(v[1] for v in fields.values() if v[0] == f32) == list(range(0, step, 4))
        known_finite = all_floats and bool(np.isfinite(rows.sum()))
    elif side_by_side:
        # One strided copy of their 12 bytes a point, as one 12-byte item (twice as fast as numpy's copy of 3 floats
        # a point at an odd stride; the same bytes).
        block = np.dtype({"names": ["xyz"], "formats": ["V12"], "offsets": [ox], "itemsize": step})
        xyz = np.ascontiguousarray(rec.view(block)["xyz"]).view(np.float32).reshape(-1, 3)
    else:
        xyz = np.empty((rec.shape[0], 3), np.float32)
        with np.errstate(over="ignore", invalid="ignore"):  # float64 beyond float32's range: inf, dropped below
            for i, n in enumerate(("x", "y", "z")):
                xyz[:, i] = rec[n]
    ring = rec["ring"] if "ring" in names else None
    dropped = 0
    if not known_finite and not np.isfinite(xyz).all():  # one pass over the whole array where every point is finite
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
