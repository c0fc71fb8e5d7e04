#!/usr/bin/env bash
# Pack the part of the pinned OpenCV source that lidarsgm's build needs into .device/opencv-trim.tar.xz (about 10 MB),
# so that tools/device_check.sh can build OpenCV on the lent GPU machine, which has no network. The source is the
# superbuild's extracted PyPI archive (run the README's build once first); the archive keeps its top folder name.
#   tools/make_opencv_trim.sh [cache dir, default ~/.cache/lidarsgm]
set -eo pipefail
cd "$(dirname "$0")/.."
VERSION=4.14.0.94
CACHE=${1:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}}
TOP=opencv_contrib_python-$VERSION
[ -f "$CACHE/src/$TOP/opencv/CMakeLists.txt" ] || { echo "no OpenCV source in $CACHE/src/$TOP (build once first)"; exit 1; }
mkdir -p .device
# The modules the superbuild builds (CMakeLists.txt: _modules), their sources without their own tests; the CMake
# machinery; the 3rdparty libraries that the build list pulls in.
paths=()
for m in core imgproc imgcodecs calib3d features2d flann ts python; do paths+=("$TOP/opencv/modules/$m"); done
for m in cudev cudastereo; do paths+=("$TOP/opencv_contrib/modules/$m"); done
for d in cmake include platforms hal data/CMakeLists.txt doc/CMakeLists.txt CMakeLists.txt LICENSE; do paths+=("$TOP/opencv/$d"); done
for d in zlib zlib-ng libpng libspng libjpeg-turbo include cpufeatures ittnotify dlpack quirc fastcv; do
  [ -e "$CACHE/src/$TOP/opencv/3rdparty/$d" ] && paths+=("$TOP/opencv/3rdparty/$d")
done
tar -C "$CACHE/src" -cJf .device/opencv-trim.tar.xz \
    --exclude="$TOP/opencv/modules/*/test" --exclude="$TOP/opencv/modules/*/perf" \
    --exclude="$TOP/opencv_contrib/modules/*/test" --exclude="$TOP/opencv_contrib/modules/*/perf" \
    --exclude="$TOP/opencv/modules/*/misc/java" --exclude="$TOP/opencv/modules/*/misc/objc" \
    "${paths[@]}"
ls -l .device/opencv-trim.tar.xz
