"""What every ROS 2 test of the package sets before rclpy is imported: the package on the path, discovery on this
machine only, a domain of its own (LIDARSGM_ROS_DOMAIN_ID, else a random one), and the package's Fast DDS profile
for this process, which publishes megabyte messages as a driver would (on the defaults most of them are lost).
Also the stopping of a node process, shared with tools/ros2_stream.py."""
import os
import random
import signal
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = os.path.join(HERE, "..", "..", "ros2", "lidarsgm_ros")
sys.path.insert(0, PACKAGE)
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = os.path.join(PACKAGE, "config", "fastdds_large_data.xml")
os.environ["ROS_DOMAIN_ID"] = os.environ.get("LIDARSGM_ROS_DOMAIN_ID", str(random.randint(100, 200)))


def log_text(log):
    """All a node process has written so far to log, the file (opened w+) that took its output."""
    log.flush()
    log.seek(0)
    return log.read()


def stop_node(proc, seconds, log=None):
    """Stops a node process as a user does, with SIGINT (the node prints its summary then), and kills it where it
    is still running after `seconds`; returns log_text(log) where a log is given."""
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(seconds)
    except subprocess.TimeoutExpired:
        proc.kill()
    return log_text(log) if log is not None else None
