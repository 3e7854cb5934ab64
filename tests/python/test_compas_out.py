"""The compas 2 Assembly that `voussoir analyze --compas-out` writes, read by the real compas
packages from PyPI (scripts/python_tests makes their virtual environment; nothing is mocked).

Invariants: the file loads as a compas_assembly `Assembly` with one node per block, the same
supports, one compas `Interface` per block-block interface of voussoir's own report, each with
one force per point, and the forces' total compression equal to the report's; compas_cra's own
RBE solver runs on a written file and, like voussoir, finds the arch standing without tension.
"""

import json
import os
import subprocess
from pathlib import Path

import pytest
from compas.data import json_load
from compas_assembly.datastructures import Assembly, Interface

ROOT = Path(__file__).resolve().parents[2]
BIN = os.environ.get("VOUSSOIR_BIN", str(ROOT / "target" / "debug" / "voussoir"))
ARCH = "compas_assembly/arch_assembly.json"


def write(rel, tmp_path):
    """voussoir's compas Assembly file (for every input format) and JSON report of the
    reference file `rel`."""
    out, report = tmp_path / "out.json", tmp_path / "report.json"
    scene = ROOT / "assets" / "compas" / rel
    args = [BIN, "analyze", str(scene), "--compas-out", str(out), "--compas-format", "assembly", "--json", str(report)]
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode in (0, 1), done.stderr
    return json_load(str(out)), json.loads(report.read_text())


def interfaces(assembly):
    return [i for u, v in assembly.graph.edges() for i in assembly.graph.edge_attribute((u, v), "interfaces")]


@pytest.mark.parametrize("rel", [ARCH, "compas_rbe/simple_arch.json", "compas_dem/dem_crossvault.json"])
def test_written_assembly_has_every_block_interface_and_force(rel, tmp_path):
    assembly, report = write(rel, tmp_path)
    assert isinstance(assembly, Assembly)
    assert assembly.graph.number_of_nodes() == len(report["blocks"])
    supports = [n for n in assembly.graph.nodes() if assembly.graph.node_attribute(n, "is_support")]
    assert len(supports) == len(report["supports"])
    names = [assembly.graph.node_attribute(n, "name") for n in sorted(assembly.graph.nodes())]
    assert names == [b["name"] for b in report["blocks"]]
    expected = [i for i in report["interfaces"] if "ground" not in (i["a"], i["b"])]
    found = interfaces(assembly)
    assert len(found) == len(expected)
    assert all(isinstance(i, Interface) and len(i.forces) == len(i.points) for i in found)
    total = sum(f["c_np"] for i in found for f in i.forces)
    assert total == pytest.approx(sum(i["compression"] for i in expected), rel=1e-9)


def test_compas_cra_rbe_solve_runs_on_a_written_file(tmp_path):
    from compas_cra.equilibrium import rbe_solve

    assembly, report = write(ARCH, tmp_path)
    assert report["stands"]
    rbe_solve(assembly, mu=0.84, density=1.0, verbose=False)
    found = interfaces(assembly)
    assert all(len(i.forces) == len(i.points) for i in found)
    compression = sum(f["c_np"] for i in found for f in i.forces)
    tension = sum(f["c_nn"] for i in found for f in i.forces)
    assert compression > 0
    assert tension <= 1e-6 * compression, "compas_cra finds tension where voussoir needs none"
