#!/usr/bin/env python3
"""Where the images alone put the LiDAR-to-camera transform of a KITTI folder, without any stereo map.

LidarCalibration judges a transform against SGM disparity maps. To tell whether its offset from calib.txt belongs to
the maps or to the data, this script judges with the images directly: each LiDAR point (nearest per pixel) is matched
by its 3x3 block of census strings (the pipeline's 9x7 centre-symmetric census) within 4 px of its disparity, with the
matcher's uniqueness rule (ratio 0.95) and the subpixel parabola, as cv::lidarsgm::matchingResidual does; the score
of a transform is the mean of min(|LiDAR disparity - matched|, 2 px) over the points of all frames. Each axis (pitch,
roll, then the z translation) is scanned around calib.txt and the score's minimum located by a parabola through the
three lowest grid points. Yaw is left out: the HDL-64E's sweep (not modelled here) moves points along the rows as a
yaw does (doc/design.md, section 7).

    PYTHONPATH=<build>/python_loader python3 tools/analysis/calibration_image_judge.py ../shared/data/kitti2015_lidar
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
from perturb_calibration import read_calib, rotation  # noqa: E402

RADIUS = 4
UNIQUENESS1024 = 973   # the matcher's default ratio 0.95, x 1024 rounded


def census(img):
    """31-bit centre-symmetric census over a 9x7 window (pixel pairs p + o, p - o), replicated border."""
    h, w = img.shape
    p = np.pad(img.astype(np.int32), ((3, 3), (4, 4)), mode='edge')
    out = np.zeros((h, w), np.int64)
    bit = 0
    for dy in range(-3, 1):
        for dx in range(-4, 5):
            if dy == 0 and dx >= 0:
                break
            out |= (p[3 + dy:3 + dy + h, 4 + dx:4 + dx + w] > p[3 - dy:3 - dy + h, 4 - dx:4 - dx + w]).astype(np.int64) << bit
            bit += 1
    return out


POP16 = np.array([bin(i).count('1') for i in range(1 << 16)], np.int32)


def popcount(x):
    return POP16[x & 0xffff] + POP16[(x >> 16) & 0xffff]


def offsets(frames, P, fB, T):
    """LiDAR disparity minus the block match's, for the unique matches of every frame's points under T."""
    out = []
    for cl, cr, X in frames:
        Y = (T @ np.c_[X[:, :3], np.ones(len(X))].T).T[:, :3]
        Y = Y[Y[:, 2] > 1]
        uvw = Y @ P[:, :3].T + P[:, 3]
        u, v, d = uvw[:, 0] / uvw[:, 2], uvw[:, 1] / uvw[:, 2], fB / Y[:, 2]
        h, w = cl.shape
        ui, vi, di = np.round(u).astype(int), np.round(v).astype(int), np.round(d).astype(int)
        m = (vi >= 1) & (vi < h - 1) & (ui - 1 - di - RADIUS >= 0) & (ui + 1 - di + RADIUS <= w - 1) & (ui + 1 < w)
        ui, vi, d, di = ui[m], vi[m], d[m], di[m]
        key = vi * w + ui
        order = np.lexsort((-d, key))   # the nearest point of each pixel first
        first = order[np.r_[True, key[order][1:] != key[order][:-1]]]
        ui, vi, d, di = ui[first], vi[first], d[first], di[first]
        n = 2 * RADIUS + 1
        C = np.zeros((len(ui), n), np.int32)
        for k in range(n):
            for oy in (-1, 0, 1):
                for ox in (-1, 0, 1):
                    C[:, k] += popcount(cl[vi + oy, ui + ox] ^ cr[vi + oy, ui + ox - (di - RADIUS + k)])
        best = C.argmin(1)
        cbest = C.min(1)
        far = np.abs(np.arange(n)[None, :] - best[:, None]) > 1
        second = np.where(far, C, np.iinfo(np.int32).max).min(1)
        ok = (best > 0) & (best < n - 1) & (cbest * 1024 <= UNIQUENESS1024 * second) & (cbest < second)
        c0, c1, c2 = (C[ok, best[ok] + k].astype(float) for k in (-1, 0, 1))
        sub = (c0 - c2) / (2 * np.maximum(c0 + c2 - 2 * c1, 1))
        out.append(d[ok] - (di[ok] - RADIUS + best[ok] + sub))
    return np.concatenate(out)


def score(frames, P, fB, T):
    return float(np.mean(np.minimum(np.abs(offsets(frames, P, fB, T)), 2.0)))


def motion(pitch, yaw, roll, t=(0, 0, 0)):
    M = np.eye(4)
    M[:3, :3] = np.array(rotation(pitch, yaw, roll))
    M[:3, 3] = t
    return M


def vertex(grid, values):
    k = int(np.clip(np.argmin(values), 1, len(values) - 2))
    y0, y1, y2 = values[k - 1:k + 2]
    den = y0 - 2 * y1 + y2
    return grid[k] + (0.5 * (y0 - y2) / den if den > 0 else 0) * (grid[1] - grid[0])


def main():
    import cv2
    data = sys.argv[1] if len(sys.argv) > 1 else '../shared/data/kitti2015_lidar'
    e, _ = read_calib(os.path.join(data, 'calib.txt'))
    P = np.array(e['P2']).reshape(3, 4)
    fB = P[0, 3] - np.array(e['P3']).reshape(3, 4)[0, 3]
    r0 = np.eye(4)
    r0[:3, :3] = np.array(e['R0_rect']).reshape(3, 3)
    tr = np.eye(4)
    tr[:3, :] = np.array(e['Tr_velo_to_cam']).reshape(3, 4)
    T0 = r0 @ tr
    ids = open(os.path.join(data, 'frames.txt')).read().split()
    frames = []
    for i in ids:
        left = cv2.imread(os.path.join(data, 'image_2', i + '_10.png'), cv2.IMREAD_GRAYSCALE)
        right = cv2.imread(os.path.join(data, 'image_3', i + '_10.png'), cv2.IMREAD_GRAYSCALE)
        scan = np.fromfile(os.path.join(data, 'velodyne', i + '.bin'), np.float32).reshape(-1, 4)
        frames.append((census(left), census(right), scan[scan[:, 0] > 1]))
    print('the images alone (census block matches, no stereo map) on %d frames of %s; score = mean min(|LiDAR - '
          'matched disparity|, 2 px)' % (len(ids), data))
    angles = np.round(np.arange(-0.16, 0.161, 0.02), 3)
    pitch = roll = 0.0
    for axis in ('pitch', 'roll'):
        vals = []
        for a in angles:
            p, r = (pitch + a, roll) if axis == 'pitch' else (pitch, roll + a)
            vals.append(score(frames, P, fB, motion(p, 0, r) @ T0))
        best = vertex(angles, np.array(vals))
        print('%s (degrees from calib.txt%s): %s' % (axis, ', pitch at its minimum' if axis == 'roll' else '',
              '  '.join('%+.2f %.4f' % (a, v) for a, v in zip(angles, vals))))
        print('  minimum at %+.3f degree' % ((pitch if axis == 'pitch' else roll) + best))
        if axis == 'pitch':
            pitch += best
        else:
            roll += best
    zs = np.round(np.arange(-0.2, 0.201, 0.05), 3)
    vals = [score(frames, P, fB, motion(pitch, 0, roll, (0, 0, z)) @ T0) for z in zs]
    print('z translation (metres, camera frame, pitch and roll at their minima): %s'
          % '  '.join('%+.2f %.4f' % (z, v) for z, v in zip(zs, vals)))
    print('  minimum at %+.3f m' % vertex(zs, np.array(vals)))


if __name__ == '__main__':
    main()
