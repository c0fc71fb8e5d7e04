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
B=$CACHE/build-${ARCH_KEY:-cuda90}
[ -f "$B/build.ninja" ] || { echo "no CUDA build in $B (run the README's build in this clone first)"; exit 1; }
git diff --quiet HEAD && git diff --cached --quiet || { echo "this clone has uncommitted changes"; exit 1; }
start=$(git rev-parse HEAD)
trap 'git checkout -q --detach "$start"' EXIT
first=1
for arg in "$@"; do
  case $arg in
    DEST=*) continue ;;
    *=*) ;;
    *) echo "pack_variants.sh: NAME=REV expected, got $arg"; exit 2 ;;
  esac
  name=${arg%%=*}; rev=${arg#*=}
  git checkout -q --detach "$rev"
  ninja -C "$B" opencv_test_lidarsgm opencv_perf_lidarsgm lidarsgm_fuse > /tmp/pack_variants_$name.log 2>&1 ||
    { tail -20 /tmp/pack_variants_$name.log; exit 1; }
  if [ $first = 1 ]; then
    PACK_NAME=prebuilt_$name bash tools/pack_device_build.sh "$CACHE"
    first=0
  else
    MODULE_ONLY=1 PACK_NAME=prebuilt_$name bash tools/pack_device_build.sh "$CACHE"
  fi
done
dest=.device
for arg in "$@"; do case $arg in DEST=*) dest=${arg#DEST=} ;; esac; done
if [ "$dest" != .device ]; then
  mkdir -p "$dest"
  for arg in "$@"; do
    case $arg in DEST=*) ;; *) cp ".device/prebuilt_${arg%%=*}.tar.xz" "$dest/" ;; esac
  done
fi
