"""Cross-check voussoir's statics against compas_cra's RBE solver (IPOPT) on the BRG reference assemblies in assets/compas.

Set-up (once): python3 -m venv /tmp/cra && /tmp/cra/bin/pip install compas_cra==0.8.0
Run:           /tmp/cra/bin/python scripts/cross_check_compas_cra.py [path/to/voussoir]

For each compas Assembly file: compas_cra's `rbe_solve_native` (the seed's penalty QP as
compas_cra builds it: w_t = 1e6, an 8-sided friction pyramid, mu = 0.84, on the interfaces stored
in the file) and `voussoir analyze --mu 0.84 --json` (pyramid8, its own interface detection). Both are compared relative to
the total free weight W: total tension, and the net normal force of every block pair found by
both. Prints a table; writes nothing.
"""

import json
import os
import subprocess
import sys
import tempfile
import time

from compas.data import json_load
from compas_cra.equilibrium import rbe_solve_native

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
DATA = os.path.join(ROOT, "assets", "compas")
FILES = [
    "compas_assembly/stack_assembly.json",
    "compas_assembly/arch_assembly.json",
    "compas_assembly/wall_assembly.json",
    "compas_assembly/crossvault_assembly.json",
    "compas_cra/armadillo_cra.json",
]
MU = 0.84


def compas_side(path):
    assembly = json_load(path)
    start = time.time()
    rbe_solve_native(assembly, mu=MU, density=1.0, verbose=False)
    seconds = time.time() - start
    weight = 0.0
    for node in assembly.graph.nodes():
        if not assembly.graph.node_attribute(node, "is_support"):
            weight += assembly.graph.node_attribute(node, "block").volume()
    pairs, tension = {}, 0.0
    for u, v in assembly.graph.edges():
        net = 0.0
        for interface in assembly.graph.edge_attribute((u, v), "interfaces"):
            for f in interface.forces or []:
                net += f["c_np"] - f["c_nn"]
                tension += f["c_nn"]
        pairs[frozenset((str(u), str(v)))] = net
    return pairs, tension / weight, weight, seconds


def voussoir_side(binary, path):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "report.json")
        start = time.time()
        subprocess.run([binary, "analyze", path, "--mu", str(MU), "--json", out], capture_output=True)
        seconds = time.time() - start
        report = json.load(open(out))
    weight = report["free_weight"]
    pairs = {}
    for i in report["interfaces"]:
        key = frozenset((i["a"], i["b"]))
        pairs[key] = pairs.get(key, 0.0) + i["normal_force"]
    return pairs, report["tension_ratio"], weight, report["stands"], seconds


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "voussoir"
    )
    print("| file | pairs (both) | compas tension / W | voussoir tension / W (stands) | max |Δ net normal| / W | "
          "median |Δ| / W, pairs > 1e-3 W | compas s | voussoir s |")
    print("|---|---|---|---|---|---|---|---|")
    for rel in FILES:
        path = os.path.join(DATA, rel)
        cp, ct, cw, cs = compas_side(path)
        vp, vt, vw, stands, vs = voussoir_side(binary, path)
        common = [k for k in cp if k in vp]
        diffs = sorted(abs(cp[k] / cw - vp[k] / vw) for k in common)
        big = sorted(abs(cp[k] / cw - vp[k] / vw) for k in common if abs(cp[k] / cw) > 1e-3)
        median = big[len(big) // 2] if big else float("nan")
        print(f"| {rel} | {len(common)} of {len(cp)} / {len(vp)} | {ct:.2e} | {vt:.2e} ({stands}) | "
              f"{diffs[-1] if diffs else float('nan'):.2e} | {median:.2e} | {cs:.2f} | {vs:.2f} |")


if __name__ == "__main__":
    main()
