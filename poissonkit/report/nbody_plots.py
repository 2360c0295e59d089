"""Figures of N-body runs: where the bodies are, how close they come, where the energy goes and
which pair model the planner chose.

Each ``*_axes`` function draws into given (or new) Axes and returns them; the registry entries at
the bottom put them in :data:`poissonkit.report.figures.PLOTS` for runs of an
:class:`~poissonkit.numerics.nbody.NBodySystem`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Protocol, cast, runtime_checkable

import numpy as np

from poissonkit.numerics.nbody import NBodySystem
from poissonkit.report.figures import RunData, register_plot
from poissonkit.report.plotkit import figure, thin
from poissonkit.traits import offers

__all__ = ["HasEnergyParts", "closest_pair_axes", "configuration_axes", "energy_partition",
           "energy_partition_axes", "model_timeline_axes", "positions_si"]

_MM = 1e3
#: Bodies are labelled by name in the configuration figure up to this many (then it is clutter).
MAX_NAMED = 30


@runtime_checkable
class HasEnergyParts(Protocol):
    """A system that splits its energy itself: ``energy_parts(y)`` maps a name
    (``"translational"``, ``"rotational"``, ``"interaction"``, ...) to one value per row [J]."""

    def energy_parts(self, y: np.ndarray) -> Mapping[str, np.ndarray]: ...


def positions_si(system: NBodySystem, y: np.ndarray) -> np.ndarray:
    """Positions of *all* bodies [m], shape ``(n, N, 3)`` (fixed ones constant)."""
    y = np.atleast_2d(y)
    r = system.unpack(y, si=True)["r"].reshape(len(y), -1, 3)
    out = np.empty((len(y), len(system.bodies), 3))
    k = 0
    for i, b in enumerate(system.bodies):
        if b.fixed:
            out[:, i] = np.asarray(b.position if b.position is not None else (0, 0, 0))
        else:
            out[:, i] = r[:, k]
            k += 1
    return out


def _axes_of(system: NBodySystem, y: np.ndarray) -> dict[int, np.ndarray]:
    """Unit axes ``ν`` of the tops at one state, by body index (fixed tops: their fixed axis)."""
    nu = system.unpack(np.atleast_2d(y))["nu"].reshape(-1, 3)
    out: dict[int, np.ndarray] = {}
    k = 0
    for i, b in enumerate(system.bodies):
        if b.fixed:
            if b.axis is not None:
                out[i] = np.asarray(b.axis, dtype=float)
        elif b.alpha is not None:
            out[i] = nu[k]
            k += 1
    return out


def configuration_axes(system: NBodySystem, y: np.ndarray, *, axes: Sequence | None = None):
    """All bodies at the first and last state in the xy and xz projections [mm].

    Paths are thin grey lines, the start a hollow circle, the end a filled one, tops' axes
    arrows at the end, fixed bodies black squares; each body is labelled by name at its end
    (up to :data:`MAX_NAMED` bodies).

    Returns
    -------
    numpy.ndarray of two matplotlib Axes (xy, xz)
    """
    if axes is None:
        _, axs = figure("Configuration at start (○) and end (●)", ncols=2, size=(10, 4.6))
        axes = axs[0]
    y = np.atleast_2d(y)
    # positions of every row of a large system would not fit: at most ~2e6 body positions
    (rows,) = thin(y, limit=_row_limit(2000, len(system.bodies)))
    path = positions_si(system, rows) * _MM
    pos = positions_si(system, y[[0, -1]]) * _MM
    ends = {"start": _axes_of(system, y[0]), "end": _axes_of(system, y[-1])}
    span = float(np.ptp(np.concatenate([path, pos]).reshape(-1, 3), axis=0).max()) or 1.0
    named = len(system.bodies) <= MAX_NAMED
    colors = [f"C{i % 10}" for i in range(len(system.bodies))]
    shown = _drawn(len(system.bodies))
    first_fixed = _first_fixed(system)
    for ax, (a, b), plane in zip(axes, ((0, 1), (0, 2)), ("xy", "xz")):
        for i in shown:
            body = system.bodies[i]
            if body.fixed:
                ax.plot(pos[0, i, a], pos[0, i, b], "s", color="k", markersize=7, zorder=4,
                        label="fixed" if i == first_fixed else None)
            else:
                ax.plot(path[:, i, a], path[:, i, b], color="0.7", linewidth=0.6)
                ax.plot(pos[0, i, a], pos[0, i, b], "o", markerfacecolor="none",
                        color=colors[i], markersize=6)
                ax.plot(pos[-1, i, a], pos[-1, i, b], "o", color=colors[i], markersize=6)
            if named:
                ax.annotate(body.name, (pos[-1, i, a], pos[-1, i, b]), fontsize=7,
                            xytext=(4, 4), textcoords="offset points")
        nu = ends["end"]
        if nu:
            idx = sorted(set(nu) & set(shown))
            vec = np.array([nu[i] for i in idx]) * 0.08 * span
            ax.quiver(pos[-1, idx, a], pos[-1, idx, b], vec[:, a], vec[:, b], angles="xy",
                      scale_units="xy", scale=1, color="tab:red", width=0.004,
                      label="axis ν (end)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"{plane[0]} [mm]")
        ax.set_ylabel(f"{plane[1]} [mm]")
        ax.set_title(f"{plane} projection", fontsize=9)
        if ax.get_legend_handles_labels()[0]:  # point masses, none fixed: nothing to explain
            ax.legend(loc="best", fontsize=7)
    return axes


#: Most bodies drawn in the configuration figure (evenly spread over the bodies beyond it:
#: a figure of 10⁵ bodies draws in bounded time and memory).
MAX_DRAWN = 2000


def _row_limit(limit: int, bodies: int) -> int:
    """Rows a figure reads: ``limit``, fewer for many bodies (about 2e6 positions at most)."""
    return max(2, min(limit, 2_000_000 // max(bodies, 1)))


def _drawn(n: int) -> list[int]:
    """Indices of the bodies drawn: all up to :data:`MAX_DRAWN`, else that many spread evenly."""
    if n <= MAX_DRAWN:
        return list(range(n))
    return sorted({int(k) for k in np.linspace(0, n - 1, MAX_DRAWN)})


def _first_fixed(system: NBodySystem) -> int:
    return next((i for i, b in enumerate(system.bodies) if b.fixed), -1)


def closest_pair(pos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance of the closest pair at each row and its indices ``(n, 2)`` (k-d tree)."""
    from scipy.spatial import cKDTree

    d = np.empty(len(pos))
    pair = np.empty((len(pos), 2), dtype=int)
    for k, p in enumerate(pos):
        dist, nb = cKDTree(p).query(p, k=2)
        i = int(np.argmin(dist[:, 1]))
        d[k], pair[k] = dist[i, 1], (min(i, nb[i, 1]), max(i, nb[i, 1]))
    return d, pair


def closest_pair_axes(system: NBodySystem, t_s: np.ndarray, y: np.ndarray, *,
                      shapes: Mapping[str, tuple[float, float]] | None = None,
                      length_unit: float = 1.0, ax=None):
    """Distance of the closest pair against time [mm], with the contact distances of that pair.

    ``shapes`` maps body names to ``(radius, half_length)`` in the internal length unit
    (``length_unit`` metres); for the pair closest at each time two dashed lines show the sum
    of the radii (cylinders side by side touch) and of the bounding-sphere radii (no contact
    is possible farther apart).

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = ax if ax is not None else figure("Closest pair")[1]
    t_s, yy = thin(np.asarray(t_s), np.atleast_2d(y), limit=_row_limit(4000, len(system.bodies)))
    d, pair = closest_pair(positions_si(system, yy))
    ax.plot(t_s, d * _MM, color="tab:blue", linewidth=0.9, label="closest-pair distance")
    if shapes:
        names = [b.name for b in system.bodies]
        rad = np.array([shapes.get(n, (0.0, 0.0))[0] for n in names]) * length_unit
        bound = np.array([np.hypot(*shapes.get(n, (0.0, 0.0))) for n in names]) * length_unit
        ax.plot(t_s, (rad[pair[:, 0]] + rad[pair[:, 1]]) * _MM, "--", color="tab:red",
                linewidth=0.8, label="contact: radii sum")
        if np.any(bound > rad):
            ax.plot(t_s, (bound[pair[:, 0]] + bound[pair[:, 1]]) * _MM, ":", color="tab:red",
                    linewidth=0.8, label="contact: bounding spheres")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("distance [mm]")
    ax.set_ylim(0, 1.15 * float(np.nanmax(d)) * _MM)  # room above for the legend
    ax.legend(loc="lower right", fontsize=7)
    return ax


def energy_partition(system: NBodySystem, y: np.ndarray) -> dict[str, np.ndarray]:
    """Translational, rotational and interaction energy [J] at each row, and the total.

    The system's own :meth:`HasEnergyParts.energy_parts` when it has one; else kinetic
    ``Σ p²/2M``, rotational ``Σ α m²/2`` (only when the system has moving tops) and
    interaction ``= H − kinetic − rotational``.
    """
    y = np.atleast_2d(y)
    if offers(system, HasEnergyParts):
        parts = {k: np.asarray(v, dtype=float) for k, v in system.energy_parts(y).items()}
        parts.setdefault("total", cast(np.ndarray, sum(parts.values())))
        return parts
    u = system.unpack(y, si=True)
    moving = [b for b in system.bodies if not b.fixed]
    tops = [b for b in moving if b.alpha is not None]
    p = u["p"].reshape(len(y), -1, 3)
    mass = np.array([b.mass for b in moving])
    kinetic = np.sum(np.sum(p**2, axis=2) / (2 * mass), axis=1)
    parts = {"translational": kinetic}
    if tops:  # point masses only: no rotational entry at all
        m = u["m"].reshape(len(y), -1, 3)
        alpha = np.array([b.alpha for b in tops])
        parts["rotational"] = np.sum(alpha * np.sum(m**2, axis=2) / 2, axis=1)
    e_unit = system.scales.unit("energy") if system.scales is not None else 1.0
    total = np.asarray(system.energy(y), dtype=float) * e_unit
    parts["interaction"] = total - sum(parts.values())
    parts["total"] = total
    return parts


def energy_partition_axes(system: NBodySystem, t_s: np.ndarray, y: np.ndarray, *, ax=None):
    """Energy partition against time [J]; returns the Axes."""
    ax = ax if ax is not None else figure("Energy partition")[1]
    t_s, yy = thin(np.asarray(t_s), np.atleast_2d(y), limit=_row_limit(4000, len(system.bodies)))
    parts = energy_partition(system, yy)
    styles = {"translational": ("tab:blue", "-"), "rotational": ("tab:orange", "-"),
              "interaction": ("tab:green", "-"), "total": ("k", "--")}
    for name, v in parts.items():
        color, ls = styles.get(name, (None, "-"))
        ax.plot(t_s, v, color=color, linestyle=ls, linewidth=0.9, label=name)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy [J]")
    ax.legend(loc="best", fontsize=7)
    return ax


def _segments(plan: Mapping[str, object], t_end: float) -> dict[str, list[tuple[float, str]]]:
    """Per pair ``[(t_start [s], model), ...]`` from a plan report (initial plan + switches)."""
    initial = plan.get("initial_plan", plan)
    pairs = initial.get("pairs", []) if isinstance(initial, Mapping) else []
    out: dict[str, list[tuple[float, str]]] = {}
    for p in pairs if isinstance(pairs, list) else []:
        out["-".join(p["bodies"])] = [(0.0, str(p["model"]))]
    for s in cast(list, plan.get("switches", []) or []):
        key = "-".join(s["bodies"])
        out.setdefault(key, [(0.0, str(s["from"]))]).append((float(s["t_s"]), str(s["to"])))
    return out


def model_timeline_axes(plan: Mapping[str, object], t_end_s: float, *, ax=None,
                        max_pairs: int = 40):
    """One bar per planned pair coloured by the model in force, against time; returns the Axes.

    A plan without recorded switches (only the initial plan is known) draws one segment per
    pair over the whole run, and the title says so.
    """
    seg = _segments(plan, t_end_s)
    switched = bool(plan.get("switches"))
    title = "Pair models (planner)" + ("" if switched else ": initial plan, no switches recorded")
    ax = ax if ax is not None else figure(title, size=(6.4, 1.2 + 0.18 * min(len(seg),
                                                                               max_pairs)))[1]
    ax.set_title(title, fontsize=10)
    models = sorted({m for s in seg.values() for _, m in s})
    color = {m: f"C{k % 10}" for k, m in enumerate(models)}
    names = list(seg)[:max_pairs]
    for row, key in enumerate(names):
        s = seg[key] + [(t_end_s, "")]
        for (t0, m), (t1, _) in zip(s, s[1:]):
            ax.barh(row, t1 - t0, left=t0, height=0.7, color=color[m])
    for m in models:
        ax.barh(0, 0, color=color[m], label=m)  # legend entries
    ax.set_yticks(range(len(names)), names, fontsize=6)
    ax.invert_yaxis()
    ax.set_xlim(0, t_end_s)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("pair" + (f" (first {max_pairs} of {len(seg)})" if len(seg) > max_pairs
                            else ""))
    ax.legend(loc="upper right", fontsize=7)
    return ax


# ------------------------------------------------------------------ registry entries
def _nbody(run: RunData) -> bool:
    return isinstance(run.system, NBodySystem)


def _system(run: RunData) -> NBodySystem:
    assert isinstance(run.system, NBodySystem)  # guarded by _nbody
    return run.system


def _length_unit(run: RunData) -> float:
    sc = _system(run).scales
    return sc.length if sc is not None else 1.0


register_plot("configuration", _nbody,
              lambda run: configuration_axes(_system(run), run.y)[0].figure, replace=True)
register_plot("closest_pair", lambda run: _nbody(run) and run.n_bodies >= 2,
              lambda run: closest_pair_axes(_system(run), run.t_s, run.y, shapes=run.shapes,
                                            length_unit=_length_unit(run)).figure,
              replace=True)
register_plot("energy_partition", _nbody,
              lambda run: energy_partition_axes(_system(run), run.t_s, run.y).figure,
              replace=True)
register_plot("model_timeline", lambda run: run.plan is not None,
              lambda run: model_timeline_axes(run.plan or {}, float(run.t_s[-1])).figure,
              replace=True)
