"""Stopping a node process and reading its log, for the ROS 2 tests and the tools that start the node
(tools/ros2_stream.py, tools/ros2_latency.py). Importing it changes nothing in the environment (ros_env does)."""
import signal
import subprocess


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
