"""Forces written into compas objects (``Analysis.write_forces``).

compas_assembly's ``Assembly`` (and compas_cra's ``CRA_Assembly``, a subclass) keep contacts on
the graph's edges: ``graph.edge_attribute((u, v), "interfaces")`` is a list of
``compas_assembly.datastructures.Interface`` with ``points``, ``frame`` (its z axis points from
u into v), ``size``, ``mesh`` and ``forces`` — per point a dict ``c_np`` (compression),
``c_nn`` (tension), ``c_u``, ``c_v`` (friction along the frame's x and y axes), the force on v.
compas_cra's solvers write the same fields; its viewers and ``rbe_solve`` read them.
"""

from __future__ import annotations

from typing import Any


def _node_keys(graph) -> dict:
    """Node key by the name voussoir gives the block (compas node keys as text)."""
    return {str(key): key for key in graph.nodes()}


def _interface(result, row: int, points: list, forces: list, flip: bool):
    """One compas Interface from row ``row`` of ``result``'s interface arrays."""
    from compas.datastructures import Mesh
    from compas.geometry import Frame
    from compas_assembly.datastructures import Interface

    origin = [float(x) for x in result.interface_centroid[row]]
    u = [float(x) for x in result.interface_u[row]]
    v = [float(x) for x in result.interface_v[row]]
    if flip:
        # The edge runs b -> a: the normal turns over (x, y = v, u) and the forces are those on
        # a, the opposite of those on b: c_u' = -c_v, c_v' = -c_u along the swapped axes.
        u, v = v, u
        forces = [{"c_np": f["c_np"], "c_nn": f["c_nn"], "c_u": -f["c_v"], "c_v": -f["c_u"]} for f in forces]
    mesh = Mesh.from_vertices_and_faces(points, [list(range(len(points)))])
    return Interface(
        size=float(result.interface_area[row]), points=points, frame=Frame(origin, u, v), forces=forces, mesh=mesh
    )


def write_forces(result, assembly) -> dict[str, Any]:
    """Writes ``result``'s interfaces and forces into ``assembly`` (see the module docs).

    Each block pair's ``interfaces`` become voussoir's (compas' own may differ in points and
    count, and forces belong to the points they were solved at); an edge is added where compas
    has none, in the direction of voussoir's normal. Interfaces with the ground plane have no
    edge and are counted only. Edges where voussoir finds no contact keep their interfaces and
    are listed. Returns ``{"interfaces", "edges_added", "ground_interfaces",
    "edges_without_contact"}``.
    """
    graph = getattr(assembly, "graph", None)
    if graph is None or not hasattr(graph, "edge_attribute"):
        raise TypeError(f"write_forces takes a compas_assembly Assembly or CRA_Assembly, not a {type(assembly).__name__}")
    if any(graph.node_attribute(key, "element") is not None for key in graph.nodes()):
        raise TypeError(
            "write_forces writes into compas_assembly Assemblies (and compas_cra's); a compas_dem "
            "BlockModel's contacts are not written yet: use Analysis.to_compas_json() for an Assembly"
        )
    keys = _node_keys(graph)
    names = result.block_names
    pairs = result.interface_blocks
    owner = result.point_interface
    points_all = result.points
    forces_all = result.point_forces
    by_row: dict[int, list[int]] = {}
    for k, row in enumerate(owner):
        by_row.setdefault(int(row), []).append(k)
    written, added, ground = 0, 0, 0
    replaced = set()
    for row, (a, b) in enumerate(pairs):
        if a < 0 or b < 0:
            ground += 1
            continue
        try:
            u, v = keys[names[a]], keys[names[b]]
        except KeyError as missing:
            raise ValueError(f"write_forces: block {missing} of the analysis is not a node of this assembly") from None
        if graph.has_edge((u, v)):
            edge, flip = (u, v), False
        elif graph.has_edge((v, u)):
            edge, flip = (v, u), True
        else:
            graph.add_edge(u, v)
            edge, flip, added = (u, v), False, added + 1
        ks = by_row.get(row, [])
        points = [[float(x) for x in points_all[k]] for k in ks]
        forces = [dict(zip(("c_np", "c_nn", "c_u", "c_v"), (float(x) for x in forces_all[k]))) for k in ks]
        interface = _interface(result, row, points, forces, flip)
        if edge not in replaced:
            graph.edge_attribute(edge, "interfaces", [])
            replaced.add(edge)
        graph.edge_attribute(edge, "interfaces").append(interface)
        written += 1
    without = [edge for edge in graph.edges() if edge not in replaced]
    return {"interfaces": written, "edges_added": added, "ground_interfaces": ground, "edges_without_contact": without}
