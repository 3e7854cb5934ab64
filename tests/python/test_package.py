"""The Python package (bindings/python, the wheel scripts/python_tests builds and installs) with
the real compas, compas_assembly, compas_cra and dask from PyPI — nothing mocked.

Invariants, one per test: compas objects pass through their data and give the verdicts of the
same files read by path, with the supports carrying exactly the free weight; verdicts agree with
compas_cra's own rbe_solve on the shared samples; the forces written into a compas Assembly
balance every free block in compas' own fields and frames (also on reversed edges); closed forms
for interfaces and load factors; errors are the CLI's messages as ValueError/OSError subclasses;
solves release the GIL; a Dask study on a 2-worker LocalCluster equals the plain loop; the
README's and the package's examples run.
"""

import doctest
import json
import math
import os
import re
import subprocess
import threading
from pathlib import Path

import numpy as np
import pytest
from compas.data import json_load

import voussoir

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "assets" / "compas"
BIN = os.environ.get("VOUSSOIR_BIN", str(ROOT / "target" / "debug" / "voussoir"))
G = 9.81  # the library's standard gravity (src/model/mod.rs)

ASSEMBLIES = [
    "compas_assembly/stack_assembly.json",
    "compas_assembly/arch_assembly.json",
    "compas_assembly/two-blocks_assembly.json",
    "compas_assembly/wall_assembly.json",
]

# compas_cra's samples set up as its examples do (16_ha.py, 05_wedge.py, 07_shelf.py): the
# supports, compas_cra's own interface detection with the example's tolerances, the wedges
# turned 90° about y. name → (supports, detection settings, turned).
LETTERS = {"nmax": 10, "amin": 1e-2, "tmax": 1e-2}
SAMPLES = {
    "H": ([0, 1], LETTERS, False),
    "A": ([0, 1], LETTERS, False),
    "shelf-stable": ([0], {"amin": 1e-6, "tmax": 1e-4}, False),
    "type-a": ([0, 1], LETTERS, True),
    "type-c": ([0, 1], LETTERS, True),
}


def cra_sample(name):
    """A compas_cra CRA_Assembly object as the sample's example prepares it."""
    from compas_cra.algorithms import assembly_interfaces_numpy
    from compas_cra.datastructures import CRA_Assembly

    supports, detect, turn = SAMPLES[name]
    assembly = json_load(str(DATA / "compas_cra" / f"{name}.json")).copy(cls=CRA_Assembly)
    assembly.set_boundary_conditions(supports)
    assembly_interfaces_numpy(assembly, **detect)
    if turn:
        assembly.rotate_assembly([0, 0, 0], [0, 1, 0], 90)
    return assembly


@pytest.mark.parametrize("rel", ASSEMBLIES + ["compas_dem/dem_crossvault.json"])
def test_from_compas_object_equals_the_file_and_supports_carry_the_weight(rel):
    obj = json_load(str(DATA / rel))
    from_obj = voussoir.analyze(voussoir.Scene.from_compas(obj), mu=0.84)
    from_file = voussoir.analyze(voussoir.Scene.from_file(DATA / rel), mu=0.84)
    assert from_obj.verdict == from_file.verdict
    assert from_obj.tension_ratio == pytest.approx(from_file.tension_ratio, abs=1e-9)
    assert len(from_obj.block_names) == len(from_file.block_names)
    if from_obj.stands:
        fx, fy, fz = from_obj.support_reaction
        w = from_obj.free_weight
        assert fz == pytest.approx(w, rel=1e-6)
        assert abs(fx) < 1e-6 * w and abs(fy) < 1e-6 * w


@pytest.mark.parametrize("rel", ["compas_cra/armadillo_cra.json", "compas_assembly/crossvault_assembly.json", "compas_cra/H.json"])
def test_from_compas_reads_the_blocks_as_their_json_does(rel):
    """Invariant: the compas object's own tables (no JSON round trip) give the scene its JSON
    data gives, bit for bit: the same blocks, force points and forces."""
    from voussoir import _compas

    obj = json_load(str(DATA / rel))
    assert _compas.block_tables(obj) is not None, "a graph of blocks takes the direct route"
    direct = voussoir.analyze(voussoir.Scene.from_compas(obj), mu=0.84)
    via_json = voussoir.analyze(voussoir.Scene.from_json(_compas.data_json(obj)), mu=0.84)
    assert direct.block_names == via_json.block_names
    assert np.array_equal(direct.points, via_json.points)
    assert np.array_equal(direct.point_forces, via_json.point_forces)


def test_from_compas_names_a_vertex_that_is_not_a_number():
    obj = json_load(str(DATA / "compas_cra/H.json"))
    key, attr = next(iter(obj.graph.nodes(data=True)))
    vertex = next(iter(attr["block"].vertex))
    attr["block"].vertex[vertex]["x"] = float("nan")
    with pytest.raises(voussoir.InputError, match=f"block '{key}': vertex '{vertex}' has a coordinate that is not a finite number"):
        voussoir.Scene.from_compas(obj)


def rbe_stands(assembly, mu):
    """compas_cra's RBE verdict with its tension criterion: no tension beyond 1e-4 of the
    compression (w_t = 1e6 leaves ~1e-7 where none is needed)."""
    from compas_cra.equilibrium import rbe_solve

    rbe_solve(assembly, mu=mu, density=1.0, verbose=False)
    forces = [f for u, v in assembly.graph.edges() for i in assembly.graph.edge_attribute((u, v), "interfaces") for f in i.forces]
    compression = sum(f["c_np"] for f in forces)
    tension = sum(f["c_nn"] for f in forces)
    return tension <= 1e-4 * compression


@pytest.mark.parametrize("rel", ASSEMBLIES)
def test_verdicts_agree_with_compas_cra_rbe_solve(rel):
    mu = 0.84
    mine = voussoir.analyze(voussoir.Scene.from_compas(json_load(str(DATA / rel))), mu=mu)
    assert mine.solver_status in ("solved", "almost_solved")
    assert mine.stands == rbe_stands(json_load(str(DATA / rel)), mu)


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_cra_assembly_objects_agree_with_rbe_solve(name):
    """A CRA_Assembly object (compas_cra's own class) goes in through its data; the verdict is
    compas_cra's rbe_solve's on the same object, and a standing one's supports carry W."""
    mu = 0.84
    assembly = cra_sample(name)
    mine = voussoir.analyze(voussoir.Scene.from_compas(assembly), mu=mu)
    assert mine.solver_status in ("solved", "almost_solved")
    assert mine.stands == rbe_stands(assembly, mu), mine
    if mine.stands:
        assert mine.support_reaction[2] == pytest.approx(mine.free_weight, rel=1e-6)


def block_forces(assembly):
    """Σ of the interface forces on each node, from compas' own fields and frames alone: the
    force on the edge's v is c_n z + c_u x + c_v y (c_n = c_np − c_nn), u receives the opposite."""
    total = {key: np.zeros(3) for key in assembly.graph.nodes()}
    for u, v in assembly.graph.edges():
        for i in assembly.graph.edge_attribute((u, v), "interfaces") or []:
            x, y, z = (np.array(list(a)) for a in (i.frame.xaxis, i.frame.yaxis, i.frame.zaxis))
            for f in i.forces:
                force = (f["c_np"] - f["c_nn"]) * z + f["c_u"] * x + f["c_v"] * y
                total[v] += force
                total[u] -= force
    return total


def reverse_edges(assembly):
    """The same assembly with every edge turned around and compas' interfaces dropped."""
    from compas_assembly.datastructures import Assembly

    turned = Assembly()
    for key in assembly.graph.nodes():
        turned.graph.add_node(key, **assembly.graph.node_attributes(key))
    for u, v in assembly.graph.edges():
        turned.graph.add_edge(v, u, interfaces=[])
    return turned


@pytest.mark.parametrize("turn", [False, True])
def test_write_forces_balances_every_free_block_in_compas_fields(turn):
    assembly = json_load(str(DATA / "compas_assembly/arch_assembly.json"))
    if turn:
        assembly = reverse_edges(assembly)
    result = voussoir.analyze(voussoir.Scene.from_compas(assembly), mu=0.84)
    assert result.stands
    summary = result.write_forces(assembly)
    assert summary["interfaces"] == sum(1 for a, b in result.interface_blocks if a >= 0 and b >= 0)
    assert summary["edges_added"] == 0 and summary["edges_without_contact"] == []
    totals = block_forces(assembly)
    w = result.free_weight
    free = [k for k in assembly.graph.nodes() if not assembly.graph.node_attribute(k, "is_support")]
    volumes = {k: assembly.graph.node_attribute(k, "block").volume() for k in free}
    for key in free:
        # One density for every block: block weights share W in proportion to volume.
        weight = w * volumes[key] / sum(volumes.values())
        assert totals[key] == pytest.approx([0.0, 0.0, weight], abs=1e-6 * w), f"block {key}"


def test_write_forces_round_trip_through_compas_json():
    """What write_forces put in the object is what compas serialises and voussoir reads back:
    the same points and forces per block pair."""
    import compas

    assembly = json_load(str(DATA / "compas_assembly/arch_assembly.json"))
    result = voussoir.analyze(voussoir.Scene.from_compas(assembly))
    result.write_forces(assembly)
    again = compas.json_loads(compas.json_dumps(assembly))
    before = sorted(f["c_np"] for _, _, f in _forces(assembly))
    after = sorted(f["c_np"] for _, _, f in _forces(again))
    assert after == pytest.approx(before, abs=0.0)
    assert sum(before) == pytest.approx(result.point_forces[:, 0].sum(), rel=1e-12)
    # And a second analysis of the written object gives the same answer.
    second = voussoir.analyze(voussoir.Scene.from_compas(again))
    assert second.verdict == result.verdict
    assert second.tension_ratio == pytest.approx(result.tension_ratio, abs=1e-9)


def _forces(assembly):
    for u, v in assembly.graph.edges():
        for i in assembly.graph.edge_attribute((u, v), "interfaces"):
            for f in i.forces:
                yield u, v, f


def _contacts(model):
    for u, v in model.graph.edges():
        for c in model.graph.edge_attribute((u, v), "contacts") or []:
            yield u, v, c


def _check_block_model(model, result, w):
    """Every contact a compas_dem FrictionContact with one force per point; each free block in
    equilibrium with its share of W by volume, from compas' own fields and frames alone (the
    force on v is c_n z + c_u x + c_v y, u receives the opposite); compas_dem's own resultant
    agrees with that sum. Returns the contact count."""
    from compas_dem.interactions import FrictionContact

    total = {key: np.zeros(3) for key in model.graph.nodes()}
    count = 0
    for u, v, c in _contacts(model):
        assert isinstance(c, FrictionContact) and len(c.forces) == len(c.points)
        f = np.zeros(3)
        for p in c.forces:
            f += (p["c_np"] - p["c_nn"]) * np.array(c.frame.zaxis) + p["c_u"] * np.array(c.frame.xaxis) + p["c_v"] * np.array(c.frame.yaxis)
        total[v] += f
        total[u] -= f
        count += 1
    free = [k for k in model.graph.nodes() if not model.graph.node_element(k).is_support]
    volumes = {k: model.graph.node_element(k).modelgeometry.volume() for k in free}
    for key in free:
        weight = w * volumes[key] / sum(volumes.values())
        assert total[key] == pytest.approx([0.0, 0.0, weight], abs=1e-6 * w), f"block {key}"
    return count


def test_write_forces_into_a_block_model_and_the_cli_block_model():
    """compas_dem's cross vault (a BlockModel: 38 blocks, 5 supports): write_forces puts one
    FrictionContact per block-block interface on the model's edges (60, none with the ground),
    every free block balances its weight from compas' fields alone, and compas saves and
    reloads the model with the same forces; `analyze --compas-out` of the BlockModel file writes
    a BlockModel that compas loads with the same contacts and the same total compression."""
    import compas

    path = DATA / "compas_dem/dem_crossvault.json"
    model = json_load(str(path))
    result = voussoir.analyze(voussoir.Scene.from_compas(model))
    assert result.stands
    summary = result.write_forces(model)
    assert summary["interfaces"] == 60 and summary["ground_interfaces"] == 0
    assert _check_block_model(model, result, result.free_weight) == 60
    compression = result.point_forces[:, 0].sum()
    again = compas.json_loads(compas.json_dumps(model))
    assert sum(p["c_np"] for _, _, c in _contacts(again) for p in c.forces) == pytest.approx(compression, rel=1e-12)

    out = Path(os.environ.get("TMPDIR", "/tmp")) / f"voussoir-bm-{os.getpid()}.json"
    done = subprocess.run([BIN, "analyze", str(path), "--compas-out", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    written = json_load(str(out))
    out.unlink()
    assert type(written).__name__ == "BlockModel"
    assert _check_block_model(written, result, result.free_weight) == 60
    assert sum(p["c_np"] for _, _, c in _contacts(written) for p in c.forces) == pytest.approx(compression, rel=1e-9)
    names = sorted(written.graph.node_element(k).name for k in written.graph.nodes())
    assert names == sorted(result.block_names)


PIER = {
    "name": "pier",
    "ground": True,
    "blocks": [
        {
            "name": "pier",
            "vertices": [[0, 0, 0], [0.4, 0, 0], [0.4, 0.3, 0], [0, 0.3, 0], [0, 0, 1.2], [0.4, 0, 1.2], [0.4, 0.3, 1.2], [0, 0.3, 1.2]],
            "faces": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
        }
    ],
}


def test_repair_from_python_is_the_cli_repair(tmp_path):
    """voussoir.repair on the paper's Fig 4a gives the design and report `voussoir repair` writes
    (the same seed, the same cut), which stands by an independent analysis; its history never
    rises; a bad cut index is an InputError with the library's message."""
    path = ROOT / "assets" / "cases" / "fig4a_m_cut.json"
    scene = voussoir.Scene.from_file(path)
    design, report = voussoir.repair(scene)
    assert report["outcome"]["kind"] == "repaired"
    assert voussoir.analyze(design).stands and not voussoir.analyze(scene).stands
    assert all(b <= a for a, b in zip(report["history"], report["history"][1:]))
    out = tmp_path / "m.json"
    done = subprocess.run([BIN, "repair", str(path), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert json.loads(out.read_text())["cuts"] == json.loads(design.to_json())["cuts"]
    with pytest.raises(voussoir.InputError, match="cut 4: there are only 1 cuts"):
        voussoir.repair(scene, cuts=[4])


def test_decompose_from_python_by_courses_and_by_thrust():
    """A 0.4 x 0.3 x 1.2 m pier as one solid, blocks of at most 0.4 m: 3 courses of one block
    each, by either strategy (the thrust is vertical: the beds settle at once, unturned), and
    the design stands; a running bond extruded to an apex is one pattern cut; a size given
    twice, an unknown strategy or a pattern without its apex is an InputError."""
    shape = voussoir.Scene.from_json(json.dumps(PIER))
    design, info = voussoir.decompose(shape, max_size=0.4)
    assert (info["courses"], info["pieces"], info["rounds"]) == (3, 3, None)
    assert design.cuts == 2 and len(design.pieces()) == 3 and voussoir.analyze(design).stands
    design, info = voussoir.decompose(shape, max_size=0.4, strategy="thrust")
    rounds = info["rounds"]
    assert rounds["settled"] and rounds["rounds"] == 1 and rounds["largest_turn_degrees"] < 1e-6
    with pytest.raises(voussoir.InputError, match="exactly one of blocks and max_size"):
        voussoir.decompose(shape, blocks=3, max_size=0.4)
    with pytest.raises(voussoir.InputError, match="strategy: 'funicular'"):
        voussoir.decompose(shape, max_size=0.4, strategy="funicular")
    # A running bond on the top extruded to an apex far below: one pattern cut.
    design, info = voussoir.decompose(shape, max_size=0.2, strategy="pattern", apex=[0.2, 0.15, -3.0])
    assert design.cuts == 1 and info["pieces"] == len(design.pieces()) >= 4
    with pytest.raises(voussoir.InputError, match="needs apex"):
        voussoir.decompose(shape, max_size=0.4, strategy="pattern")


def test_write_forces_refuses_what_it_cannot_write():
    result = voussoir.analyze(voussoir.Scene.builtin("stack?n=2"))
    with pytest.raises(TypeError, match="Assembly"):
        result.write_forces(42)


def cube(x, y, z, a=1.0):
    v = [[x, y, z], [x + a, y, z], [x + a, y + a, z], [x, y + a, z]]
    v += [[p[0], p[1], z + a] for p in v]
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    return np.array(v), faces


def test_from_arrays_interfaces_and_weight_closed_forms():
    """Two unit cubes stacked, the lower one a support: one interface of area 1 with a vertical
    normal; the support carries ρ g · 1 m³; a 1-m cube on a support tips at λ* = b/h = 1 when
    friction cannot slide it (μ = 2, along x)."""
    scene = voussoir.Scene.from_arrays([cube(0, 0, 0), cube(0, 0, 1)], supports=[0], density=2000.0)
    assert scene.block_names == ["0", "1"]
    found = voussoir.detect_interfaces(scene)
    assert found["blocks"].shape == (1, 2)
    assert found["area"] == pytest.approx([1.0], rel=1e-12)
    assert abs(found["normal"][0][2]) == pytest.approx(1.0, rel=1e-12)
    assert found["polygons"][0].shape == (4, 3)
    result = voussoir.analyze(scene)
    assert result.stands
    assert result.free_weight == pytest.approx(2000.0 * G, rel=1e-12)
    assert result.support_reaction[2] == pytest.approx(2000.0 * G, rel=1e-6)
    assert result.points.shape == (4, 3) and result.point_forces.shape == (4, 4)
    assert result.point_forces[:, 0].sum() == pytest.approx(2000.0 * G, rel=1e-6)
    report = voussoir.load_factor(scene, mu=2.0, direction=0.0)
    assert report["robustness"]["load_factor"] == pytest.approx(1.0, rel=1e-5)


def test_sequence_and_drop_of_a_stack():
    scene = voussoir.Scene.builtin("stack?n=3")
    report = voussoir.sequence(scene, order="bottom-up")
    assert len(report["steps"]) == 3 and all(s["stands"] for s in report["steps"])
    assert report["first_failure"] is None
    dropped = voussoir.drop(scene, duration=0.5)
    assert dropped["stands"] and dropped["engine"] == "rapier" and "exact" not in dropped


def test_drop_on_the_exact_engine():
    # A 15-voussoir arch just above and below its static threshold t/R = 0.10607: hard contacts
    # stand and fall with the statics; the account names the model and balances the energy (an
    # identity of the scheme, to the solves' accuracy: the cone's SOCPs reach ~1e-7 of it).
    for t, stands in [(0.107, True), (0.105, False)]:
        scene = voussoir.Scene.builtin(f"arch?n=15&t={t}")
        dropped = voussoir.drop(scene, engine="exact", duration=0.5, friction_model="cone")
        assert dropped["engine"] == "exact" and dropped["stands"] == stands
        exact = dropped["exact"]
        assert exact["friction_model"] == "cone" and exact["status"] in ("solved", "almost_solved")
        assert exact["energy"]["error"] < 1e-6
    # Its steps run on the structured solver, or on clarabel with solver="clarabel": the same
    # verdict.
    scene = voussoir.Scene.builtin("arch?n=15&t=0.105")
    runs = {s: voussoir.drop(scene, engine="exact", duration=0.5, solver=s) for s in ("structured", "clarabel")}
    assert runs["structured"]["exact"]["structured_solves"] == runs["structured"]["exact"]["solves"] > 0
    assert runs["clarabel"]["exact"]["structured_solves"] == 0
    assert not runs["structured"]["stands"] and not runs["clarabel"]["stands"]
    with pytest.raises(voussoir.InputError, match="engine: 'soft' is not one of rapier, exact"):
        voussoir.drop(voussoir.Scene.builtin("stack?n=2"), engine="soft")


def test_shake_returns_the_response_as_numpy_arrays():
    # A 0.5 g pulse of 0.2 s brings the thin arch (λ* 0.1505 g, the robustness command's) down
    # in both engines; the trace is one sample per step, the ground's 0.5 g held for the pulse.
    thin = voussoir.Scene.builtin("arch?n=15&t=0.15")
    report = voussoir.shake(thin, pulse="rect:0.5,0.2", engine="both", duration=1.0)
    assert abs(report["static_load_factor"] - 0.1505) < 5e-4
    assert [r["result"]["engine"] for r in report["runs"]] == ["exact", "rapier"]
    for run in report["runs"]:
        trace = run["trace"]
        assert isinstance(trace["times"], np.ndarray) and trace["rotation"].shape == trace["times"].shape
        assert np.allclose(np.diff(trace["times"]), 1 / 240)
        during = trace["times"][1:] <= 0.2 - 1 / 240
        assert np.allclose(trace["ground_g"][1:][during], 0.5)
        assert run["collapsed"] and 0.2 < run["collapse_time_s"] < trace["times"][-1]
    # The thicker arch (λ* 0.41 g) does not move under El Centro's 0.28 g in the exact engine.
    standing = voussoir.shake(voussoir.Scene.builtin("arch?n=15&t=0.25"), record="builtin:elcentro", duration=2.0)
    assert not standing["runs"][0]["collapsed"] and standing["runs"][0]["trace"]["rotation"].max() == 0.0
    with pytest.raises(voussoir.InputError, match="unknown shape 'heat'"):
        voussoir.shake(thin, pulse="heat:0.5,0.2")


def test_the_exact_engine_s_switches():
    # The collapsing arch lands on the floor: its impacts split steps, unless split_impacts is
    # off (then no step is split, and the run still balances its energy).
    scene = voussoir.Scene.builtin("arch?n=15&t=0.08")
    split = voussoir.drop(scene, engine="exact", duration=1.0)["exact"]
    whole = voussoir.drop(scene, engine="exact", duration=1.0, split_impacts=False)["exact"]
    assert split["split_steps"] > 0 and whole["split_steps"] == 0
    assert whole["energy"]["error"] < 1e-6
    # Its moving steps go by the contacts' states, unless by_states is off (then every step
    # is the rounds' interior-point solves, at least twice as many of them).
    rounds = voussoir.drop(scene, engine="exact", duration=1.0, by_states=False)["exact"]
    assert split["state_steps"] > 0 and rounds["state_steps"] == 0
    assert 2 * split["solves"] <= rounds["solves"]
    # compas_cra's H bar between its posts: the kinematic check's motion from rest (the bar
    # slides down with no force on it) by default; held by an equilibrium with
    # rest_when_admissible.
    h = voussoir.Scene.from_file(DATA / "compas_cra" / "H.json")
    free = voussoir.drop(h, engine="exact", duration=0.2, supports="lowest", mu=0.84)
    held = voussoir.drop(h, engine="exact", duration=0.2, supports="lowest", mu=0.84, rest_when_admissible=True)
    assert not free["stands"] and held["stands"] and held["max_drift"] == 0.0


def test_a_column_crushes_at_its_strength():
    # Three 1 m cubes of 600 kg/m³ on a slab: the base joint carries 3 ρ g a³ on a², so the
    # stone needs σ = 3 ρ g a = 17 658 Pa; just below, the column crushes; a strength that is
    # not a finite number > 0 is one clear error.
    scene = voussoir.Scene.builtin("stack?n=3&a=1")
    needed = 3 * 600 * 9.81 * 1.0
    standing = voussoir.analyze(scene, strength=1.001 * needed)
    assert standing.verdict == "stands"
    assert abs(standing.crushing["needed"] - needed) <= 1e-6 * needed
    assert "base" in (standing.crushing["a"], standing.crushing["b"])
    assert voussoir.analyze(scene, strength=0.999 * needed).verdict == "crushes"
    assert voussoir.analyze(scene).crushing is None
    with pytest.raises(voussoir.InputError, match="compressive strength -1"):
        voussoir.analyze(scene, strength=-1.0)


def box(x0, y0, z0, x1, y1, z1):
    v = [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]]
    v += [[p[0], p[1], z1] for p in v]
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    return np.array(v), faces


def test_tolerance_margins():
    # A 1 x 1 x 0.6 block whose weight acts 0.2 inside its pier's edge survives every joint
    # shrunk by 0.2 (to the bisection's 1e-6 of the model size); its normal force survives
    # a tilt of the whole friction angle.
    scene = voussoir.Scene.from_arrays([box(0.3, 0, -1, 2, 1, 0), box(0, 0, 0, 1, 1, 0.6)], supports=[0])
    margins = voussoir.tolerance(scene)
    assert abs(margins["shrink"]["value"] - 0.2) < 1e-5
    assert (margins["shrink"]["governing"]["a"], margins["shrink"]["governing"]["b"]) == ("0", "1")
    assert abs(margins["tilt"]["relative"] - 1.0) < 1e-6
    with pytest.raises(voussoir.InputError, match="does not stand as drawn"):
        voussoir.tolerance(voussoir.Scene.builtin("arch?n=15&t=0.09"))


def test_settle_a_block_on_a_tilting_slab():
    # A 0.5 x 0.5 x 1 block on a slab that turns by 60 degrees about y: with mu = 0.8 > b/h it
    # tips at atan(0.5) = 26.565 degrees (within 0.1); an unknown block is one clear error.
    scene = voussoir.Scene.from_arrays([box(-1, -1, -0.5, 1, 1, 0), box(-0.25, -0.25, 0, 0.25, 0.25, 1)], supports=[0])
    result = voussoir.settle(scene, moves=["0:0,0,0:0,60,0"], quasi_static=True, mu=0.8)
    outcome = result["quasi_static"]["outcome"]
    assert outcome["kind"] == "collapses"
    assert abs(outcome["fraction"] * 60 - 26.565051177) < 0.1
    assert [j["state"] for j in result["quasi_static"]["mechanism"]] == ["hinging"]
    assert "exact" not in result
    with pytest.raises(voussoir.InputError, match="movement of 'nowhere': no block of that name"):
        voussoir.settle(scene, moves=["nowhere:1,0,0"], quasi_static=True)


def test_settle_with_a_stone_that_crushes_tips_earlier():
    # The same block in a stone of strength sigma = W / (0.2 b d): its joint's stress block
    # reaches the downhill edge when h tan(t) + W cos(t) / (sigma d) = b, at 22.3 degrees
    # (bisection here) instead of atan(b/h) = 26.6: the quasi-static run tips there within 0.1.
    scene = voussoir.Scene.from_arrays([box(-1, -1, -0.5, 1, 1, 0), box(-0.25, -0.25, 0, 0.25, 0.25, 1)], supports=[0])
    b, h, d = 0.5, 1.0, 0.5
    w = 600.0 * b * d * h * 9.81
    sigma = w / (0.2 * b * d)
    lo, hi = 0.0, math.atan(b / h)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if h * math.tan(mid) + w * math.cos(mid) / (sigma * d) < b:
            lo = mid
        else:
            hi = mid
    result = voussoir.settle(scene, moves=["0:0,0,0:0,60,0"], quasi_static=True, mu=0.8, strength=sigma)
    assert result["strength"] == pytest.approx(sigma)
    outcome = result["quasi_static"]["outcome"]
    assert outcome["kind"] == "collapses"
    assert abs(outcome["fraction"] * 60 - math.degrees(lo)) < 0.1


def test_infill_meets_the_lever_rule():
    # A plank overhanging its support's edge (x = 0) by a centroid arm of 0.2, a tail on its back
    # with arm 0.4 (tests/it/infill.rs): V_plank = 0.4, V_tail = 0.1, so it stands exactly when
    # rho_tail >= 2 rho_plank. The lightest within [150, 600]: 150 and 300; the design written
    # stands and carries the densities by piece; with [150, 250] none holds it.
    scene = voussoir.Scene.from_arrays(
        [box(-1, 0, -1, 0, 1, 0), box(-0.8, 0, 0, 1.2, 1, 0.2), box(-0.8, 0, 0.2, 0, 1, 0.325)], supports=[0]
    )
    assert voussoir.analyze(scene).verdict == "needs_tension"
    design, report = voussoir.infill(scene, density_range=(150, 600))
    after = {b["block"]: b["after"] for b in report["blocks"]}
    assert list(after.values()) == pytest.approx([150, 300], rel=1e-9)
    assert report["outcome"]["kind"] == "stands" and report["verdict_after"] == "stands"
    assert voussoir.analyze(design).verdict == "stands"
    assert json.loads(design.to_json())["densities"] == pytest.approx(after, rel=1e-12)
    none, report = voussoir.infill(scene, density_range=(150, 250))
    assert none is None and report["outcome"]["kind"] == "impossible" and report["mechanism"]["blocks"]
    with pytest.raises(voussoir.InputError, match="density range"):
        voussoir.infill(scene, density_range=(0, 600))


def test_cut_history_and_supports_edits():
    scene = voussoir.Scene.builtin("stack?n=1&a=1")
    cut = scene.with_cut([0.0, 0.0, 0.5], [0.0, 0.0, 1.0])
    assert scene.cuts == 0 and cut.cuts == 1
    assert scene.pieces() == ["base", "box0"]
    assert cut.pieces() == ["base", "box0.0-", "box0.0+"]
    again = voussoir.Scene.from_json(cut.to_json())
    assert again.pieces() == cut.pieces()


def test_pattern_cut_is_a_running_bond():
    """A line across a 2 x 2 x 0.5 slab, then a half line on either side of it, extruded to an
    apex 3 m below: 4 pieces, not 6 (each half line cuts only the piece its cone meets), the
    slab's volume kept, every internal joint's plane through the apex (as tests/it/pattern_cut.rs);
    a target that is not a piece is an InputError naming the cut."""
    slab = {
        "name": "slab",
        "ground": True,
        "blocks": [
            {
                "name": "slab",
                "vertices": [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0.5], [1, -1, 0.5], [1, 1, 0.5], [-1, 1, 0.5]],
                "faces": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
            }
        ],
    }
    scene = voussoir.Scene.from_json(json.dumps(slab))
    apex = [0.0, 0.0, -3.0]
    bond = [
        [[0.0, -1.0, 0.5], [0.0, 1.0, 0.5]],
        [[-1.0, 0.3, 0.5], [0.0, 0.3, 0.5]],
        [[0.0, -0.4, 0.5], [1.0, -0.4, 0.5]],
    ]
    cut = scene.with_pattern_cut(apex, bond)
    assert scene.cuts == 0 and cut.cuts == 1 and len(cut.pieces()) == 4
    result = voussoir.analyze(cut)
    assert result.stands
    internal = np.all(result.interface_blocks >= 0, axis=1)
    assert int(internal.sum()) == 5
    to_apex = np.asarray(apex) - result.interface_centroid[internal]
    assert np.max(np.abs(np.sum(result.interface_normal[internal] * to_apex, axis=1))) < 1e-9
    assert voussoir.Scene.from_json(cut.to_json()).pieces() == cut.pieces()
    with pytest.raises(voussoir.InputError, match="cut 0 targets 'nope', which is not a piece"):
        scene.with_pattern_cut(apex, bond, target="nope")


def cli_error(*args):
    done = subprocess.run([BIN, *args], capture_output=True, text=True)
    assert done.returncode == 2, done
    return done.stderr.strip()


def test_errors_are_exceptions_with_the_cli_messages(tmp_path):
    missing = tmp_path / "missing.json"
    with pytest.raises(voussoir.FileError) as e:
        voussoir.Scene.from_file(missing)
    assert isinstance(e.value, OSError)
    assert str(e.value) in cli_error("analyze", str(missing))

    broken = tmp_path / "broken.json"
    broken.write_text('{"blocks": [')
    with pytest.raises(voussoir.InputError) as e:
        voussoir.Scene.from_file(broken)
    assert isinstance(e.value, ValueError)
    assert str(e.value) in cli_error("analyze", str(broken))

    scene = voussoir.Scene.from_file(DATA / "compas_assembly/arch_assembly.json")
    with pytest.raises(voussoir.InputError, match="the scene has no block named 'nope'"):
        voussoir.analyze(scene, supports=["nope"])
    with pytest.raises(voussoir.InputError, match="friction_model: 'coulomb' is not one of"):
        voussoir.analyze(scene, friction_model="coulomb")
    with pytest.raises(voussoir.InputError, match="friction coefficient -1"):
        voussoir.analyze(scene, mu=-1.0)
    open_box = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]), [[0, 2, 1], [0, 1, 3]])
    with pytest.raises(voussoir.InputError, match="block 'lid'"):
        voussoir.analyze(voussoir.Scene.from_arrays([open_box], names=["lid"]))
    with pytest.raises(TypeError, match="from_compas takes"):
        voussoir.Scene.from_compas(3.5)


def test_solves_release_the_gil():
    """A Python thread keeps counting while a solve runs: with the GIL held it could not."""
    scene = voussoir.Scene.builtin("wall?courses=10&bricks=15")
    ticks = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks[0] += 1

    worker = threading.Thread(target=count)
    worker.start()
    try:
        before = ticks[0]
        result = voussoir.analyze(scene)
        during = ticks[0] - before
    finally:
        stop.set()
        worker.join()
    assert result.stands
    assert during > 1000, f"the counting thread ran only {during} times during the solve"


def test_dask_study_on_a_local_cluster_equals_the_loop():
    from dask.distributed import Client, LocalCluster

    from voussoir import study

    cases = [(t, mu) for t in (0.05, 0.1, 0.15, 0.2) for mu in (0.3, 0.6)]
    plain = study.run(study.arch, cases)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            distributed = study.run(study.arch, cases, client=client)
    assert distributed == plain
    assert [r["verdict"] for r in plain if r["t_over_r"] == 0.05] == ["needs_tension", "needs_tension"]
    # Thick enough (t/R ≥ 0.15 with 15 voussoirs) and rough enough (μ = 0.6): stands, with a
    # positive horizontal load factor growing with thickness; at μ = 0.3 the springers slide.
    standing = [r for r in plain if r["t_over_r"] >= 0.15 and r["mu"] == 0.6]
    assert [r["verdict"] for r in standing] == ["stands", "stands"]
    assert 0 < standing[0]["load_factor"] < standing[1]["load_factor"]
    assert all(r["verdict"] == "needs_friction" for r in plain if r["t_over_r"] >= 0.15 and r["mu"] == 0.3)


def test_package_docstring_examples_run():
    from voussoir import study

    for module in (voussoir, study):
        failures, tried = doctest.testmod(module, verbose=False)
        assert tried > 0 and failures == 0, module.__name__


def test_readme_python_example_runs(monkeypatch):
    """Every ```pycon block of the README and of the guide (docs/guide/*.md) runs as a doctest."""
    monkeypatch.chdir(ROOT)  # the example's paths are the checkout's
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```pycon\n(.*?)```", text, flags=re.S)
    assert blocks, "the README has no ```pycon example"
    parser, runner = doctest.DocTestParser(), doctest.DocTestRunner(verbose=False)
    for path in [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]:
        name = str(path.relative_to(ROOT))
        blocks = re.findall(r"```pycon\n(.*?)```", path.read_text(), flags=re.S)
        for k, block in enumerate(blocks):
            test = parser.get_doctest(block, {"__file__": str(path)}, f"{name}[{k}]", name, 0)
            runner.run(test)
    assert runner.failures == 0 and runner.tries > 0
