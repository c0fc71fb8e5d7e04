"""The LiDAR-to-camera rotation refined from the sets whose LiDAR lands misplaced on their images, shared by the node
(in the background) and the bag command (in order, so that its output does not depend on timing).

Each set that Fusion fuses as stereo alone (cv2.lidarsgm.LidarFailSafe condemned its LiDAR) is kept: its images, its
cloud and its camera geometry, the last `sets` of them. When the pool is full, and again after every `sets / 2` new
ones, cv2.lidarsgm.LidarCalibration refines the rotation from the pool. The correction is taken only if it brings the
calibration residual under 1 px (the DDC's Q1 band) and every pooled set's LiDAR is then trusted by the fail-safe; the
caller switches to it and logs it with its uncertainty.
"""
from collections import deque

import numpy as np

from .fusion import optical_transform, rectified_transform


class Recalibration:
    def __init__(self, cv2, scan_rate=0.0, sets=8):
        if sets < 2:
            raise ValueError("recalibration needs at least 2 sets, not %d" % sets)
        self.cv2, self.scan_rate, self.sets = cv2, float(scan_rate), int(sets)
        self.pool = deque(maxlen=self.sets)
        self.new = 0

    def add(self, result):
        """Keeps a set fused as stereo alone (a fusion.Result)."""
        self.pool.append((result.left_grey, result.right_grey, result.points, result.geometry))
        self.new += 1

    def due(self):
        """Whether the pool is full and has taken half its size since the last attempt."""
        return len(self.pool) == self.sets and self.new >= max(self.sets // 2, 1)

    def refine(self, lidar_to_camera, num_disparities=128):
        """(corrected 4x4 or None, a line saying what was found) from the pool; resets the count of new sets."""
        cv2 = self.cv2
        self.new = 0
        g = self.pool[-1][3]
        pool = [p for p in self.pool if p[3].size == g.size and np.array_equal(p[3].projection, g.projection) and
                np.array_equal(p[3].rectification, g.rectification)]
        # LidarCalibration and the check work in the rectified frame that P projects; the caller's transform ends in
        # the left optical frame (Fusion applies camera_info's R after it), and so does the corrected one returned.
        rectified = rectified_transform(g, lidar_to_camera)
        try:
            cal = cv2.lidarsgm.LidarCalibration.create(g.projection, g.focal_baseline, num_disparities,
                                                       self.scan_rate)
            for left, right, points, _ in pool:
                cal.addFrame(left, right, points)
            c = cal.refine(rectified)
        except cv2.error as e:
            return None, "recalibration from %d sets failed: %s" % (len(pool), getattr(e, "err", e))
        deg = np.degrees(np.asarray(c.rotation).ravel())
        std = np.degrees(np.asarray(c.rotationStd).ravel())
        text = ("correction from %d sets: pitch %+.3f +- %.3f, yaw %+.3f +- %.3f, roll %+.3f +- %.3f degrees; "
                "calibration residual %.2f -> %.2f px" % (len(pool), deg[0], std[0], deg[1], std[1], deg[2], std[2],
                                                          c.residualBefore, c.residualAfter))
        fail_safe = cv2.lidarsgm.LidarFailSafe.create()
        if not c.residualAfter <= fail_safe.maxResidual():
            return None, text + ": above %.0f px, not taken" % fail_safe.maxResidual()
        corrected = np.asarray(c.lidarToCamera, np.float64)
        for left, right, points, geometry in pool:
            sparse = cv2.lidarsgm.projectPointsToDisparity(points, geometry.projection, corrected,
                                                           geometry.focal_baseline, geometry.size)
            try:
                ok = not fail_safe.check(left, right, sparse).stereoAlone
            except cv2.error:
                ok = False
            if not ok:
                return None, text + ": a pooled set's LiDAR is still misplaced under it, not taken"
        self.pool.clear()
        return optical_transform(g, corrected), text
