#!/usr/bin/env bash
# What limits one kernel of a lidarsgm_fuse call (the call's part that the tool marks with cuProfilerStart/Stop, its
# first launch of the kernel): the busiest pipes (% of peak), the largest stall reasons per issued instruction, the
# warps a scheduler holds and the kernel's time, largest first. For tools/device_check.sh (SM_PIPES) and
# tools/device_variants.sh (PIPES=1); run on the device machine.
#   tools/ncu_pipes.sh KERNEL_REGEX path/to/lidarsgm_fuse [its arguments...]
set -eo pipefail
kernel=$1; shift
ncu --profile-from-start off --clock-control none -k "regex:$kernel" --launch-count 1 \
  --metrics "regex:sm__pipe_.*_cycles_active\.avg\.pct_of_peak_sustained_active,regex:sm__inst_executed_pipe_.*\.avg\.pct_of_peak_sustained_active,regex:smsp__average_warps_issue_stalled_.*_per_issue_active\.ratio,smsp__issue_active.avg.pct_of_peak_sustained_active,smsp__warps_active.avg.per_cycle_active,gpu__time_duration.sum" \
  "$@" 2>&1 | grep -E "^ +[a-z_]+__" | awk '{gsub(/,/, "", $NF); print $NF, $1}' \
  | sort -g -r | awk '$1 > 0.5' | head -24 | sed 's/^/    /'
