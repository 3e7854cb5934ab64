"""voussoir: rigid-block assemblies from Python — interfaces, equilibrium (the RBE penalty
formulation: minimum tension, minimum friction excess), load factors, assembly sequences and the
rapier drop test, as a fast backend for COMPAS (compas_assembly, compas_cra, compas_dem).

Units: m, kg, N, s; z up; compression positive. Errors about the input raise
:class:`InputError` (a ``ValueError``) or :class:`FileError` (an ``OSError``) with the message
the ``voussoir`` command line prints; a solver that does not converge is not an exception but a
status (``Analysis.solver_status``, ``Analysis.residual``).

>>> import voussoir
>>> arch = voussoir.Scene.builtin("arch?n=15&t=0.15")
>>> result = voussoir.analyze(arch)
>>> result.verdict
'stands'
>>> fx, fy, fz = result.support_reaction   # what the supports carry, N
>>> abs(fz - result.free_weight) < 1e-6 * result.free_weight
True
>>> voussoir.analyze(voussoir.Scene.builtin("arch?n=15&t=0.05")).verdict
'needs_tension'
"""

from ._native import (
    Analysis,
    FileError,
    InputError,
    Scene,
    __version__,
    analyze,
    decompose,
    detect_interfaces,
    drop,
    infill,
    load_factor,
    repair,
    report,
    sequence,
    settle,
    shake,
    tolerance,
)

__all__ = [
    "Analysis",
    "FileError",
    "InputError",
    "Scene",
    "__version__",
    "analyze",
    "decompose",
    "detect_interfaces",
    "drop",
    "infill",
    "load_factor",
    "repair",
    "report",
    "sequence",
    "settle",
    "shake",
    "tolerance",
]
