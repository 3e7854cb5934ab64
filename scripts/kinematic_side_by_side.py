"""compas_cra's CRA beside voussoir's kinematic check, on the same scenes, in one run (issue #25).

Run by hand, not in CI: `scripts/side_by_side --kinematic [path/to/voussoir] [--limit S] [--only a,b]`
makes the virtual environment (compas_cra from PyPI: its wheel links IPOPT in-process, no pyomo,
no executable) and calls this file with its Python.

Both tools ask whether the blocks stand once released, with no squeeze that nothing applies:
compas_cra's coupled rigid-block analysis (`cra_solve`: equilibrium coupled to a virtual
displacement, Kao et al. 2022, Eq. 11, on IPOPT) and `voussoir analyze --kinematic`. Each scene is
one compas Assembly JSON, prepared here and given to both: supports as `is_support`, interfaces
found by compas (voussoir ignores them and detects its own), the wedges turned as in
05_wedge.py, the wall and the dome with voussoir's builtin geometry.
- compas_cra: the `cra_solve` call alone, wall clock, each in a child process stopped after
  --limit seconds (and 2 min more to load); median of 3 on the small scenes, one run on the big
  ones. Verdict as in its
  examples, which call `cra_solve` and look: a solve that converges is a compatible equilibrium
  within the displacement bound (stands); one IPOPT gives up on (infeasible, restoration failed,
  iteration limit) raises, and is read as falls, with IPOPT's status named.
- voussoir: the whole `voussoir analyze FILE --kinematic --mu 0.84` process (load, detect, statics,
  kinematic check, report), median of 5, beside the median of the check's own solver time
  (`kinematic.solver_seconds`); both of its verdicts.
Prints the table row by row (a CRA solve may take an hour); writes the prepared scenes under
${TMPDIR:-/tmp}/voussoir-kinematic-side-by-side and nothing into the repository.
"""

import argparse
import contextlib
import io
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from compas.data import json_dump
from compas.data import json_load

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SAMPLES = os.path.join(ROOT, "assets", "compas", "compas_cra")
WORK = os.path.join(tempfile.gettempdir(), "voussoir-kinematic-side-by-side")

# One μ for both tools and every scene: the μ of compas_cra's examples (05_wedge.py, 16_ha.py, the
# cra_solve default) and of voussoir's tests/it/kinematic_check.rs. 07_shelf.py uses 0.9; the tests keep
# 0.84 on the shelves too, so does this. Density: compas_cra's examples' 1 (its loads are volumes),
# voussoir its default 600 kg/m³ under g: the same problem up to a scale both verdicts ignore.
MU = 0.84
# cra_solve's defaults; the examples that change them say so below.
CRA = {"mu": MU, "density": 1.0, "d_bnd": 1e-3, "eps": 1e-4}
VOUSSOIR_RUNS = 5


# -- scenes ---------------------------------------------------------------------------------------


def compas_cra_sample(name, supports, detect, turn=False):
    """A compas_cra sample set up as its example does: the supports, the interfaces by compas_cra's
    own detection with the example's tolerances, and for the wedges the whole assembly turned
    90° about y after that (05_wedge.py), so both tools see the turned geometry and gravity -z."""
    from compas_cra.algorithms import assembly_interfaces_numpy
    from compas_cra.datastructures import CRA_Assembly

    assembly = json_load(os.path.join(SAMPLES, f"{name}.json")).copy(cls=CRA_Assembly)
    assembly.set_boundary_conditions(supports)
    assembly_interfaces_numpy(assembly, **detect)
    if turn:
        assembly.rotate_assembly([0, 0, 0], [0, 1, 0], 90)
    return assembly


# voussoir's Mesh::cuboid vertex order (min/max per axis, bottom ring then top ring) and faces,
# outward for a positive volume; Mesh::hexahedron reuses them and flips them if not.
HEX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def cuboid(x0, y0, z0, x1, y1, z1):
    return [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0], [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]]


def hexahedron_faces(vertices):
    """HEX_FACES, reversed when they enclose a negative volume (compas's block volume and face
    frames, hence the interface normals CRA uses, need them outward)."""
    p = np.asarray(vertices)
    volume = sum(np.dot(p[f[0]], np.cross(p[f[k]], p[f[k + 1]])) for f in HEX_FACES for k in range(1, len(f) - 1))
    return HEX_FACES if volume > 0 else [f[::-1] for f in HEX_FACES]


def wall_blocks(courses, bricks, l=0.4, d=0.2, h=0.1):
    """voussoir's `builtin:wall` (src/model/builtin.rs), the same arithmetic for the same floats:
    running bond, odd courses start and end with half bricks, on a support slab under the whole
    length. Yields (vertices, is_support)."""
    length = bricks * l
    yield cuboid(0.0, -d / 2, -h, length, d / 2, 0.0), True
    for c in range(courses):
        z = c * h
        if c % 2 == 0:
            edges = [i * l for i in range(bricks + 1)]
        else:
            edges = [0.0] + [(i + 0.5) * l for i in range(bricks)] + [length]
        for x0, x1 in zip(edges, edges[1:]):
            if x1 > x0:
                yield cuboid(x0, -d / 2, z, x1, d / 2, z + h), False


def dome_blocks(courses, blocks, r=5.0, t=0.3, oculus=10.0):
    """voussoir's `builtin:dome`: courses × blocks voussoirs between radii r ± t/2 from the ground
    to the oculus. The builtin stands on voussoir's ground plane, which compas_cra has no notion
    of: a support slab whose top face is that plane (z = 0, wider than the dome) takes its place,
    for both tools."""
    ri, ro = r - t / 2, r + t / 2
    top = math.pi / 2 - math.radians(oculus)

    def sph(rad, phi, th):
        return [rad * math.cos(phi) * math.cos(th), rad * math.cos(phi) * math.sin(th), rad * math.sin(phi)]

    for c in range(courses):
        p0, p1 = top * c / courses, top * (c + 1) / courses
        for k in range(blocks):
            t0, t1 = 2 * math.pi * k / blocks, 2 * math.pi * (k + 1) / blocks
            yield [sph(ri, p0, t0), sph(ro, p0, t0), sph(ro, p0, t1), sph(ri, p0, t1),
                   sph(ri, p1, t0), sph(ro, p1, t0), sph(ro, p1, t1), sph(ri, p1, t1)], False
    yield cuboid(-ro - t, -ro - t, -t, ro + t, ro + t, 0.0), True


def assembly_of(blocks, tmax=1e-4, amin=1e-3):
    """A CRA_Assembly of (vertices, is_support) hexahedra, with interfaces by compas_assembly's
    face-face detection (`mesh_mesh_interfaces`). Its drivers choose the pairs to test by the 10
    nearest centroids, which misses a slab under a whole wall or dome (16 and 12 bricks on it,
    centroids metres away); with all pairs the 331-block wall takes over ten minutes. So the pairs
    here are those whose bounding boxes touch — every pair that can share a face."""
    from compas_assembly.algorithms import mesh_mesh_interfaces
    from compas_assembly.datastructures import Block
    from compas_cra.datastructures import CRA_Assembly

    assembly = CRA_Assembly()
    meshes, supports = [], []
    for key, (vertices, support) in enumerate(blocks):
        mesh = Block.from_vertices_and_faces(vertices, hexahedron_faces(vertices))
        assembly.add_block(mesh, node=key)
        if support:
            assembly.set_boundary_condition(key)
        meshes.append(mesh)
        supports.append(support)
    boxes = np.array([[np.min(m.vertices_attributes("xyz"), axis=0), np.max(m.vertices_attributes("xyz"), axis=0)]
                      for m in meshes])
    lo, hi = boxes[:, 0], boxes[:, 1]
    touch = np.all((lo[:, None] <= hi[None] + tmax) & (lo[None] <= hi[:, None] + tmax), axis=2)
    for i, j in zip(*np.nonzero(np.triu(touch, 1))):
        if supports[i] and supports[j]:
            continue
        interfaces = mesh_mesh_interfaces(meshes[i], meshes[j], tmax=tmax, amin=amin)
        if interfaces:
            assembly.graph.add_edge(int(i), int(j), interfaces=interfaces)
    return assembly


LETTERS = {"nmax": 10, "amin": 1e-2, "tmax": 1e-2}  # 16_ha.py, 05_wedge.py
SHELF = {"amin": 1e-6, "tmax": 1e-4}  # 07_shelf.py

# name → (prepare: None for a file used as it is, else a function returning the assembly; the file
# in that case; CRA's keyword arguments; how many CRA solves to take the median of).
SCENES = {
    "H": (lambda: compas_cra_sample("H", [0, 1], LETTERS), None, CRA, 3),
    "A": (lambda: compas_cra_sample("A", [0, 1], LETTERS), None, CRA, 3),
    # 07_shelf.py's displacement bound and overlap (its μ 0.9 aside, see MU).
    "shelf-stable": (lambda: compas_cra_sample("shelf-stable", [0], SHELF), None, {**CRA, "d_bnd": 1e-1, "eps": 1e-3}, 3),
    **{
        f"wedge-{t}-turned": (lambda t=t: compas_cra_sample(f"type-{t}", [0, 1], LETTERS, turn=True), None,
                              {**CRA, "d_bnd": 1e-2}, 3)  # 05_wedge.py: d_bnd = 1e-2
        for t in "abcd"
    },
    "wall-20x16": (lambda: assembly_of(wall_blocks(20, 16)), None, CRA, 1),
    "dome-6x12": (lambda: assembly_of(dome_blocks(6, 12)), None, CRA, 1),
    "Armadillo": (None, os.path.join(SAMPLES, "armadillo_cra.json"), CRA, 1),
}


def scene_file(name):
    prepare, path, _, _ = SCENES[name]
    if prepare is None:
        return path
    os.makedirs(WORK, exist_ok=True)
    path = os.path.join(WORK, name + ".json")
    json_dump(prepare(), path)
    return path


# -- compas_cra -----------------------------------------------------------------------------------


def cra_worker(path, kwargs):
    """In the child: one `cra_solve` on a fresh load of `path`; prints its seconds and status as
    JSON. cra_solve prints its matrices' shapes and a line per block; kept off the report."""
    from compas_cra.equilibrium import cra_solve

    assembly = json_load(path)
    chatter = io.StringIO()
    start = time.perf_counter()
    try:
        with contextlib.redirect_stdout(chatter):
            cra_solve(assembly, verbose=False, **kwargs)
        status, stands = chatter.getvalue().rsplit("result:", 1)[-1].strip(), True
    except ValueError as failed:
        # cra_solve's own check, "solve failed: <status> (<IPOPT's return status>)"
        if not str(failed).startswith("solve failed: "):
            raise
        status, stands = str(failed).partition("(")[2].removesuffix(")"), False
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "status": status, "stands": stands}))


def cra(path, kwargs, runs, limit):
    """Median seconds and the verdict of `runs` solves, each its own process so that a solve past
    `limit` can be stopped (IPOPT runs in compiled code inside the extension: ending its process
    is the sure way to stop it); None for the seconds when one was stopped."""
    results = []
    for _ in range(runs):
        command = [sys.executable, os.path.abspath(__file__), "--cra-worker", path, json.dumps(kwargs)]
        try:
            # the limit bounds the solve; loading the file and importing compas come on top
            done = subprocess.run(command, capture_output=True, text=True, timeout=limit + 120)
        except subprocess.TimeoutExpired:
            return None, f"none (stopped after {limit:g} s)"
        if done.returncode != 0:
            raise RuntimeError(f"compas_cra on {path}:\n{done.stderr}")
        results.append(json.loads(done.stdout.strip().splitlines()[-1]))
    statuses = sorted({r["status"] for r in results})
    verdicts = {r["stands"] for r in results}
    verdict = ("stands" if verdicts == {True} else "falls" if verdicts == {False} else "mixed") + f" ({', '.join(statuses)})"
    return statistics.median(r["seconds"] for r in results), verdict


# -- voussoir -------------------------------------------------------------------------------------


def voussoir(binary, path):
    """Median process seconds and kinematic solver seconds of VOUSSOIR_RUNS runs, the block and
    support counts, and the statics' and the kinematic check's verdicts (the last run's; they do
    not change between runs)."""
    seconds, solver = [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "report.json")
        for _ in range(VOUSSOIR_RUNS):
            start = time.perf_counter()
            done = subprocess.run([binary, "analyze", path, "--kinematic", "--mu", str(MU), "--json", out],
                                  capture_output=True, text=True)
            seconds.append(time.perf_counter() - start)
            if done.returncode not in (0, 1):  # 1: something falls, an answer like 0
                raise RuntimeError(f"voussoir on {path}:\n{done.stderr}")
            with open(out) as f:
                report = json.load(f)
            solver.append(report["kinematic"]["solver_seconds"])
    verdict = f"{report['verdict']} / {report['kinematic']['verdict']}"
    return statistics.median(seconds), statistics.median(solver), len(report["blocks"]), len(report["supports"]), verdict


# -- main -----------------------------------------------------------------------------------------


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary", nargs="?", default=os.path.join(ROOT, "target", "release", "voussoir"))
    parser.add_argument("--limit", type=float, default=3600.0, help="seconds allowed to one CRA solve (3600)")
    parser.add_argument("--only", help="comma-separated scene names (default: all, in order: " + ", ".join(SCENES) + ")")
    args = parser.parse_args()
    names = args.only.split(",") if args.only else list(SCENES)
    unknown = [n for n in names if n not in SCENES]
    if unknown:
        parser.error(f"unknown scene(s) {unknown}; known: {list(SCENES)}")

    import compas_cra
    from compas_cra._native import IPOPT_VERSION

    version = subprocess.run([args.binary, "--version"], capture_output=True, text=True).stdout.strip()
    print(f"compas_cra {compas_cra.__version__} (IPOPT {IPOPT_VERSION}), {version}, μ = {MU}; "
          f"prepared scenes in {WORK}")
    print("load average (1, 5, 15 min) at the start: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(f"{'scene':17} {'blocks':>11} {'CRA':>10} {'CRA verdict':36} {'voussoir':>9} {'kin. solver':>11}"
          f" {'statics / kinematic':22} {'× CRA/voussoir':>14} {'load':>5}")
    for name in names:
        load = os.getloadavg()[0]
        path = scene_file(name)
        _, _, kwargs, runs = SCENES[name]
        v_seconds, v_solver, blocks, supports, v_verdict = voussoir(args.binary, path)
        c_seconds, c_verdict = cra(path, kwargs, runs, args.limit)
        shown = f"{c_seconds:9.3f}s" if c_seconds is not None else f"> {args.limit:g} s".rjust(10)
        ratio = f"{c_seconds / v_seconds:14.1f}" if c_seconds is not None else f"> {args.limit / v_seconds:.0f}".rjust(14)
        print(f"{name:17} {f'{blocks} ({supports} sup)':>11} {shown} {c_verdict:36} {v_seconds:8.3f}s {v_solver:10.4f}s"
              f" {v_verdict:22} {ratio} {load:5.2f}", flush=True)
    print("load average (1, 5, 15 min) at the end: " + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    print("CRA: " + "; ".join(f"{n}: " + ", ".join(f"{k} {v:g}" for k, v in SCENES[n][2].items()) + f", median of {SCENES[n][3]}"
                              for n in names))


if __name__ == "__main__":
    if sys.argv[1:2] == ["--cra-worker"]:
        cra_worker(sys.argv[2], json.loads(sys.argv[3]))
    else:
        main()
