"""KITTI frames as the ROS 2 messages a robot's drivers publish (to try the node and the bag command on the shipped
data, and to test them).

The calibration goes over in ROS's convention: the left camera's P = [K | 0], the right's P = [K | (-f x baseline,
0, 0)], and the LiDAR-to-camera transform takes Velodyne points to the left (camera 2) optical frame:
[I | K^-1 P2[:, 3]] * R0_rect * Tr_velo_to_cam. Projected with these, a scan gives the same sparse map as KITTI's P2
with R0_rect * Tr_velo_to_cam.
"""
import os
import sys

import numpy as np

from .messages import INPUT_TYPES, MessageKit

LEFT_FRAME = "camera_left_optical"
LIDAR_FRAME = "velodyne"


def ros_calibration(calibration):
    """(K 3x3, left P 3x4, right P 3x4, LiDAR-to-left-camera 4x4) from a cv2.lidarsgm.KittiCalibration."""
    p2 = np.asarray(calibration.projection, np.float64)
    k = p2[:, :3].copy()
    shift = np.eye(4)
    shift[:3, 3] = np.linalg.solve(k, p2[:, 3])  # camera 2's centre in the rectified camera-0 frame
    left = np.hstack([k, np.zeros((3, 1))])
    right = left.copy()
    right[0, 3] = -calibration.focalBaseline
    return k, left, right, shift @ np.asarray(calibration.lidarToCamera, np.float64)


def ring_index(points):
    """Each point's laser ring (0 = lowest beam, as Velodyne's ROS driver numbers them) of a raw KITTI scan in the
    driver's order: a ring ends where the azimuth jumps back (as cv2.lidarsgm.countLidarRings counts them)."""
    az = np.degrees(np.arctan2(points[:, 1].astype(np.float64), points[:, 0].astype(np.float64))) % 360.0
    starts = np.concatenate([[0], np.flatnonzero(az[1:] < az[:-1] - 90.0) + 1])
    scan_ring = np.zeros(len(points), np.int64)
    scan_ring[starts[1:]] = 1
    scan_ring = np.cumsum(scan_ring)
    elevation = np.arctan2(points[:, 2], np.hypot(points[:, 0], points[:, 1]))
    medians = np.array([np.median(elevation[scan_ring == r]) for r in range(scan_ring[-1] + 1)])
    rank = np.empty_like(scan_ring[:len(medians)])
    rank[np.argsort(medians)] = np.arange(len(medians))
    return rank[scan_ring].astype(np.uint16)


def velodyne_records(points):
    """A Velodyne driver's point layout: x y z intensity (float32) and ring (uint16), 18 bytes a point, and its
    fields [(name, offset, PointField datatype)]."""
    dtype = np.dtype({"names": ["x", "y", "z", "intensity", "ring"],
                      "formats": ["<f4", "<f4", "<f4", "<f4", "<u2"], "offsets": [0, 4, 8, 12, 16], "itemsize": 18})
    rec = np.zeros(len(points), dtype)
    for i, n in enumerate(("x", "y", "z", "intensity")):
        rec[n] = points[:, i]
    rec["ring"] = ring_index(points)
    return rec.view(np.uint8).reshape(len(points), 18), [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("intensity", 12, 7),
                                                          ("ring", 16, 4)]


def frame_messages(kit, frame, points, stamp_ns):
    """{topic: message} of one KITTI frame (cv2.lidarsgm.loadKittiFrame's, and its Velodyne scan, N x 4 float32):
    left/image_rect (bgr8 as stored), right/image_rect (mono8), left and right camera_info, points."""
    k, p_left, p_right, _ = ros_calibration(frame.calibration)
    h, w = frame.left.shape[:2]
    header = kit.header(stamp_ns, LEFT_FRAME)
    left = frame.leftImage
    records, fields = velodyne_records(points)
    return {
        "left/image_rect": kit.image(header, left, "bgr8" if left.ndim == 3 else "mono8"),
        "right/image_rect": kit.image(kit.header(stamp_ns, "camera_right_optical"), frame.right, "mono8"),
        "left/camera_info": kit.camera_info(header, w, h, k, p_left),
        "right/camera_info": kit.camera_info(kit.header(stamp_ns, "camera_right_optical"), w, h, k, p_right),
        "points": kit.cloud(kit.header(stamp_ns, LIDAR_FRAME), records, fields),
    }


def write_bag(kitti_dir, out, storage="mcap", ids=None, period_ns=100000000, namespace="", lidar_offset_ns=0):
    """Writes the frames of a KITTI-layout folder (all, or ids) to a rosbag2 (storage 'mcap' or 'sqlite3'): the five
    inputs of the node under namespace, 0.1 s apart, and /tf_static with the LiDAR-to-camera transform. The scans
    are stamped lidar_offset_ns after the images (a LiDAR not triggered by the cameras: approximate sync)."""
    import cv2
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    from .transforms import rotation_quaternion

    ts = get_typestore(Stores.ROS2_JAZZY)
    kit = MessageKit.rosbags(ts)
    ids = ids or cv2.lidarsgm.readKittiFrameIds(kitti_dir)
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    with Writer(out, version=9, storage_plugin=plugin) as writer:
        conns = {n: writer.add_connection(namespace.rstrip("/") + "/" + n, t, typestore=ts)
                 for n, t in INPUT_TYPES.items()}
        tf_conn = writer.add_connection("/tf_static", "tf2_msgs/msg/TFMessage", typestore=ts)
        for i, fid in enumerate(ids):
            frame = cv2.lidarsgm.loadKittiFrame(kitti_dir, fid)
            points = cv2.lidarsgm.readVelodyneScan(os.path.join(kitti_dir, "velodyne", fid + ".bin"))
            stamp = (i + 1) * period_ns
            if i == 0:
                m = ros_calibration(frame.calibration)[3]
                q = rotation_quaternion(m[:3, :3])
                tr = ts.types["geometry_msgs/msg/Transform"](
                    translation=ts.types["geometry_msgs/msg/Vector3"](x=m[0, 3], y=m[1, 3], z=m[2, 3]),
                    rotation=ts.types["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3]))
                t = ts.types["geometry_msgs/msg/TransformStamped"](header=kit.header(stamp, LEFT_FRAME),
                                                                   child_frame_id=LIDAR_FRAME, transform=tr)
                msg = ts.types["tf2_msgs/msg/TFMessage"](transforms=[t])
                writer.write(tf_conn, stamp, ts.serialize_cdr(msg, "tf2_msgs/msg/TFMessage"))
            for name, msg in frame_messages(kit, frame, points, stamp).items():
                t = stamp
                if name == "points" and lidar_offset_ns:
                    t += lidar_offset_ns
                    msg.header.stamp = kit.time(t)
                writer.write(conns[name], t, ts.serialize_cdr(msg, INPUT_TYPES[name]))
    return len(ids)


def main(argv=None):
    """lidarsgm_kitti_to_bag KITTI_DIR OUT [--storage mcap|sqlite3] [--ids 000002 ...] [--namespace /stereo]
    [--lidar-offset-ms MS]"""
    import argparse
    p = argparse.ArgumentParser(prog="lidarsgm_kitti_to_bag", description="A KITTI-layout folder (image_2, "
                                "image_3, velodyne, calib.txt) as a rosbag2 of the lidarsgm node's inputs.")
    p.add_argument("kitti_dir")
    p.add_argument("output", help="rosbag2 folder to create")
    p.add_argument("--storage", choices=("mcap", "sqlite3"), default="mcap")
    p.add_argument("--ids", nargs="+", help="frame ids (default: all)")
    p.add_argument("--namespace", default="")
    p.add_argument("--lidar-offset-ms", type=float, default=0, help="stamp the scans this much after the images")
    args = p.parse_args(argv)
    try:
        n = write_bag(args.kitti_dir, args.output, args.storage, args.ids, namespace=args.namespace,
                      lidar_offset_ns=int(args.lidar_offset_ms * 1e6))
    except Exception as e:  # cv2.error (unreadable frame) or the bag writer's (output exists)
        print("lidarsgm_kitti_to_bag: %s" % getattr(e, "err", e), file=sys.stderr)
        return 1
    print("wrote %d frames to %s" % (n, args.output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
