"""The Armadillo's load factor as a simplex LP (HiGHS), cold and warm-started across directions,
beside voussoir's interior point: does a warm-started simplex make the worst-direction sweep
fast (issues #21 and #24)? A measurement, not a test: run by hand through
scripts/simplex_load_factor (its own venv: highspy from PyPI and the release wheel of this
checkout); results in docs/benchmarks.md.

The LP is built independently of voussoir's solver, from its detected interfaces (points, frames)
and the scene's block meshes: each force point's force is a non-negative combination of the 8
edges of voussoir's outer pyramid (faces |c_u|, |c_v| <= mu c_n and |c_u +- c_v| <= sqrt2 mu c_n,
so the edges lie at 22.5 deg + k 45 deg, at mu / cos 22.5 deg), which is the pyramid8 model in
generator form: 6 equilibrium rows per free block (force, and moment about its centroid),
8 columns per point, and lambda's column (1 g horizontally along the direction, on each free
block's volume; the weight is the right-hand side). lambda* = max lambda.
"""

import argparse
import json
import time
from pathlib import Path

import highspy
import numpy as np
import scipy.sparse as sp

import voussoir

ROOT = Path(__file__).resolve().parents[1]


def block_mass_properties(scene):
    """Volume and centroid of every block (divergence theorem over fan triangles)."""
    volumes, centroids = [], []
    for block in json.loads(scene.to_json())["blocks"]:
        v = np.asarray(block["vertices"], dtype=float)
        six_v, moment = 0.0, np.zeros(3)
        for face in block["faces"]:
            for i in range(1, len(face) - 1):
                a, b, c = v[face[0]], v[face[i]], v[face[i + 1]]
                d = float(np.dot(a, np.cross(b, c)))
                six_v += d
                moment += d * (a + b + c) / 4.0
        volumes.append(six_v / 6.0)
        centroids.append(moment / six_v)
    return np.array(volumes), np.array(centroids)


def generator_lp(scene, mu):
    """A (6 rows per free block x 8 columns per point), the free blocks' volumes and rows."""
    analysis = voussoir.analyze(scene, mu=mu)
    support = np.array(analysis.block_is_support)
    free = np.flatnonzero(~support)
    row_of = {int(b): k for k, b in enumerate(free)}
    volumes, centroids = block_mass_properties(scene)
    angles = np.pi / 8 + np.arange(8) * np.pi / 4
    reach = mu / np.cos(np.pi / 8)
    rows, cols, vals = [], [], []
    col = 0
    for p, i in enumerate(analysis.point_interface):
        a, b = analysis.interface_blocks[i]
        n, u, v = analysis.interface_normal[i], analysis.interface_u[i], analysis.interface_v[i]
        for angle in angles:
            f = n + reach * (np.cos(angle) * u + np.sin(angle) * v)  # acts on b, -f on a
            for block, sign in ((b, 1.0), (a, -1.0)):
                if block < 0 or support[block]:
                    continue
                r = row_of[int(block)]
                wrench = np.concatenate([sign * f, np.cross(analysis.points[p] - centroids[block], sign * f)])
                rows.extend(range(6 * r, 6 * r + 6))
                cols.extend([col] * 6)
                vals.extend(wrench)
            col += 1
    a = sp.csc_matrix((vals, (rows, cols)), shape=(6 * len(free), col))
    # In units of the mean free volume (lambda* does not change), so that HiGHS's absolute
    # tolerances mean the same on every model.
    return a, volumes[free] / volumes[free].mean()


def live_column(volumes, degrees):
    column = np.zeros(6 * len(volumes))
    column[0::6] = volumes * np.cos(np.radians(degrees))
    column[1::6] = volumes * np.sin(np.radians(degrees))
    return column


def highs_model(a, volumes, degrees, solver):
    """max lambda s.t. A alpha + lambda L = -D (D the weight), alpha >= 0, lambda free."""
    m, n = a.shape
    full = sp.hstack([a, sp.csc_matrix(live_column(volumes, degrees).reshape(-1, 1))]).tocsc()
    dead = np.zeros(m)
    dead[2::6] = -volumes
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = n + 1, m
    lp.col_cost_ = np.r_[np.zeros(n), -1.0]
    lp.col_lower_ = np.r_[np.zeros(n), -highspy.kHighsInf]
    lp.col_upper_ = np.full(n + 1, highspy.kHighsInf)
    lp.row_lower_ = lp.row_upper_ = -dead
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = full.indptr, full.indices, full.data
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("solver", solver)
    for tolerance in ("primal_feasibility_tolerance", "dual_feasibility_tolerance"):
        h.setOptionValue(tolerance, 1e-10)
    h.passModel(lp)
    return h


def run(h):
    start = time.perf_counter()
    h.run()
    seconds = time.perf_counter() - start
    info = h.getInfo()
    assert h.getModelStatus() == highspy.HighsModelStatus.kOptimal, h.modelStatusToString(h.getModelStatus())
    return -info.objective_function_value, seconds, info


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default=str(ROOT / "assets/compas/compas_cra/armadillo_cra.json"))
    parser.add_argument("--mu", type=float, default=0.84)
    parser.add_argument("--step", type=float, default=10.0, help="degrees between the warm-started directions")
    parser.add_argument("--directions", type=int, default=9, help="warm-started directions after 0 deg")
    args = parser.parse_args()
    scene = voussoir.Scene.from_file(args.file)
    a, volumes = generator_lp(scene, args.mu)
    print(f"{args.file}: LP of {a.shape[0]} rows x {a.shape[1] + 1} columns, {a.nnz} non-zeros; HiGHS {highspy.Highs().version()}")

    def voussoir_lf(degrees):
        start = time.perf_counter()
        report = voussoir.load_factor(scene, direction=degrees, mu=args.mu)
        return report["robustness"]["load_factor"], time.perf_counter() - start, report["robustness"]["iterations"]

    lam, seconds, iterations = voussoir_lf(0.0)
    print(f"0 deg  voussoir (interior point, whole call): lambda* {lam:.9f}  {seconds:7.3f} s  {iterations} iterations")
    h = highs_model(a, volumes, 0.0, "ipm")
    h.setOptionValue("run_crossover", "off")
    lam_h, seconds, info = run(h)
    print(f"0 deg  HiGHS IPX (no crossover):             lambda* {lam_h:.9f}  {seconds:7.3f} s  {info.ipm_iteration_count} iterations")
    h = highs_model(a, volumes, 0.0, "simplex")
    lam_h, seconds, info = run(h)
    print(f"0 deg  HiGHS dual simplex, cold:             lambda* {lam_h:.9f}  {seconds:7.3f} s  {info.simplex_iteration_count} pivots")
    # Warm starts: only lambda's column changes with the direction; HiGHS keeps its basis.
    m, n = a.shape
    for k in range(1, args.directions + 1):
        degrees = k * args.step
        column = live_column(volumes, degrees)
        for r in range(m):
            if r % 6 in (0, 1):
                h.changeCoeff(r, n, column[r])
        lam_h, seconds, info = run(h)
        lam, v_seconds, _ = voussoir_lf(degrees)
        pivots = info.simplex_iteration_count  # this run's
        print(f"{degrees:5.1f} deg  HiGHS simplex warm from {degrees - args.step:.1f}: lambda* {lam_h:.9f}  {seconds:7.3f} s  "
              f"{pivots} pivots | voussoir {lam:.9f}  {v_seconds:.3f} s  (rel. diff {abs(lam_h - lam) / lam:.1e})")


if __name__ == "__main__":
    main()
