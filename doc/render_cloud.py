#!/usr/bin/env python3
"""Renders a point cloud written by the tool (--format ply: binary little-endian x y z float, red green blue uchar) as
seen by a virtual camera behind and above the left camera, for doc/tutorial.md.

  python3 doc/render_cloud.py points.ply out.png
"""
import sys

import numpy as np
import cv2 as cv


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        count = next(int(l.split()[2]) for l in header if l.startswith("element vertex"))
        props = [l.split()[2] for l in header if l.startswith("property")]
        if header[1] != "format binary_little_endian 1.0" or props != ["x", "y", "z", "red", "green", "blue"]:
            raise ValueError(path + " is not a PLY of the tool's layout")
        dtype = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("r", "u1"), ("g", "u1"), ("b", "u1")])
        return np.frombuffer(f.read(count * dtype.itemsize), dtype, count)


def render(v, size=(1400, 700), f=640.0, eye=(0.0, -9.0, -9.0), pitch_deg=24.0, max_depth=45.0):
    keep = v["z"] < max_depth
    v = v[keep]
    p = np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64) - np.array(eye)
    a = np.deg2rad(pitch_deg)   # the virtual camera looks down by pitch_deg (camera y points down)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    q = p @ rot.T
    front = q[:, 2] > 0.5
    q, v = q[front], v[front]
    u = (f * q[:, 0] / q[:, 2] + size[0] / 2).astype(int)
    w = (f * q[:, 1] / q[:, 2] + size[1] / 2).astype(int)
    img = np.full((size[1], size[0], 3), 255, np.uint8)
    order = np.argsort(-q[:, 2])   # far points first, near ones painted over them
    for dy in (0, 1):
        for dx in (0, 1):
            uu, ww = u[order] + dx, w[order] + dy
            ok = (uu >= 0) & (uu < size[0]) & (ww >= 0) & (ww < size[1])
            img[ww[ok], uu[ok]] = np.stack([v["b"], v["g"], v["r"]], 1)[order][ok]
    ys, xs = np.nonzero(img.min(axis=2) < 255)   # cropped to the drawn points, with a margin
    if len(ys):
        img = img[max(ys.min() - 8, 0):ys.max() + 9, max(xs.min() - 8, 0):xs.max() + 9]
    return img


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    cv.imwrite(sys.argv[2], render(read_ply(sys.argv[1])), [cv.IMWRITE_PNG_COMPRESSION, 9])
