"""One stereo-LiDAR fusion of a synchronised set of messages, shared by the node and the bag command.

A Fusion holds the matcher (cv2.lidarsgm.StereoLidarSGM) and the LiDAR-to-camera transform; fuse() takes the five
messages (left and right Image and CameraInfo, the PointCloud2) and returns the outputs as arrays; a set that cannot
be fused raises conversions.ConversionError saying why (the caller skips it and counts it).
"""
from collections import namedtuple

import numpy as np

from . import camera_info, clouds, images, outputs
from .conversions import ConversionError

class CalibrationError(ConversionError):
    """The cloud was read, but the transform puts none of it on the images (or there is none)."""


MODES = ("sgm", "dsgm", "sdsgm")  # the mode parameter's values: StereoLidarSGM_MODE_SGM, _DSGM, _SDSGM

# The node's parameters that set the matcher: ROS name -> (matcher property, Python type). The first six carry
# stereo_image_proc's DisparityNode names.
MATCHER_PARAMETERS = {
    "min_disparity": ("MinDisparity", int),
    "disparity_range": ("NumDisparities", int),
    "P1": ("P1", int),
    "P2": ("P2", int),
    "uniqueness_ratio": ("UniquenessRatio", float),
    "disp12_max_diff": ("LRMaxDiff", int),
    "alpha": ("Alpha", float),
    "Q1": ("Q1", int),
    "Q2": ("Q2", int),
}

# Why a set went as stereo alone (the fail-safe's path: MODE_SGM with the left-right check, no sparse map): the
# classes the node's diagnostics count, each with its own text in Result.reason.
NO_CLOUD = "no cloud"          # none paired with the images within the LiDAR timeout
CALIBRATION = "calibration"    # no transform, or the LiDAR lands misplaced on the images (LidarFailSafe)
BAD_CLOUD = "bad message"      # the cloud could not be read
ALONE_CLASSES = (NO_CLOUD, CALIBRATION, BAD_CLOUD)

# sparse: the LiDAR's map (None without one); points: the cloud (N x 3, its own frame; None without one); check:
# cv2.lidarsgm.LidarFailSafe's verdict (None where the images cannot tell or there is no map); stereo_alone: the class
# (one of ALONE_CLASSES) of a set fused without the LiDAR, else ""; reason: what happened, for a log line;
# dropped_points: the cloud's non-finite points (not projected).
Result = namedtuple("Result", "disparity16 confidence geometry left_bgr sparse left_grey right_grey points check "
                              "stereo_alone reason dropped_points")


def rectified_transform(geometry, lidar_to_camera):
    """lidar_to_camera, which ends in the left camera's optical frame (camera_info's frame_id, as tf gives it),
    followed by the left camera_info's R: the transform to the rectified frame that P projects (R after, not before)."""
    r = np.eye(4)
    r[:3, :3] = geometry.rectification
    return r @ np.asarray(lidar_to_camera, np.float64)


def optical_transform(geometry, rectified):
    """The inverse of rectified_transform: a transform to the rectified frame as one to the left optical frame."""
    r = np.eye(4)
    r[:3, :3] = geometry.rectification.T
    return r @ rectified


def residual_summary(residuals, bound):
    """(median, how many above bound, cv2.lidarsgm.LidarFailSafe.maxResidual()) of matching residuals, the median as
    the module takes it (the upper of two middle values)."""
    r = sorted(residuals)
    return r[len(r) // 2], sum(v > bound for v in r)


def _to_text(cv2, sgm):
    fs = cv2.FileStorage(".yml", cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_MEMORY)
    sgm.write(fs)
    return fs.releaseAndGetString()


def _from_text(cv2, text):
    fs = cv2.FileStorage(text, cv2.FILE_STORAGE_READ | cv2.FILE_STORAGE_MEMORY)
    sgm = cv2.lidarsgm.StereoLidarSGM.create()
    sgm.read(fs.root())  # every value through its setter's check, then the relations (P1 <= P2, Q1 <= Q2)
    return sgm


def cv_message(cv2, e):
    return e.err if isinstance(e, cv2.error) and getattr(e, "err", None) else str(e)


class Fusion:
    """The matcher, its settings and the LiDAR-to-camera transform (4x4, LiDAR frame -> left optical frame)."""

    def __init__(self, cv2, params_file="", use_cuda=False, lidar_to_camera=None, trust_lidar=False, rectify=False):
        self.cv2 = cv2
        # Raw images (a camera driver's image_raw): rectified here with their camera_info's K, D, R and P when
        # rectify, refused otherwise where they differ from their rectified view.
        self.rectify = bool(rectify)
        self._maps = {}
        # The fail-safe (cv2.lidarsgm.LidarFailSafe): a set whose LiDAR lands misplaced on its images is fused as
        # stereo alone, unless trust_lidar.
        self.trust_lidar = bool(trust_lidar)
        self.max_residual = cv2.lidarsgm.LidarFailSafe.maxResidual()
        self._stereo = None
        self.sgm = cv2.lidarsgm.StereoLidarSGM.load(params_file) if params_file else \
            cv2.lidarsgm.StereoLidarSGM.create()
        self.use_cuda = False
        self.set_use_cuda(use_cuda)
        self.lidar_to_camera = None
        if lidar_to_camera is not None:
            self.set_lidar_to_camera(lidar_to_camera)

    # -- settings: each change is tried on a copy first, so a refused value leaves the matcher as it was
    def value(self, name):
        if name == "mode":
            return next(m for m in MODES if self._mode(m) == self.sgm.getMode())
        prop, typ = MATCHER_PARAMETERS[name]
        return typ(getattr(self.sgm, "get" + prop)())

    def set(self, name, value):
        """Sets one parameter (a MATCHER_PARAMETERS name or 'mode'); raises ValueError with the module's message."""
        cv2 = self.cv2
        trial = _from_text(cv2, _to_text(cv2, self.sgm))
        try:
            if name == "mode":
                if value not in MODES:
                    raise ValueError("mode must be one of %s, not '%s'" % (", ".join(MODES), value))
                trial.setMode(self._mode(value))
            else:
                prop, typ = MATCHER_PARAMETERS[name]
                getattr(trial, "set" + prop)(typ(value))
            trial = _from_text(cv2, _to_text(cv2, trial))
        except cv2.error as e:
            raise ValueError(cv_message(cv2, e))
        self.sgm = trial
        self._stereo = None

    def stereo_matcher(self):
        """The fail-safe's stereo-alone matcher of the matcher (cv2.lidarsgm.LidarFailSafe.stereoAloneMatcher),
        kept until a setting changes."""
        if self._stereo is None:
            self._stereo = self.cv2.lidarsgm.LidarFailSafe.stereoAloneMatcher(self.sgm)
        return self._stereo

    def _mode(self, name):
        return getattr(self.cv2.lidarsgm, "StereoLidarSGM_MODE_" + name.upper())

    def set_use_cuda(self, on):
        if on and self.cv2.cuda.getCudaEnabledDeviceCount() < 1:  # -1: no driver
            raise ValueError("use_cuda: this cv2 has no CUDA device (build with CUDA, or set use_cuda false)")
        self.use_cuda = bool(on)

    def set_lidar_to_camera(self, values):
        m = np.asarray(values, np.float64)
        if m.size not in (12, 16):
            raise ValueError("lidar_to_camera takes 12 or 16 numbers (a 3x4 or 4x4 matrix, row by row), got %d"
                             % m.size)
        m = np.vstack([m.reshape(-1, 4)[:3], [0, 0, 0, 1]])
        r = m[:3, :3]
        if not np.all(np.isfinite(m)) or np.abs(r @ r.T - np.eye(3)).max() > 1e-4 or np.linalg.det(r) < 0:
            raise ValueError("lidar_to_camera is not a rigid transform (its rotation is not orthonormal with det 1)")
        self.lidar_to_camera = m

    # -- one frame
    def sparse(self, geometry, cloud):
        """The projected scan (CV_32F disparities of the rectified left view, 0 = none), the points and how many
        non-finite points were dropped."""
        if self.lidar_to_camera is None:
            raise CalibrationError("no LiDAR-to-camera transform: set the lidar_to_camera parameter")
        points, _, dropped = clouds.cloud_points(cloud)
        return self.project(geometry, points), points, dropped

    def project(self, geometry, points):
        """The sparse map of N x 3 float32 points (raises ConversionError where none lands in the image)."""
        sparse = self.cv2.lidarsgm.projectPointsToDisparity(points, geometry.projection,
                                                            rectified_transform(geometry, self.lidar_to_camera),
                                                            geometry.focal_baseline, geometry.size)
        if not self.cv2.countNonZero(sparse):
            # Stereo alone under a wrong transform would pass for a fusion: say so instead.
            raise CalibrationError("none of the cloud's %d points projects into the left image (is lidar_to_camera "
                                  "the transform from the cloud's frame to the left optical frame?)" % len(points))
        return sparse

    def check(self, grey_l, grey_r, sparse):
        """The fail-safe's judgement of the set's sparse map (cv2.lidarsgm.LidarCheck), None where the images cannot
        tell (residual NaN)."""
        try:
            check = self.cv2.lidarsgm.LidarFailSafe.create(self.trust_lidar).check(grey_l, grey_r, sparse)
        except self.cv2.error as e:
            raise ConversionError(cv_message(self.cv2, e))
        return None if check.residual != check.residual else check

    def compute(self, sgm, grey_l, grey_r, sparse, confidence=False):
        """(disparity16, confidence or None) of the matcher on the host images: on the GPU where use_cuda, the
        GpuMats uploaded and the outputs downloaded; ConversionError where OpenCV refuses."""
        cv2 = self.cv2
        try:
            if self.use_cuda:
                g = [cv2.cuda_GpuMat(a) for a in (grey_l, grey_r, sparse)]
                if confidence:
                    gd, gc = cv2.cuda.computeStereoLidarSGMWithConfidence(sgm, *g)
                    return gd.download(), gc.download()
                return cv2.cuda.computeStereoLidarSGM(sgm, *g).download(), None
            if confidence:
                disp, conf = sgm.computeWithConfidence(grey_l, grey_r, sparse)
                return disp, conf
            return sgm.compute(grey_l, grey_r, sparse), None
        except cv2.error as e:
            raise ConversionError(cv_message(cv2, e))

    def _gpu_thread(self):
        """The thread that runs the GPU's fusion beside the fail-safe's check (made on first use)."""
        if getattr(self, "_gpu_pool", None) is None:
            from concurrent.futures import ThreadPoolExecutor
            self._gpu_pool = ThreadPoolExecutor(1, "lidarsgm_gpu")
        return self._gpu_pool

    def rectified(self, side, info, image):
        """A raw image rectified with its camera_info (the maps kept while the camera_info stays the same)."""
        key = (side, info.distortion_model, tuple(info.d), tuple(info.k), tuple(info.r), tuple(info.p),
               int(info.width), int(info.height))
        if key not in self._maps:
            self._maps = {k: v for k, v in self._maps.items() if k[0] != side}
            self._maps[key] = camera_info.rectification_maps(self.cv2, info, side)
        mx, my = self._maps[key]
        return self.cv2.remap(image, mx, my, self.cv2.INTER_LINEAR, borderMode=self.cv2.BORDER_CONSTANT)

    def fuse(self, left, left_info, right, right_info, cloud, confidence=False, raw=False, alone=None):
        """Fuses one synchronised set; raises ConversionError (the reason) where the images cannot be fused. raw: the
        images come on image_raw topics (refused unless rectify where they differ from their rectified view).

        The images are fused as stereo alone, Result.stereo_alone saying why, where there is no cloud (cloud None),
        alone = (class, reason) says so (no transform), the cloud cannot be read, or its LiDAR lands misplaced on
        the images (the fail-safe, unless trust_lidar)."""
        cv2 = self.cv2
        geometry = camera_info.stereo_geometry(left_info, right_info)
        size = geometry.size
        for side, img in (("left", left), ("right", right)):
            if (int(img.width), int(img.height)) != size:
                raise ConversionError("the %s image is %dx%d, its camera_info %dx%d"
                                      % (side, img.width, img.height, size[0], size[1]))
        if self.rectify:
            # As the tool's --rig: the left image rectified in colour, then made grey.
            left_bgr = self.rectified("left", left_info, images.to_bgr(left, cv2))
            grey_l = cv2.cvtColor(left_bgr, cv2.COLOR_BGR2GRAY) if left.encoding in images.COLOUR_ENCODINGS else \
                self.rectified("left", left_info, images.to_grey(left, cv2))
            grey_r = self.rectified("right", right_info, images.to_grey(right, cv2))
        else:
            if raw and (camera_info.is_raw(left_info, "left") or camera_info.is_raw(right_info, "right")):
                raise ConversionError("the images come on image_raw and their camera_info has distortion (or a "
                                      "rectification): rectify them first (image_proc), or set rectify to rectify "
                                      "them here")
            left_bgr = None
            grey_l, grey_r = images.to_grey(left, cv2), images.to_grey(right, cv2)
        if grey_l.dtype != grey_r.dtype:
            raise ConversionError("the left image is %s, the right %s: send both with one bit depth"
                                  % (left.encoding, right.encoding))
        sparse, points, check, dropped = None, None, None, 0
        kind, reason = alone if alone else ("", "")
        if cloud is None and not kind:
            kind, reason = NO_CLOUD, "no cloud"
        if not kind:
            try:
                sparse, points, dropped = self.sparse(geometry, cloud)
            except CalibrationError as e:
                kind, reason = CALIBRATION, str(e)
            except ConversionError as e:
                kind, reason = BAD_CLOUD, "the cloud: %s" % e
        pending = None
        if sparse is not None:
            if self.use_cuda:
                # The GPU fuses with the LiDAR while the CPU checks it (a thread of its own; cv2 lets go of the GIL):
                # the check costs no time where it trusts the map, and a verdict of stereo alone computes again.
                pending = self._gpu_thread().submit(self.compute, self.sgm, grey_l, grey_r, sparse, confidence)
            try:
                check = self.check(grey_l, grey_r, sparse)
            except ConversionError:
                if pending is not None:
                    pending.exception()  # the GPU's call over before the set is given up
                raise
            if check is not None and check.stereoAlone:
                kind, reason = CALIBRATION, "the LiDAR misplaced on the images (%.2f px)" % check.residual
        if kind:
            if pending is not None:
                pending.exception()  # (the fusion with the LiDAR finished, unused, before the GPU computes again)
            disp, conf = self.compute(self.stereo_matcher(), grey_l, grey_r, np.zeros(grey_l.shape, np.float32),
                                      confidence)
        elif pending is not None:
            disp, conf = pending.result()
        else:
            disp, conf = self.compute(self.sgm, grey_l, grey_r, sparse, confidence)
        return Result(disp, conf, geometry, images.to_bgr(left, cv2) if left_bgr is None else left_bgr, sparse, grey_l,
                      grey_r, points, check, kind, reason, dropped)

    @staticmethod
    def matching_residual(result):
        """How far the set's LiDAR disparities lie from where the images match (cv2.lidarsgm.matchingResidual,
        px); None where the images cannot tell (too few comparable points)."""
        return None if result.check is None else result.check.residual

    @staticmethod
    def verdict(result):
        """A line on a set whose LiDAR is misplaced on its images; '' for the others."""
        c = result.check
        if c is None or c.trusted:
            return ""
        turn = "turned %.2f degrees and " % c.turn if c.turn else ""
        return "the LiDAR misplaced on the images (%.2f px, %.2f %smoved by (%d, %d)): %s" % (
            c.residual, c.shiftedResidual, turn, c.shift[0], c.shift[1],
            "fused as stereo alone" if result.stereo_alone else "fused anyway (trust_lidar)")

    # -- outputs
    def outputs(self, result, depth_encoding="32FC1", alloc=None, mark=None, bands=None):
        """(disparity pixels, valid window, depth image, organised x y z rgb records) of a Result. alloc(shape,
        dtype, name) gives the arrays to write them into: a MessageKit's, so that the messages take them without a
        copy, and the next call writes into the same ones once the messages have gone out.

        bands: the rows go through in that many horizontal bands at the same time, on threads, so that numpy's and
        OpenCV's single-threaded passes share the cores (default: outputs.output_bands of this process's CPUs
        and cv2.getNumThreads()); 1: in turn. The arrays are the same byte for byte either way. mark(step), where
        given, is called after each step (tools/ros2_latency.py times them): each of them with one band, else once
        for them all."""
        import os
        from concurrent.futures import ThreadPoolExecutor, wait
        cv2, g = self.cv2, result.geometry
        alloc = alloc or (lambda shape, dtype, name: np.empty(shape, dtype))
        mark = mark or (lambda step: None)
        d16, mind = result.disparity16, self.sgm.getMinDisparity()
        h, w = d16.shape
        if depth_encoding not in ("32FC1", "16UC1"):
            raise ConversionError("depth encoding must be 32FC1 (metres) or 16UC1 (millimetres), not '%s'"
                                  % depth_encoding)
        if result.left_bgr.shape[:2] != (h, w):  # (a band's rows of a larger image would pass unseen)
            raise ConversionError("points are %s, the colour image %s" % ((h, w), result.left_bgr.shape[:2]))
        disp = alloc((h, w), np.float32, "disparity")
        # 32FC1: the metres in the message's own array, NaN set in place; 16UC1: the metres in a reused array.
        metres = alloc((h, w), np.float32, "depth" if depth_encoding == "32FC1" else "depth metres")
        depth = metres if depth_encoding == "32FC1" else alloc((h, w), np.uint16, "depth")
        records = alloc((h, w, 4), np.float32, "points2")
        q = cv2.lidarsgm.reprojectionMatrix(g.projection, g.focal_baseline)
        cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
        rows = outputs.row_bands(h, bands or outputs.output_bands(cpus, cv2.getNumThreads()))
        qs = [outputs.band_reprojection(q, r0) for r0, _ in rows]
        if len(rows) == 1 or any(b is None for b in qs):
            rows, qs = [(0, h)], [q]

        def into(a, out):  # OpenCV writes into out where it takes it as it is; else its own array is copied there
            if a is not out and not np.shares_memory(a, out):
                out[...] = a

        def band(i, step=lambda name: None):
            r = slice(*rows[i])
            outputs.disparity_image(d16[r], disp[r])
            step("disparity image")
            m = metres[r]
            # 32FC1: REP 118's NaN written by the conversion itself; 16UC1: millimetres from the metres
            into(cv2.lidarsgm.disparityToDepth(d16[r], g.focal_baseline, m, minDisparity=mind,
                                               invalidDepth=np.nan if depth is metres else 0.0), m)
            step("disparityToDepth")
            if depth is not metres:
                outputs.depth_image(m, depth_encoding, out=depth[r])
                step("depth image")
            into(outputs.point_cloud_array(d16[r], qs[i], result.left_bgr[r], mind, cv2, records[r]), records[r])
            step("x y z rgb cloud")

        if len(rows) == 1:
            window = outputs.valid_window(d16, mind, cv2)
            mark("valid window")
            band(0, mark)
        else:
            pool = getattr(self, "_output_pool", None)
            if pool is None or pool[1] < len(rows):
                pool = self._output_pool = (ThreadPoolExecutor(len(rows), "lidarsgm_outputs"), len(rows))
            jobs = [pool[0].submit(band, i) for i in range(len(rows))]
            window = outputs.valid_window(d16, mind, cv2)  # meanwhile, here
            wait(jobs)
            for j in jobs:
                j.result()  # a band's exception, raised here
            mark("all %d bands at once" % len(rows))
        return disp, window, depth, records
