"""Graph builders: chains, rings, lattices, random clusters, and completion of any user graph.

Every builder returns a :class:`networkx.Graph` whose nodes are ``0..n-1`` carrying body
attributes (see :mod:`poissonkit.scene.bodies`: a copy of ``body`` plus the position ``r`` and,
for tops, the axis ``nu``) and whose edges are the interacting pairs. ``G.graph["potential"]``
and ``G.graph["params"]`` hold the default pair potential; an edge may override them with its
own ``potential`` and ``params`` attributes.

``interactions="complete"`` (default) makes every pair interact (long-range forces);
``"neighbours"`` keeps only the structural edges (nearest neighbours of the chain, ring or
lattice).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.errors import InputError
from poissonkit.validation import count
from poissonkit.scene.bodies import BodyModel

if TYPE_CHECKING:
    import networkx as nx

_INTERACTIONS = ("complete", "neighbours")


def _unit(v: Sequence[float], what: str) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(a))
    if a.shape != (3,) or not math.isfinite(n) or n == 0.0:
        raise InputError(f"{what} must be a non-zero 3-vector, got {v!r}")
    return a / n


def _is_top(body: Mapping[str, Any]) -> bool:
    return body.get("alpha") is not None or body.get("inertia") is not None


def _new_graph(potential: str | None, params: Mapping[str, Any] | None, kind: str) -> nx.Graph:
    import networkx as nx  # loaded when a graph is built or checked

    G = nx.Graph(assembly=kind)
    if potential is not None:
        G.graph["potential"] = potential
    G.graph["params"] = dict(params or {})
    return G


def _add_bodies(G: nx.Graph, body: Mapping[str, Any], positions: np.ndarray,
                axes: np.ndarray | None) -> None:
    if "mass" not in body:
        raise InputError("body template needs a 'mass' (kg)")
    top = _is_top(body)
    for k, r in enumerate(positions):
        attrs = dict(body)
        attrs.setdefault("name", f"b{k}")
        if len(positions) > 1 and "name" in body:
            attrs["name"] = f"{body['name']}{k}"
        attrs["r"] = tuple(float(x) for x in r)
        if top and axes is not None:
            attrs["nu"] = tuple(float(x) for x in axes[k])
        BodyModel.from_attrs(attrs)  # fail early, naming the body and the attribute
        G.add_node(k, **attrs)


def _finish(G: nx.Graph, structural: list[tuple[int, int]], interactions: str) -> nx.Graph:
    if interactions not in _INTERACTIONS:
        raise InputError(f"interactions must be one of {_INTERACTIONS}, got {interactions!r}")
    if interactions == "complete":
        G.add_edges_from(itertools.combinations(G.nodes, 2))
    else:
        G.add_edges_from(structural)
    return G


def chain(n: int, spacing: float, body: Mapping[str, Any], *, direction: Sequence[float] = (1, 0, 0),
          axes: str = "aligned", potential: str | None = None,
          params: Mapping[str, Any] | None = None, interactions: str = "complete",
          origin: Sequence[float] = (0, 0, 0)) -> nx.Graph:
    """Bodies on a straight line.

    Parameters
    ----------
    n
        Number of bodies (≥ 1).
    spacing
        Centre-to-centre distance [m].
    body
        Node attributes shared by every body (mass, alpha, magnet parameters, ...).
    direction
        Direction of the line.
    axes
        ``"aligned"`` (every axis along the line: head to tail), ``"alternating"`` (along the
        line, alternating sign) or ``"transverse"`` (perpendicular to the line, all parallel).
    potential, params
        Default pair potential name and parameters (stored on the graph).
    interactions
        ``"complete"`` or ``"neighbours"``.
    origin
        Position of the first body [m].
    """
    n = _count(n)
    spacing = _length(spacing, "spacing")
    d = _unit(direction, "direction")
    pos = np.asarray(origin, float) + spacing * np.arange(n)[:, None] * d
    if axes == "aligned":
        ax = np.tile(d, (n, 1))
    elif axes == "alternating":
        ax = np.array([d * (-1) ** k for k in range(n)])
    elif axes == "transverse":
        ax = np.tile(_perpendicular(d), (n, 1))
    else:
        raise InputError(f"axes must be 'aligned', 'alternating' or 'transverse', got {axes!r}")
    G = _new_graph(potential, params, "chain")
    _add_bodies(G, body, pos, ax)
    return _finish(G, [(k, k + 1) for k in range(n - 1)], interactions)


def ring(n: int, radius: float, body: Mapping[str, Any], *, axes: str = "tangent",
         potential: str | None = None, params: Mapping[str, Any] | None = None,
         interactions: str = "complete", center: Sequence[float] = (0, 0, 0)) -> nx.Graph:
    """Bodies evenly spaced on a circle (radius ``ring_radius`` in scenes) in the xy-plane.

    ``axes``: ``"tangent"`` (head to tail around the ring), ``"radial"`` or ``"normal"`` (all
    along +z).
    """
    n = _count(n, minimum=2)
    radius = _length(radius, "radius")
    phi = 2 * math.pi * np.arange(n) / n
    radial = np.stack([np.cos(phi), np.sin(phi), np.zeros(n)], axis=1)
    tangent = np.stack([-np.sin(phi), np.cos(phi), np.zeros(n)], axis=1)
    pos = np.asarray(center, float) + radius * radial
    choice = {"tangent": tangent, "radial": radial, "normal": np.tile([0.0, 0.0, 1.0], (n, 1))}
    if axes not in choice:
        raise InputError(f"axes must be one of {sorted(choice)}, got {axes!r}")
    G = _new_graph(potential, params, "ring")
    _add_bodies(G, body, pos, choice[axes])
    return _finish(G, [(k, (k + 1) % n) for k in range(n)] if n > 2 else [(0, 1)], interactions)


def lattice(shape: Sequence[int], spacing: float, body: Mapping[str, Any], *,
            axes: str = "aligned", axis: Sequence[float] = (0, 0, 1),
            potential: str | None = None, params: Mapping[str, Any] | None = None,
            interactions: str = "complete", origin: Sequence[float] = (0, 0, 0)) -> nx.Graph:
    """A square (2D) or cubic (3D) lattice of bodies.

    Parameters
    ----------
    shape
        ``(nx, ny)`` in the xy-plane, or ``(nx, ny, nz)``.
    spacing
        Lattice constant [m].
    axes
        ``"aligned"`` (every axis along ``axis``) or ``"checkerboard"`` (sign alternating with
        the parity of the site: the antiferromagnetic ground-state guess).
    """
    shape = tuple(int(s) for s in shape)
    if len(shape) not in (2, 3) or min(shape) < 1:
        raise InputError(f"lattice shape must be 2 or 3 positive integers, got {shape!r}")
    spacing = _length(spacing, "spacing")
    sites = list(itertools.product(*(range(s) for s in shape)))
    idx = {s: k for k, s in enumerate(sites)}
    coords = np.zeros((len(sites), 3))
    coords[:, : len(shape)] = np.array(sites, float)
    pos = np.asarray(origin, float) + spacing * coords
    a = _unit(axis, "axis")
    if axes == "aligned":
        ax = np.tile(a, (len(sites), 1))
    elif axes == "checkerboard":
        ax = np.array([a * (-1) ** sum(s) for s in sites])
    else:
        raise InputError(f"axes must be 'aligned' or 'checkerboard', got {axes!r}")
    G = _new_graph(potential, params, f"lattice{len(shape)}d")
    _add_bodies(G, body, pos, ax)
    structural = []
    for s in sites:
        for dim in range(len(shape)):
            t = list(s)
            t[dim] += 1
            if tuple(t) in idx:
                structural.append((idx[s], idx[tuple(t)]))
    return _finish(G, structural, interactions)


def random_cluster(n: int, radius: float, body: Mapping[str, Any], *, seed: int = 0,
                   min_distance: float | None = None, axes: str = "random",
                   potential: str | None = None, params: Mapping[str, Any] | None = None,
                   interactions: str = "complete", max_tries: int = 10000) -> nx.Graph:
    """``n`` bodies placed uniformly at random in a ball, no two closer than ``min_distance``.

    Parameters
    ----------
    radius
        Radius of the ball holding the centres [m].
    seed
        Seed of the random generator (same seed, same cluster).
    min_distance
        Minimum centre distance [m]; default: twice the body's bounding radius (so bodies
        never overlap), which then must be known from ``radius``/``length`` of ``body``.
    axes
        ``"random"`` (uniform on the sphere) or ``"aligned"`` (+z).
    max_tries
        Rejection-sampling attempts per body before giving up with an :class:`InputError`.
    """
    n = _count(n)
    radius = _length(radius, "radius")
    if min_distance is None:
        template = BodyModel.from_attrs({**body, "r": (0, 0, 0), "nu": (0, 0, 1)}, "template")
        if template.bounding_radius == 0.0:
            raise InputError("random_cluster: give min_distance (the body has no size)")
        min_distance = 2.0 * template.bounding_radius
    min_distance = _length(min_distance, "min_distance")
    rng = np.random.default_rng(count(seed, "random_cluster: seed"))
    pos: list[np.ndarray] = []
    # accepted centres hashed by cells of side min_distance: a trial is compared with the
    # centres of its 27 neighbouring cells only (the same test, O(n) instead of O(n^2))
    cells: dict[tuple[int, int, int], list[np.ndarray]] = {}
    for k in range(n):
        for _ in range(max_tries):
            x = rng.uniform(-radius, radius, 3)
            if x @ x <= radius * radius and _far_from(x, cells, min_distance):
                pos.append(x)
                cells.setdefault(_cell(x, min_distance), []).append(x)
                break
        else:
            raise InputError(f"random_cluster: could not place body {k} of {n} with "
                             f"min_distance {min_distance:g} m in a ball of radius {radius:g} m; "
                             "increase radius")
    if axes == "random":
        ax = rng.normal(size=(n, 3))
        ax /= np.linalg.norm(ax, axis=1)[:, None]
    elif axes == "aligned":
        ax = np.tile([0.0, 0.0, 1.0], (n, 1))
    else:
        raise InputError(f"axes must be 'random' or 'aligned', got {axes!r}")
    G = _new_graph(potential, params, "random_cluster")
    _add_bodies(G, body, np.array(pos), ax)
    if interactions == "neighbours":
        # structural edges: pairs closer than twice the minimum distance
        return _finish(G, _near_pairs(np.array(pos), 2 * min_distance), interactions)
    return _finish(G, [], interactions)


def _cell(x: np.ndarray, side: float) -> tuple[int, int, int]:
    # a slightly larger cell keeps two centres closer than ``side`` in neighbouring cells
    # despite the rounding of x / side
    c = np.floor(x / (side * (1 + 1e-9)))
    return (int(c[0]), int(c[1]), int(c[2]))


def _far_from(x: np.ndarray, cells: Mapping[tuple[int, int, int], list[np.ndarray]],
              min_distance: float) -> bool:
    """True if ``x`` is at least ``min_distance`` from every hashed centre (only centres in
    the neighbouring cells can be closer)."""
    cx, cy, cz = _cell(x, min_distance)
    for key in itertools.product((cx - 1, cx, cx + 1), (cy - 1, cy, cy + 1), (cz - 1, cz, cz + 1)):
        for y in cells.get(key, ()):
            if not np.linalg.norm(x - y) >= min_distance:
                return False
    return True


def _near_pairs(P: np.ndarray, reach: float) -> list[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i < j`` in lexicographic order, with centres closer than ``reach``
    (candidates from a k-d tree, then the exact test)."""
    from scipy.spatial import cKDTree

    found = cKDTree(P).query_pairs(reach * (1 + 1e-9), output_type="ndarray")  # round-off margin
    candidates = sorted((int(min(a, b)), int(max(a, b))) for a, b in found)
    return [(i, j) for i, j in candidates if np.linalg.norm(P[i] - P[j]) < reach]


def _count(n: Any, minimum: int = 1) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < minimum:
        raise InputError(f"number of bodies must be an integer ≥ {minimum}, got {n!r}")
    return int(n)


def _length(x: Any, what: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a number [m], got {x!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{what} must be finite and > 0 [m], got {x!r}")
    return v


def _perpendicular(d: np.ndarray) -> np.ndarray:
    trial = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    v = np.cross(d, trial)
    return v / np.linalg.norm(v)
