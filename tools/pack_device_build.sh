#!/usr/bin/env bash
# Pack this machine's CUDA build (the superbuild's build-cuda<arch>: the OpenCV libraries with lidarsgm, the test,
# perf and tool binaries, and the two system image libraries they link that the device image may lack) into
# .device/prebuilt.tar.xz, so that tools/device_check.sh can run the CUDA checks on the lent GPU machine without
# building there (a build there takes about 4 of its minutes). The CUDA runtime is linked statically; the GPU machine
# brings the driver. Python is not packed (the device's Python differs): PY=ON runs build from source there.
#   tools/pack_device_build.sh [cache dir, default ~/.cache/lidarsgm] [arch key, default cuda90]
# PACK_NAME=prebuilt_base packs into .device/prebuilt_base.tar.xz instead: the "before" build of CPU_SCALING.
# MODULE_ONLY=1 packs only what a change to the module alters (libopencv_lidarsgm and the three binaries, about a
# third of the size): tools/device_variants.sh completes such a build with prebuilt_base's other libraries.
set -eo pipefail
cd "$(dirname "$0")/.."
CACHE=${1:-${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}}
B=$CACHE/build-${2:-cuda90}
[ -x "$B/bin/opencv_test_lidarsgm" ] || { echo "no CUDA build in $B (run the README's build first)"; exit 1; }
tmp=$(mktemp -d)
mkdir -p "$tmp/prebuilt/bin" "$tmp/prebuilt/lib" .device
cp "$B/bin/opencv_test_lidarsgm" "$B/bin/opencv_perf_lidarsgm" "$B/bin/lidarsgm_fuse" "$tmp/prebuilt/bin/"
if [ "${MODULE_ONLY:-0}" = 1 ]; then
  cp -P "$B"/lib/libopencv_lidarsgm.so* "$tmp/prebuilt/lib/"
  touch "$tmp/prebuilt/MODULE_ONLY"
else
  cp -P "$B"/lib/libopencv_*.so* "$tmp/prebuilt/lib/"
  for l in libjpeg.so.62 libpng16.so.16; do
    p=$(ldd "$B/lib/libopencv_imgcodecs.so" | awk -v l=$l '$1 == l {print $3}')
    [ -n "$p" ] && cp -L "$p" "$tmp/prebuilt/lib/$l"
  done
fi
git rev-parse HEAD > "$tmp/prebuilt/COMMIT"
git diff --quiet HEAD -- src src_cuda include test perf samples || echo "+ uncommitted changes" >> "$tmp/prebuilt/COMMIT"
tar -C "$tmp" -cJf .device/${PACK_NAME:-prebuilt}.tar.xz prebuilt
rm -rf "$tmp"
ls -l .device/${PACK_NAME:-prebuilt}.tar.xz
