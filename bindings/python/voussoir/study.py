"""Parameter studies: one function per case, run by a plain loop or on Dask.

A study is a list of cases (tuples of arguments) and a function of one case that returns a
dict of plain numbers; :func:`run` maps the function over the cases — here in a loop, on a
``dask.distributed`` cluster when given a client (a ``LocalCluster`` on one machine, or
``Client("tcp://scheduler:8786")`` for a cluster: the same code). Results come back in the
order of the cases, so a study gives the same table wherever it runs.

>>> from voussoir import study
>>> rows = study.run(study.arch, [(0.15, 0.6, 15), (0.05, 0.6, 15)])
>>> [(r["t_over_r"], r["verdict"]) for r in rows]
[(0.15, 'stands'), (0.05, 'needs_tension')]
"""

from __future__ import annotations

from typing import Any, Callable, Iterable, Optional, Sequence


def arch(t_over_r: float, mu: float, blocks: int = 15, radius: float = 1.0) -> dict[str, Any]:
    """One semicircular voussoir arch (``builtin:arch``) of thickness ``t_over_r`` × radius
    with ``blocks`` voussoirs, analysed with friction ``mu``: the verdict, the graded ratios,
    and for an arch that stands its horizontal load factor across its span (λ*, in g)."""
    from . import Scene, analyze, load_factor

    scene = Scene.builtin(f"arch?n={blocks}&r={radius}&t={t_over_r * radius}")
    result = analyze(scene, mu=mu)
    row = {
        "t_over_r": t_over_r,
        "mu": mu,
        "blocks": blocks,
        "verdict": result.verdict,
        "tension_ratio": result.tension_ratio,
        "friction_excess_ratio": result.friction_excess_ratio,
        "load_factor": None,
    }
    if result.stands:
        row["load_factor"] = load_factor(scene, mu=mu, direction=0.0)["robustness"]["load_factor"]
    return row


def run(fn: Callable[..., dict], cases: Iterable[Sequence[Any]], client: Optional[Any] = None) -> list[dict]:
    """``fn(*case)`` for every case, in order: a loop without ``client``, else on its Dask
    cluster (``client.map``: each case one task, any worker)."""
    cases = [tuple(c) for c in cases]
    if client is None:
        return [fn(*c) for c in cases]
    futures = client.map(fn, *zip(*cases), pure=True) if cases else []
    return client.gather(futures)
