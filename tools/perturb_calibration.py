#!/usr/bin/env python3
"""A KITTI-layout folder whose calib.txt carries a known LiDAR-to-camera error, the rest linked to the original.

The error is a rigid motion in the rectified camera frame: points X (rectified camera coordinates, R0_rect *
Tr_velo_to_cam * X_velo) become R X + t, with R = Rx(pitch) Ry(yaw) Rz(roll) (degrees about the camera's x (right),
y (down) and z (forward) axes) and t in metres. calib.txt keeps R0_rect and gets Tr_velo_to_cam' =
R0_rect^-1 [R | t] R0_rect Tr_velo_to_cam, so that R0_rect Tr_velo_to_cam' = [R | t] R0_rect Tr_velo_to_cam.

    perturb_calibration.py SRC DST [--yaw DEG] [--pitch DEG] [--roll DEG] [--x M] [--y M] [--z M]
"""
import argparse
import math
import os
import sys


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))] for i in range(len(a))]


def homogeneous(r, t=(0.0, 0.0, 0.0)):
    return [list(r[0]) + [t[0]], list(r[1]) + [t[1]], list(r[2]) + [t[2]], [0.0, 0.0, 0.0, 1.0]]


def rotation(pitch, yaw, roll):
    a, b, c = (math.radians(v) for v in (pitch, yaw, roll))
    rx = [[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]]
    ry = [[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]]
    rz = [[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]]
    return matmul(matmul(rx, ry), rz)


def read_calib(path):
    entries, order = {}, []
    with open(path) as f:
        for line in f:
            if ':' not in line:
                continue
            key, vals = line.split(':', 1)
            entries[key.strip()] = [float(v) for v in vals.split()]
            order.append(key.strip())
    return entries, order


def perturbed_calib(entries, pitch=0.0, yaw=0.0, roll=0.0, t=(0.0, 0.0, 0.0)):
    """The entries with Tr_velo_to_cam moved by the error (see the module docstring)."""
    for key in ('R0_rect', 'Tr_velo_to_cam'):
        if key not in entries:
            raise ValueError('calib.txt has no ' + key)
    r = entries['R0_rect']
    r0 = [r[0:3], r[3:6], r[6:9]]
    r0inv = [[r0[j][i] for j in range(3)] for i in range(3)]   # a rotation: its inverse is its transpose
    tr = entries['Tr_velo_to_cam']
    tr4 = [tr[0:4], tr[4:8], tr[8:12], [0.0, 0.0, 0.0, 1.0]]
    moved = matmul(matmul(matmul(homogeneous(r0inv), homogeneous(rotation(pitch, yaw, roll), t)), homogeneous(r0)), tr4)
    out = dict(entries)
    out['Tr_velo_to_cam'] = [v for row in moved[:3] for v in row]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('src')
    ap.add_argument('dst')
    for k in ('yaw', 'pitch', 'roll'):
        ap.add_argument('--' + k, type=float, default=0.0, help='degrees')
    for k in ('x', 'y', 'z'):
        ap.add_argument('--' + k, type=float, default=0.0, help='metres')
    a = ap.parse_args()
    calib = os.path.join(a.src, 'calib.txt')
    if not os.path.isfile(calib):
        sys.exit('perturb_calibration.py: %s not found' % calib)
    entries, order = read_calib(calib)
    try:
        out = perturbed_calib(entries, a.pitch, a.yaw, a.roll, (a.x, a.y, a.z))
    except ValueError as e:
        sys.exit('perturb_calibration.py: ' + str(e))
    os.makedirs(a.dst, exist_ok=True)
    for name in os.listdir(a.src):
        if name == 'calib.txt':
            continue
        link = os.path.join(a.dst, name)
        if not os.path.lexists(link):
            os.symlink(os.path.abspath(os.path.join(a.src, name)), link)
    with open(os.path.join(a.dst, 'calib.txt'), 'w') as f:
        for key in order:
            f.write('%s: %s\n' % (key, ' '.join('%.12e' % v for v in out[key])))


if __name__ == '__main__':
    main()
