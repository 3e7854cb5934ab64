"""Forces written into compas objects (``Analysis.write_forces``).

compas_assembly's ``Assembly`` (and compas_cra's ``CRA_Assembly``, a subclass) keep contacts on
the graph's edges: ``graph.edge_attribute((u, v), "interfaces")`` is a list of
``compas_assembly.datastructures.Interface`` with ``points``, ``frame`` (its z axis points from
u into v), ``size`` and ``forces`` — per point a dict ``c_np`` (compression),
``c_nn`` (tension), ``c_u``, ``c_v`` (friction along the frame's x and y axes), the force on v.
compas_cra's solvers write the same fields; its viewers and ``rbe_solve`` read them.

compas_dem's ``BlockModel`` (a compas_model ``Model``) keeps them in the graph's ``contacts``
edge attribute: a list of ``compas_dem.interactions.FrictionContact`` with the same ``points``,
``frame``, ``size`` and ``forces``, from which compas_dem computes its resultant, compression
and friction forces.
"""

from __future__ import annotations

import json
from typing import Any


def data_json(obj) -> str:
    """The JSON ``Scene.from_compas`` reads for a compas object, through its data: for a graph
    of blocks (compas_assembly ``Assembly``, compas_cra ``CRA_Assembly``) only the nodes' blocks
    and supports — voussoir detects the interfaces itself, and serialising the stored ones costs
    ten times more (the Armadillo: 27 ms against 350 ms); for anything else (a compas_dem
    ``BlockModel``, a list of meshes) the whole ``compas.json_dumps``."""
    import compas
    from compas.data import DataEncoder

    nodes = _block_nodes(obj)
    if nodes is None:
        return compas.json_dumps(obj)
    node = {
        str(key): {"block": {"dtype": attr["block"].__dtype__, "data": attr["block"].__data__}, "is_support": bool(attr.get("is_support"))}
        for key, attr in nodes
    }
    data = {"dtype": obj.__dtype__, "data": {"graph": {"data": {"node": node, "edge": {}}}}}
    return json.dumps(data, cls=DataEncoder)


def _block_nodes(obj):
    """The graph's ``(key, attributes)`` pairs when ``obj`` is a graph whose every node holds a
    block (compas_assembly ``Assembly``, compas_cra ``CRA_Assembly``), else ``None``."""
    graph = getattr(obj, "graph", None)
    nodes = list(graph.nodes(data=True)) if graph is not None and hasattr(graph, "nodes") else []
    if not nodes or any(attr.get("block") is None for _, attr in nodes):
        return None
    return nodes


def block_tables(obj):
    """For a graph of blocks (compas_assembly ``Assembly``, compas_cra ``CRA_Assembly``): per
    node its key (as text), whether it is a support, and its block's vertex and face tables as
    compas keeps them (``Mesh.vertex``, ``Mesh.face``) — what ``Scene.from_compas`` reads
    without a JSON round trip (the Armadillo's from_compas: 8.4 ms against 29.8 ms); ``None`` for anything
    else, which goes through ``data_json``."""
    nodes = _block_nodes(obj)
    if nodes is None:
        return None
    blocks = [attr["block"] for _, attr in nodes]
    if not all(isinstance(getattr(b, "vertex", None), dict) and isinstance(getattr(b, "face", None), dict) for b in blocks):
        return None
    return [(str(key), bool(attr.get("is_support")), b.vertex, b.face) for (key, attr), b in zip(nodes, blocks)]


def _node_keys(graph) -> dict:
    """Node key by the name voussoir gives the block (compas node keys as text)."""
    return {str(key): key for key in graph.nodes()}


def _interface(frames: dict, row: int, points: list, forces: list, flip: bool, contact: bool = False):
    """One compas_assembly Interface (or, with ``contact``, a compas_dem FrictionContact) from
    row ``row`` of the interface arrays in ``frames``."""
    from compas.geometry import Frame

    origin, u, v = frames["origin"][row], frames["u"][row], frames["v"][row]
    if flip:
        # The edge runs b -> a: the normal turns over (x, y = v, u) and the forces are those on
        # a, the opposite of those on b: c_u' = -c_v, c_v' = -c_u along the swapped axes.
        u, v = v, u
        forces = [{"c_np": f["c_np"], "c_nn": f["c_nn"], "c_u": -f["c_v"], "c_v": -f["c_u"]} for f in forces]
    if contact:
        from compas_dem.interactions import FrictionContact

        return FrictionContact(points=points, frame=Frame(origin, u, v), size=frames["area"][row], forces=forces)
    from compas_assembly.datastructures import Interface

    # No mesh: compas_assembly's Interface makes it from the points when asked (a third of the
    # cost of writing the Armadillo's 1014 interfaces, otherwise).
    return Interface(size=frames["area"][row], points=points, frame=Frame(origin, u, v), forces=forces)


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
        raise TypeError(
            f"write_forces takes a compas_assembly Assembly, a compas_cra CRA_Assembly or a compas_dem "
            f"BlockModel, not a {type(assembly).__name__}"
        )
    # A compas_model Model (compas_dem's BlockModel): nodes hold elements, edges contacts.
    model = any(graph.node_attribute(key, "element") is not None for key in graph.nodes())
    attribute = "contacts" if model else "interfaces"
    keys = _node_keys(graph)
    # Each array once, as lists (a getter builds its array anew; numpy scalars are slow to index).
    names = result.block_names
    pairs = result.interface_blocks.tolist()
    owner = result.point_interface.tolist()
    points_all = result.points.tolist()
    forces_all = result.point_forces.tolist()
    frames = {
        "origin": result.interface_centroid.tolist(),
        "u": result.interface_u.tolist(),
        "v": result.interface_v.tolist(),
        "area": result.interface_area.tolist(),
    }
    by_row: dict[int, list[int]] = {}
    for k, row in enumerate(owner):
        by_row.setdefault(row, []).append(k)
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
        points = [points_all[k] for k in ks]
        forces = [dict(zip(("c_np", "c_nn", "c_u", "c_v"), forces_all[k])) for k in ks]
        interface = _interface(frames, row, points, forces, flip, contact=model)
        if edge not in replaced:
            graph.edge_attribute(edge, attribute, [])
            replaced.add(edge)
        graph.edge_attribute(edge, attribute).append(interface)
        written += 1
    without = [edge for edge in graph.edges() if edge not in replaced]
    return {"interfaces": written, "edges_added": added, "ground_interfaces": ground, "edges_without_contact": without}
