#!/usr/bin/env bash
# Rewrites doc/benchmarks/ros2_stream_node_<host>.txt: the ROS 2 node streamed to as on a robot (tools/ros2_stream.py
# node): 100 KITTI sets at 5 Hz from a best-effort and from a reliable driver-like publisher with the package's Fast
# DDS profile, the same from a publisher on Fast DDS's defaults, 40 sets at 1080p at 1 Hz, and the soak (2000 sets at
# 10 Hz: answered, skipped, latency percentiles, the node's RSS at the start, after 100 sets and at the end).
# Needs the README's build (cv2 in its python_loader, the ROS 2 environment); run it on a quiet machine.
#   tools/ros2_benchmarks.sh [host name for the file, default 2core-xeon]
set -eo pipefail
cd "$(dirname "$0")/.."
CACHE=${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}
PY=${LIDARSGM_ROS2_PYTHON:-$(ls -d "$CACHE"/ros2-py*/bin/python | head -1)}
export PYTHONPATH=$CACHE/build-cuda90/python_loader LIDARSGM_TESTDATA=$PWD/testdata ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
export ROS_DOMAIN_ID=${ROS_DOMAIN_ID:-$((150 + RANDOM % 50))}
unset FASTDDS_DEFAULT_PROFILES_FILE FASTDDS_BUILTIN_TRANSPORTS
f=doc/benchmarks/ros2_stream_node_${1:-2core-xeon}.txt
run() {
  echo "\$ python3 tools/ros2_stream.py node $*   (load $(cut -d' ' -f1 /proc/loadavg))"
  "$PY" tools/ros2_stream.py node "$@"
  echo
}
{ echo "# $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD), $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), 2 OpenCV threads"
  echo "# Command: tools/ros2_benchmarks.sh; columns: sent | rate | publisher QoS | node profile (none: as a user"
  echo "# launches it, the node applies the package's) | publisher profile | size | answered | stamp to DisparityImage"
  echo "# median / p99 / max | node RSS at the start / after 100 sets / at the end"
  echo
  run --sets 100 --rate 5 --reliability best_effort --publisher-profile shipped
  run --sets 100 --rate 5 --reliability reliable --publisher-profile shipped
  run --sets 100 --rate 5 --reliability best_effort --publisher-profile none
  run --sets 40 --rate 1 --size 1080p --reliability best_effort --publisher-profile shipped
  run --soak --reliability best_effort --publisher-profile shipped
} > "$f" 2>&1
echo "wrote $f"
