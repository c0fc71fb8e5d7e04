#!/usr/bin/env bash
# Rewrites the calibration outputs in doc/benchmarks/ (the figures of doc/accuracy.md's "Calibration errors", the
# README and doc/design.md section 7): tools/calibration_benchmark.py on the 20 shared KITTI frames with kitti_best.yml,
# with the LiDAR's sweep modelled (calibration_kitti20.txt, 10 Hz) and without it (calibration_kitti20_scan_rate_0.txt);
# then the fail-safe for a transform that is off (tools/fail_safe_benchmark.py,
# fail_safe_kitti20.txt: its bag part runs in the ROS 2 environment the README's test command makes, or the Python of
# LIDARSGM_ROS2_PYTHON). FAIL_SAFE_ONLY=1 runs the last alone.
# Needs the OpenCV build made by the README's commands (its tool and its cv2) and a Python with numpy: the one of
# LIDARSGM_PYTHON, else the build's virtual environment where it exists, else python3.
#   tools/calibration_benchmarks.sh [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [shared data dir]
set -eo pipefail
cd "$(dirname "$0")/.."
B=${1:-$HOME/.cache/lidarsgm/build-cuda90}
DATA=${2:-../shared/data}
PY=${LIDARSGM_PYTHON:-$(ls $HOME/.cache/lidarsgm/pyenv-*/bin/python 2>/dev/null | head -1)}
PY=${PY:-python3}
C=$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src src_cuda include samples tools || echo " + uncommitted changes")
ROS_PY=${LIDARSGM_ROS2_PYTHON:-$(ls $HOME/.cache/lidarsgm/ros2-py*/bin/python 2>/dev/null | head -1)}
header() { echo "# $(date -u +%Y-%m-%d), commit $C, $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))$1"; }
if [ -z "$FAIL_SAFE_ONLY" ]; then
for rate in 10 0; do
  f=doc/benchmarks/calibration_kitti20.txt
  [ $rate = 0 ] && f=doc/benchmarks/calibration_kitti20_scan_rate_0.txt
  args=(--tool "$B/bin/lidarsgm_fuse" --data "$DATA/kitti2015_lidar" --params doc/params/kitti_best.yml
        --scan-rate $rate)
  { echo "# $(date -u +%Y-%m-%d), commit $C, $(nproc) CPU cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), CPU path"
    echo "# Command: tools/calibration_benchmark.py ${args[*]}"
    echo
    PYTHONPATH="$B/python_loader" "$PY" tools/calibration_benchmark.py "${args[@]}"; } > "$f" 2>&1
  echo "wrote $f"
done
fi
f=doc/benchmarks/fail_safe_kitti20.txt
args=(--tool "$B/bin/lidarsgm_fuse" --data "$DATA/kitti2015_lidar")
{ header ", CPU path"
  echo "# Command: tools/fail_safe_benchmark.py ${args[*]}"
  echo
  PYTHONPATH="$B/python_loader" "${ROS_PY:-$PY}" tools/fail_safe_benchmark.py "${args[@]}"; } > "$f" 2>&1
echo "wrote $f"
