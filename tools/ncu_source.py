#!/usr/bin/env python3
"""Where one kernel's warps stall, instruction by instruction: reads `ncu --import REPORT --page source --csv
--print-source sass` (a report with the SourceCounters section) and prints the kernel's totals and its TOP SASS
instructions by warp stall samples, with their share of all samples and their executions, and the stall reasons'
shares of all samples (the stall_* columns: the kernel's bound in one line; tools/ncu_source.sh).
Columns are found by their heading's words, so that ncu versions that rename a few still work; if a needed one is
missing, the headings are printed.
Usage: tools/ncu_source.py FILE.csv [TOP]"""
import csv
import sys


def find(head, *words):
    for i, h in enumerate(head):
        if all(w.lower() in h.lower() for w in words):
            return i
    return None


def number(s):
    try:
        return float(s.replace(",", ""))
    except ValueError:
        return 0.0


def main(path, top):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    start = next((i for i, r in enumerate(rows) if find(r, "source") is not None and find(r, "address") is not None),
                 None)
    if start is None:
        print("no source table in", path)
        for r in rows[:5]:
            print("  ", r[:12])
        return 1
    head = rows[start]
    src, samples = find(head, "source"), find(head, "stall sampling", "all")
    if samples is None:
        samples = find(head, "sampling")
    executed = find(head, "instructions executed")
    if samples is None or executed is None:
        print("headings:", head)
        return 1
    body = [r for r in rows[start + 1:] if len(r) == len(head)]
    total = sum(number(r[samples]) for r in body) or 1.0
    inst = sum(number(r[executed]) for r in body)
    print("    %d SASS instructions, %.1f M warp instructions executed, %d stall samples" %
          (len(body), inst * 1e-6, total))
    # The reasons: columns stall_<reason> (ncu also has "<reason> (Not Issued)", a part of them).
    reasons = [(h, i) for i, h in enumerate(head) if h.startswith("stall_") and "not issued" not in h.lower()]
    if reasons:
        shares = sorted(((sum(number(r[i]) for r in body), h[6:]) for h, i in reasons), reverse=True)
        print("    stall reasons (% of samples): " +
              ", ".join("%s %.1f" % (name, 100 * v / total) for v, name in shares[:6] if v > 0))
    print("    % samples   executed  instruction")
    for r in sorted(body, key=lambda r: -number(r[samples]))[:top]:
        print("    %6.2f %12d  %s" % (100 * number(r[samples]) / total, number(r[executed]), r[src].strip()[:90]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 30))
