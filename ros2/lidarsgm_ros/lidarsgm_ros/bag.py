"""lidarsgm_bag: fuses the stereo pairs and scans of a rosbag2 (MCAP or sqlite3) into an MCAP bag of the node's outputs.

  python3 -m lidarsgm_ros.bag INPUT OUTPUT [--namespace /stereo] [--params-file kitti_best.yml] [--with-inputs]
                              [--lidar-to-camera 16 numbers] [--approximate-sync] [--resume]

Reads <ns>/left/image_rect, <ns>/left/camera_info, <ns>/right/image_rect, <ns>/right/camera_info and <ns>/points
(--topic NAME=TOPIC renames one), synchronises them as the node does, and writes <ns>/disparity, <ns>/depth and
<ns>/points2 (and <ns>/confidence with --confidence, the inputs with --with-inputs) to OUTPUT, a folder of rosbag2
MCAP bags of --segment-frames sets each (part_0000, part_0001, ...; Foxglove, rerun and rosbags open them). A
segment appears only when complete, so an interrupted run continues with --resume where it stopped. The
LiDAR-to-camera transform comes from --lidar-to-camera or else the bag's /tf_static; each fused set's matching
residual (the LiDAR against the images, cv2.lidarsgm.matchingResidual) is printed, and their median at the end,
with the sets above 1 px: a transform that is off.

Raw images (--topic left/image_rect=.../image_raw): refused where their camera_info has distortion or a rectification
rotation, unless --rectify rectifies them with it. The LiDAR-to-camera transform ends in the left camera's optical
frame (as tf gives it); the left camera_info's R then turns it into the rectified frame.

An image pair that no scan pairs with (none of its stamp, or with --approximate-sync none within --tolerance,
before the scans move past it or --lidar-timeout of images later; a bag without the points topic) is fused as stereo
alone, as the node does: the same outputs, and <ns>/fusion_status (diagnostic_msgs/DiagnosticArray, one per set)
says how each set was fused. A scan that cannot be read gives stereo alone too; a stamp that repeats or goes back
(bags joined) restarts the synchroniser.

The fail-safe: a set whose LiDAR lands misplaced on its images (cv2.lidarsgm.LidarFailSafe) is fused as stereo alone
and the set's line says so (--trust-lidar fuses it anyway). Those sets are pooled, and the rotation is refined from
the last --recalibration-sets of them (cv2.lidarsgm.LidarCalibration; --scan-rate for scans that are not
motion-compensated); the command switches to the corrected transform once it brings the residual under 1 px and
every pooled set's LiDAR is trusted under it, and prints the correction with its uncertainty
(--recalibration-sets 0: never). Exit codes: 0 done, 1 error (unreadable bag, no set fused), 2 bad command line.
"""
import argparse
import os
import shutil
import sys
import time

import cv2

import numpy as np

from . import health
from .conversions import ConversionError, stamp_ns
from .fusion import ALONE_CLASSES, CALIBRATION, MATCHER_PARAMETERS, Fusion, residual_summary
from .messages import INPUT_TYPES, OUTPUT_TYPES, MessageKit, output_messages
from .recalibration import Recalibration
from .sync import ApproximateSync, ExactSync, LidarPairing
from .transforms import TransformBuffer, chain_transform

STATUS_TYPE = "diagnostic_msgs/msg/DiagnosticArray"

INPUTS = tuple(INPUT_TYPES)


def parse_args(argv):
    p = argparse.ArgumentParser(prog="lidarsgm_bag", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", help="rosbag2 folder or .mcap / .db3 file")
    p.add_argument("output", help="output folder (segments part_NNNN, each a rosbag2 MCAP bag)")
    p.add_argument("--namespace", default="", help="prefix of every topic, e.g. /stereo")
    p.add_argument("--topic", action="append", default=[], metavar="NAME=TOPIC",
                   help="the topic of one input (%s)" % ", ".join(INPUTS))
    p.add_argument("--params-file", default="", help="matcher parameters (StereoLidarSGM.save), e.g. kitti_best.yml")
    p.add_argument("--mode", choices=("sgm", "dsgm", "sdsgm"))
    for name, (_, typ) in MATCHER_PARAMETERS.items():
        p.add_argument("--" + name.replace("_", "-"), dest=name, type=typ)
    p.add_argument("--lidar-to-camera", type=float, nargs="+", metavar="V",
                   help="12 or 16 numbers, row by row: points' frame -> left optical frame (default: /tf_static)")
    p.add_argument("--rectify", action="store_true",
                   help="the images are raw (image_raw): rectify them with their camera_info's K, D, R and P")
    p.add_argument("--trust-lidar", action="store_true",
                   help="fuse every set with its LiDAR, also where it lands misplaced on the images")
    p.add_argument("--recalibration-sets", type=int, default=8, metavar="N",
                   help="refine the rotation from the last N sets fused as stereo alone (0: never; default 8)")
    p.add_argument("--scan-rate", type=float, default=0.0, metavar="HZ",
                   help="the recalibration's LiDAR sweep rate for scans that are not motion-compensated (KITTI: 10)")
    p.add_argument("--approximate-sync", action="store_true")
    p.add_argument("--tolerance", type=float, default=0.05, help="approximate sync: widest stamp spread (s)")
    p.add_argument("--queue-size", type=int, default=10, help="messages kept per input while waiting for a set")
    p.add_argument("--lidar-timeout", type=float, default=0.5, metavar="S",
                   help="an image pair that no scan pairs with before images S seconds newer is fused as stereo "
                        "alone (default 0.5, the node's lidar_timeout)")
    p.add_argument("--depth-encoding", choices=("32FC1", "16UC1"), default="32FC1")
    p.add_argument("--confidence", action="store_true", help="also write <ns>/confidence")
    p.add_argument("--with-inputs", action="store_true", help="also copy the five inputs into the output")
    p.add_argument("--cuda", action="store_true", help="fuse on the GPU")
    p.add_argument("--segment-frames", type=int, default=100, help="sets per output segment (the resume unit)")
    p.add_argument("--resume", action="store_true", help="keep the complete segments of OUTPUT, fuse the rest")
    args = p.parse_args(argv)
    topics = {n: (args.namespace.rstrip("/") + "/" + n) for n in INPUTS}
    for item in args.topic:
        name, _, topic = item.partition("=")
        if name not in topics or not topic:
            p.error("--topic takes NAME=TOPIC with NAME one of %s, not '%s'" % (", ".join(INPUTS), item))
        topics[name] = topic
    if not args.lidar_timeout > 0:
        p.error("--lidar-timeout must be > 0 seconds")
    if args.segment_frames < 1:
        p.error("--segment-frames must be at least 1")
    if args.recalibration_sets == 1 or args.recalibration_sets < 0:
        p.error("--recalibration-sets must be 0 (never) or at least 2")
    args.topics = topics
    return args, p


def static_transforms(reader):
    """(parent, child, 4x4 child -> parent) of the bag's /tf_static transforms (a child's last one)."""
    buf = TransformBuffer()
    conns = [c for c in reader.connections if c.topic == "/tf_static"]
    for conn, _, raw in reader.messages(connections=conns):
        buf.add(reader.deserialize(raw, conn.msgtype).transforms, static=True)
    return buf.edges(0)[0]


class Segments:
    """The output folder: complete segments part_NNNN, the one being written in .partial/part_NNNN (moved up when
    closed, so its MCAP file keeps the segment's name)."""

    def __init__(self, out, per_segment, resume, typestore):
        self.out, self.per, self.ts = out, per_segment, typestore
        if os.path.exists(out) and not resume and os.listdir(out):
            raise SystemExit("lidarsgm_bag: %s exists and is not empty: pass --resume to continue it, or remove it"
                             % out)
        os.makedirs(out, exist_ok=True)
        self.partial = os.path.join(out, ".partial")
        shutil.rmtree(self.partial, ignore_errors=True)  # an interrupted segment: redone
        self.done = 0
        while os.path.isfile(os.path.join(out, "part_%04d" % self.done, "metadata.yaml")):
            self.done += 1
        self.writer, self.index, self.count = None, None, 0

    def skip(self, k):
        """Whether set number k lies in a complete segment."""
        return k // self.per < self.done

    def write(self, k, items):
        """Writes set number k: items [(topic, msgtype, timestamp, serialised bytes)]."""
        from rosbags.rosbag2 import StoragePlugin, Writer
        seg = k // self.per
        if self.index != seg:
            self.close()
            self.index = seg
            self.name = "part_%04d" % seg
            os.makedirs(self.partial, exist_ok=True)
            self.writer = Writer(os.path.join(self.partial, self.name), version=9, storage_plugin=StoragePlugin.MCAP)
            self.writer.open()
            self.conns = {}
        for topic, msgtype, t, data in items:
            if topic not in self.conns:
                self.conns[topic] = self.writer.add_connection(topic, msgtype, typestore=self.ts)
            self.writer.write(self.conns[topic], t, data)
        self.count += 1

    def close(self):
        if self.writer is not None:
            self.writer.close()
            os.replace(os.path.join(self.partial, self.name), os.path.join(self.out, self.name))
            os.rmdir(self.partial)
            self.writer = None


def configured_fusion(args, parser):
    """The fusion with the command line's matcher settings and transform, and the recalibration (None: off); a value
    the module refuses ends the command as a bad command line."""
    try:
        fusion = Fusion(cv2, args.params_file, args.cuda, trust_lidar=args.trust_lidar, rectify=args.rectify)
        recal = Recalibration(cv2, args.scan_rate, args.recalibration_sets) \
            if args.recalibration_sets and not args.trust_lidar else None
        if args.mode:
            fusion.set("mode", args.mode)
        for name in MATCHER_PARAMETERS:
            if getattr(args, name) is not None:
                fusion.set(name, getattr(args, name))
        if args.lidar_to_camera:
            fusion.set_lidar_to_camera(args.lidar_to_camera)
    except (ValueError, cv2.error) as e:
        parser.error(str(e.err if isinstance(e, cv2.error) else e))
    return fusion, recal


def open_bag(path, typestore):
    """The input bag, open; None (the reason printed) where it cannot be read."""
    from pathlib import Path
    from rosbags.highlevel import AnyReader
    try:
        reader = AnyReader([Path(path)], default_typestore=typestore)
        reader.open()
    except Exception as e:  # rosbags raises its own error classes per storage; all mean an unreadable bag
        print("lidarsgm_bag: cannot read %s: %s" % (path, e), file=sys.stderr)
        return None
    return reader


def input_connections(reader, args):
    """The bag's connections by topic; None (the reason printed) where an input other than the points is missing. A
    bag without the points gets a warning: every set is fused as stereo alone."""
    by_topic = {c.topic: c for c in reader.connections}
    missing = [t for n, t in args.topics.items() if t not in by_topic and n != "points"]
    if missing:
        print("lidarsgm_bag: %s has no topic %s (it has: %s)" % (args.input, ", ".join(missing),
              ", ".join(sorted(by_topic))), file=sys.stderr)
        return None
    if args.topics["points"] not in by_topic:
        print("lidarsgm_bag: %s has no topic %s: every set is fused as stereo alone" % (
            args.input, args.topics["points"]), file=sys.stderr)
    return by_topic


def synchroniser(args):
    """The node's synchroniser: the images and their camera_info exactly (or approximately) in sync, a scan paired
    with them."""
    tol = int(args.tolerance * 1e9) if args.approximate_sync else 0
    images = ApproximateSync(len(INPUTS) - 1, args.queue_size, tol) if args.approximate_sync \
        else ExactSync(len(INPUTS) - 1, args.queue_size)
    return LidarPairing(images, tol, int(args.lidar_timeout * 1e9), args.queue_size)


def output_segments(args, typestore):
    """The output folder's Segments; None (the reason printed) where it holds something and --resume is not given."""
    try:
        segments = Segments(args.output, args.segment_frames, args.resume, typestore)
    except SystemExit as e:
        print(e, file=sys.stderr)
        return None
    if segments.done:
        print("resuming: %d complete segment(s) of %d sets kept" % (segments.done, args.segment_frames))
    return segments


class BagSets:
    """The sets of one bag as the synchroniser gives them: each fused, written to its segment with its fusion_status
    and its line printed; the sets fused as stereo alone for their calibration go to the recalibration. Keeps the
    counts, the matching residuals and the sets after which a corrected transform was taken, for the summary."""

    def __init__(self, args, fusion, recal, kit, typestore, segments, tf_edges, total):
        self.args, self.fusion, self.recal, self.kit, self.ts = args, fusion, recal, kit, typestore
        self.segments, self.tf_edges, self.total = segments, tf_edges, total
        self.ns = args.namespace.rstrip("/")
        self.raw_images = any(args.topics[n].endswith("image_raw") for n in ("left/image_rect", "right/image_rect"))
        self.counts = {"sets": 0, "fused": 0, "skipped": 0, "points": 0}
        self.counts.update({cls: 0 for cls in ALONE_CLASSES})
        # The recalibration's correction, applied on top of the transform from /tf_static (4x4).
        self.correction = np.eye(4)
        self.switched = []  # the sets after which the corrected transform was taken
        self.residuals = []  # each fused set's matching residual (px), where the images can tell
        self.raw_of = {}  # id of a message waiting for a set -> (topic, msgtype, timestamp, serialised bytes)
        self.t_start = time.perf_counter()

    def run(self, reader, by_topic, sync):
        """Feeds the bag's inputs to sync in the bag's order and processes each set it gives, then those it holds at
        the end; closes the last segment."""
        index = {self.args.topics[n]: i for i, n in enumerate(INPUTS)}
        conns = [by_topic[t] for t in self.args.topics.values() if t in by_topic]
        for conn, t, raw in reader.messages(connections=conns):
            msg = reader.deserialize(raw, conn.msgtype)
            self.raw_of[id(msg)] = (conn.topic, conn.msgtype, t, raw)
            for stamp, msgs in sync.add(index[conn.topic], stamp_ns(msg), msg):
                self.process(stamp, msgs)
            # Keep the raw bytes of the messages still waiting for a set only.
            live = set(id(m) for m in sync.held())
            self.raw_of = {key: v for key, v in self.raw_of.items() if key in live}
        for stamp, msgs in sync.finish():
            self.process(stamp, msgs)
        self.segments.close()

    def process(self, stamp, msgs):
        """Fuses, writes and reports one set, unless it lies in a segment kept from before."""
        number = self.counts["sets"]
        self.counts["sets"] += 1
        if self.segments.skip(number):
            return
        t0 = time.perf_counter()
        fused = self.fuse(number, stamp, msgs)
        if fused is None:
            return
        result, out = fused
        self.write(number, msgs, result, out)
        self.report(number, t0, result)
        self.recalibrate(number, result)

    def fuse(self, number, stamp, msgs):
        """(the fusion's result, the output messages) of a set; None where it is skipped (the reason printed)."""
        left, left_info, right, right_info, cloud = msgs
        try:
            alone = None
            if self.tf_edges is not None and cloud is not None:
                try:
                    self.fusion.set_lidar_to_camera(self.correction @ chain_transform(
                        self.tf_edges, cloud.header.frame_id, left.header.frame_id or left_info.header.frame_id))
                except ConversionError as e:
                    alone = (CALIBRATION, "no transform from the scan's frame in /tf_static (%s)" % e)
            result = self.fusion.fuse(left, left_info, right, right_info, cloud, confidence=self.args.confidence,
                                      raw=self.raw_images, alone=alone)
            out = output_messages(self.kit, self.fusion, result, left.header.frame_id, stamp_ns(left),
                                  self.args.depth_encoding)
        except (ConversionError, ValueError) as e:
            self.counts["skipped"] += 1
            print("set %d of ~%d (stamp %d.%09d) skipped: %s" % (number + 1, self.total, stamp // 1000000000,
                                                                 stamp % 1000000000, e))
            return None
        return result, out

    def write(self, number, msgs, result, out):
        """Writes a fused set's outputs and fusion_status (and with --with-inputs its inputs) to its segment."""
        stamp = stamp_ns(msgs[0])
        level, text = health.set_status(result)
        status = health.diagnostic_array(self.kit._new, out[0][1].header, level, text,
                                         [("source", "stereo alone" if result.stereo_alone else "lidar"),
                                          ("class", result.stereo_alone)])
        items = [(self.ns + "/" + name, OUTPUT_TYPES[name], stamp, self.ts.serialize_cdr(m, OUTPUT_TYPES[name]))
                 for name, m in out]
        items.append((self.ns + "/" + health.FUSION_STATUS, STATUS_TYPE, stamp,
                      self.ts.serialize_cdr(status, STATUS_TYPE)))
        if self.args.with_inputs:
            items += [self.raw_of[id(m)] for m in msgs if m is not None]
        self.segments.write(number, items)

    def report(self, number, t0, result):
        """Counts a fused set and prints its line: the time since t0, the matching residual, how it was fused."""
        self.counts["fused"] += 1
        self.counts["points"] += result.dropped_points
        if result.stereo_alone:
            self.counts[result.stereo_alone] += 1
        r = self.fusion.matching_residual(result)
        if r is not None:
            self.residuals.append(r)
        verdict = self.fusion.verdict(result) or ("stereo alone: " + result.reason if result.stereo_alone else "")
        print("set %d of ~%d fused in %.0f ms, matching residual %s%s" % (
            number + 1, self.total, 1000 * (time.perf_counter() - t0), "%.2f px" % r if r is not None else "-",
            "; " + verdict if verdict else ""), flush=True)

    def recalibrate(self, number, result):
        """Pools a set fused as stereo alone for its calibration; when the pool is due, refines the rotation from it
        and switches to the corrected transform where the refinement gives one."""
        if result.stereo_alone != CALIBRATION or result.points is None or self.recal is None:
            return
        self.recal.add(result)
        if not self.recal.due():
            return
        fusion = self.fusion
        corrected, text = self.recal.refine(fusion.lidar_to_camera, fusion.sgm.getNumDisparities())
        print("  " + text, flush=True)
        if corrected is not None:
            self.correction = corrected @ np.linalg.inv(fusion.lidar_to_camera) @ self.correction
            fusion.set_lidar_to_camera(corrected)
            self.switched.append(number + 1)
            print("  switched to the corrected transform from set %d on: %s" % (
                number + 2, " ".join("%.9g" % v for v in corrected.ravel())), flush=True)


def print_summary(args, sets, sync):
    """Prints the run's totals, the sets fused as stereo alone by class, the non-finite points dropped, the median
    matching residual, and a hint where no scan shared a stamp with the images under exact sync."""
    counts, switched = sets.counts, sets.switched
    print("%d sets fused, %d skipped, %d kept from before, %d %s dropped, %d restarts; %.1f s; output: %s"
          % (counts["fused"], counts["skipped"], min(counts["sets"], sets.segments.done * args.segment_frames),
             sync.dropped, sync.unit, sync.restarts, time.perf_counter() - sets.t_start, args.output))
    alone = sum(counts[c] for c in ALONE_CLASSES)
    if alone or switched:
        print("%d sets fused as stereo alone (%s)%s" % (
            alone, ", ".join("%d %s" % (counts[c], c) for c in ALONE_CLASSES),
            "; the corrected transform taken after set %s" % ", ".join(map(str, switched)) if switched else ""))
    if counts["points"]:
        print("%d non-finite points dropped from the scans" % counts["points"])
    if sets.residuals:
        max_residual = sets.fusion.max_residual
        median, above = residual_summary(sets.residuals, max_residual)
        print("matching residual (the LiDAR against the images): median %.2f px over %d sets, %d above %.0f px%s"
              % (median, len(sets.residuals), above, max_residual,
                 ": the LiDAR pulls the fusion off the images there; check the transform" if above else ""))
    if counts[ALONE_CLASSES[0]] and counts["fused"] == counts[ALONE_CLASSES[0]] and sync.unpaired_clouds \
            and not args.approximate_sync:
        print("lidarsgm_bag: no scan shares a stamp with the images: if the LiDAR is not triggered by the cameras, "
              "pass --approximate-sync", file=sys.stderr)


def main(argv=None):
    """Runs the command; returns its exit code (0 done, 1 error, 2 bad command line)."""
    args, parser = parse_args(sys.argv[1:] if argv is None else argv)
    from rosbags.typesys import Stores, get_typestore
    fusion, recal = configured_fusion(args, parser)
    typestore = get_typestore(Stores.ROS2_JAZZY)
    kit = MessageKit.rosbags(typestore)
    reader = open_bag(args.input, typestore)
    if reader is None:
        return 1
    try:
        by_topic = input_connections(reader, args)
        if by_topic is None:
            return 1
        tf_edges = None if fusion.lidar_to_camera is not None else static_transforms(reader)
        sync = synchroniser(args)
        segments = output_segments(args, typestore)
        if segments is None:
            return 2
        sets = BagSets(args, fusion, recal, kit, typestore, segments, tf_edges,
                       by_topic[args.topics["left/image_rect"]].msgcount)
        sets.run(reader, by_topic, sync)
    finally:
        reader.close()
    print_summary(args, sets, sync)
    return 0 if sets.counts["fused"] or segments.done else 1


if __name__ == "__main__":
    sys.exit(main())
