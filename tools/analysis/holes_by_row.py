#!/usr/bin/env python3
"""Where the total D1 of a KITTI folder run comes from, by image row band: the share of the ground truth in each
band, the holes (ground-truth pixels without an estimate), the outliers among estimates and among the holes after
the devkit's interpolation (doc/accuracy.md, "Fewer LiDAR lines").

  lidarsgm_fuse --kitti DATA/kitti2015_lidar --modes sdsgm [--lidar-lines 16] --out OUT [...]
  PYTHONPATH=<opencv build>/python_loader python3 tools/analysis/holes_by_row.py OUT [DATA/kitti2015_lidar] [SUFFIX]

SUFFIX is the tool's frame-folder suffix of line-count runs (e.g. _16lines).
"""
import sys

import numpy as np
import cv2 as cv

BANDS = [(0, 150), (150, 200), (200, 250), (250, 300), (300, 340), (340, 375)]


def main():
    out = sys.argv[1]
    data = sys.argv[2] if len(sys.argv) > 2 else "../shared/data/kitti2015_lidar"
    suffix = sys.argv[3] if len(sys.argv) > 3 else ""
    stats = np.zeros((len(BANDS), 4))
    for fid in open(data + "/frames.txt").read().split():
        gt = cv.imread("%s/disp_occ_0/%s_10.png" % (data, fid), cv.IMREAD_UNCHANGED) / 256.0
        d = cv.imread("%s/%s%s/disparity_sdsgm.png" % (out, fid, suffix), cv.IMREAD_UNCHANGED) / 256.0
        est = d.astype(np.float32)
        est[d == 0] = -1
        filled = cv.lidarsgm.interpolateBackground(est)
        has = gt > 0
        err = np.abs(filled - gt)
        bad = (err > 3) & (err > 0.05 * gt) & has
        hole = (d == 0) & has
        for b, (y0, y1) in enumerate(BANDS):
            stats[b] += [has[y0:y1].sum(), hole[y0:y1].sum(), (bad & ~hole)[y0:y1].sum(), (bad & hole)[y0:y1].sum()]
    total = stats[:, 0].sum()
    print("| rows | share of the ground truth | holes | outliers among estimates (pp of all) | outliers in holes (pp) |")
    print("| --- | --- | --- | --- | --- |")
    for (y0, y1), (g, h, eb, hb) in zip(BANDS, stats):
        print("| %d-%d | %.1f %% | %.2f %% | %.2f | %.2f |" % (y0, y1, 100 * g / total, 100 * h / max(g, 1),
                                                           100 * eb / total, 100 * hb / total))
    print("| all | 100 %% | %.2f %% | %.2f | %.2f |" % (100 * stats[:, 1].sum() / total, 100 * stats[:, 2].sum() / total,
                                                       100 * stats[:, 3].sum() / total))


if __name__ == "__main__":
    main()
