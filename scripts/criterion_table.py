#!/usr/bin/env python3
"""Turns `cargo bench` (criterion) output into a markdown table of medians, with growth
exponents for size series. Usage: cargo bench --bench statics | python3 scripts/criterion_table.py"""
import math
import re
import sys

UNITS = {"ns": 1e-9, "µs": 1e-6, "us": 1e-6, "ms": 1e-3, "s": 1.0}
rows = []
name = None
for line in sys.stdin:
    m = re.match(r"^(\S+/\S+)\s*(time:.*)?$", line.strip())
    if m and not line.startswith(" ") and "Benchmarking" not in line:
        name = m.group(1)
    t = re.search(r"time:\s+\[([\d.]+) (\S+) ([\d.]+) (\S+) ([\d.]+) (\S+)\]", line)
    if t and name:
        median = float(t.group(3)) * UNITS[t.group(4)]
        rows.append((name, median))
        name = None

print("| benchmark | median |")
print("|---|---|")
for n, v in rows:
    shown = f"{v * 1e3:.1f} ms" if v < 1 else f"{v:.2f} s"
    print(f"| {n} | {shown} |")

# Growth: consecutive entries of the same series whose last path part is a number.
series = {}
for n, v in rows:
    head, _, tail = n.rpartition("/")
    if tail.isdigit():
        series.setdefault(head, []).append((int(tail), v))
if series:
    print()
    print("| series | sizes | time ratio | growth exponent (overall) |")
    print("|---|---|---|---|")
    for head, pts in series.items():
        if len(pts) < 2:
            continue
        (n0, t0), (n1, t1) = pts[0], pts[-1]
        k = math.log(t1 / t0) / math.log(n1 / n0)
        print(f"| {head} | {n0} → {n1} | {t1 / t0:.0f}× | n^{k:.2f} |")
