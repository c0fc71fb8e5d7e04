"""geometry_msgs/Transform and tf trees to 4 x 4 matrices: transform_matrix and rotation_quaternion between a
translation and quaternion and a matrix, chain_transform through a tree of transforms from one frame to another, and
TransformBuffer, the contents of /tf_static and /tf looked up at a stamp (a /tf edge interpolated between its
samples); ConversionError where no chain of known transforms links two frames.
"""
import math

import numpy as np

from .conversions import ConversionError, stamp_ns

__all__ = ["transform_matrix", "rotation_quaternion", "chain_transform", "TransformBuffer"]


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
