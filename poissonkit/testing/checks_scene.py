"""``check_assembly`` and ``check_scene``: builders of bodies and whole runs.

* An **assembly** builds the same graph twice from the same parameters (deterministic), gives
  nodes that are valid bodies, and answers a bad value of each declared parameter (a string no
  choice has, a negative or zero number) with a typed :class:`~poissonkit.errors.PoissonkitError`
  or a valid graph, never a bare Python or numpy exception.
* A **scene** loads the same run twice (deterministic), and runs clean for its first
  ``steps`` steps: no body overlaps at the start, no event fires, the energy stays within the
  scene's ``energy_tol`` (default :data:`ENERGY_TOL`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from poissonkit.errors import PoissonkitError
from poissonkit.plugin.contributions import Assembly, Param, SceneEntry
from poissonkit.testing.lookup import findings_for

#: Energy tolerance of a scene that declares none.
ENERGY_TOL = 1e-6


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return bool(np.array_equal(np.asarray(a), np.asarray(b)))
    if isinstance(a, Mapping) and isinstance(b, Mapping):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return bool(a == b)


def _graph_rows(G: Any) -> tuple[list[Any], list[Any], dict[str, Any]]:
    nodes = [(n, dict(G.nodes[n])) for n in G.nodes]
    edges = [(u, v, dict(d)) for u, v, d in G.edges(data=True)]
    return nodes, edges, dict(G.graph)


def _bad_values(p: Param) -> list[Any]:
    """Values of ``p`` the builder must refuse with a typed error (or accept)."""
    if p.type == "str":
        return ["__not_a_choice__"]
    if p.type in ("float", "int"):
        return [0, -1] if not p.positive else []
    return []


def check_assembly(assembly: Assembly | str, *, params: Mapping[str, Any] | None = None
                   ) -> None:
    """Check an assembly; raise :class:`CheckFailed` listing every defect.

    Parameters
    ----------
    assembly
        The :class:`~poissonkit.plugin.Assembly` or its registered name.
    params
        Example parameters; required integers not given are 3, required floats 1.0.

    Raises
    ------
    CheckFailed
    """
    from poissonkit.scene.assembly import bodies_of

    entry, out = findings_for(assembly, "assembly", Assembly)
    given = dict(params or {})
    for p in entry.params:  # example values of required numbers: 3 bodies, unit sizes
        if p.name not in given and p.default is None and not p.optional:
            given[p.name] = {"int": 3, "float": 1.0}.get(p.type)
    try:
        resolved = entry.resolve_params(given)
    except PoissonkitError as exc:
        out.add("params", f"the example parameters are refused: {exc} (give params=)")
        out.raise_if_any()
        return
    with out.guard("deterministic"):
        first, second = entry.build(**resolved), entry.build(**resolved)
        if not _same(_graph_rows(first), _graph_rows(second)):
            out.add("deterministic", "two builds from the same parameters differ (seed the "
                                     "random generator from a parameter)")
        with out.guard("bodies"):
            bodies_of(first)
    for p in entry.params:
        for bad in _bad_values(p):
            try:
                entry.build(**entry.resolve_params({**resolved, p.name: bad}))
            except PoissonkitError:
                continue
            except Exception as exc:  # noqa: BLE001 - the defect
                out.add("validation", f"{p.name} = {bad!r} raises {type(exc).__name__} "
                                      f"({exc}), not a typed InputError naming the parameter")
    out.raise_if_any()


def _spec(entry: SceneEntry, params: Mapping[str, Any]) -> Any:
    """The scene's :class:`~poissonkit.numerics.runspec.RunSpec`."""
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.scene.build import build_run

    loaded = entry.load(**entry.resolve_params(dict(params)))
    return loaded if isinstance(loaded, RunSpec) else build_run(loaded)


def check_scene(scene: SceneEntry | str, *, params: Mapping[str, Any] | None = None,
                steps: int = 200) -> None:
    """Check a scene; raise :class:`CheckFailed` listing every defect.

    Parameters
    ----------
    scene
        The :class:`~poissonkit.plugin.SceneEntry` or its registered name.
    params
        Parameters handed to ``load``.
    steps
        Steps of the run checked (the scene's own step; adaptive scenes: ``t_end/steps``).

    Raises
    ------
    CheckFailed
    """
    from poissonkit.numerics import solve

    entry, out = findings_for(scene, "scene", SceneEntry)
    given = dict(params or {})
    try:
        spec, again = _spec(entry, given), _spec(entry, given)
    except Exception as exc:  # noqa: BLE001 - reported
        out.add("load", f"does not load: {type(exc).__name__}: {exc}")
        out.raise_if_any()
        return
    if not (_same(np.asarray(spec.y0), np.asarray(again.y0)) and spec.t_end == again.t_end
            and float(spec.system.energy(spec.y0)) == float(again.system.energy(again.y0))):
        out.add("deterministic", "two loads give different initial states or energies")
    step = spec.step if spec.step is not None else spec.t_end / steps
    t_end = min(spec.t_end, steps * step)
    with out.guard("runs_clean"):
        sol = solve(spec.system, spec.y0, t_end, method=spec.method, step=spec.step,
                    tol=spec.tol, events=spec.events)
        if sol.events:
            ev = sol.events[0]
            out.add("runs_clean", f"{ev.kind} at t = {ev.time:.6g} (internal units) within "
                                  f"the first {steps} steps")
        tol = spec.energy_tol if spec.energy_tol is not None else ENERGY_TOL
        drift = float(np.max(sol.energy_error()))
        if not drift <= tol:
            out.add("runs_clean", f"relative energy error {drift:.3g} over {steps} steps "
                                  f"exceeds the scene's tolerance {tol:g}")
    out.raise_if_any()
