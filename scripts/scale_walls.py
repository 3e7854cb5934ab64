#!/usr/bin/env python3
"""Running-bond walls from 1 000 to 100 000 bricks through `voussoir analyze`: wall time, peak
memory and the pipeline's own timings per size, and the growth exponent between sizes (issue #24).

Run by hand, not in CI (the largest wall takes about two minutes and 5 GB):

    cargo build --release
    python3 scripts/scale_walls.py [path/to/voussoir] [--max BRICKS]

Each size is one process (`builtin:wall?courses=C&bricks=B`, 0.4 × 0.2 × 0.1 m bricks on one
support slab, one connected component); its peak resident memory comes from the kernel's
accounting of that child alone (`os.wait4`). Standard library only; writes nothing.
"""

import math
import os
import re
import subprocess
import sys
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
# (courses, bricks): about 1 000, 4 000, 10 000, 50 000 and 100 000 bricks.
SIZES = [(20, 50), (40, 100), (100, 100), (100, 500), (200, 500)]
TIMINGS = re.compile(r"time: validate ([\d.]+) ms, detect ([\d.]+) ms, assemble ([\d.]+) ms, solve ([\d.]+) ms")
SCENE = re.compile(r"(\d+) blocks .*?, (\d+) interfaces")


def run(binary, courses, bricks):
    """One `analyze` process: (blocks, interfaces, wall seconds, peak MB, [validate, detect,
    assemble, solve] seconds, verdict line)."""
    spec = f"builtin:wall?courses={courses}&bricks={bricks}"
    start = time.perf_counter()
    child = subprocess.Popen([binary, "analyze", spec], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) not in (0, 1):
        sys.exit(f"{spec}: voussoir failed:\n{out}")
    timings = [float(v) / 1e3 for v in TIMINGS.search(out).groups()]
    blocks, interfaces = (int(v) for v in SCENE.search(out).groups())
    return blocks, interfaces, seconds, usage.ru_maxrss / 1024.0, timings, out.splitlines()[0]


def main():
    args = sys.argv[1:]
    limit = 100_000
    if "--max" in args:
        i = args.index("--max")
        limit = int(args[i + 1])
        del args[i : i + 2]
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    binary = args[0] if args else os.path.join(target, "release", "voussoir")
    print(f"{'bricks':>8} {'interfaces':>10} {'wall s':>8} {'peak MB':>8} {'validate':>8} {'detect':>7} "
          f"{'assemble':>8} {'solve':>7}  growth (time, memory) since the previous size")
    prev = None
    for courses, bricks in SIZES:
        if courses * bricks > limit:
            break
        blocks, interfaces, seconds, mb, (v, d, a, s), verdict = run(binary, courses, bricks)
        growth = ""
        if prev:
            k = math.log(blocks / prev[0])
            growth = f"n^{math.log(seconds / prev[1]) / k:.2f}, n^{math.log(mb / prev[2]) / k:.2f}"
        print(f"{blocks:>8} {interfaces:>10} {seconds:>8.2f} {mb:>8.0f} {v:>8.2f} {d:>7.2f} {a:>8.2f} {s:>7.2f}  {growth}")
        if not verdict.startswith("STANDS"):
            print(f"  (verdict: {verdict})")
        prev = (blocks, seconds, mb)


if __name__ == "__main__":
    main()
