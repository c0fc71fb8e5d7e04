#!/usr/bin/env python3
"""Metrics per kernel of one pipeline call, from an `ncu --csv --print-units base` run (tools/device_check.sh,
DRAM_SIZES and INSTRUCTIONS). The call is the second one in the trace (the first includes module loading): the kernels
from the second call's first censusKernel up to the next call's (with disparity windows every call has two, the
coarse pass's second). Prints, for whichever of them the run measured, each kernel's DRAM bytes read and written, time
and warp instructions executed, and their sums; with instructions, last, the line
`LABEL aggregation warp instructions per call: N`, N summed over the aggregation's kernels (src_cuda/aggregation.cu;
with windows, the coarse pass's path kernel included).
Usage: tools/ncu_call.py FILE.csv LABEL"""
import csv
import sys

COLUMNS = [  # metric, heading, scale
    ("dram__bytes_read.sum", "read GB", 1e-9),
    ("dram__bytes_write.sum", "write GB", 1e-9),
    ("gpu__time_duration.sum", "time us", 1e-3),
    ("smsp__inst_executed.sum", "warp instr M", 1e-6),
]
AGGREGATION = ("pathKernel", "factsKernel", "windowPathKernel", "packedWindowPathKernel", "zeroWindowsKernel",
               "windowCostsKernel")


def main(path, label):
    kernels = {}   # ID -> (name, {metric: value})
    order = []
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if len(r) > 10]
    head = rows[0]
    col = {k: head.index(k) for k in ("ID", "Kernel Name", "Metric Name", "Metric Value")}
    for r in rows[1:]:
        kid = r[col["ID"]]
        if kid not in kernels:
            name = r[col["Kernel Name"]].split("(")[0].split("<")[0].split("::")[-1].replace("void ", "").strip()
            kernels[kid] = (name, {})
            order.append(kid)
        try:
            kernels[kid][1][r[col["Metric Name"]]] = float(r[col["Metric Value"]].replace(",", ""))
        except ValueError:
            pass
    census = [i for i, kid in enumerate(order) if kernels[kid][0].startswith("censusKernel")]
    # A windowed call (its windows' kernel) has two census kernels.
    per = 2 if any(kernels[kid][0] == "windowsKernel" for kid in order) else 1
    if len(census) < 2 * per:
        print(f"{label}: fewer than two calls in the trace")
        return 1
    end = census[2 * per] if len(census) > 2 * per else len(order)
    call = [kernels[kid] for kid in order[census[per]:end]]
    cols = [c for c in COLUMNS if any(c[0] in m for _, m in call)]
    print(f"== {label}: one call (the second), per kernel")
    print(f"  {'kernel':<24}" + "".join(f" {h:>12}" for _, h, _ in cols))
    for name, m in call:
        print(f"  {name:<24}" + "".join(f" {m.get(k, 0.0) * s:12.3f}" for k, _, s in cols))
    print(f"  {'sum':<24}" + "".join(f" {sum(m.get(k, 0.0) for _, m in call) * s:12.3f}" for k, _, s in cols))
    if any(k == "smsp__inst_executed.sum" for k, _, _ in cols):
        agg = sum(m.get("smsp__inst_executed.sum", 0.0) for n, m in call if n.startswith(AGGREGATION))
        print(f"{label} aggregation warp instructions per call: {int(agg)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
