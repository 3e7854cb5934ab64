"""Is a load factor's collapse mechanism unique? The Armadillo's load-factor LP (scripts/
simplex_load_factor.py's generator form, built independently of voussoir's solver) solved by
HiGHS's interior point without and with crossover: the rank of the columns that carry force at
the interior solution (the dual optimal face's dimension is the row count less that rank), and
how far the interior-point mechanism (the rows' duals) lies from the crossover's vertex. A
measurement for issue #73, by hand (minutes), in the environment scripts/simplex_load_factor
makes: ${TMPDIR:-/tmp}/voussoir-simplex/bin/python scripts/mechanism_face.py. Results in
docs/benchmarks.md (2026-11-28).
"""

import argparse

import numpy as np
import scipy.sparse as sp
import voussoir

from simplex_load_factor import ROOT, generator_lp, highs_model, live_column, run


def moving_blocks(z, still=1e-3):
    """Blocks whose largest velocity component exceeds `still` of the mechanism's largest."""
    per_block = np.abs(z.reshape(-1, 6)).max(axis=1)
    return int((per_block > still * per_block.max()).sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", default=str(ROOT / "assets/compas/compas_cra/armadillo_cra.json"))
    parser.add_argument("--mu", type=float, default=0.84)
    parser.add_argument("--direction", type=float, default=0.0, help="degrees: 1 g horizontal along it")
    args = parser.parse_args()
    a, volumes = generator_lp(voussoir.Scene.from_file(args.file), args.mu)
    full = sp.hstack([a, sp.csc_matrix(live_column(volumes, args.direction).reshape(-1, 1))]).tocsc()
    rows = a.shape[0]
    mechanisms = {}
    for crossover in ("off", "on"):
        h = highs_model(a, volumes, args.direction, "ipm")
        h.setOptionValue("run_crossover", crossover)
        lam, seconds, _ = run(h)
        x, z = np.array(h.getSolution().col_value), np.array(h.getSolution().row_dual)
        mechanisms[crossover] = z
        print(f"crossover {crossover}: lambda* {lam:.9f} in {seconds:.1f} s; {moving_blocks(z)} moving blocks")
        for share in (1e-9, 1e-7, 1e-5, 1e-3):
            carrying = np.flatnonzero(x > share * x.max())
            line = f"  columns carrying more than {share:g} of the largest force: {len(carrying)}"
            if crossover == "off" and share == 1e-7:
                singular = np.linalg.svd(full[:, carrying].toarray(), compute_uv=False)
                rank = int((singular > 1e-9 * singular[0]).sum())
                line += f", rank {rank} of {rows} rows: dual optimal face of dimension {rows - rank}"
            print(line)
    zi, zv = mechanisms["off"], mechanisms["on"]
    print(f"interior-point mechanism against the vertex: {np.linalg.norm(zi - zv) / np.linalg.norm(zv):.2e} (relative)")


if __name__ == "__main__":
    main()
