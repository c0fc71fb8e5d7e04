"""The files and tables of a KITTI folder run, as the C++ tool writes them (lidarsgm_fuse --kitti DIR --out
OUT): every file under a temporary name first, each frame's metrics.yml (the options key, the devkit's counts and the
time per row), and the summary table. Used by lidarsgm_ray.py, so that the tool and the Ray sample resume each other's
runs and print the same table.
"""
import os

import cv2 as cv


def write_atomically(path, write):
    """write(tmp) under a hidden name beside path (extension kept: imwrite picks the format by it), then rename."""
    folder, name = os.path.split(path)
    stem, ext = os.path.splitext(name)
    tmp = os.path.join(folder, ".%s.partial-%d%s" % (stem, os.getpid(), ext))
    try:
        if write(tmp) is False:
            raise IOError("cannot write " + path)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def imwrite_atomically(path, img):
    write_atomically(path, lambda tmp: cv.imwrite(tmp, img))


def row_labels(modes, check):
    return ["%s (%s)" % (m.upper(), check) for m in modes] + ["LiDAR points alone", "semidense map (SDSGM input)"]


def write_metrics(path, key, rows, check=None, stereo_alone=False):
    """metrics.yml as the C++ tool writes it: the options key, then per row the devkit's counts and the time, then the
    frame's LiDAR check (cv.lidarsgm.LidarFailSafe's verdict, None where the images could not tell) and whether the frame
    was fused as stereo alone."""
    def write(tmp):
        fs = cv.FileStorage(tmp, cv.FILE_STORAGE_WRITE)
        fs.write("options", key)
        fs.startWriteStruct("rows", cv.FILE_NODE_SEQ)
        for r in rows:
            fs.startWriteStruct("", cv.FILE_NODE_MAP)
            fs.write("label", r["label"])
            for k in ("gt", "est", "estBad", "totalBad", "ms"):
                fs.write(k, float(r[k]))
            fs.endWriteStruct()
        fs.endWriteStruct()
        nan = float("nan")
        fs.write("matchingResidual", check.residual if check is not None else nan)
        fs.write("residualFailure", "" if check is not None else
                 "fewer than 200 LiDAR pixels can be compared with the images")
        fs.write("shiftedResidual", check.shiftedResidual if check is not None else nan)
        fs.startWriteStruct("shift", cv.FILE_NODE_SEQ | cv.FILE_NODE_FLOW)
        for v in (check.shift if check is not None else (0, 0)):
            fs.write("", int(v))
        fs.endWriteStruct()
        fs.write("turn", float(check.turn) if check is not None else 0.0)
        fs.write("misplaced", int(check is not None and not check.trusted))
        fs.write("stereoAlone", int(stereo_alone))
        fs.release()
    write_atomically(path, write)


def read_metrics(path, key, labels):
    """A finished frame's rows from its metrics.yml; None where it was written with other options or rows."""
    fs = cv.FileStorage(path, cv.FILE_STORAGE_READ)
    if fs.getNode("options").string() != key:
        return None
    node = fs.getNode("rows")
    if node.size() != len(labels):
        return None
    rows = []
    for i, label in enumerate(labels):
        n = node.at(i)
        if n.getNode("label").string() != label:
            return None
        rows.append(dict(label=label, **{k: n.getNode(k).real() for k in ("gt", "est", "estBad", "totalBad", "ms")}))
    return rows


def options_key(args):
    """The tool's key of the options that decide a frame's results: '--NAME VALUE ' for each given one, by name."""
    given = {"kitti": None, "modes": args.modes_given, "check": args.check_given, "params": args.params,
             "trust-lidar": "1" if args.trust_lidar else None}
    return lambda folder: "".join("--%s %s " % (k, folder if k == "kitti" else v)
                                  for k, v in sorted(given.items()) if k == "kitti" or v is not None)


def print_table(title, sums, times):
    print("\n" + title)
    print("| %-28s | coverage | covered %-5s | total %-5s | ms/frame |" % ("method", "D1", "D1"))
    print("|------------------------------|----------|---------------|-------------|----------|")
    for label, s in sums.items():
        e = cv.lidarsgm.DisparityErrors()
        e.groundTruthPixels, e.estimatedPixels = int(s["gt"]), int(s["est"])
        e.estimatedOutliers, e.totalOutliers = int(s["estBad"]), int(s["totalBad"])
        t = sorted(times.get(label, []))
        ms = "%.1f" % t[len(t) // 2] if t else "-"
        if label.startswith("semidense"):
            print("| %-28s | %6.2f %% | %11.2f %% | %11s | %8s |" % (label, e.coverage(), e.coveredError(), "-", "-"))
        else:
            print("| %-28s | %6.2f %% | %11.2f %% | %9.2f %% | %8s |" % (label, e.coverage(), e.coveredError(),
                                                                         e.totalError(), ms))
