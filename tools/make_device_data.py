#!/usr/bin/env python3
"""Pack ../shared/data compactly for the device machine (the raw scans are too large to travel): KITTI images as grey
PNGs, each raw scan projected by the module (cv2.lidarsgm.projectPointsToDisparity, CV_16U KITTI encoding) into
sparse16/<id>.png, Middlebury copied as is. Usage: PYTHONPATH=<opencv build>/python_loader tools/make_device_data.py
[shared_data_dir] [out_dir]"""
import os
import shutil
import sys

import numpy as np
import cv2 as cv

src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', '..', 'shared', 'data')
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), '..', '.device', 'shared')
k_src, k_out = os.path.join(src, 'kitti2015_lidar'), os.path.join(out, 'kitti2015_lidar')
for d in ('image_2', 'image_3', 'sparse16'):
    os.makedirs(os.path.join(k_out, d), exist_ok=True)
calib = {}
with open(os.path.join(k_src, 'calib.txt')) as f:
    for line in f:
        if ':' in line:
            k, v = line.split(':', 1)
            calib[k] = np.array([float(x) for x in v.split()])
r0 = np.eye(4)
r0[:3, :3] = calib['R0_rect'].reshape(3, 3)
tr = np.eye(4)
tr[:3, :4] = calib['Tr_velo_to_cam'].reshape(3, 4)
fb = calib['P2'][3] - calib['P3'][3]
ids = open(os.path.join(k_src, 'frames.txt')).read().split()
for i in ids:
    for d in ('image_2', 'image_3'):
        img = cv.imread(os.path.join(k_src, d, i + '_10.png'), cv.IMREAD_GRAYSCALE)
        cv.imwrite(os.path.join(k_out, d, i + '_10.png'), img)
    pts = np.fromfile(os.path.join(k_src, 'velodyne', i + '.bin'), dtype=np.float32).reshape(-1, 4)
    sparse = cv.lidarsgm.projectPointsToDisparity(pts, calib['P2'].reshape(3, 4), r0 @ tr, fb,
                                                  (img.shape[1], img.shape[0]), dtype=cv.CV_16U)
    cv.imwrite(os.path.join(k_out, 'sparse16', i + '.png'), sparse)
shutil.copy(os.path.join(k_src, 'frames.txt'), k_out)
shutil.copy(os.path.join(k_src, 'calib.txt'), k_out)
shutil.copytree(os.path.join(src, 'middlebury'), os.path.join(out, 'middlebury'), dirs_exist_ok=True)
print('packed', len(ids), 'KITTI frames and the Middlebury scenes into', out)
