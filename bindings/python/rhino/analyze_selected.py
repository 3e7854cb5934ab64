#! python3
# r: compas>=2.4
"""voussoir in Rhino 8's ScriptEditor (CPython 3): analyse the selected blocks and draw their
interfaces — blue compression, red tension (the minimum the design would need), orange where
friction is used beyond 80 % of μ — with compas' Rhino scene objects.

NOT RUN IN voussoir's CI (there is no Rhino on Linux): everything this script calls — the
package, Scene.from_arrays, analyze and its arrays — is tested by tests/python; this file is not.

Install once into Rhino's CPython (the wheel built for the Rhino machine's platform with
`maturin build --release -m bindings/python/Cargo.toml -o dist`; "voussoir" on PyPI is another
project, so `# r:` cannot fetch it):
    ~/.rhinocode/py39-rh8/python3.9 -m pip install dist/voussoir_blocks-*.whl

Use: select closed meshes or closed polysurfaces (one per block); blocks on a layer named
"supports" are fixed, else the lowest ones are. Units: the model's, taken as metres.
"""

import Rhino
import rhinoscriptsyntax as rs
import scriptcontext as sc
from compas.colors import Color
from compas.geometry import Polygon
from compas.scene import Scene as DrawingScene

import voussoir

MU = 0.6


def block_arrays(guid):
    """(vertices, faces) of a closed mesh or polysurface, faces counter-clockwise from outside."""
    geometry = rs.coercegeometry(guid)
    if isinstance(geometry, Rhino.Geometry.Brep):
        meshes = Rhino.Geometry.Mesh.CreateFromBrep(geometry, Rhino.Geometry.MeshingParameters.Minimal)
        mesh = Rhino.Geometry.Mesh()
        for part in meshes:
            mesh.Append(part)
    else:
        mesh = geometry.DuplicateMesh()
    mesh.Weld(3.14159)  # one vertex per corner: interfaces need shared planes, not shading normals
    mesh.UnifyNormals()
    if mesh.Volume() < 0:
        mesh.Flip(True, True, True)
    vertices = [[p.X, p.Y, p.Z] for p in mesh.Vertices]
    faces = [[f.A, f.B, f.C] if f.IsTriangle else [f.A, f.B, f.C, f.D] for f in mesh.Faces]
    return vertices, faces


def main():
    guids = rs.GetObjects("Blocks to analyse", rs.filter.mesh | rs.filter.polysurface, preselect=True)
    if not guids:
        return
    names = [str(g) for g in guids]
    supports = [k for k, g in enumerate(guids) if rs.ObjectLayer(g).split("::")[-1].lower() == "supports"]
    scene = voussoir.Scene.from_arrays([block_arrays(g) for g in guids], names=names, supports=supports)
    try:
        result = voussoir.analyze(scene, mu=MU, supports=None if supports else "lowest")
    except voussoir.InputError as error:  # names the block (its Rhino id) and what is wrong
        print(f"voussoir: {error}")
        return
    print(f"voussoir: {result.verdict} — tension {result.tension_ratio:.2e} W, "
          f"friction excess {result.friction_excess_ratio:.2e} W, {len(result.interface_blocks)} interfaces")
    drawing = DrawingScene()
    points, owner = result.points, result.point_interface
    for row in range(len(result.interface_blocks)):
        corners = [list(points[k]) for k in range(len(owner)) if owner[k] == row]
        if len(corners) < 3:
            continue
        tension = result.point_forces[owner == row, 1].sum()
        if tension > 1e-6 * result.free_weight:
            color = Color.red()
        elif result.friction_utilization[row] > 0.8:
            color = Color.orange()
        else:
            color = Color.blue()
        drawing.add(Polygon(corners), color=color)
    drawing.draw()
    sc.doc.Views.Redraw()


if __name__ == "__main__":
    main()
