#!/usr/bin/env python3
"""DRAM bytes and time per kernel of one pipeline call, from an `ncu --csv --print-units base` run with the metrics
dram__bytes_read.sum, dram__bytes_write.sum and gpu__time_duration.sum (tools/device_check.sh, DRAM_SIZES).
The call is the second one in the trace (the first includes module loading): the kernels from the second censusKernel
up to the next. Usage: ncu_call_bytes.py FILE.csv LABEL"""
import csv
import sys


def main(path, label):
    kernels = {}   # ID -> [name, read, write, ns]
    order = []
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if len(r) > 10]
    head = rows[0]
    col = {k: head.index(k) for k in ("ID", "Kernel Name", "Metric Name", "Metric Value")}
    for r in rows[1:]:
        kid = r[col["ID"]]
        if kid not in kernels:
            name = r[col["Kernel Name"]].split("(")[0].split("<")[0].split("::")[-1].replace("void ", "").strip()
            kernels[kid] = [name, 0.0, 0.0, 0.0]
            order.append(kid)
        v = float(r[col["Metric Value"]].replace(",", ""))
        m = r[col["Metric Name"]]
        k = kernels[kid]
        if m == "dram__bytes_read.sum":
            k[1] += v
        elif m == "dram__bytes_write.sum":
            k[2] += v
        elif m == "gpu__time_duration.sum":
            k[3] += v
    census = [i for i, kid in enumerate(order) if kernels[kid][0].startswith("censusKernel")]
    if len(census) < 2:
        print(f"{label}: fewer than two calls in the trace")
        return 1
    end = census[2] if len(census) > 2 else len(order)
    call = [kernels[kid] for kid in order[census[1]:end]]
    print(f"== {label}: DRAM bytes of one call (the second), per kernel")
    print(f"  {'kernel':<24} {'read GB':>9} {'write GB':>9} {'time us':>10}")
    tr = tw = tt = 0.0
    for name, rd, wr, ns in call:
        print(f"  {name:<24} {rd / 1e9:9.3f} {wr / 1e9:9.3f} {ns / 1e3:10.1f}")
        tr, tw, tt = tr + rd, tw + wr, tt + ns
    print(f"  {'sum':<24} {tr / 1e9:9.3f} {tw / 1e9:9.3f} {tt / 1e3:10.1f}   read + write {(tr + tw) / 1e9:.2f} GB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
