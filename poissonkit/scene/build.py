"""From a validated :class:`~poissonkit.scene.schema.Scene` to a graph and a ready run."""

from __future__ import annotations

from typing import Any

import networkx as nx

from poissonkit.errors import PoissonkitError, SceneError
from poissonkit.numerics.runspec import RunSpec
from poissonkit.scene.schema import Scene


def scene_graph(scene: Scene) -> nx.Graph:
    """The scene's bodies (nodes) and interacting pairs (edges) as a networkx graph.

    Node attributes follow :mod:`poissonkit.scene.bodies`; edges carry ``potential``,
    ``params`` and ``first`` for listed pairs; ``G.graph`` holds the default potential.
    """
    from poissonkit.plugin import assembly
    from poissonkit.scene.assembly import complete

    if scene.assembly is not None:
        name, params = scene.assembly
        entry = assembly(name)
        try:
            G = entry.build(**entry.resolve_params(params))
        except PoissonkitError as exc:
            raise SceneError(f"assembly: {exc}") from None
        for node in G.nodes:
            G.nodes[node].update(scene.assembly_overrides)
    else:
        G = nx.Graph()
        for k, body in enumerate(scene.bodies):
            G.add_node(k, **dict(body))
        if scene.pairs_mode == "all":
            G = complete(G)
    if scene.potential is not None:
        G.graph["potential"] = scene.potential
    G.graph["params"] = {**dict(G.graph.get("params") or {}), **dict(scene.potential_params)}
    if scene.pairs_mode == "listed":
        G.remove_edges_from(list(G.edges))
    by_name = {G.nodes[n].get("name", str(n)): n for n in G.nodes}
    for k, pair in enumerate(scene.pairs):
        a, b = pair.bodies
        for end in (a, b):
            if end not in by_name:
                raise SceneError(f"interactions.pair[{k}].bodies: unknown body {end!r}; "
                                 f"available: {', '.join(sorted(by_name))}")
        G.add_edge(by_name[a], by_name[b], potential=pair.potential, params=dict(pair.params),
                   first=by_name[a])
    return G


def build_run(scene: Scene) -> RunSpec:
    """Everything ``poissonkit run`` needs to integrate the scene.

    The bodies and pairs are built by :mod:`poissonkit.scene.assembly` (the same path as any assembly); if the
    scene has a ``[planner]`` the magnet pairs get the cheapest model within its force tolerance
    at t = 0 (the plan is in ``metadata["plan"]``; re-planning during the run is
    :func:`poissonkit.scene.planner.run_planned`). Durations and steps are converted to the
    system's internal time unit; ``metadata`` keeps the SI values.
    """
    from poissonkit.scene.assembly import bodies_of, edges_of, pairs_of, state_of, system_of

    G = scene_graph(scene)
    metadata: dict[str, Any] = {"scene": scene.name, "source": scene.source,
                                "description": scene.description,
                                "duration_s": scene.run.duration, "step_s": scene.run.step}
    try:
        bodies = bodies_of(G)
        if scene.planner is not None:
            from poissonkit.scene.planner import Planner

            planner = Planner.from_spec(scene.planner)
            bodies, pairs, plan = planner.prepare(bodies, edges_of(G))
            metadata["plan"] = plan.report()
        else:
            pairs = pairs_of(G, bodies)
        system = system_of(bodies, pairs, cutoff=scene.cutoff, scales="auto")
        y0 = state_of(bodies, system)
    except SceneError:
        raise
    except PoissonkitError as exc:
        raise SceneError(f"scene {scene.name!r}: {exc}") from None
    time_unit = system.scales.time if system.scales is not None else 1.0
    length_unit = system.scales.length if system.scales is not None else 1.0
    events = () if scene.run.contact == "ignore" else contact_events(bodies, length_unit)
    metadata["time_unit_s"] = time_unit
    metadata["scales"] = None if system.scales is None else {
        "length": system.scales.length, "mass": system.scales.mass, "time": system.scales.time}
    return RunSpec(
        name=scene.name, system=system, y0=y0, t_end=scene.run.duration / time_unit,
        method=scene.run.method,
        step=None if scene.run.step is None else scene.run.step / time_unit,
        tol=scene.run.tol, metadata=metadata, events=events, energy_tol=scene.run.energy_tol)


def contact_events(bodies: Any, length_unit: float = 1.0) -> tuple[Any, ...]:
    """The default event of a scene: :class:`~poissonkit.numerics.events.Contact` of its
    finite-size bodies (magnets with ``radius`` and ``length``: cylinders; ``radius`` only:
    balls), in the system's internal length unit; ``()`` with fewer than two such bodies."""
    from poissonkit.numerics.events import BodyShape, Contact

    shapes = []
    for b in bodies:
        mag = getattr(b, "magnet", None) or {}
        radius = float(mag.get("radius", 0.0))
        if radius > 0:
            shapes.append(BodyShape(b.name, radius / length_unit,
                                    float(mag.get("half_length", 0.0)) / length_unit))
    return (Contact(tuple(shapes)),) if len(shapes) >= 2 else ()
