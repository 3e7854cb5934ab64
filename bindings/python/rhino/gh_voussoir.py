#! python3
# r: compas>=2.4
"""voussoir as a Grasshopper Python 3 component (Rhino 8).

NOT RUN IN voussoir's CI (no Rhino/Grasshopper on Linux): the package it calls is tested by
tests/python; this component is not. Install the wheel into Rhino's CPython first (see
analyze_selected.py).

Inputs (set the type hints in the component):
    blocks    list of closed Mesh (one per block)
    supports  list of int — indices of the fixed blocks (empty: the lowest ones)
    mu        float — friction coefficient (default 0.6)
Outputs:
    verdict   str — "stands", "needs_tension", "needs_friction", …
    tension   float — minimum total tension / free weight
    excess    float — minimum total friction excess / free weight
    polygons  list of Polyline — the interfaces
    colors    list of Color — blue compression, red tension, orange friction > 80 % of μ
"""

import System.Drawing
import Rhino.Geometry as rg

import voussoir


def arrays(mesh):
    mesh = mesh.DuplicateMesh()
    mesh.Weld(3.14159)
    mesh.UnifyNormals()
    if mesh.Volume() < 0:
        mesh.Flip(True, True, True)
    vertices = [[p.X, p.Y, p.Z] for p in mesh.Vertices]
    faces = [[f.A, f.B, f.C] if f.IsTriangle else [f.A, f.B, f.C, f.D] for f in mesh.Faces]
    return vertices, faces


scene = voussoir.Scene.from_arrays([arrays(m) for m in blocks], supports=list(supports or []))  # noqa: F821
result = voussoir.analyze(scene, mu=mu or 0.6, supports=None if supports else "lowest")  # noqa: F821
verdict, tension, excess = result.verdict, result.tension_ratio, result.friction_excess_ratio
polygons, colors = [], []
owner = result.point_interface
for row in range(len(result.interface_blocks)):
    corners = [rg.Point3d(*result.points[k]) for k in range(len(owner)) if owner[k] == row]
    if len(corners) < 3:
        continue
    polygons.append(rg.Polyline(corners + corners[:1]))
    if result.point_forces[owner == row, 1].sum() > 1e-6 * result.free_weight:
        colors.append(System.Drawing.Color.Red)
    elif result.friction_utilization[row] > 0.8:
        colors.append(System.Drawing.Color.Orange)
    else:
        colors.append(System.Drawing.Color.Blue)
