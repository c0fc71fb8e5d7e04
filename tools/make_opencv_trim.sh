#!/usr/bin/env bash
# Pack the part of the pinned OpenCV source that lidarsgm's build needs into .device/opencv-trim.tar.xz (about 10 MB),
# so that tools/device_check.sh can build OpenCV on the lent GPU machine, which has no network. The source is the
# superbuild's extracted PyPI archive (run the README's build once first); the archive keeps its top folder name.
#   [OPENCV_VERSION=5.0.0.93] tools/make_opencv_trim.sh [cache dir, default ~/.cache/lidarsgm]
# (another version: .device/opencv-trim-<version>.tar.xz)
set -eo pipefail
cd "$(dirname "$0")/.."
VERSION=${OPENCV_VERSION:-4.14.0.94}
CACHE=${1:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}}
TOP=opencv_contrib_python-$VERSION
OUTF=.device/opencv-trim.tar.xz
[ "$VERSION" = 4.14.0.94 ] || OUTF=.device/opencv-trim-$VERSION.tar.xz
[ -f "$CACHE/src/$TOP/opencv/CMakeLists.txt" ] || { echo "no OpenCV source in $CACHE/src/$TOP (build once first)"; exit 1; }
mkdir -p .device
# The modules the superbuild builds (CMakeLists.txt: _modules), their sources without their own tests (cudev's are
# kept: its CMakeLists adds them unconditionally in 5.x); the CMake
# machinery; the 3rdparty libraries that the build list pulls in.
paths=()
if [ "${VERSION%%.*}" -ge 5 ]; then
  mods="core imgproc imgcodecs stereo geometry flann ts videoio highgui python"   # ts needs videoio, highgui
else
  mods="core imgproc imgcodecs calib3d features2d flann ts videoio highgui python"   # ts needs videoio, highgui
fi
for m in $mods; do paths+=("$TOP/opencv/modules/$m"); done
for m in cudev cudastereo; do paths+=("$TOP/opencv_contrib/modules/$m"); done
for d in cmake include platforms hal data/CMakeLists.txt doc/CMakeLists.txt docs_sphinx/CMakeLists.txt CMakeLists.txt \
         LICENSE; do
  [ -e "$CACHE/src/$TOP/opencv/$d" ] && paths+=("$TOP/opencv/$d")
done
for d in zlib zlib-ng libpng libspng libjpeg-turbo include cpufeatures ittnotify dlpack quirc fastcv; do
  [ -e "$CACHE/src/$TOP/opencv/3rdparty/$d" ] && paths+=("$TOP/opencv/3rdparty/$d")
done
tar -C "$CACHE/src" -cJf "$OUTF" \
    --exclude="$TOP/opencv/modules/*/test" --exclude="$TOP/opencv/modules/*/perf" \
    --exclude="$TOP/opencv_contrib/modules/cudastereo/test" --exclude="$TOP/opencv_contrib/modules/*/perf" \
    --exclude="$TOP/opencv/modules/*/misc/java" --exclude="$TOP/opencv/modules/*/misc/objc" \
    "${paths[@]}"
ls -l "$OUTF"
# tools/device_check.sh PY=ON builds the Python bindings there; their tests read and write point clouds with plyfile
# and pypcd4 and check the typing stubs with mypy, which the device's Python (3.12) lacks: their wheels, and their
# dependencies but numpy, travel in .device/wheels.
python3 -m pip download -q --no-deps plyfile==1.1.5 -d .device/wheels
python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
  --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 \
  --platform manylinux1_x86_64 -d .device/wheels pypcd4==1.5.1 pydantic==2.14.4 pydantic-core==2.50.5 \
  python-neo-lzf==0.3.5 annotated-types==0.8.0 typing-extensions==4.16.0 typing-inspection==0.4.5
python3 -m pip download -q --only-binary=:all: --python-version 3.12 --implementation cp \
  --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 --platform manylinux2014_x86_64 \
  -d .device/wheels mypy==2.4.1
