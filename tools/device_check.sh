#!/usr/bin/env bash
# Check the CUDA path on the lent GPU machine: the CUDA tests (bit-exact against the CPU path, graph capture), then
# CUDA-event timings against cv::cuda::StereoSGM. The machine has no network, so what it needs travels in .device/
# (carry it): either the CPU machine's CUDA build (tools/pack_device_build.sh: .device/prebuilt.tar.xz, used unless
# PY=ON) or the trimmed OpenCV source (tools/make_opencv_trim.sh: .device/opencv-trim.tar.xz) to build there.
#   tools/device_check.sh [extra gtest filter]        (SM_COUNTS="8 16": also time on that many SMs, --sm-count)
set -eo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/lidarsgm-out}; mkdir -p "$OUT"
CACHE=/tmp/lidarsgm-cache
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
date -u
t0=$(date +%s)
if [ -f .device/prebuilt.tar.xz ] && [ "${PY:-OFF}" != ON ] && [ "${OPENCV_VERSION:-4.14.0.94}" = 4.14.0.94 ]; then
  # The build made on the CPU machine (tools/pack_device_build.sh): no build here.
  tar -xJf .device/prebuilt.tar.xz -C /tmp
  B=/tmp/prebuilt/bin
  export LD_LIBRARY_PATH=/tmp/prebuilt/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  echo "prebuilt binaries of $(head -c 12 /tmp/prebuilt/COMMIT) $(tail -n +2 /tmp/prebuilt/COMMIT)"
else
  # OPENCV_VERSION=5.0.0.93: build against that OpenCV (tools/make_opencv_trim.sh with the same variable packs it).
  V=${OPENCV_VERSION:-4.14.0.94}
  SRC=$CACHE/src/opencv_contrib_python-$V
  TRIM=.device/opencv-trim.tar.xz; [ "$V" = 4.14.0.94 ] || TRIM=.device/opencv-trim-$V.tar.xz
  if [ ! -f "$SRC/opencv/CMakeLists.txt" ]; then mkdir -p $CACHE/src && tar -xJf $TRIM -C $CACHE/src; fi
  # The trimmed archive (tools/make_opencv_trim.sh) leaves out the modules' test folders; OpenCV's python module
  # adds its own unconditionally.
  mkdir -p "$SRC/opencv/modules/python/test" && touch "$SRC/opencv/modules/python/test/CMakeLists.txt"
  # The image's default compiler (CXX=/opt/gcc/bin/g++, a wrapper of the system's GCC 13) links libstdc++ statically
  # into every library, so that each OpenCV library carries its own copy of the C++ runtime, and a stream made by one
  # and used by another crashes cv2 (imread's logging). The system's compiler links the shared libstdc++.
  if [ -x /usr/bin/g++ ]; then export CC=/usr/bin/gcc CXX=/usr/bin/g++ CUDAHOSTCXX=/usr/bin/g++; fi
  # PY=ON: the bindings' test dependencies the device's Python lacks, from the wheels make_opencv_trim.sh downloads.
  [ "${PY:-OFF}" = ON ] && python3 -m pip install -q --no-index --find-links .device/wheels plyfile pypcd4 mypy
  cmake -S . -B build-device -G Ninja -DLIDARSGM_CACHE_DIR=$CACHE -DLIDARSGM_WITH_PYTHON=${PY:-OFF} \
    -DLIDARSGM_WITH_RAY=OFF -DLIDARSGM_WITH_ROS2=OFF \
    -DLIDARSGM_OPENCV=$V -DLIDARSGM_OPENCV_ALSO= \
    -DLIDARSGM_WITH_CUDA=ON -DLIDARSGM_WITH_SANITIZERS=OFF > "$OUT/configure.log" 2>&1 || { tail -40 "$OUT/configure.log"; exit 1; }
  cmake --build build-device > "$OUT/build.log" 2>&1 || { grep -E "error|FAILED" "$OUT/build.log" | head -30; exit 1; }
  B=$CACHE/build-cuda90/bin
  [ "$V" = 4.14.0.94 ] || B=$CACHE/build-cuda90-opencv$V/bin
fi
echo "build: $(( $(date +%s) - t0 )) s"
# The shared data travels packed (tools/make_device_data.py) when .device/shared exists.
[ -d .device/shared ] && export LIDARSGM_SHARED_DATA=$PWD/.device/shared
OPENCV_TEST_DATA_PATH=testdata $B/opencv_test_lidarsgm --gtest_filter="${1:-*CUDA*}" > "$OUT/tests.log" 2>&1 || true
if [ "${PY:-OFF}" = ON ]; then
  PYTHONPATH=$CACHE/build-cuda90/python_loader:$SRC/opencv/modules/python/test OPENCV_PYTEST_LIDARSGM_DATA=$PWD/testdata \
    python3 -m unittest discover -v -s modules/lidarsgm/misc/python/test -p "test_*.py" 2>&1 | tail -8
  # The ROS 2 package's fusion on the GPU (no ROS there: plain messages) and its conversions' cost.
  PYTHONPATH=$CACHE/build-cuda90/python_loader LIDARSGM_TESTDATA=$PWD/testdata \
    python3 -m unittest discover -v -s test/ros2 -p "test_conversions.py" 2>&1 | grep -E "cuda|^Ran|^OK|FAIL|Error"
  # (each output also in $OUT, for doc/benchmarks/ros2_latency_<device>.txt)
  PYTHONPATH=$CACHE/build-cuda90/python_loader python3 tools/ros2_latency.py --cuda --node-frames 0 | tee "$OUT/ros2_latency_cuda.txt"
  PYTHONPATH=$CACHE/build-cuda90/python_loader python3 tools/ros2_latency.py --node-frames 0 | tee "$OUT/ros2_latency_cpu.txt"
fi
grep -E "^\[  FAILED|^\[  PASSED|^\[     SKIP|Failure" "$OUT/tests.log" | sort | uniq -c | head -40
for id in 000002 000046; do
  $B/lidarsgm_fuse --kitti-frame testdata/kitti --id $id --cuda --modes sgm,dsgm,sdsgm
done
[ "${TIMING:-1}" = 1 ] && $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 50 --rounds ${ROUNDS:-1}
# The same calls on a few of the GPU's SMs (a CUDA green context; SM_COUNTS, default 8 and 16: a Jetson Orin NX's and
# an AGX Orin's count), with the create() defaults, kitti_best.yml, and kitti_best.yml at full range.
if [ "${TIMING:-1}" = 1 ]; then
  for n in ${SM_COUNTS:-8 16}; do
    for p in "" "--params doc/params/kitti_best.yml" "--params doc/params/kitti_best.yml --search-window 0"; do
      echo "== --sm-count $n ${p:-(create() defaults)}"
      $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 15 --sm-count $n $p | grep -E "SMs"
    done
  done
fi
if [ "${SIZES:-0}" = 1 ]; then
  for sz in 1920x1080 3840x2160; do
    $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 20 --resize $sz --num-disparities 256 | grep -v "^000002"
  done
fi
if [ "${FAILSAFE:-0}" = 1 ]; then
  # The fail-safe on the GPU path: the test frames with a 2-degree rotation error, CUDA (2 streams) against the CPU.
  python3 tools/perturb_calibration.py testdata/kitti /tmp/wrong --pitch 1.2 --yaw -1.5 --roll 0.8
  for dev in "--cuda --streams 2" "--threads 16"; do
    for dir in testdata/kitti /tmp/wrong; do
      echo "== $dir $dev"
      $B/lidarsgm_fuse --kitti $dir $dev --quiet --params doc/params/kitti_best.yml --modes sgm,sdsgm \
        --out /tmp/fs_$(basename $dir)_${dev%% *} | grep -E "^\| S|stereo alone|anyway"
    done
  done
  for dir in kitti wrong; do
    cmp -s /tmp/fs_${dir}_--cuda/000002/disparity_sdsgm.png /tmp/fs_${dir}_--threads/000002/disparity_sdsgm.png &&
      cmp -s /tmp/fs_${dir}_--cuda/000046/disparity_sdsgm.png /tmp/fs_${dir}_--threads/000046/disparity_sdsgm.png &&
      echo "$dir: CUDA and CPU SDSGM maps byte for byte equal" || echo "$dir: CUDA and CPU SDSGM maps DIFFER"
  done
fi
if [ "${BASE:-0}" = 1 ] && [ -f .device/prebuilt_base.tar.xz ]; then
  # The same timings with .device/prebuilt_base.tar.xz (tools/pack_device_build.sh with PACK_NAME=prebuilt_base, from
  # an earlier commit), for a before/after on the same card.
  mkdir -p /tmp/base && tar -xJf .device/prebuilt_base.tar.xz -C /tmp/base
  echo "== base build $(head -c 12 /tmp/base/prebuilt/COMMIT)"
  # Each size timed by the base build, then by this build, BASE_ROUNDS times (default 1; TIMING=0: none); with WINDOWS
  # set, both with --search-window WINDOWS (the windows' before/after).
  [ "${TIMING:-1}" = 1 ] || BASE_ROUNDS=0
  for ((r = 0; r < ${BASE_ROUNDS:-1}; r++)); do
    for a in "" "--resize 1920x1080 --num-disparities 256" "--resize 1920x1080 --num-disparities 256 --paths 4" \
             "--resize 3840x2160 --num-disparities 256"; do
      LD_LIBRARY_PATH=/tmp/base/prebuilt/lib /tmp/base/prebuilt/bin/lidarsgm_fuse --kitti-frame testdata/kitti \
        --id 000002 --cuda 1 --timing 20 $a ${WINDOWS:+--search-window $WINDOWS} | grep -E "^device:|lidarsgm SDSGM " \
        | sed "s/^/base ${a:-KITTI}: /"
      $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 20 $a \
        ${WINDOWS:+--search-window $WINDOWS} | grep -E "lidarsgm SDSGM " | sed "s/^/this build ${a:-KITTI}: /"
    done
  done
fi
if [ "${SANITIZE:-0}" = 1 ] && command -v compute-sanitizer >/dev/null; then
  # memcheck over MEM_FILTER and racecheck over RACE_FILTER, at the same time; racecheck split into RACE_SHARDS
  # processes (gtest sharding). Racecheck takes about half a minute per KITTI-size configuration, so its default set
  # is every small-image test plus one KITTI-size configuration per kernel variant (mode, check, paths).
  MEM_FILTER=${MEM_FILTER:-'*CUDA*-*shared_data*'}
  RACE_FILTER=${RACE_FILTER:-'*CUDA_Random*:*roi_input*:*projection*:*graph*:*Kitti*f000002_SDSGM_stereo_lidar_p8*:*Kitti*f000002_DSGM_camera_lidar_p4*:*Kitti*f000002_SGM_stereo_p8*:*Kitti*f000002_SGM_none_p4*'}
  san() {  # tool filter shard shards
    local log="$OUT/sanitize_$1_$3.log" rc=0
    # (exit 124: SAN_TIMEOUT seconds passed first; the tests it finished are counted.)
    timeout ${SAN_TIMEOUT:-200} compute-sanitizer --tool $1 --error-exitcode 99 env OPENCV_TEST_DATA_PATH=testdata \
      GTEST_TOTAL_SHARDS=$4 GTEST_SHARD_INDEX=$3 $B/opencv_test_lidarsgm --gtest_filter="$2" > "$log" 2>&1 || rc=$?
    echo "compute-sanitizer $1 shard $3/$4: exit $rc ($(grep -E 'ERROR SUMMARY|RACECHECK SUMMARY' "$log" | tail -1))" \
         "$(grep -cE '^\[       OK' "$log") OK, $(grep -E '^\[  (PASSED|FAILED)' "$log" | head -1)"
  }
  for ((k = 0; k < ${RACE_SHARDS:-1}; k++)); do san racecheck "$RACE_FILTER" $k ${RACE_SHARDS:-1} & done
  [ "$MEM_FILTER" != none ] && san memcheck "$MEM_FILTER" 0 1 &
  wait
fi
if [ "${PERF:-0}" = 1 ]; then
  OPENCV_TEST_DATA_PATH=testdata $B/opencv_perf_lidarsgm --gtest_filter='*CUDA*' --perf_min_samples=30 2>&1 \
    > "$OUT/perf_cuda.log" 2>&1
  grep -E "^\[ RUN|PERFSTAT" "$OUT/perf_cuda.log" | paste - - | sed -E 's/.*Lidarsgm_KITTI_CUDA[_A-Za-z]*\.([a-zA-Z_0-9]+)\/[0-9]+, where GetParam\(\) = (.*) \[ PERFSTAT.*median=([0-9.]+).*/\1 \2 median \3 ms/' | head -20
fi
if [ "${PATHS4:-0}" = 1 ]; then
  # 4 paths at 1080p against cv::cuda::StereoSGM's 4 paths (MODE_HH4).
  $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 20 --resize 1920x1080 \
    --num-disparities 256 --paths 4 | grep -E "device:|lidarsgm SDSGM|StereoSGM 4"
fi
if [ -n "${WINDOWS:-}" ]; then
  # The disparity windows (--search-window WINDOWS) against the full range, each beside cv::cuda::StereoSGM in the
  # same process: KITTI size (defaults, kitti_best.yml), 1080p with 4 and 8 paths and 512 disparities, 4K.
  for a in "" "--params doc/params/kitti_best.yml" "--resize 1920x1080 --num-disparities 256 --paths 4" \
           "--resize 1920x1080 --num-disparities 256" "--resize 1920x1080 --num-disparities 512" \
           "--resize 3840x2160 --num-disparities 256"; do
    for w in 0 $WINDOWS; do
      echo "== ${a:-KITTI defaults} --search-window $w"
      $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 20 $a --search-window $w \
        | grep -E "lidarsgm SDSGM |StereoSGM|cells searched" || true
    done
  done
fi
if [ "${BEST:-0}" = 1 ]; then
  echo "doc/params/kitti_best.yml at KITTI size (against the defaults above):"
  $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 50 \
    --params doc/params/kitti_best.yml | grep "lidarsgm"
fi
if [ "${THROUGHPUT:-0}" = 1 ]; then
  # A KITTI folder of 100 frames (copies of the two test frames under their own ids) through 1-16 workers with their
  # own streams, without and with the files written.
  TP=/tmp/tp; rm -rf $TP; mkdir -p $TP/image_2 $TP/image_3 $TP/velodyne $TP/disp_occ_0; cp testdata/kitti/calib.txt $TP/
  for i in $(seq 100); do
    id=$(printf %06d $i); src=$([ $((i % 2)) = 0 ] && echo 000002 || echo 000046); echo $id >> $TP/frames.txt
    for d in image_2 image_3 disp_occ_0; do cp testdata/kitti/$d/${src}_10.png $TP/$d/${id}_10.png; done
    cp testdata/kitti/velodyne/$src.bin $TP/velodyne/$id.bin
  done
  for s in ${STREAMS:-1 2 4 8 16}; do
    echo "folder run, --cuda --streams $s:"
    $B/lidarsgm_fuse --kitti $TP --cuda --streams $s --quiet | grep -E "SDSGM|frames:" || true
  done
  for s in 1 16; do
    echo "folder run with outputs (--out, KITTI PNGs and pictures), --cuda --streams $s:"
    rm -rf /tmp/tp_out; $B/lidarsgm_fuse --kitti $TP --cuda --streams $s --quiet --out /tmp/tp_out | grep -E "frames:" || true
  done
  echo "the same folder on the CPU, 16 threads, one worker:"
  $B/lidarsgm_fuse --kitti $TP --quiet --threads 16 | grep -E "SDSGM|frames:" || true
fi
if [ "${RAW:-0}" = 1 ]; then
  # A KITTI raw drive (tools/make_raw_drive.sh) on the GPU with depth and PLY out; its disparity files against the
  # CPU's of the same drive.
  rm -rf /tmp/raw; D=$(tools/make_raw_drive.sh /tmp/raw)
  $B/lidarsgm_fuse --kitti-raw $D --out /tmp/raw/gpu --cuda --streams 2 --modes sgm,sdsgm \
    --format kitti,depth,ply --quiet
  $B/lidarsgm_fuse --kitti-raw $D --out /tmp/raw/cpu --modes sgm,sdsgm --format kitti,depth,ply --quiet \
    > /dev/null
  for f in /tmp/raw/gpu/*/*.png /tmp/raw/gpu/*/*.ply; do
    cmp -s "$f" "/tmp/raw/cpu/${f#/tmp/raw/gpu/}" && echo "same as the CPU: ${f#/tmp/raw/gpu/}" \
      || echo "DIFFERS from the CPU: ${f#/tmp/raw/gpu/}"
  done
fi
if [ -n "${SPREAD:-}" ]; then
  # Fresh processes of the CPU timing at each thread count of SPREAD (tools/process_spread.sh), 8 paths.
  for t in $SPREAD; do tools/process_spread.sh ${SPREAD_N:-10} $t 8 "$B/.." | tail -n +2; done
fi
if [ "${CPU_SCALING:-0}" = 1 ]; then
  # The CPU path on the host's cores: cv::setNumThreads 1..16 (CPU_THREADS), every cv::StereoSGBM mode alongside.
  # With .device/prebuilt_base.tar.xz (tools/pack_device_build.sh with PACK_NAME=prebuilt_base, from an earlier
  # commit) that build's process follows this one's at each thread count, for a before/after on the same host.
  builds=$B
  if [ -f .device/prebuilt_base.tar.xz ]; then
    mkdir -p /tmp/base && tar -xJf .device/prebuilt_base.tar.xz -C /tmp/base && builds="$B /tmp/base/prebuilt/bin"
  fi
  for t in ${CPU_THREADS:-1 2 4 8 16}; do
    for b in $builds; do
      echo "== $t threads, $(head -c 12 $b/../COMMIT 2>/dev/null || echo built here)"
      LD_LIBRARY_PATH=$b/../lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} $b/lidarsgm_fuse --kitti-frame testdata/kitti \
        --id 000002 --timing ${CPU_REPS:-5} --threads $t ${CPU_ARGS:-} | grep -E "lidarsgm SDSGM  |SGBM_3WAY" || true
    done
  done
fi
if [ "${PROFILE_PATHS:-0}" = 1 ] && command -v ncu >/dev/null; then
  # The path kernel of one SDSGM call: time, registers per thread, achieved occupancy, issue activity.
  ncu --clock-control none -k regex:pathKernel --launch-skip 2 --launch-count 1 --metrics \
      gpu__time_duration.sum,launch__registers_per_thread,sm__warps_active.avg.pct_of_peak_sustained_active,sm__inst_executed.avg.per_cycle_active,smsp__issue_active.avg.pct_of_peak_sustained_active \
      $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 1 2>&1 \
    | grep -E "pathKernel|gpu__|launch__|sm__|smsp__" | sed -E 's/ +/ /g' | cut -c1-150
fi
if [ "${PROFILE:-0}" = 1 ] && command -v ncu >/dev/null; then
  # Per-kernel durations of one SDSGM call (the second: the first includes module loading).
  ncu --clock-control none --metrics gpu__time_duration.sum --launch-skip 6 --launch-count 7 \
      $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 --cuda --timing 1 2>&1 \
    | grep -E "^  [a-zA-Z_].*\(|gpu__time_duration" | paste - - | awk '{print $1, $(NF-1), $NF}' | head -20
fi
# The tool's arguments for one SDSGM call at a WxH:disparities:paths[:margin[:params file]] spec of DRAM_SIZES /
# PROFILE_SIZES / INSTRUCTIONS (margin: --search-window, the disparity windows; the file: --params, e.g.
# doc/params/kitti_best.yml, whose own size, disparities and paths the spec's override); "--cuda 1", which a base
# build's older tool also takes.
spec_args() {
  IFS=: read -r sz nd np nw pf <<< "$1"
  echo "--kitti-frame testdata/kitti --id 000002 --cuda 1 --timing 1 ${pf:+--params $pf} --resize $sz --num-disparities $nd --paths $np --search-window ${nw:-0}"
}
if [ -n "${DRAM_SIZES:-}" ] && command -v ncu >/dev/null; then
  # DRAM bytes read and written by each kernel of one SDSGM call at each WxH:disparities:paths of DRAM_SIZES (the
  # first DRAM_LAUNCHES kernel launches, default 40, must hold two calls: a windowed call has about 45).
  for spec in $DRAM_SIZES; do
    args=$(spec_args "$spec"); sz=${spec%%:*}
    ncu --clock-control none --csv --print-units base --launch-count ${DRAM_LAUNCHES:-40} \
      --metrics dram__bytes_read.sum,dram__bytes_write.sum,gpu__time_duration.sum $B/lidarsgm_fuse $args \
      > "$OUT/dram_$sz.csv" 2> "$OUT/dram_$sz.err"
    python3 tools/ncu_call.py "$OUT/dram_$sz.csv" "$spec" || tail -5 "$OUT/dram_$sz.err"
  done
fi
if [ -n "${INSTRUCTIONS:-}" ] && command -v ncu >/dev/null; then
  # Time and warp instructions executed by each kernel of one SDSGM call at each WxH:disparities:paths of
  # INSTRUCTIONS, ending with the aggregation's sum (tools/ncu_call.py); then the path kernel's issue
  # activity, occupancy and registers (this build, then the base build where BASE=1).
  bins=$B; [ "${BASE:-0}" = 1 ] && [ -d /tmp/base/prebuilt/bin ] && bins="$B /tmp/base/prebuilt/bin"
  for spec in $INSTRUCTIONS; do
    args=$(spec_args "$spec"); sz=${spec%%:*}
    for b in $bins; do
      echo "== $spec, $(head -c 12 $b/../COMMIT 2>/dev/null || echo 'built here')"
      label=$spec; [ "$b" = "$B" ] || label="base $spec"
      LD_LIBRARY_PATH=$b/../lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} ncu --clock-control none --csv --print-units base \
        --launch-count 80 --metrics gpu__time_duration.sum,smsp__inst_executed.sum $b/lidarsgm_fuse $args \
        > "$OUT/instr_$sz.csv" 2> "$OUT/instr_$sz.err"
      python3 tools/ncu_call.py "$OUT/instr_$sz.csv" "$label" || tail -5 "$OUT/instr_$sz.err"
      LD_LIBRARY_PATH=$b/../lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} ncu --clock-control none -k regex:pathKernel \
        --launch-skip 1 --launch-count 1 --metrics smsp__issue_active.avg.pct_of_peak_sustained_active,sm__warps_active.avg.pct_of_peak_sustained_active,launch__registers_per_thread \
        $b/lidarsgm_fuse $args 2>&1 | grep -E "^ +[a-z_]+__" | awk '{print "   ", $1, $NF}'
    done
  done
fi
if [ "${WINDOWS_PAY:-0}" = 1 ]; then
  # Whether the disparity windows pay: kitti_best.yml as shipped (windows) against its searchWindow 0, on the whole
  # card and on 8 SMs (PAY_SMS: those counts instead), at KITTI size and 1280x720 (PAY_SIZES="1242x375 1280x720"),
  # margins PAY_WINDOWS (default "4 0"); the base build first where BASE=1 (its archive unpacked above).
  bins=$B; [ "${BASE:-0}" = 1 ] && [ -d /tmp/base/prebuilt/bin ] && bins="/tmp/base/prebuilt/bin $B"
  for n in ${PAY_SMS:-8}; do
    for b in $bins; do
      for sz in ${PAY_SIZES:-1242x375 1280x720}; do
        for sw in ${PAY_WINDOWS:-4 0}; do
          echo "== $([ "$b" = "$B" ] && echo 'this build' || echo base) $sz --search-window $sw"
          LD_LIBRARY_PATH=$b/../lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} $b/lidarsgm_fuse --kitti-frame testdata/kitti \
            --id 000002 --cuda --timing 30 --sm-count $n --params doc/params/kitti_best.yml --search-window $sw \
            $([ $sz = 1242x375 ] || echo --resize $sz) | grep -E "lidarsgm SDSGM \||StereoSGM 8 paths"
        done
      done
    done
  done
fi
if [ -n "${SM_PROFILE:-}" ] && command -v ncu >/dev/null; then
  # Time and warp instructions of each kernel of one KITTI-size SDSGM call on N SMs (a green context; SM_PROFILE:
  # "N[:margin[:params file]] ...", e.g. 8:4:doc/params/kitti_best.yml): ncu sees only the partition's SDSGM calls,
  # which the tool marks (--profile-from-start off).
  # (this build, then the base build where BASE=1)
  bins=$B; [ "${BASE:-0}" = 1 ] && [ -d /tmp/base/prebuilt/bin ] && bins="$B /tmp/base/prebuilt/bin"
  for spec in $SM_PROFILE; do
    IFS=: read -r n nw pf <<< "$spec"; tag=$(echo "$spec" | tr ':/.' '___')
    for b in $bins; do
      label="$n SMs, $spec"; [ "$b" = "$B" ] || { label="base $label"; tag=base_$tag; }
      LD_LIBRARY_PATH=$b/../lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} ncu --profile-from-start off --clock-control none \
        --csv --print-units base --metrics gpu__time_duration.sum,smsp__inst_executed.sum $b/lidarsgm_fuse \
        --kitti-frame testdata/kitti --id 000002 --cuda --timing 1 --sm-count $n ${pf:+--params $pf} \
        --search-window ${nw:-0} > "$OUT/sm_profile_$tag.csv" 2> "$OUT/sm_profile_$tag.err"
      python3 tools/ncu_call.py "$OUT/sm_profile_$tag.csv" "$label" || tail -5 "$OUT/sm_profile_$tag.err"
    done
  done
fi
if [ -n "${SM_PIPES:-}" ] && command -v ncu >/dev/null; then
  # What limits one kernel (STALL_KERNEL, default pathKernel) of a KITTI-size SDSGM call on N SMs (SM_PIPES, specs as
  # SM_PROFILE's): the busiest pipes and the largest stall reasons per issued instruction.
  for spec in $SM_PIPES; do
    IFS=: read -r n nw pf <<< "$spec"
    echo "== $n SMs, $spec: ${STALL_KERNEL:-pathKernel}, pipes (% of peak, active cycles) and stalls per issue"
    bash tools/ncu_pipes.sh "${STALL_KERNEL:-pathKernel}" $B/lidarsgm_fuse --kitti-frame testdata/kitti --id 000002 \
      --cuda --timing 1 --sm-count $n ${pf:+--params $pf} --search-window ${nw:-0}
  done
fi
if [ -n "${PROFILE_SIZES:-}" ] && command -v ncu >/dev/null; then
  # Per-kernel durations of the second SDSGM call at each WxH:disparities:paths of PROFILE_SIZES (the first call
  # includes module loading), e.g. PROFILE_SIZES="1242x375:128:8 1920x1080:256:8". With STALLS=1 also the warp
  # states, scheduler and memory statistics of one path kernel (skipping STALL_SKIP path kernels, default 9;
  # STALL_KERNEL: the kernel name's pattern, default pathKernel).
  for spec in $PROFILE_SIZES; do
    args=$(spec_args "$spec"); sz=$(tr ':/.' '___' <<< "$spec")
    echo "== $spec: kernels of one SDSGM call (the second), summed by name:"
    ncu --clock-control none --print-units base --metrics gpu__time_duration.sum --launch-count 80 \
      $B/lidarsgm_fuse $args 2>&1 | grep -E "^  [a-zA-Z_].*\(.*Context|gpu__time_duration" | paste - - \
      | sed -E 's/^ +(void )?//; s/\(anonymous namespace\):: *//; s/[<(].*gpu__time_duration.sum/ /' | awk '{sub(/^.*::/, "", $1); gsub(/,/, "", $3); print $1, $3 / 1000}' \
      > "$OUT/kernels_$sz.txt"
    # The second call: from its first census kernel (with windows every call has two, the coarse pass's second).
    nw=$(cut -d: -f4 <<< "$spec"); per=1; [ "${nw:-0}" -gt 0 ] && per=2
    awk -v a=$((per + 1)) -v b=$((2 * per)) '$1 ~ /censusKernel/ {c++} c >= a && c <= b' "$OUT/kernels_$sz.txt" \
      | awk '{t[$1]+=$2; n[$1]++} END {for (k in t) {printf "  %-36s %3d launches %10.1f us\n", k, n[k], t[k]; s+=t[k]} printf "  %-36s %23.1f us\n", "sum", s}' | sort -k4 -n -r
    if [ "${STALLS:-0}" = 1 ]; then
      ncu --clock-control none -k regex:${STALL_KERNEL:-pathKernel} --launch-skip $(( ${STALL_SKIP:-9} )) --launch-count 1 \
        --section SpeedOfLight --section Occupancy --section SchedulerStats --section WarpStateStats \
        --section MemoryWorkloadAnalysis $B/lidarsgm_fuse $args 2>&1 | grep -vE "^==PROF==|^ +-+$|^$" \
        | grep -E "pathKernel|Duration|Throughput|Occupancy|Warp Cycles|Stall|Issue|Eligible|Active Warps|Registers|L2 Hit|L1/TEX Hit|Mem Busy|Max Bandwidth|No Eligible|Issued Warp" | head -45
      echo "  stall reasons (warps stalled per issued instruction), largest first:"
      ncu --clock-control none -k regex:${STALL_KERNEL:-pathKernel} --launch-skip $(( ${STALL_SKIP:-9} )) --launch-count 1 \
        --metrics "regex:smsp__average_warps_issue_stalled_.*_per_issue_active\.ratio" $B/lidarsgm_fuse $args 2>&1 \
        | grep "stalled" | awk '{gsub(/,/, "", $NF); sub(/smsp__average_warps_issue_stalled_/, "", $1); print $NF, $1}' \
        | sort -g -r | head -8 | sed 's/^/    /'
    fi
  done
fi
