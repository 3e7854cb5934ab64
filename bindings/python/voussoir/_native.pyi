"""Type stubs of voussoir's extension module (voussoir._native). Units: m, kg, N, s; z up."""

from os import PathLike
from typing import Any, Literal, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

Supports = Union[Literal["lowest"], Sequence[str]]
FrictionModel = Literal["pyramid8", "pyramid", "cone", "box4", "box"]
Solver = Literal["structured", "clarabel"]

class InputError(ValueError):
    """Bad input: a file, block, face or setting voussoir cannot use (the message names it)."""

class FileError(OSError):
    """A file voussoir cannot read or write (the message names it)."""

class Scene:
    """A design: blocks, supports, material and cut history. Immutable."""

    @staticmethod
    def from_file(path: Union[str, PathLike[str]]) -> Scene:
        """voussoir JSON, compas Assembly / CRA_Assembly / BlockModel JSON, a compas mesh list,
        legacy compas_rbe JSON, OBJ or STL."""
    @staticmethod
    def from_json(text: str, source: str = "<json>") -> Scene:
        """JSON text in any JSON format from_file reads; `source` names it in errors."""
    @staticmethod
    def from_compas(obj: Any) -> Scene:
        """A compas_assembly Assembly, compas_cra CRA_Assembly, compas_dem BlockModel or a list
        of compas Meshes, through its data. Blocks are named by the node keys (as text)."""
    @staticmethod
    def builtin(spec: str) -> Scene:
        """A built-in scene, e.g. "arch?n=15&t=0.1" (the command line's builtin: specs)."""
    @staticmethod
    def from_arrays(
        blocks: Sequence[tuple[npt.ArrayLike, Sequence[Sequence[int]]]],
        *,
        names: Optional[Sequence[str]] = None,
        supports: Optional[Sequence[int]] = None,
        density: Optional[float] = None,
        ground: bool = False,
        name: str = "arrays",
    ) -> Scene:
        """Blocks as (vertices (n, 3), faces counter-clockwise from outside); `supports` are
        indices; `density` in kg/m³."""
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str:
        """What errors call this scene: its file, or what built it."""
    @property
    def block_names(self) -> list[str]: ...
    @property
    def support_names(self) -> list[str]: ...
    @property
    def ground(self) -> bool: ...
    @property
    def cuts(self) -> int:
        """Number of cuts in the history."""
    def pieces(self) -> list[str]:
        """The blocks an analysis sees: the cut history replayed."""
    def with_cut(self, point: Sequence[float], normal: Sequence[float], target: Optional[str] = None) -> Scene:
        """A plane cut appended to the history (the `-` pieces on the side the normal points away
        from); `target` cuts one piece only."""
    def with_pattern_cut(
        self,
        apex: Sequence[float],
        segments: Sequence[Sequence[Sequence[float]]],
        target: Optional[str] = None,
    ) -> Scene:
        """A pattern cut appended to the history: each segment [p, q] (in order) cuts with the
        plane through apex, p and q, only the pieces the cone from the apex through the segment
        meets; `target` restricts it to one piece and the pieces cut from it."""
    def with_supports(self, supports: Supports) -> Scene: ...
    def to_json(self) -> str:
        """voussoir scene JSON, with the cut history."""
    def write(self, path: Union[str, PathLike[str]]) -> None:
        """to_json() written atomically."""
    def __len__(self) -> int: ...

class Analysis:
    """The result of analyze(): verdict, graded ratios, forces (N) on interfaces and points."""

    verdict: Literal[
        "stands", "needs_tension", "needs_friction", "needs_tension_and_friction", "crushes", "unsupported",
        "unresolved",
    ]
    stands: bool
    crushing: Optional[dict[str, Any]]
    """With `strength`: needed, strength (Pa), utilization, interface, a, b; else None."""
    tension_ratio: float
    """Minimum total tension / total free weight."""
    friction_excess_ratio: float
    """Minimum total friction excess / total free weight."""
    max_friction_utilization: float
    free_weight: float
    """Total weight of the free blocks, N."""
    friction_coefficient: float
    friction_model: str
    solver_status: str
    residual: float
    """Largest equilibrium residual of any block, N."""
    kinematic_verdict: Optional[Literal["stands", "fails", "undecided"]]
    dynamic_stands: Optional[bool]
    block_names: list[str]
    block_is_support: list[bool]
    support_reaction: tuple[float, float, float]
    """Total force of the supports and the ground on the free blocks, N."""
    interface_blocks: npt.NDArray[np.int64]
    """(m, 2) blocks a, b of each interface (indices into block_names; -1 the ground)."""
    interface_area: npt.NDArray[np.float64]
    interface_normal: npt.NDArray[np.float64]
    """(m, 3) unit normals from a into b."""
    interface_u: npt.NDArray[np.float64]
    interface_v: npt.NDArray[np.float64]
    interface_centroid: npt.NDArray[np.float64]
    normal_force: npt.NDArray[np.float64]
    """(m,) net normal force, compression positive, N."""
    friction_force: npt.NDArray[np.float64]
    friction_utilization: npt.NDArray[np.float64]
    resultant: npt.NDArray[np.float64]
    """(m, 3) resultant force on b, N."""
    points: npt.NDArray[np.float64]
    """(P, 3) force points."""
    point_interface: npt.NDArray[np.int64]
    """(P,) the interface row of each force point."""
    point_forces: npt.NDArray[np.float64]
    """(P, 4) c_np, c_nn, c_u, c_v per point (compas' fields), N, acting on b."""
    timings: dict[str, float]
    def to_dict(self) -> dict[str, Any]:
        """The JSON report of `voussoir analyze --json`."""
    def to_html(self, mode: Optional[Literal["compression", "friction", "vectors"]] = None, threshold: Optional[float] = None) -> str:
        """`voussoir report`'s self-contained HTML page of this analysis."""
    def _repr_html_(self) -> str:
        """Jupyter's display: the report in an iframe."""
    def to_compas_json(self) -> str:
        """compas 2 Assembly JSON with the interfaces and forces (`analyze --compas-out`)."""
    def write_forces(self, assembly: Any) -> dict[str, Any]:
        """Writes the interfaces and forces into a compas_assembly Assembly / compas_cra
        CRA_Assembly (edge `interfaces`) or a compas_dem BlockModel (edge `contacts`, as
        FrictionContacts) in compas' own fields; returns a summary."""

def analyze(
    scene: Scene,
    *,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
    strict: bool = False,
    kinematic: bool = False,
    dynamic: bool = False,
) -> Analysis:
    """Interfaces detected and equilibrium solved (GIL released); on request the kinematic
    check and the drop test beside it."""

def detect_interfaces(
    scene: Scene, *, supports: Optional[Supports] = None, ground: Optional[bool] = None
) -> dict[str, Any]:
    """block_names, blocks (m, 2), area, centroid, normal, u, v, polygons."""

def settle(
    scene: Scene,
    *,
    moves: Optional[list[str]] = None,
    increments: Optional[int] = None,
    quasi_static: bool = False,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> dict[str, Any]:
    """`voussoir settle --json`: supports, path_movement, model_size, quasi_static (and exact,
    rapier unless `quasi_static`), each with outcome, stages, mechanism, steps."""

def tolerance(
    scene: Scene,
    *,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> dict[str, Any]:
    """`voussoir analyze --tolerance`: shrink (m) and tilt (degrees) margins, each with
    `value`, `relative`, `governing`; `block_size`, `solves`."""

def load_factor(
    scene: Scene,
    *,
    direction: Optional[float] = None,
    directions: Optional[int] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> dict[str, Any]:
    """`voussoir robustness --json`: λ* of the live loads, of 1 g along `direction`, or in the
    worst horizontal direction."""

def sequence(
    scene: Scene,
    *,
    order: Union[Literal["bottom-up", "from-supports"], Sequence[str], None] = None,
    props: bool = False,
    search: bool = False,
    dynamic: bool = False,
    kinematic: bool = False,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> dict[str, Any]:
    """`voussoir sequence --json`: every step of an assembly order checked."""

def drop(
    scene: Scene,
    *,
    duration: Optional[float] = None,
    dt: Optional[float] = None,
    engine: Optional[str] = None,
    split_impacts: Optional[bool] = None,
    rest_when_admissible: Optional[bool] = None,
    floor: Optional[bool] = None,
    by_states: Optional[bool] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
) -> dict[str, Any]:
    """The drop test's result on rapier (default) or the exact engine ("exact")."""

def shake(
    scene: Scene,
    *,
    pulse: Optional[str] = None,
    sine: Optional[str] = None,
    record: Optional[str] = None,
    scale: float = 1.0,
    direction: float = 0.0,
    engine: Optional[str] = None,
    duration: Optional[float] = None,
    dt: Optional[float] = None,
    shake_supports: Optional[Sequence[str]] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
) -> dict[str, Any]:
    """`voussoir shake --json`: the static load factor and each engine's run, its trace as
    numpy arrays (times, ground_g, rotation, drift)."""

def repair(
    scene: Scene,
    *,
    cuts: Optional[Sequence[int]] = None,
    max_turn: Optional[float] = None,
    robust: bool = True,
    seed: Optional[int] = None,
    particles: Optional[int] = None,
    iterations: Optional[int] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> tuple[Scene, dict[str, Any]]:
    """`voussoir repair`: the design with its cuts (all, or `cuts`) moved and turned until it
    stands, then (`robust`) stands most safely; and the report (`repair --json`). The same
    `seed` gives the same design."""

def infill(
    scene: Scene,
    *,
    density_range: Optional[tuple[float, float]] = None,
    objective: Literal["stand", "robust"] = "stand",
    cells: Optional[int] = None,
    azimuth: Optional[float] = None,
    directions: Optional[int] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> tuple[Optional[Scene], dict[str, Any]]:
    """`voussoir infill`: densities within `density_range` (kg/m³) that make the design stand —
    the lightest ("stand") or carrying the largest horizontal load ("robust"), per block or per
    cell (`cells` per axis); the infilled design (None when no density holds it, the report's
    `mechanism` then says why) and the report (`infill --json`)."""

def decompose(
    scene: Scene,
    *,
    blocks: Optional[int] = None,
    max_size: Optional[float] = None,
    strategy: Literal["courses", "thrust", "pattern"] = "courses",
    center: Optional[Sequence[float]] = None,
    axis: Optional[Sequence[float]] = None,
    stagger: bool = True,
    apex: Optional[Sequence[float]] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> tuple[Scene, dict[str, Any]]:
    """`voussoir decompose`: a cut history for a source shape (exactly one of `blocks` and
    `max_size`; beds through the axis `center` + s·`axis` for arches; "pattern": a running bond
    extruded to `apex`); the design and
    `{courses, pieces, max_size, rounds}` (`rounds` for "thrust")."""

def report(
    scene: Scene,
    *,
    path: Union[str, PathLike[str], None] = None,
    mode: Optional[Literal["compression", "friction", "vectors"]] = None,
    threshold: Optional[float] = None,
    robustness: bool = False,
    direction: Optional[float] = None,
    directions: Optional[int] = None,
    dynamic: bool = False,
    engine: Optional[Literal["rapier", "exact"]] = None,
    duration: Optional[float] = None,
    settle: bool = False,
    moves: Optional[Sequence[str]] = None,
    mu: Optional[float] = None,
    friction_model: Optional[FrictionModel] = None,
    solver: Optional[Solver] = None,
    supports: Optional[Supports] = None,
    ground: Optional[bool] = None,
    density: Optional[float] = None,
    strength: Optional[float] = None,
) -> str:
    """`voussoir report`: one self-contained HTML page (returned; written to `path` when given)."""
