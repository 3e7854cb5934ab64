"""The exact engine's cost over an ensemble of collapsing arches, not one draw.

A collapse is chaotic: a change of round-off alone (the same equations, rounded differently)
moves one dropped arch's engine time by ×0.7 to ×2.4, and the sum over 39 arches by a few per cent
(docs/benchmarks.md, 2026-11-29 afternoon). A change to the engine's steps is therefore judged
by sums over many arches, each run to 2 s as `voussoir drop ... --engine exact` runs it:

- `drop` (default): the semicircular arch `builtin:arch?n=N&t=T`, N 9…21 × t/R 0.06, 0.07, 0.08
  (39 arches);
- `drop2`: N 9…23 × t/R 0.065, 0.075, 0.085 (45 arches), a second draw of the same kind;
- `shake`: six standing arches under El Centro's first 10 s (`voussoir shake --record
  builtin:elcentro`).

Prints, per ensemble, the sum of the engine's wall time (`dynamic.wall_s` of the JSON report),
its interior-point solves, its failed and unsettled steps, and how many runs ended at rest. By
hand, after `cargo build --release`:

    python3 scripts/collapse_ensemble.py [drop drop2 shake] [--bin target/release/voussoir]
"""

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

ENSEMBLES = {
    "drop": [(n, t) for n in range(9, 22) for t in (0.06, 0.07, 0.08)],
    "drop2": [(n, t) for n in range(9, 24) for t in (0.065, 0.075, 0.085)],
    "shake": [(15, 0.15), (13, 0.14), (17, 0.15), (11, 0.13), (15, 0.14), (19, 0.16)],
}


def run(binary, name, n, t, out):
    scene = f"builtin:arch?n={n}&t={t}"
    if name == "shake":
        args = ["shake", scene, "--record", "builtin:elcentro", "--engine", "exact", "--duration", "10"]
    else:
        args = ["drop", scene, "--engine", "exact"]
    out.unlink(missing_ok=True)
    # Exit 1 is a verdict (the design falls); 2 and above, or no report, is a failed run.
    done = subprocess.run([binary, *args, "--json", str(out)], cwd=ROOT, capture_output=True, text=True)
    if done.returncode > 1 or not out.exists():
        sys.exit(f"{binary} {' '.join(args)}: exit {done.returncode}: {done.stderr.strip()}")
    report = json.loads(out.read_text())
    return next(found(report, "dynamic")) if name != "shake" else report


def found(o, key):
    """Every value under `key` in a JSON tree, depth first (a shake's report nests its runs)."""
    if isinstance(o, dict):
        for k, v in o.items():
            if k == key:
                yield v
            yield from found(v, key)
    elif isinstance(o, list):
        for v in o:
            yield from found(v, key)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("ensembles", nargs="*", default=["drop"], choices=sorted(ENSEMBLES))
    parser.add_argument("--bin", default=str(ROOT / "target" / "release" / "voussoir"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "report.json"
        for name in args.ensembles:
            wall = solves = failed = unsettled = rest = 0
            for n, t in ENSEMBLES[name]:
                report = run(args.bin, name, n, t, out)
                wall += next(found(report, "wall_s"))
                solves += next(found(report, "solves"))
                failed += next(found(report, "failed_steps"))
                unsettled += next(found(report, "unsettled_steps"))
                rest += bool(next(found(report, "at_rest"), False))
            runs = len(ENSEMBLES[name])
            print(f"{name}: {runs} arches, engine {wall:.3f} s, {solves} solves, {failed} failed and "
                  f"{unsettled} unsettled steps, {rest}/{runs} at rest")
    return 0


if __name__ == "__main__":
    sys.exit(main())
