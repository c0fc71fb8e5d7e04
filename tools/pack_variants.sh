#!/usr/bin/env bash
# Builds and packs several revisions for one tools/device_variants.sh call: for each NAME=REV, checks REV out
# (detached) in this clone, builds the module's three binaries in the cache's CUDA build (which the README's build
# configured for this clone) and packs it as .device/prebuilt_NAME.tar.xz (tools/pack_device_build.sh): the first
# in full (name it base: the others borrow its libraries), the others MODULE_ONLY=1. Then copies the archives to
# DEST (default: this clone's .device) and checks out the revision it started from again.
# Run in a clone whose working tree is clean, not in the checkout you edit; the revisions are the clone's (fetch the
# candidates first: git fetch ../main "+refs/heads/*:refs/remotes/main/*"):
#   tools/pack_variants.sh base=main/main fw=main/fw rf=main/rf [DEST=/path/to/checkout/.device]
set -eo pipefail
cd "$(dirname "$0")/.."
CACHE=${LIDARSGM_CACHE_DIR:-$HOME/.cache/lidarsgm}
KEY=${ARCH_KEY:-cuda90}   # the CUDA build's key, as tools/pack_device_build.sh takes it
B=$CACHE/build-$KEY
[ -f "$B/build.ninja" ] || { echo "no CUDA build in $B (run the README's build in this clone first)"; exit 1; }
git diff --quiet HEAD && git diff --cached --quiet || { echo "this clone has uncommitted changes"; exit 1; }
dest=.device; builds=()
for arg in "$@"; do
  case $arg in
    DEST=*) dest=${arg#DEST=} ;;
    *=*) builds+=("$arg") ;;
    *) echo "pack_variants.sh: NAME=REV expected, got $arg"; exit 2 ;;
  esac
done
start=$(git rev-parse HEAD)
trap 'git checkout -q --detach "$start"' EXIT
for arg in "${builds[@]}"; do
  name=${arg%%=*}; rev=${arg#*=}
  git checkout -q --detach "$rev"
  ninja -C "$B" opencv_test_lidarsgm opencv_perf_lidarsgm lidarsgm_fuse > /tmp/pack_variants_$name.log 2>&1 ||
    { tail -20 /tmp/pack_variants_$name.log; exit 1; }
  only=1; [ "$arg" = "${builds[0]}" ] && only=0   # the first in full
  MODULE_ONLY=$only PACK_NAME=prebuilt_$name bash tools/pack_device_build.sh "$CACHE" "$KEY"
  if [ "$dest" != .device ]; then
    mkdir -p "$dest" && cp ".device/prebuilt_$name.tar.xz" "$dest/"
  fi
done
