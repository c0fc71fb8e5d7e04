#!/usr/bin/env python3
"""Stereo-LiDAR fusion of whole KITTI-layout folders on a Ray cluster: one actor per GPU (or per CPU worker where
there is none), each holding its own matchers; the same per-frame outputs, metrics.yml and summary table as the C++
tool's folder run (lidarsgm_fuse --kitti DIR --out OUT), so the two can resume each other's runs.

  python3 lidarsgm_ray.py --kitti DIR [DIR ...] --out OUT [--modes sgm,dsgm,sdsgm] [--check C] [--params FILE]
                          [--resume] [--trust-lidar] [--address auto] [--cpu] [--num-cpus N]
                          [--threads-per-worker T] [--quiet]

One folder writes OUT/ID/; several write OUT/NAME/ID/ (NAME: the folder's own name). Every file is written under a
temporary name and renamed when complete, metrics.yml last; --resume takes a frame whose metrics.yml exists from the
earlier run. A frame that cannot be read or computed is reported and skipped; the run exits with 1 at the end and
lists them. A worker that dies is restarted and its frame computed again. Without --address a local Ray instance is
started (--num-cpus caps its CPUs); --address auto joins a running cluster (`ray start --head` ...), whose nodes must
all see DIR and OUT at the same paths and have cv2 with the lidarsgm module. Exit codes: 0 done, 1 failed frames or
error, 2 bad command line.
"""
import argparse
import os
import sys
import tempfile
import time

import cv2 as cv

import lidarsgm_folder as lfo
import lidarsgm_fuse as lf

MODE_NAMES = ["sgm", "dsgm", "sdsgm"]
CHECK_NAMES = ["none", "stereo", "camera-lidar", "stereo-lidar"]


class FrameFuser:
    """One worker: its matchers (one per mode, plus the SDSGM one whose semidense map is written), on its GPU when
    Ray gave it one. Turned into a Ray actor by main()."""

    def __init__(self, params_text, modes, check, threads, use_cuda):
        cv.setNumThreads(threads)
        path = None
        if params_text:
            fd, path = tempfile.mkstemp(suffix=".yml")
            with os.fdopen(fd, "w") as f:
                f.write(params_text)
        try:
            def make(mode):
                m = cv.lidarsgm.StereoLidarSGM.load(path) if path else cv.lidarsgm.StereoLidarSGM.create()
                m.setMode(MODE_NAMES.index(mode))
                m.setConsistencyCheck(CHECK_NAMES.index(check))
                return m
            self.matchers = [(mode, make(mode)) for mode in modes]
            self.sdsgm = make("sdsgm")
            # a frame whose LiDAR lands misplaced: stereo alone, the fail-safe's matcher, as the tool fuses it
            self.stereo = cv.lidarsgm.LidarFailSafe.stereoAloneMatcher(make("sgm"))
        finally:
            if path:
                os.remove(path)
        self.labels = lfo.row_labels(modes, check)
        self.cuda = use_cuda
        self.stream = cv.cuda.Stream() if self.cuda else None

    def _compute(self, m, left, right, sparse, semidense=False):
        if not self.cuda:
            return m.semidensify(left, right, sparse) if semidense else m.compute(left, right, sparse)
        f = cv.cuda.semidensifyStereoLidarSGM if semidense else cv.cuda.computeStereoLidarSGM
        g = f(m, cv.cuda_GpuMat(left), cv.cuda_GpuMat(right), cv.cuda_GpuMat(sparse), stream=self.stream)
        out = g.download(self.stream)
        self.stream.waitForCompletion()
        return out

    def fuse(self, root, fid, frame_out, key, trust_lidar=False):
        """Computes frame fid of folder root, writes the tool's outputs to frame_out, metrics.yml last; its rows."""
        try:
            frame = cv.lidarsgm.loadKittiFrame(root, fid)
        except cv.error as e:
            raise IOError(e.err) from None   # the reader's message, without OpenCV's source location
        left, right, sparse, gt = frame.left, frame.right, frame.sparse, frame.groundTruth
        if gt is None or not gt.size:
            raise IOError("no ground truth %s/disp_occ_0/%s_10.png" % (root, fid))
        os.makedirs(frame_out, exist_ok=True)
        for name in os.listdir(frame_out):  # partial files of a run killed mid-write
            if name.startswith(".") and ".partial-" in name:
                os.remove(os.path.join(frame_out, name))

        # The fail-safe, as the tool's: a LiDAR misplaced on the images (a transform that is off) is left out.
        check = cv.lidarsgm.LidarFailSafe.create(trust_lidar).check(left, right, sparse)
        if check.residual != check.residual:
            check = None   # NaN: the images cannot tell
        alone = check is not None and check.stereoAlone
        fused = sparse * 0 if alone else sparse
        rows = []
        for (mode, m), label in zip(self.matchers, self.labels):
            m = self.stereo if alone else m
            t0 = time.perf_counter()
            disp16 = self._compute(m, left, right, fused)
            ms = 1000 * (time.perf_counter() - t0)
            rows.append(self._row(label, disp16, gt, m.getMinDisparity(), ms))
            self._write_disparity(frame_out, "_" + mode, disp16, m, gt)
        lidar = sparse.copy()
        lidar[sparse <= 0] = -1
        rows.append(self._row(self.labels[-2], lidar, gt, 0, -1))
        semi16 = self._compute(self.sdsgm, left, right, sparse, semidense=True)
        rows.append(self._row(self.labels[-1], semi16, gt, self.sdsgm.getMinDisparity(), -1))

        min_d = self.sdsgm.getMinDisparity()
        max_d = min_d + self.sdsgm.getNumDisparities()
        lidar_points = cv.lidarsgm.drawSparseDisparity(left, sparse, max_d)
        lfo.imwrite_atomically(os.path.join(frame_out, "lidar_points.png"),
                               cv.lidarsgm.addDisparityLegend(lidar_points, max_d, title="LiDAR disparity (px)",
                                                              showNone=False))
        semi = lf.disparity_to_float(semi16, min_d)
        lfo.imwrite_atomically(os.path.join(frame_out, "semidense.png"), cv.lidarsgm.encodeKittiDisparity(semi))
        lfo.imwrite_atomically(os.path.join(frame_out, "semidense_color.png"),
                               cv.lidarsgm.addDisparityLegend(cv.lidarsgm.colorizeDisparity(semi, max_d), max_d,
                                                              title="semidense disparity (px)"))
        lfo.write_metrics(os.path.join(frame_out, "metrics.yml"), key, rows, check, alone)
        return rows, (fid if alone else None)

    @staticmethod
    def _row(label, disp, gt, min_d, ms):
        e = cv.lidarsgm.evaluateDisparity(disp, gt, cv.lidarsgm.METRIC_KITTI_D1, 0, min_d)
        return dict(label=label, gt=e.groundTruthPixels, est=e.estimatedPixels, estBad=e.estimatedOutliers,
                    totalBad=e.totalOutliers, ms=ms)

    @staticmethod
    def _write_disparity(folder, suffix, disp16, m, gt):
        min_d = m.getMinDisparity()
        disp = lf.disparity_to_float(disp16, min_d)
        base = os.path.join(folder, "disparity" + suffix)
        lfo.imwrite_atomically(base + ".png", cv.lidarsgm.encodeKittiDisparity(disp))
        max_d = min_d + m.getNumDisparities()
        lfo.imwrite_atomically(base + "_color.png",
                               cv.lidarsgm.addDisparityLegend(cv.lidarsgm.colorizeDisparity(disp, max_d), max_d))
        err = cv.lidarsgm.colorizeDisparityError(cv.lidarsgm.interpolateBackground(disp), gt)
        lfo.imwrite_atomically(os.path.join(folder, "error" + suffix + ".png"), cv.lidarsgm.addErrorLegend(err))


def parse(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--kitti", nargs="+", required=True, help="KITTI-layout folders (frames.txt lists the frames)")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--modes", dest="modes_given", help="comma list of sgm, dsgm, sdsgm (default all)")
    p.add_argument("--check", dest="check_given", choices=CHECK_NAMES, help="default stereo-lidar")
    p.add_argument("--params", help="matcher parameters saved with StereoLidarSGM.save (e.g. doc/params/kitti_best.yml)")
    p.add_argument("--resume", action="store_true", help="take frames with a metrics.yml from the earlier run")
    p.add_argument("--trust-lidar", action="store_true", help="fuse every frame with its LiDAR (by default a frame "
                   "whose LiDAR lands misplaced on its images is fused as stereo alone, as the tool does)")
    p.add_argument("--address", help="Ray cluster to join ('auto': the one `ray start` runs here); default: a local one")
    p.add_argument("--num-cpus", type=int, help="CPUs of the local Ray instance (default: all)")
    p.add_argument("--cpu", action="store_true", help="CPU workers even where the cluster has GPUs")
    p.add_argument("--threads-per-worker", type=int, default=1, help="OpenCV threads (and Ray CPUs) per CPU worker")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    args = p.parse_args(argv)
    args.modes = (args.modes_given or "sgm,dsgm,sdsgm").split(",")
    bad = [m for m in args.modes if m not in MODE_NAMES]
    if bad:
        p.error("unknown mode '%s' (sgm, dsgm or sdsgm)" % bad[0])
    args.check = args.check_given or "stereo-lidar"
    names = [os.path.basename(os.path.normpath(d)) for d in args.kitti]
    if len(set(names)) != len(names):
        p.error("--kitti folders must have different names (their outputs go to OUT/NAME/)")
    return args


def main(argv):
    args = parse(argv)
    try:
        jobs, sums, times = [], {}, {}
        params_text = open(args.params).read() if args.params else None
        key_of = lfo.options_key(args)
        labels = lfo.row_labels(args.modes, args.check)
        for folder in args.kitti:
            with open(os.path.join(folder, "frames.txt")) as f:
                ids = f.read().split()
            if not ids:
                raise IOError(folder + "/frames.txt lists no frame")
            base = args.out if len(args.kitti) == 1 else os.path.join(args.out, os.path.basename(os.path.normpath(folder)))
            jobs += [(folder, fid, os.path.join(base, fid)) for fid in ids]
            sums[folder] = {label: dict(gt=0, est=0, estBad=0, totalBad=0) for label in labels}
            times[folder] = {}
        os.makedirs(args.out, exist_ok=True)
        FrameFuser(params_text, args.modes, args.check, 1, False)  # bad parameters fail here, before Ray starts
    except (IOError, OSError, cv.error) as e:
        print("lidarsgm_ray.py: error: %s" % e, file=sys.stderr)
        return 1

    failures, done, resumed, frames = [], 0, 0, {folder: 0 for folder in args.kitti}
    alone = []   # frames fused as stereo alone, their LiDAR misplaced

    def add(folder, rows):
        frames[folder] += 1
        for r in rows:
            s = sums[folder][r["label"]]
            for k in ("gt", "est", "estBad", "totalBad"):
                s[k] += r[k]
            if r["ms"] >= 0:
                times[folder].setdefault(r["label"], []).append(r["ms"])

    todo = []
    for folder, fid, frame_out in jobs:
        metrics = os.path.join(frame_out, "metrics.yml")
        if args.resume and os.path.isfile(metrics):
            rows = lfo.read_metrics(metrics, key_of(folder), labels)
            if rows is None:
                failures.append("%s: %s was written with other options (rerun without --resume, or into another --out)"
                                % (fid, metrics))
            else:
                add(folder, rows)
                resumed += 1
            continue
        todo.append((folder, fid, frame_out))

    t0 = time.perf_counter()
    workers, gpus = 0, 0
    if todo:
        import ray
        import ray.cloudpickle
        for m in (lf, lfo):   # workers get the helpers with the code, not from their sys.path
            ray.cloudpickle.register_pickle_by_value(m)
        init = dict(include_dashboard=False, logging_level="ERROR", log_to_driver=False)
        if args.address:
            ray.init(address=args.address, **init)
        else:
            ray.init(num_cpus=args.num_cpus, **init)
        res = ray.cluster_resources()
        gpus = 0 if args.cpu else int(res.get("GPU", 0))
        if gpus:
            workers, opts = gpus, dict(num_gpus=1, num_cpus=1)
        else:
            workers = max(1, int(res.get("CPU", 1)) // args.threads_per_worker)
            opts = dict(num_cpus=args.threads_per_worker)
        # A dead worker is restarted and its frame computed again; a frame that kills its worker every time fails.
        actor_cls = ray.remote(max_restarts=2, max_task_retries=2, **opts)(FrameFuser)
        actors = [actor_cls.remote(params_text, args.modes, args.check, 1 if gpus else args.threads_per_worker, gpus > 0)
                  for _ in range(min(workers, len(todo)))]
        pending, queue = {}, list(todo)
        free = [a for _ in range(2) for a in actors]  # two frames in flight per worker: reading overlaps computing
        while queue or pending:
            while queue and free:
                folder, fid, frame_out = queue.pop(0)
                a = free.pop(0)
                pending[a.fuse.remote(folder, fid, frame_out, key_of(folder), args.trust_lidar)] = (a, folder, fid)
            ready, _ = ray.wait(list(pending), num_returns=1)
            a, folder, fid = pending.pop(ready[0])
            free.append(a)
            try:
                rows, condemned = ray.get(ready[0])
                add(folder, rows)
                if condemned:
                    alone.append(condemned)
                done += 1
            except ray.exceptions.RayError as e:
                cause = e.cause if isinstance(e, ray.exceptions.RayTaskError) and e.cause is not None else e
                why = str(cause).strip().splitlines()[-1] if str(cause).strip() else type(cause).__name__
                failures.append("%s: %s" % (fid, why))
                if not args.quiet:
                    print("\nlidarsgm_ray.py: frame %s skipped: %s" % (fid, why), file=sys.stderr)
            if not args.quiet:
                n, total, s = done + len(failures), len(todo), time.perf_counter() - t0
                fps = n / max(s, 1e-9)
                print("\r[%d/%d] frames, %.2f frames/s, %.0f s left   " % (n, total, fps, (total - n) / fps),
                      end="\n" if n == total else "", file=sys.stderr)
        ray.shutdown()

    for folder in args.kitti:
        lfo.print_table("KITTI %s: %d frames, D1 (KITTI devkit rules), sums over frames, %d Ray workers (%s)"
                    % (folder, frames[folder], workers, "GPU" if gpus else "CPU"), sums[folder], times[folder])
    if alone:
        print("the LiDAR misplaced on the images (cv.lidarsgm.LidarFailSafe; check the calibration), fused as stereo alone: "
              + ", ".join(sorted(alone)))
    print("frames: %d computed, %d taken from earlier runs (--resume), %d failed" % (done, resumed, len(failures)))
    if failures:
        print("lidarsgm_ray.py: %d frame(s) failed:" % len(failures), file=sys.stderr)
        for f in failures:
            print("  " + f, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
