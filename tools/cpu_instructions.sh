#!/usr/bin/env bash
# Rewrites doc/benchmarks/cpu_instructions.txt: the instructions of one compute() call at 1 thread on KITTI 000002
# through cv2, counted by callgrind (valgrind), so the figures are exact and the same on every machine with the same
# build: a process of 2 calls minus a process of 1 call (tools/cpu_instructions.py), for the create() defaults,
# doc/params/kitti_best.yml as the file sets it and with searchWindow 0, and cv::StereoSGBM MODE_SGBM_3WAY counted the
# same way. Then, per stage, the instructions of that call (inclusive counts of the stage functions, the same
# difference). Needs valgrind (apt install valgrind).
#   tools/cpu_instructions.sh [OpenCV build dir, default ~/.cache/lidarsgm/build-cuda90] [configurations]
# CONFIGS (or the second argument): a subset of "3way defaults best best_w0" (default: all); OUT=- prints instead of
# writing the file.
set -eo pipefail
cd "$(dirname "$0")/.."
B=${1:-$HOME/.cache/lidarsgm/build-cuda90}
CONFIGS=${2:-${CONFIGS:-3way defaults best best_w0}}
PY=python3
for p in "$B/../pyenv-"*/bin/python; do [ -x "$p" ] && PY=$p; done
command -v valgrind > /dev/null || { echo "cpu_instructions.sh: valgrind is missing (apt install valgrind)" >&2; exit 2; }
OUT=${OUT:-doc/benchmarks/cpu_instructions.txt}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
C=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD -- src include 2>/dev/null || echo " + uncommitted changes")

count() {   # count CONFIG CALLS: callgrind's total, the per-function inclusive table in $work/CONFIG.CALLS.txt
  PYTHONPATH="$B/python_loader" OPENCV_FOR_THREADS_NUM=1 OPENBLAS_NUM_THREADS=1 \
    valgrind --tool=callgrind --callgrind-out-file="$work/$1.$2.out" "$PY" tools/cpu_instructions.py "$1" "$2" \
    > "$work/$1.$2.log" 2>&1 || { cat "$work/$1.$2.log" >&2; exit 1; }
  callgrind_annotate --inclusive=yes --threshold=100 "$work/$1.$2.out" 2>/dev/null > "$work/$1.$2.txt"
  sed -n 's/.*Collected : //p' "$work/$1.$2.log"
}

report() {
  echo "# $(date -u +%Y-%m-%d), commit $C, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), valgrind $(valgrind --version | sed 's/valgrind-//')"
  echo "# Command: tools/cpu_instructions.sh (callgrind, 1 thread, KITTI 000002 through cv2: 2 calls minus 1 call)"
  echo "| configuration | instructions per call | / MODE_SGBM_3WAY |"
  echo "| --- | --- | --- |"
  local ref=""
  for c in $CONFIGS; do
    a=$(count "$c" 1); b=$(count "$c" 2)
    n=$((b - a))
    [ "$c" = 3way ] && ref=$n
    case $c in
      3way) name="MODE_SGBM_3WAY (128 disparities, the tool's)";;
      defaults) name="create() defaults (SDSGM, 8 paths)";;
      best) name="kitti_best.yml as the file sets it";;
      best_w0) name="kitti_best.yml, searchWindow 0";;
      best_w4) name="kitti_best.yml, searchWindow 4";;
    esac
    if [ -n "$ref" ]; then
      awk -v n="$n" -v r="$ref" -v s="$name" 'BEGIN { printf "| %s | %\047.0f | %.3f |\n", s, n, n / r }'
    else
      awk -v n="$n" -v s="$name" 'BEGIN { printf "| %s | %\047.0f | |\n", s, n }'
    fi
  done
  echo
  echo "Per stage (inclusive, millions of instructions per call; the 2-call process minus the 1-call one):"
  for c in $CONFIGS; do
    echo "## $c"
    # Functions whose inclusive count grew by at least 1 M between the processes, lidarsgm's stages and OpenCV's
    # stereo code only (the interpreter's and the loader's lines differ by a call's worth of bookkeeping).
    "$PY" - "$work/$c.1.txt" "$work/$c.2.txt" <<'PYEOF'
import re, sys
def table(path):
    t = {}
    for line in open(path):
        m = re.match(r"\s*([\d,]+)\s+\([^)]*\)\s+[^:]*:(.*?)(\s+\[.*\])?$", line)
        if m:   # with debug information a function is listed once per source file of its lines: the largest
            k = m.group(2)
            t[k] = max(t.get(k, 0), int(m.group(1).replace(",", "")))
    return t
a, b = table(sys.argv[1]), table(sys.argv[2])
keep = re.compile(r"lidarsgm::detail::|SGBM3Way|calcPixelCostBT|StereoSGBMImpl::compute|StereoLidarSGMImpl::compute")
rows = []
for k, v in b.items():
    d = (v - a.get(k, 0)) / 1e6
    if d >= 1 and keep.search(k):
        name = k
        for x in ("cv::lidarsgm::detail::", "opt_AVX2::", "opt_SSE4_1::", "(anonymous namespace)::", "cv::"):
            name = name.replace(x, "")
        while True:   # argument lists out, lambdas' kept short
            n = re.sub(r"\([^()]*\)", "()", name)
            if n == name:
                break
            name = n
        rows.append((d, name))
for d, name in sorted(rows, reverse=True)[:40]:
    print("%9.1f  %s" % (d, name))
PYEOF
  done
}

if [ "$OUT" = - ]; then
  report
else
  report > "$OUT"
  cat "$OUT"
  echo "wrote $OUT"
fi
