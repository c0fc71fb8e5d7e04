#!/usr/bin/env bash
# Regenerates the pictures of doc/tutorial.md and the README from the shipped KITTI frame 000002 with the tool
# (after the README's build command), at half size to keep the repository small; the legends below the frames are the
# tool's, drawn large enough to stay readable at half size.
#   doc/make_pictures.sh [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90]
set -eo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-$HOME/.cache/lidarsgm/build-cuda90}
TMP=$(mktemp -d)
# The Python of the build's bindings (the superbuild's virtual environment where it made one).
PY=python3
for p in "$BUILD/../pyenv-"*/bin/python; do [ -x "$p" ] && PY=$p; done
"$BUILD/bin/lidarsgm_fuse" --kitti-frame testdata/kitti --id 000002 --modes sgm,sdsgm --format kitti,ply \
  --out "$TMP"
PYTHONPATH="$BUILD/python_loader" "$PY" doc/render_cloud.py "$TMP/points_sdsgm.ply" "$TMP/cloud.png"
PYTHONPATH="$BUILD/python_loader" "$PY" - "$TMP" doc/images <<'PY'
import sys, cv2 as cv
src, dst = sys.argv[1], sys.argv[2]
for name, out in [("lidar_points.png", "000002_lidar_points.png"), ("semidense_color.png", "000002_semidense.png"),
                  ("disparity_sgm_color.png", "000002_sgm.png"), ("disparity_sdsgm_color.png", "000002_sdsgm.png"),
                  ("error_sgm.png", "000002_sgm_error.png"), ("error_sdsgm.png", "000002_sdsgm_error.png"),
                  ("cloud.png", "000002_cloud.png")]:
    img = cv.imread(src + "/" + name)
    # INTER_AREA keeps single-pixel detail as averages; the LiDAR dots are 3x3 and survive halving.
    cv.imwrite(dst + "/" + out, cv.resize(img, None, fx=0.5, fy=0.5, interpolation=cv.INTER_AREA),
               [cv.IMWRITE_PNG_COMPRESSION, 9])
PY
rm -rf "$TMP"
ls -l doc/images
