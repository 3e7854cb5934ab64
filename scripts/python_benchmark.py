"""The Armadillo from Python, in one process and one run: voussoir's package (Scene.from_compas +
analyze + write_forces, end to end) against compas_cra's rbe_solve (IPOPT) on the same compas
object. A benchmark, not a test: run by hand (scripts/python_benchmark makes its environment and
the release wheel), results in docs/benchmarks.md.

Both solve the RBE penalty problem of the seed paper with μ = 0.84 and an 8-sided friction
pyramid; compas_cra on the interfaces stored in the file, voussoir on the ones it detects.
Prints the medians of --runs runs each and their ratio.
"""

import argparse
import statistics
import time
from pathlib import Path

from compas.data import json_load

import voussoir

ROOT = Path(__file__).resolve().parents[1]
MU = 0.84


def time_voussoir(path, runs):
    seconds, solver = [], []
    for _ in range(runs):
        assembly = json_load(str(path))  # not timed: the user's object exists already
        start = time.perf_counter()
        result = voussoir.analyze(voussoir.Scene.from_compas(assembly), mu=MU)
        result.write_forces(assembly)
        seconds.append(time.perf_counter() - start)
        solver.append(result.timings["solve"])
    return statistics.median(seconds), statistics.median(solver), result


def time_rbe(path, runs):
    from compas_cra.equilibrium import rbe_solve

    seconds = []
    for _ in range(runs):
        assembly = json_load(str(path))
        start = time.perf_counter()
        rbe_solve(assembly, mu=MU, density=1.0, verbose=False)
        seconds.append(time.perf_counter() - start)
    tension = sum(
        f["c_nn"] for e in assembly.graph.edges() for i in assembly.graph.edge_attribute(e, "interfaces") for f in i.forces
    )
    compression = sum(
        f["c_np"] for e in assembly.graph.edges() for i in assembly.graph.edge_attribute(e, "interfaces") for f in i.forces
    )
    return statistics.median(seconds), tension / compression


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default=str(ROOT / "assets/compas/compas_cra/armadillo_cra.json"))
    parser.add_argument("--runs", type=int, default=5, help="voussoir runs (median)")
    parser.add_argument("--rbe-runs", type=int, default=3, help="rbe_solve runs (median)")
    args = parser.parse_args()
    v_total, v_solve, result = time_voussoir(args.file, args.runs)
    r_total, r_tension = time_rbe(args.file, args.rbe_runs)
    print(f"file: {args.file}")
    print(f"voussoir {voussoir.__version__}: from_compas + analyze + write_forces {v_total:.3f} s "
          f"(solve {v_solve:.3f} s), median of {args.runs}; verdict {result.verdict}, "
          f"{len(result.block_names)} blocks, {len(result.interface_blocks)} interfaces")
    print(f"compas_cra rbe_solve: {r_total:.3f} s, median of {args.rbe_runs}; tension / compression {r_tension:.2e}")
    print(f"ratio (rbe_solve / voussoir end to end): {r_total / v_total:.1f}x")


if __name__ == "__main__":
    main()
