"""From a graph of bodies to a numerics :class:`~poissonkit.numerics.nbody.NBodySystem`."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError
from poissonkit.scene.bodies import BodyModel, ParamValue, pair_params

if TYPE_CHECKING:
    import networkx as nx
    from poissonkit.numerics.nbody import NBodySystem
    from poissonkit.numerics.units import Scales
    from poissonkit.plugin.contributions import PairPotential


@dataclass(frozen=True)
class PairSpec:
    """One interacting pair, resolved: body indices ``i < j``, potential name and parameters."""

    i: int
    j: int
    potential: str
    params: Mapping[str, ParamValue]


def complete(G: nx.Graph) -> nx.Graph:
    """A copy of ``G`` in which every pair of bodies interacts (existing edge data is kept)."""
    H = G.copy()
    for u, v in itertools.combinations(list(H.nodes), 2):
        if not H.has_edge(u, v):
            H.add_edge(u, v)
    return H


def require_graph(G: object) -> nx.Graph:
    """``G`` itself if it is a networkx graph; else an :class:`InputError` naming its type."""
    import networkx as nx  # loaded when a graph is built or checked

    if not isinstance(G, nx.Graph):  # DiGraph and MultiGraph are Graph subclasses too
        raise InputError(f"expected a networkx graph of bodies, got {type(G).__name__} {G!r:.60}")
    return G


def bodies_of(G: nx.Graph) -> list[BodyModel]:
    """Validated body models of every node, in node order."""
    require_graph(G)
    if G.number_of_nodes() == 0:
        raise InputError("the graph has no bodies")
    return [BodyModel.from_attrs(G.nodes[n], str(n)) for n in G.nodes]


@dataclass(frozen=True)
class EdgeSpec:
    """One edge before its parameters are resolved: bodies ``i < j``, potential name (or
    ``None`` if neither the edge nor the graph names one) and the given parameters, with
    ``1``/``2`` suffixes already referring to bodies ``i``/``j``."""

    i: int
    j: int
    potential: str | None
    params: Mapping[str, ParamValue]
    #: True if the edge names its own potential (a listed pair), False if it is a default.
    own_potential: bool = True


def edges_of(G: nx.Graph, default_potential: str | None = None,
             default_params: Mapping[str, ParamValue] | None = None) -> list[EdgeSpec]:
    """The interacting pairs of ``G`` (every pair if it has no edges), unresolved.

    An edge's ``potential``/``params`` attributes override the graph defaults
    (``G.graph["potential"]``, ``G.graph["params"]``), which override ``default_potential`` /
    ``default_params``. Parameters suffixed ``1``/``2`` in an edge's ``params`` refer to the
    endpoint named by the edge attribute ``first`` (body 1) and the other one (body 2); without
    ``first``, body 1 is the endpoint that comes first in node order. Pairs are stored as
    ``i < j`` (node order), suffixes swapped as needed.
    """
    require_graph(G)
    index = {n: k for k, n in enumerate(G.nodes)}
    edges = list(G.edges(data=True))
    if not edges:
        edges = [(u, v, {}) for u, v in itertools.combinations(G.nodes, 2)]
    base_potential = G.graph.get("potential", default_potential)
    base_params = {**dict(default_params or {}), **dict(G.graph.get("params") or {})}
    out: list[EdgeSpec] = []
    for u, v, data in edges:
        i, j = index[u], index[v]
        own = dict(data.get("params") or {})
        if i > j:
            i, j = j, i
        if data.get("first") is not None and index[data["first"]] != i:
            own = {_swap_suffix(k): val for k, val in own.items()}
        out.append(EdgeSpec(i, j, data.get("potential", base_potential), {**base_params, **own},
                            own_potential=data.get("potential") is not None))
    return out


def resolve(edge: EdgeSpec, bodies: list[BodyModel], potential: str | None = None) -> PairSpec:
    """Resolve an edge with its own potential (or ``potential``) and body-derived parameters.

    Parameters the chosen potential does not know are dropped only when they came from a
    different potential's defaults; unknown names given for this potential raise.
    """
    from poissonkit.plugin import potential as lookup_potential

    name = potential or edge.potential
    where = f"pair ({bodies[edge.i].name}, {bodies[edge.j].name}): "
    if name is None:
        raise InputError(f"{where}no potential (give default_potential or an edge 'potential')")
    entry = lookup_potential(name)
    given = dict(edge.params)
    if potential is not None and potential != edge.potential:
        known = {p.name for p in entry.params}
        given = {k: v for k, v in given.items() if k in known}
    params = pair_params(entry, bodies[edge.i], bodies[edge.j], given, where=where)
    return PairSpec(edge.i, edge.j, name, params)


def pairs_of(G: nx.Graph, bodies: list[BodyModel] | None = None,
             default_potential: str | None = None,
             default_params: Mapping[str, ParamValue] | None = None) -> list[PairSpec]:
    """Resolve every edge of ``G`` into a :class:`PairSpec` (see :func:`edges_of`)."""
    bodies = bodies if bodies is not None else bodies_of(G)
    return [resolve(e, bodies) for e in edges_of(G, default_potential, default_params)]


def _swap_suffix(key: str) -> str:
    if key.endswith("1"):
        return key[:-1] + "2"
    if key.endswith("2"):
        return key[:-1] + "1"
    return key


def auto_scales(bodies: list[BodyModel], pairs: Sequence[PairSpec] | None = None) -> Scales:
    """Internal units for a scene of these bodies (see :mod:`poissonkit.numerics.units`).

    Length: the smallest centre distance (or the largest body size for a single body); mass: the
    mean mass; energy: :func:`energy_scale`; time follows as ``L sqrt(M / E)``.

    Parameters
    ----------
    bodies
        The scene's bodies.
    pairs
        Its resolved pairs; ``None`` when they are not known yet (then only the scales that
        registered potentials declare are used, see :func:`energy_scale`).
    """
    from poissonkit.numerics.units import Scales

    pos = np.array([b.r for b in bodies], float)
    length = 0.0
    if len(bodies) > 1:
        length = _smallest_distance(pos)
    if not length > 0 or not math.isfinite(length):
        length = max((b.bounding_radius for b in bodies), default=0.0) or 1.0
    mass = float(np.mean([b.mass for b in bodies]))
    return Scales.from_energy(length, mass, energy_scale(bodies, pairs, length))


def _smallest_distance(pos: np.ndarray) -> float:
    """Smallest distance between two of the points (a k-d tree beyond a few hundred)."""
    if len(pos) <= 512:  # the dense form, as it always was (same numbers)
        d = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
        d[np.diag_indices(len(pos))] = np.inf
        return float(d.min())
    from scipy.spatial import cKDTree

    dist, _nearest = cKDTree(pos).query(pos, k=2)
    return float(dist[:, 1].min())


#: Relative orientations ``(c1, c2, c3)`` at which a potential is evaluated for the energy
#: unit: axes along the line of centres (aligned, opposed) and across it (parallel, opposed).
_ORIENTATIONS = ((1.0, 1.0, 1.0), (1.0, -1.0, -1.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0))


def energy_scale(bodies: Sequence[BodyModel], pairs: Sequence[PairSpec] | None,
                 length: float) -> float:
    """The energy unit [J] of a scene, from the interactions it has.

    1. Potentials that declare ``energy_scale`` (``PairPotential.energy_scale``, e.g. the
       dipole energy of the strongest magnets, or ``G M^2 / L`` of gravity): the largest value
       they give for these bodies at ``length``. With ``pairs`` the potentials present in them
       are asked, otherwise every registered potential.
    2. Otherwise the largest ``|U(length)|`` of the potentials present, each evaluated with the
       parameters of its pairs (a parameter read from the bodies at the largest magnitude any
       body has) at four orientations (axes along and across the line of centres, aligned and
       opposed).
    3. Where all of those are zero: the kinetic energy of the initial state, or 1 J.
    """
    from poissonkit.plugin.contributions import PairPotential
    from poissonkit.plugin.manager import entries

    registered = entries("potential")
    if pairs is None:
        present = [e for e in registered.values() if isinstance(e, PairPotential)]
    else:
        present = [registered[name] for name in dict.fromkeys(p.potential for p in pairs)
                   if isinstance(registered.get(name), PairPotential)]
    declared = [e.energy_scale(list(bodies), length) for e in present
                if e.energy_scale is not None]
    values = [float(v) for v in declared if v is not None and math.isfinite(v) and v > 0]
    if values:
        return max(values)
    if pairs:
        largest = _largest_pair_energy(bodies, pairs, length)
        if largest > 0:
            return largest
    kinetic = sum(float(np.dot(b.p, b.p)) / (2 * b.mass) for b in bodies)
    kinetic += sum(0.5 * b.alpha * float(np.dot(b.m, b.m)) for b in bodies
                   if b.alpha is not None and b.m is not None)
    return kinetic if kinetic > 0 and math.isfinite(kinetic) else 1.0


def _largest_pair_energy(bodies: Sequence[BodyModel], pairs: Sequence[PairSpec],
                         length: float) -> float:
    """Largest ``|U(length)|`` over the distinct (potential, parameters) of ``pairs``."""
    from poissonkit.plugin import potential as lookup

    strongest: dict[str, float] = {}  # attribute -> value of largest magnitude over bodies
    seen: set[tuple[str, tuple[tuple[str, str], ...]]] = set()
    largest = 0.0
    for p in pairs:
        entry = lookup(p.potential)
        params = dict(p.params)
        for name, attr, _which in entry.body_params:
            if attr not in strongest:
                vals = [v for v in (b.attr(attr) for b in bodies) if isinstance(v, float)]
                strongest[attr] = max(vals, key=abs) if vals else math.nan
            if name in params and math.isfinite(strongest[attr]):
                params[name] = strongest[attr]
        key = (p.potential, tuple(sorted((k, repr(v)) for k, v in params.items())))
        if key in seen:
            continue
        seen.add(key)
        largest = max(largest, _pair_energy(entry, params, length))
    return largest


def _pair_energy(entry: PairPotential, params: Mapping[str, object], length: float) -> float:
    """Largest finite ``|U(length, c1, c2, c3)|`` over :data:`_ORIENTATIONS` (0 if none)."""
    orientations = _ORIENTATIONS[2:3] if entry.orientation == "none" else _ORIENTATIONS
    out = 0.0
    if entry.expr is not None:
        expr = entry.expr(dict(params))
        symbols = {s.name: s for s in expr.free_symbols}
        for c in orientations:
            values = dict(zip(("r", "c1", "c2", "c3"), (length, *c)))
            try:
                u = float(expr.subs({symbols[k]: v for k, v in values.items() if k in symbols}))
            except (TypeError, ValueError):  # a symbol left over: no number to take
                continue
            if math.isfinite(u):
                out = max(out, abs(u))
    elif entry.kernel is not None:
        f = entry.kernel(dict(params))
        for c in orientations:
            u = float(f(length, *c)[0])
            if math.isfinite(u):
                out = max(out, abs(u))
    return out


def from_graph(G: nx.Graph, cutoff: float | None = None, default_potential: str | None = None,
               default_params: Mapping[str, ParamValue] | None = None,
               scales: Scales | str | None = "auto") -> NBodySystem:
    """Build a numerics ``NBodySystem`` from a graph of bodies.

    Parameters
    ----------
    G
        Nodes carry body attributes (:mod:`poissonkit.scene.bodies`), edges the interacting
        pairs (all pairs if the graph has no edges).
    cutoff
        Pairs farther apart than this [m] are skipped by the numerics (``None``: never).
    default_potential, default_params
        Potential of edges without their own ``potential`` attribute.
    scales
        Internal units: a :class:`~poissonkit.numerics.units.Scales`, ``"auto"`` (default,
        :func:`auto_scales`) or ``None`` (integrate in SI numbers as given).

    Returns
    -------
    NBodySystem
        Use :func:`initial_state` for the matching initial state vector.
    """
    bodies = bodies_of(G)
    pair = uniform_graph_pair(G, bodies, default_potential, default_params)
    if pair is not None:  # every pair alike: one AllPairs, no pair list (O(N) set-up)
        return all_pairs_system(bodies, pair, cutoff=cutoff, scales=scales)
    pairs = pairs_of(G, bodies, default_potential, default_params)
    return system_of(bodies, pairs, cutoff=cutoff, scales=scales)


def uniform_graph_pair(G: nx.Graph, bodies: list[BodyModel],
                       default_potential: str | None = None,
                       default_params: Mapping[str, ParamValue] | None = None
                       ) -> PairSpec | None:
    """The pair of :func:`uniform_all_pairs` when every pair of ``G`` interacts alike: ``G``
    has no edges or all ``N(N-1)/2`` of them, none with its own data, and the graph's default
    potential (see :func:`edges_of`) gives every pair the same parameters up to those read
    from the bodies. ``None`` otherwise (then :func:`pairs_of` lists the pairs).

    The system :func:`all_pairs_system` builds from it is the one :func:`system_of` builds
    from the full pair list; only the set-up differs (O(N) instead of O(N²)).
    """
    import networkx as nx  # G is a networkx graph: the module is loaded already

    n = G.number_of_nodes()
    if G.is_directed() or G.is_multigraph() or G.number_of_edges() not in (0, n * (n - 1) // 2):
        return None
    if G.number_of_edges() and (nx.number_of_selfloops(G)
                                or any(data for _u, _v, data in G.edges(data=True))):
        return None
    potential = G.graph.get("potential", default_potential)
    if potential is None:
        return None
    params = {**dict(default_params or {}), **dict(G.graph.get("params") or {})}
    return uniform_all_pairs(bodies, potential, params)


def system_of(bodies: list[BodyModel], pairs: Sequence[PairSpec], cutoff: float | None = None,
              scales: Scales | str | None = "auto") -> NBodySystem:
    """The ``NBodySystem`` of resolved bodies and pairs (see :func:`from_graph`).

    Parameters that a potential takes from each body (``PairPotential.body_params``, e.g.
    gravity's masses) and whose value is the body's own are left to the numerics, which read
    them per pair from the bodies: then all such pairs share one compiled kernel, and a group
    of pairs that joins every two of its bodies with the same potential becomes one
    ``AllPairs`` (cell list with a cutoff, orientation-free fast path) instead of a pair list.
    """
    from poissonkit.numerics.nbody import AllPairs, Body, Interaction, NBodySystem
    from poissonkit.plugin import potential as lookup

    if isinstance(scales, str) and scales == "auto":
        scales = auto_scales(bodies, pairs)
    attrs: dict[int, dict[str, float]] = {k: {} for k in range(len(bodies))}
    groups: dict[tuple, list[tuple[int, int]]] = {}
    order: list[tuple] = []
    for p in pairs:
        entry = lookup(p.potential)
        params = dict(p.params)
        for name, attr, which in entry.body_params:
            k = p.i if which == 1 else p.j
            value = bodies[k].attr(attr)
            # a number the pair takes from its body is read per body by the numerics (any
            # attribute name); a vector stays a pair parameter
            if name in params and isinstance(value, float) and params[name] == value:
                del params[name]
                if attr not in ("mass", "alpha"):
                    attrs[k][attr] = value
        key = (p.potential, tuple(sorted(params.items())))
        if key not in groups:
            groups[key] = []
            order.append(key)
        groups[key].append((p.i, p.j))
    # the numerics read an attribute column for every body: give it to each body that has it,
    # not only to those whose pairs took it (a planned or listed pair of another potential)
    read = {a for values in attrs.values() for a in values}
    for k, b in enumerate(bodies):
        for attr in read - attrs[k].keys():
            value = b.attr(attr)
            if isinstance(value, float):
                attrs[k][attr] = value
    inter: list[AllPairs | Interaction] = []
    for key in order:
        name, items = key
        edges = groups[key]
        members = sorted({k for e in edges for k in e})
        complete = len(edges) == len(members) * (len(members) - 1) // 2 and len(members) > 2
        # fixed-fixed pairs would add a constant to the energy: keep those groups as pair lists
        if complete and len(edges) == len(set(edges)) and not any(bodies[k].fixed
                                                                   for k in members):
            inter.append(AllPairs(name, dict(items), members=members))
        else:
            inter.extend(Interaction(i, j, name, dict(items)) for i, j in edges)
    nb = [Body(b.name, b.mass, alpha=b.alpha, fixed=b.fixed,
               position=b.r if b.fixed else None,
               axis=b.nu if (b.fixed and b.is_top) else None,
               attributes=attrs[k]) for k, b in enumerate(bodies)]
    return NBodySystem(nb, inter, cutoff=cutoff, scales=scales)


def uniform_all_pairs(bodies: list[BodyModel], potential: str,
                      given: Mapping[str, ParamValue] | None = None) -> PairSpec | None:
    """The pair (0, 1) with its resolved parameters, when every pair of ``bodies`` interacting
    through ``potential`` differs from it only in parameters read from the bodies
    (``body_params``, numbers on every body); ``None`` otherwise (fixed bodies, fewer than three
    bodies, a parameter filled per pair by the ``<base>1``/``<base>2`` convention from an
    attribute whose value differs between bodies).

    Then :func:`all_pairs_system` builds the same system as :func:`system_of` of every pair,
    without listing the pairs. The check reads each body once: O(N).
    """
    from poissonkit.plugin import potential as lookup

    if len(bodies) < 3 or any(b.fixed for b in bodies):
        return None
    entry = lookup(potential)
    given = dict(given or {})
    bound = {name for name, _attr, _which in entry.body_params if name not in given}
    for name, attr, _which in entry.body_params:
        if name in bound and not all(isinstance(b.attr(attr), float) for b in bodies):
            return None
    for param in entry.params:
        if (param.name not in given and param.name not in bound and param.name[-1:] in "12"
                and not _same_on_every_body(bodies, param.name[:-1])):
            return None
    where = f"pair ({bodies[0].name}, {bodies[1].name}): "
    return PairSpec(0, 1, potential, pair_params(entry, bodies[0], bodies[1], given,
                                                 where=where))


def _same_on_every_body(bodies: Sequence[BodyModel], attr: str) -> bool:
    """True if every body has the same value of ``attr`` (or none has it): then a parameter
    ``<attr>1``/``<attr>2`` filled from the bodies is the same for every pair."""
    first = bodies[0].attr(attr)
    return all(b.attr(attr) == first for b in bodies)


def all_pairs_system(bodies: list[BodyModel], pair: PairSpec, cutoff: float | None = None,
                     scales: Scales | str | None = "auto") -> NBodySystem:
    """The system in which every pair of ``bodies`` interacts like ``pair`` (from
    :func:`uniform_all_pairs`): one ``AllPairs`` whose body-read parameters come from each
    body, built in O(N) (the same system :func:`system_of` builds from the full pair list)."""
    from poissonkit.numerics.nbody import AllPairs, Body, NBodySystem
    from poissonkit.plugin import potential as lookup

    if isinstance(scales, str) and scales == "auto":
        scales = auto_scales(bodies, [pair])
    entry = lookup(pair.potential)
    shared = dict(pair.params)
    attrs: dict[int, dict[str, float]] = {k: {} for k in range(len(bodies))}
    for name, attr, which in entry.body_params:
        first = bodies[pair.i if which == 1 else pair.j]
        if name in shared and shared[name] == first.attr(attr):
            del shared[name]
            if attr not in ("mass", "alpha"):
                for k, b in enumerate(bodies):
                    attrs[k][attr] = float(b.attr(attr))  # type: ignore[arg-type]
    nb = [Body(b.name, b.mass, alpha=b.alpha, fixed=False, attributes=attrs[k])
          for k, b in enumerate(bodies)]
    inter = AllPairs(pair.potential, dict(sorted(shared.items())),
                     members=list(range(len(bodies))))
    return NBodySystem(nb, [inter], cutoff=cutoff, scales=scales)


def state_arrays(bodies: list[BodyModel]) -> dict[str, np.ndarray]:
    """SI initial state of every body as (N, 3) arrays ``r``, ``p``, ``nu``, ``m`` (zero rows
    for the axis and angular momentum of point masses)."""
    zero = (0.0, 0.0, 0.0)
    return {
        "r": np.array([b.r for b in bodies], float),
        "p": np.array([b.p for b in bodies], float),
        "nu": np.array([b.nu if b.is_top else zero for b in bodies], float),
        "m": np.array([b.m if b.is_top else zero for b in bodies], float),
    }


def initial_state(G: nx.Graph, system: NBodySystem) -> np.ndarray:
    """The state vector of ``system`` (built by :func:`from_graph` from ``G``) at t = 0."""
    return state_of(bodies_of(G), system)


def state_of(bodies: list[BodyModel], system: NBodySystem) -> np.ndarray:
    """The state vector of ``system`` for the initial state of ``bodies`` (SI → internal)."""
    a = state_arrays(bodies)
    si = system.scales is not None
    return np.asarray(system.pack(a["r"], a["p"], a["nu"], a["m"], si=si, normalize=True),
                      dtype=float)
