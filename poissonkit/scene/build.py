"""From a validated :class:`~poissonkit.scene.schema.Scene` to a graph and a ready run."""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import PoissonkitError, SceneError
from poissonkit.numerics.runspec import RunSpec
from poissonkit.scene.bodies import BodyModel
from poissonkit.scene.schema import Scene

if TYPE_CHECKING:
    import networkx as nx

    from poissonkit.numerics.events import Contact
    from poissonkit.numerics.fields.contact import SolidContact
    from poissonkit.plugin.contributions import Assembly
    from poissonkit.numerics.nbody import NBodySystem
    from poissonkit.numerics.units import Scales


def scene_graph(scene: Scene, *, edges: bool = True) -> nx.Graph:
    """The scene's bodies (nodes) and interacting pairs (edges) as a networkx graph.

    Node attributes follow :mod:`poissonkit.scene.bodies`; edges carry ``potential``,
    ``params`` and ``first`` for listed pairs; ``G.graph`` holds the default potential.

    Parameters
    ----------
    scene
        A validated scene.
    edges
        ``False``: the bodies only, with no edges, built without ever holding the
        ``N(N-1)/2`` edges of a scene (or an assembly with ``interactions = "complete"``) in
        which every pair interacts; for callers that need the bodies alone.
    """
    from poissonkit.plugin import assembly
    from poissonkit.scene.assembly import complete

    if scene.assembly is not None:
        name, params = scene.assembly
        entry = assembly(name)
        try:
            resolved = entry.resolve_params(params)
            if not edges and _joins_every_pair(entry, resolved):
                resolved = {**resolved, "interactions": "neighbours"}
            G = entry.build(**resolved)
        except PoissonkitError as exc:
            raise SceneError(f"assembly: {exc}") from None
        if scene.assembly_overrides or scene.assembly_bodies:
            from poissonkit.scene.overrides import apply_overrides

            apply_overrides([G.nodes[n] for n in G.nodes], scene.assembly_overrides,
                            scene.assembly_bodies)
    else:
        import networkx as nx  # only when a graph is built: a run's start-up skips it
        G = nx.Graph()
        for k, body in enumerate(scene.bodies):
            G.add_node(k, **dict(body))
        if edges and scene.pairs_mode == "all":
            G = complete(G)
    if scene.potential is not None:
        G.graph["potential"] = scene.potential
    G.graph["params"] = {**dict(G.graph.get("params") or {}), **dict(scene.potential_params)}
    if not edges:
        G.remove_edges_from(list(G.edges))
        return G
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


def _joins_every_pair(entry: Assembly, resolved: Mapping[str, object]) -> bool:
    """True if the assembly takes an ``interactions`` parameter and it asks for every pair
    (``"complete"``, the convention of the registered graph builders)."""
    return (any(p.name == "interactions" for p in entry.params)
            and resolved.get("interactions") == "complete")


def every_pair_alike(scene: Scene) -> bool:
    """True if every pair of the scene's bodies interacts through the scene's one default
    potential (``pairs = "all"``, no listed pair, no planner; an assembly asked for
    ``interactions = "complete"``). Such a scene is built without listing its pairs when the
    pair parameters read from the bodies allow it (:func:`build_scene`)."""
    from poissonkit.plugin import assembly

    if scene.planner is not None or scene.pairs_mode != "all" or scene.pairs:
        return False
    if scene.assembly is None:
        return scene.potential is not None
    name, params = scene.assembly
    entry = assembly(name)
    try:
        resolved = entry.resolve_params(params)
    except PoissonkitError:
        return False
    return _joins_every_pair(entry, resolved)


@dataclass(frozen=True)
class BuiltScene:
    """A scene turned into numbers: what runs and sweeps integrate.

    Attributes
    ----------
    system
        The numerics system (:class:`~poissonkit.numerics.nbody.NBodySystem`).
    y0
        Initial state vector (internal units).
    bodies
        The validated body models, in node order (after the planner's changes, if any).
    t_end, step
        Duration and fixed step (``None``: adaptive) in internal time units.
    plan
        The planner's report at t = 0 (``None`` without a ``[planner]``).
    """

    system: NBodySystem
    y0: np.ndarray
    bodies: list[BodyModel]
    t_end: float
    step: float | None
    plan: Mapping[str, object] | None = None

    @property
    def scales(self) -> Scales | None:
        """The system's internal units (``None``: SI numbers as given)."""
        return self.system.scales

    @property
    def time_unit(self) -> float:
        """SI value of the internal time unit [s]."""
        return self.scales.time if self.scales is not None else 1.0

    @property
    def length_unit(self) -> float:
        """SI value of the internal length unit [m]."""
        return self.scales.length if self.scales is not None else 1.0


@contextmanager
def _named_errors(scene: Scene) -> Iterator[None]:
    """Re-raise any typed error while building ``scene`` as a :class:`SceneError` naming it.

    Floating-point overflow of huge values (``1e308`` m) is not printed as numpy warnings:
    the checks that follow refuse the non-finite results with typed errors, and an
    ``ArithmeticError`` of Python numbers becomes one too.
    """
    try:
        with _quiet_floats():
            yield
    except SceneError:
        raise
    except PoissonkitError as exc:
        raise SceneError(f"scene {scene.name!r}: {exc}") from None
    except ArithmeticError as exc:  # ZeroDivisionError, OverflowError of huge values
        raise SceneError(f"scene {scene.name!r}: a value is out of floating-point range "
                         f"({exc})") from None


def _quiet_floats() -> np.errstate:
    return np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore")


def build_scene(scene: Scene, scales: Scales | str | None = "auto") -> BuiltScene:
    """Build a scene's system, initial state and internal units: the one path runs
    (:func:`build_run`) and sweeps (:class:`poissonkit.sweeps.targets.TomlScene`) share.

    Parameters
    ----------
    scene
        A validated scene.
    scales
        ``"auto"`` (units from the scene, :func:`poissonkit.scene.assembly.auto_scales`), given
        :class:`~poissonkit.numerics.units.Scales` (e.g. those of a sweep's first point, so
        every point shares compiled kernels) or ``None`` (SI numbers as given).

    Returns
    -------
    BuiltScene

    Raises
    ------
    SceneError
        Naming the scene, for anything that fails while building (a missing parameter, ...).
    """
    from poissonkit.scene.assembly import bodies_of, edges_of, pairs_of, state_of, system_of

    direct = _all_pairs_direct(scene, scales)
    if direct is not None:
        return direct
    with _quiet_floats():  # positions of huge assemblies overflow; checked as they are built
        G = scene_graph(scene)
    plan = None
    with _named_errors(scene):
        bodies = bodies_of(G)
        if scene.planner is not None:
            from poissonkit.scene.planner import Planner

            planner = Planner.from_spec(scene.planner)
            bodies, pairs, chosen = planner.prepare(bodies, edges_of(G))
            plan = chosen.report()
        else:
            pairs = pairs_of(G, bodies)
        system = system_of(bodies, pairs, cutoff=scene.cutoff, scales=scales)
        y0 = state_of(bodies, system)
    return _built(scene, system, y0, bodies, plan)


def _all_pairs_direct(scene: Scene, scales: Scales | str | None) -> BuiltScene | None:
    """A scene whose bodies all interact through one potential, with per-pair parameters
    that differ only by what they read from the bodies, built without listing its pairs
    (``None`` if it is not one): set-up in O(N) time and memory."""
    from poissonkit.scene.assembly import all_pairs_system, bodies_of, state_of, uniform_graph_pair

    if not every_pair_alike(scene):
        return None
    with _named_errors(scene):
        if scene.assembly is None:
            bodies = [BodyModel.from_attrs(b, str(b.get("name", k)))
                      for k, b in enumerate(scene.bodies)]
            import networkx as nx  # only when a graph is built: a run's start-up skips it
            G = nx.Graph(potential=scene.potential, params=dict(scene.potential_params))
        else:
            G = scene_graph(scene, edges=False)
            bodies = bodies_of(G)
        pair = uniform_graph_pair(G, bodies) if len(bodies) > 2 else None
        if pair is None:
            return None
        system = all_pairs_system(bodies, pair, cutoff=scene.cutoff, scales=scales)
        y0 = state_of(bodies, system)
    return _built(scene, system, y0, bodies)


def _built(scene: Scene, system: NBodySystem, y0: np.ndarray, bodies: list[BodyModel],
           plan: Mapping[str, object] | None = None) -> BuiltScene:
    """The built scene, its duration and step converted to the system's time unit."""
    if scene.fields:
        from poissonkit.scene.fields import with_scene_fields

        with _named_errors(scene):
            system = with_scene_fields(system, y0, bodies, scene.fields, scene.units)
    unit = system.scales.time if system.scales is not None else 1.0
    step = None if scene.run.step is None else scene.run.step / unit
    return BuiltScene(system, y0, bodies, scene.run.duration / unit, step, plan)


def build_run(scene: Scene) -> RunSpec:
    """Everything ``poissonkit run`` needs to integrate the scene.

    The system is built by :func:`build_scene` (the same path as sweeps); if the scene has a
    ``[planner]`` the magnet pairs get the cheapest model within its force tolerance at t = 0
    (the plan is in ``metadata["plan"]``; re-planning during the run is
    :func:`poissonkit.scene.planner.run_planned`). Durations and steps are converted to the
    system's internal time unit; ``metadata`` keeps the SI values.
    """
    metadata: dict[str, object] = {"scene": scene.name, "source": scene.source,
                                   "description": scene.description,
                                   "duration_s": scene.run.duration, "step_s": scene.run.step}
    if not scene.units.is_si:  # the scene's own units: what its outputs speak
        from poissonkit.scene.units import run_metadata

        metadata.update(run_metadata(scene))
    built = build_scene(scene)
    if built.plan is not None:
        metadata["plan"] = built.plan
    system = built.system
    events: tuple[Contact | SolidContact, ...] = () if scene.run.contact == "ignore" \
        else contact_events(built.bodies, built.length_unit)
    if scene.run.contact != "ignore" and system.fields:  # field sources are solids too
        from poissonkit.scene.fields import field_contact_events

        events = (*events, *field_contact_events(system, built.bodies, built.length_unit))
    metadata["time_unit_s"] = built.time_unit
    if system.fields:
        metadata["fields"] = [{"source": f.name, **dict(f.info)} for f in system.fields]
    metadata["scales"] = None if system.scales is None else {
        "length": system.scales.length, "mass": system.scales.mass, "time": system.scales.time}
    return RunSpec(
        name=scene.name, system=system, y0=built.y0, t_end=built.t_end,
        method=scene.run.method, step=built.step,
        tol=scene.run.tol, metadata=metadata, events=events, energy_tol=scene.run.energy_tol,
        save_every=scene.run.save_every, max_steps=scene.run.max_steps,
        options=dict(scene.run.options),
        save_dt=None if scene.run.save_dt is None else scene.run.save_dt / built.time_unit)


def contact_events(bodies: Sequence[BodyModel], length_unit: float = 1.0
                   ) -> tuple[Contact, ...]:
    """The default event of a scene: :class:`~poissonkit.numerics.events.Contact` of its
    finite-size bodies (magnets with ``radius`` and ``length``: cylinders; ``radius`` only:
    balls), in the system's internal length unit; ``()`` with fewer than two such bodies."""
    from poissonkit.numerics.events import BodyShape, Contact

    shapes = []
    for b in bodies:
        mag = b.magnet
        radius = float(mag.get("radius", 0.0))
        if radius > 0:
            shapes.append(BodyShape(b.name, radius / length_unit,
                                    float(mag.get("half_length", 0.0)) / length_unit))
    return (Contact(tuple(shapes)),) if len(shapes) >= 2 else ()
