#!/usr/bin/env bash
# Where one kernel of a lidarsgm_fuse call (the part the tool marks with cuProfilerStart/Stop, the kernel's first
# launch there) stalls, SASS instruction by instruction: ncu's SourceCounters section, then tools/ncu_source.py's
# totals and top instructions by warp stall samples. For tools/device_variants.sh (SOURCE=1); run on the device machine.
#   tools/ncu_source.sh KERNEL_REGEX OUT_PREFIX path/to/lidarsgm_fuse [its arguments...]
set -eo pipefail
kernel=$1; prefix=$2; shift 2
ncu --profile-from-start off --clock-control none -k "regex:$kernel" --launch-count 1 --section SourceCounters \
  --section WarpStateStats -f -o "$prefix" "$@" > "$prefix.log" 2>&1 || { tail -5 "$prefix.log"; exit 1; }
ncu --import "$prefix.ncu-rep" --page source --csv --print-source sass > "$prefix.csv" 2> "$prefix.err" ||
  { tail -5 "$prefix.err"; exit 1; }
python3 "$(dirname "$0")/ncu_source.py" "$prefix.csv" "${TOP:-30}"
