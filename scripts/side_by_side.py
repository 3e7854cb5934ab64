"""voussoir beside compas_cra on the Armadillo and the dome, in one run (issue #24).

Run by hand, not in CI: `scripts/side_by_side [path/to/voussoir]` makes the virtual
environment (compas_cra and clarabel from PyPI) and calls this file with its Python.

Per file, the same penalty QP of the seed paper (compas_cra's `rbe_problem`: an 8-sided friction
pyramid, mu = 0.84, w_tension = 1e6, on the interfaces stored in the file):
- compas_cra: `rbe_solve_native` (its in-process IPOPT), the solve alone;
- Clarabel from Python: the same QP (compas_cra's matrices, bounds and weights) given to clarabel,
  the solve alone;
- voussoir: the whole `voussoir analyze FILE --mu 0.84` process (load, detect its own interfaces,
  solve, report), median of 5 runs.
Prints the times and the ratios; writes nothing.
"""

import os
import statistics
import subprocess
import sys
import time

import clarabel
import numpy as np
from compas.data import json_load
from compas_cra.equilibrium import rbe_solve_native
from compas_cra.equilibrium.cra_nlp import rbe_problem
from scipy import sparse

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
FILES = {
    "armadillo": "assets/compas/compas_cra/armadillo_cra.json",
    "dome": "assets/compas/compas_assembly/dome_assembly.json",
}
MU = 0.84


def ipopt_seconds(path):
    assembly = json_load(path)
    start = time.perf_counter()
    rbe_solve_native(assembly, mu=MU, density=1.0, verbose=False)
    return time.perf_counter() - start


def clarabel_seconds(path):
    """compas_cra's RBE problem as a conic QP: equilibrium rows (zero cone), friction rows and the
    bounds fn+, fn- >= 0 (nonnegative cone), objective sum(w x^2) = 1/2 x' (2W) x."""
    problem, _ = rbe_problem(json_load(path), mu=MU, density=1.0)
    n = problem.n
    jac = sparse.csr_matrix((problem.jacobian(problem.x0), (problem.jac_rows, problem.jac_cols)),
                            shape=(len(problem.g_l), n))
    equal = problem.g_l == problem.g_u
    upper = ~equal & np.isfinite(problem.g_u)
    lower_bounded = np.flatnonzero(np.isfinite(problem.x_l))
    bounds = sparse.csr_matrix((-np.ones(len(lower_bounded)), (np.arange(len(lower_bounded)), lower_bounded)),
                               shape=(len(lower_bounded), n))
    a = sparse.vstack([jac[equal], jac[upper], bounds]).tocsc()
    b = np.concatenate([problem.g_u[equal], problem.g_u[upper], -problem.x_l[lower_bounded]])
    hess = problem.hessian(problem.x0, 1.0, None)
    p = sparse.csc_matrix((hess, (problem.hess_rows, problem.hess_cols)), shape=(n, n))
    cones = [clarabel.ZeroConeT(int(equal.sum())), clarabel.NonnegativeConeT(int(upper.sum()) + len(lower_bounded))]
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    start = time.perf_counter()
    solver = clarabel.DefaultSolver(p, np.zeros(n), a, b, cones, settings)
    solution = solver.solve()
    seconds = time.perf_counter() - start
    if str(solution.status) not in ("Solved", "SolverStatus.Solved"):
        raise RuntimeError(f"clarabel: {solution.status}")
    return seconds


def voussoir_seconds(binary, path):
    times = []
    for _ in range(5):
        start = time.perf_counter()
        done = subprocess.run([binary, "analyze", path, "--mu", str(MU)], capture_output=True)
        times.append(time.perf_counter() - start)
        if done.returncode not in (0, 1):
            raise RuntimeError(done.stderr.decode())
    return statistics.median(times)


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target", "release", "voussoir")
    print(f"{'design':10} {'compas_cra IPOPT':>17} {'Clarabel (Python)':>18} {'voussoir process':>17}"
          f" {'× IPOPT':>8} {'× Clarabel':>11}")
    for name, rel in FILES.items():
        path = os.path.join(ROOT, rel)
        ipopt = ipopt_seconds(path)
        cla = clarabel_seconds(path)
        vou = voussoir_seconds(binary, path)
        print(f"{name:10} {ipopt:16.3f}s {cla:17.3f}s {vou:16.3f}s {ipopt / vou:8.1f} {cla / vou:11.1f}")


if __name__ == "__main__":
    main()
