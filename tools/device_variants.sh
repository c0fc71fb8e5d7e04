#!/usr/bin/env bash
# Several builds on one GPU in one device call, for a before/after of candidate changes: every
# .device/prebuilt*.tar.xz (tools/pack_device_build.sh; PACK_NAME=prebuilt_<name> for each candidate, prebuilt_base
# for the commit they start from), each unpacked to /tmp/variants/<name>; a build packed with MODULE_ONLY=1 takes the
# other libraries from prebuilt_base.
# - TESTS=1: each build's CUDA tests first (gtest filter TEST_FILTER, default *CUDA*): passed and failed counts.
# - TIMING=1 (default): ROUNDS rounds (default 2), each build in turn, of lidarsgm_fuse --timing REPS (default 20) on
#   KITTI 000002 with kitti_best.yml, on the whole card and on SMS SMs (default 8, a green context): with the windows
#   (margin 4) and at full range at KITTI size, with the windows at 1280x720 (SIZES: the sizes). Then a table of the
#   medians over the rounds per build, cv::cuda::StereoSGM's 8 paths on the same SMs beside.
# - PROFILE=1: each build's kernels of one KITTI-size kitti_best.yml call (margin 4) on SMS SMs under ncu, time and
#   warp instructions per kernel (tools/ncu_call.py), before the timing.
# - PIPES=1: the pipes and stall reasons of one kernel (STALL_KERNEL, default packedWindowPathKernel) of that call on
#   SMS SMs under ncu, each build's.
# - SOURCE=1: the same kernel's SASS instructions with the most warp stall samples (tools/ncu_source.sh; TOP of them,
#   default 30), each build's; the report and its source page stay in OUT.
# BUILDS: the names of the builds to test and time (default: every archive's), so that one call need not run them all.
# Run on the device machine from the repository root, .device carried:
#   TESTS=1 bash tools/device_variants.sh
set -eo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/lidarsgm-out}; mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
date -u
archives=$(ls .device/prebuilt*.tar.xz 2>/dev/null || true)
[ -n "$archives" ] || { echo "no .device/prebuilt*.tar.xz (tools/pack_device_build.sh makes them)"; exit 2; }
names=""
for a in $archives; do
  n=$(basename "$a" .tar.xz); n=${n#prebuilt}; n=${n#_}; n=${n:-this}
  mkdir -p "/tmp/variants/$n" && tar -xJf "$a" -C "/tmp/variants/$n"
  echo "build $n: $(head -c 12 "/tmp/variants/$n/prebuilt/COMMIT") $(tail -n +2 "/tmp/variants/$n/prebuilt/COMMIT")"
  names="$names $n"
done
for n in $names; do
  d=/tmp/variants/$n/prebuilt
  [ -e "$d/MODULE_ONLY" ] || continue
  [ -e /tmp/variants/base/prebuilt/lib ] && [ ! -e /tmp/variants/base/prebuilt/MODULE_ONLY ] ||
    { echo "build $n is packed MODULE_ONLY=1 but there is no full .device/prebuilt_base.tar.xz"; exit 2; }
  cp -Pn /tmp/variants/base/prebuilt/lib/* "$d/lib/"
done
if [ -n "${BUILDS:-}" ]; then
  for n in $BUILDS; do
    [ -d "/tmp/variants/$n" ] || { echo "BUILDS names $n, which no .device/prebuilt_$n.tar.xz holds"; exit 2; }
  done
  names=$BUILDS
fi
run() {  # build, then the tool's arguments
  local d=/tmp/variants/$1/prebuilt; shift
  LD_LIBRARY_PATH=$d/lib $d/bin/lidarsgm_fuse "$@"
}
if [ "${TESTS:-0}" = 1 ]; then
  for n in $names; do
    d=/tmp/variants/$n/prebuilt
    OPENCV_TEST_DATA_PATH=testdata LD_LIBRARY_PATH=$d/lib $d/bin/opencv_test_lidarsgm \
      --gtest_filter="${TEST_FILTER:-*CUDA*}" > "$OUT/tests_$n.log" 2>&1 || true
    echo "tests $n: $(grep -E '^\[  (PASSED|FAILED)  \] [0-9]+ test' "$OUT/tests_$n.log" | tr '\n' ' ')"
    grep -E '^\[  FAILED  \] [A-Za-z]' "$OUT/tests_$n.log" | head -5 || true
  done
fi
# The call that PROFILE, PIPES and SOURCE look into.
profiled=(--kitti-frame testdata/kitti --id 000002 --cuda --timing 1 --sm-count "${SMS:-8}"
          --params doc/params/kitti_best.yml --search-window 4)
if [ "${PROFILE:-0}" = 1 ]; then
  command -v ncu > /dev/null || { echo "PROFILE=1: no ncu on this machine"; exit 2; }
  for n in $names; do
    d=/tmp/variants/$n/prebuilt
    LD_LIBRARY_PATH=$d/lib ncu --profile-from-start off --clock-control none --csv --print-units base \
      --metrics gpu__time_duration.sum,smsp__inst_executed.sum $d/bin/lidarsgm_fuse "${profiled[@]}" \
      > "$OUT/profile_$n.csv" 2> "$OUT/profile_$n.err"
    python3 tools/ncu_call.py "$OUT/profile_$n.csv" "build $n, ${SMS:-8} SMs" || tail -5 "$OUT/profile_$n.err"
  done
fi
if [ "${PIPES:-0}" = 1 ] || [ "${SOURCE:-0}" = 1 ]; then
  command -v ncu > /dev/null || { echo "PIPES=1, SOURCE=1: no ncu on this machine"; exit 2; }
  kernel=${STALL_KERNEL:-packedWindowPathKernel}
  for n in $names; do
    d=/tmp/variants/$n/prebuilt
    if [ "${PIPES:-0}" = 1 ]; then
      echo "== build $n, ${SMS:-8} SMs: $kernel, pipes (% of peak) and stalls per issue"
      LD_LIBRARY_PATH=$d/lib bash tools/ncu_pipes.sh "$kernel" $d/bin/lidarsgm_fuse "${profiled[@]}"
    fi
    if [ "${SOURCE:-0}" = 1 ]; then
      echo "== build $n, ${SMS:-8} SMs: $kernel, SASS instructions by stall samples"
      LD_LIBRARY_PATH=$d/lib bash tools/ncu_source.sh "$kernel" "$OUT/source_$n" $d/bin/lidarsgm_fuse \
        "${profiled[@]}" || true
    fi
  done
fi
[ "${TIMING:-1}" = 1 ] || exit 0
log=$OUT/variants_timing.txt; : > "$log"
for ((r = 0; r < ${ROUNDS:-2}; r++)); do
  for n in $names; do
    for sz in ${SIZES:-1242x375 1280x720}; do
      for sw in 4 0; do
        [ "$sz" = 1242x375 ] || [ $sw = 4 ] || continue
        run "$n" --kitti-frame testdata/kitti --id 000002 --cuda --timing "${REPS:-20}" --sm-count "${SMS:-8}" \
          --params doc/params/kitti_best.yml --search-window $sw $([ "$sz" = 1242x375 ] || echo --resize "$sz") \
          | grep -E "lidarsgm SDSGM \||StereoSGM 8 paths" | sed "s/^/$n $sz sw$sw /" >> "$log"
      done
    done
  done
done
python3 - "$log" $names <<'EOF'
import re, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    m = re.match(r'(\S+) (\S+) sw(\d) \|\s*(?:(\d+) SMs: )?(lidarsgm SDSGM|cv::cuda::StereoSGM 8 paths)\s*\|\s*([\d.]+) ms', line)
    if m:
        build, size, sw, sms, what, ms = m.groups()
        rows.setdefault((size, sw, sms or 'all', what), {}).setdefault(build, []).append(float(ms))
names = sys.argv[2:]
print('| size | windows | SMs | what | ' + ' | '.join(names) + ' |')
print('| --- ' * (4 + len(names)) + '|')
for key in sorted(rows, key=lambda k: (k[0], -int(k[1]), k[2], k[3])):
    cells = ['%.3f' % statistics.median(rows[key][b]) if b in rows[key] else '' for b in names]
    print('| %s | %s | %s | %s | ' % (key[0], 'margin 4' if key[1] == '4' else 'full range', key[2], key[3]) +
          ' | '.join(cells) + ' |')
EOF
