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
from poissonkit.report.axis_units import quantity_unit, run_axis_units
from poissonkit.report.figures import RunData, register_plot
from poissonkit.report.plotkit import (COARSE, caption, constant_to_roundoff, figure, layout,
                                       samples_per_turn, thin)
from poissonkit.report.scene_kind import IN_FIELD, NBODY, PLANETARY, TWO_BODY
from poissonkit.report.source_shapes import SourceShape, outline, source_shapes
from poissonkit.traits import offers

__all__ = ["HasEnergyParts", "axes_of_tops", "closest_pair_axes", "configuration_axes",
           "energy_partition", "energy_partition_axes", "model_timeline_axes", "positions_si"]

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


def axes_of_tops(system: NBodySystem, y: np.ndarray) -> dict[int, np.ndarray]:
    """Unit axes ``ν`` of the tops at every row ``(n, 3)``, by body index (fixed tops: their
    fixed axis repeated)."""
    y = np.atleast_2d(y)
    nu = system.unpack(y)["nu"].reshape(len(y), -1, 3)
    out: dict[int, np.ndarray] = {}
    k = 0
    for i, b in enumerate(system.bodies):
        if b.fixed:
            if b.axis is not None:
                out[i] = np.tile(np.asarray(b.axis, dtype=float), (len(y), 1))
        elif b.alpha is not None:
            out[i] = nu[:, k]
            k += 1
    return out


def configuration_axes(system: NBodySystem, y: np.ndarray, *, axes: Sequence | None = None,
                       sources: Sequence[SourceShape] | None = None):
    """All bodies at the first and last state in the xy and xz projections.

    Paths are thin grey lines (points when the saved states are too far apart for the motion,
    said in the caption), the start a hollow circle, the end a filled one, tops' axes arrows
    at the end, fixed bodies black squares, field sources with a shape (``sources``, default
    the system's own: :func:`~poissonkit.report.source_shapes.source_shapes`) their outlines;
    each body is labelled by name at its end (up to :data:`MAX_NAMED` bodies). Lengths are in
    the unit :func:`~poissonkit.report.axis_units.run_axis_units` chooses.

    Returns
    -------
    numpy.ndarray of two matplotlib Axes (xy, xz)
    """
    new = axes is None
    if axes is None:
        _, axs = figure("Configuration at start (○) and end (●)", ncols=2, size=(10, 4.6))
        axes = axs[0]
    y = np.atleast_2d(y)
    sources = source_shapes(system) if sources is None else list(sources)
    # positions of every row of a large system would not fit: at most ~2e6 body positions
    (rows,) = thin(y, limit=_row_limit(2000, len(system.bodies)))
    path_si = positions_si(system, rows)
    unit, _ = run_axis_units(np.zeros(1), path_si)
    path = unit.of(path_si)
    pos = unit.of(positions_si(system, y[[0, -1]]))
    turns = _samples_per_orbit(path_si)
    coarse = turns < COARSE
    ends = {"start": _axes_of(system, y[0]), "end": _axes_of(system, y[-1])}
    drawn = [path.reshape(-1, 3), pos.reshape(-1, 3)]
    drawn += [unit.of(outline(src))[::4] for src in sources]  # arrows scale with the sources
    every = np.concatenate(drawn)
    span = float(np.nanmax(np.nanmax(every, axis=0) - np.nanmin(every, axis=0))) or 1.0
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
            elif coarse:
                ax.plot(path[:, i, a], path[:, i, b], ".", color="0.6", markersize=2)
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
        normal = np.cross(np.eye(3)[a], np.eye(3)[b])
        for k, src in enumerate(sources):
            edge = unit.of(outline(src, seen_along=normal))
            ax.plot(edge[:, a], edge[:, b], color="tab:brown", linewidth=0.8,
                    label=src.label if k == 0 or src.label != sources[0].label else None)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"{plane[0]} [{unit.name}]")
        ax.set_ylabel(f"{plane[1]} [{unit.name}]")
        ax.set_title(f"{plane} projection", fontsize=9)
        if ax.get_legend_handles_labels()[0]:  # point masses, none fixed: nothing to explain
            ax.legend(loc="best", fontsize=7)
    if coarse:
        caption(axes[0].figure, f"Saved states too far apart for the motion (about {turns:.0f} "
                                "per turn): paths drawn as points, not joined by chords.")
    if new:
        layout(axes[0].figure)
    return axes


def _samples_per_orbit(path: np.ndarray) -> float:
    """Fewest samples per turn of any body about the mean position of all ``(n, N, 3)``."""
    if path.shape[1] < 2:
        return float("inf")
    rel = path - path.mean(axis=1, keepdims=True)
    return min(samples_per_turn(rel[:, i]) for i in range(min(path.shape[1], MAX_NAMED)))


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
    """Distance of the closest pair against time, with the contact distances of that pair.

    The pair is named: the title says which pair is closest most of the time (``closest pair:
    a–c``), and when it changes, the curve is coloured by pair with one legend entry each.

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
    pos = positions_si(system, yy)
    d, pair = closest_pair(pos)
    unit, tunit = run_axis_units(t_s, pos)  # the scene's scale: as in the other figures
    t = tunit.of(t_s)
    names = [b.name for b in system.bodies]
    label = [f"{names[i]}–{names[j]}" for i, j in pair]
    order = sorted(set(label), key=lambda p: -label.count(p))
    ax.set_title(f"Closest pair: {order[0]}" + (f" (and {len(order) - 1} other pair"
                                                 f"{'s' if len(order) > 2 else ''})"
                                                 if len(order) > 1 else ""), fontsize=10)
    ax.plot(t, unit.of(d), color="0.6" if len(order) > 1 else "tab:blue", linewidth=0.9,
            label="closest-pair distance" if len(order) == 1 else None)
    if len(order) > 1:  # colour by pair: which pair is closest, when
        for k, p in enumerate(order[:MAX_PAIRS]):
            on = np.array([q == p for q in label])
            ax.plot(t[on], unit.of(d[on]), ".", color=f"C{k % 10}", markersize=2.5,
                    label=f"{p} ({_percent(on.mean())} of the time)")
    if shapes:
        rad = np.array([shapes.get(n, (0.0, 0.0))[0] for n in names]) * length_unit
        bound = np.array([np.hypot(*shapes.get(n, (0.0, 0.0))) for n in names]) * length_unit
        ax.plot(t, unit.of(rad[pair[:, 0]] + rad[pair[:, 1]]), "--", color="tab:red",
                linewidth=0.8, label="contact: radii sum")
        if np.any(bound > rad):
            ax.plot(t, unit.of(bound[pair[:, 0]] + bound[pair[:, 1]]), ":", color="tab:red",
                    linewidth=0.8, label="contact: bounding spheres")
    ax.set_xlabel(f"t [{tunit.name}]")
    ax.set_ylabel(f"distance [{unit.name}]")
    ax.set_ylim(0, 1.15 * float(np.nanmax(unit.of(d))))  # room above for the legend
    ax.legend(loc="lower right", fontsize=7)
    return ax


def _percent(fraction: float) -> str:
    return "< 1 %" if 0 < fraction < 0.005 else f"{100 * fraction:.0f} %"


#: Most pairs coloured separately in the closest-pair figure.
MAX_PAIRS = 6


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
    """Energy partition against time (J, or the scene's energy unit); returns the Axes."""
    ax = ax if ax is not None else figure("Energy partition")[1]
    t_s, yy = thin(np.asarray(t_s), np.atleast_2d(y), limit=_row_limit(4000, len(system.bodies)))
    parts = energy_partition(system, yy)
    _, tunit = run_axis_units(t_s, None)
    eunit = quantity_unit("energy", np.concatenate([np.ravel(v) for v in parts.values()]))
    styles = {"translational": ("tab:blue", "-"), "rotational": ("tab:orange", "-"),
              "interaction": ("tab:green", "-"), "total": ("k", "--")}
    flat = []
    for name, v in parts.items():
        color, ls = styles.get(name, (None, "-"))
        if constant_to_roundoff(v):
            flat.append(name)
        ax.plot(tunit.of(t_s), eunit.of(v), color=color, linestyle=ls, linewidth=0.9,
                label=name)
    if flat:  # the others set the scale; say which are flat rather than zoom into noise
        ax.set_title(f"{ax.get_title()} — {', '.join(flat)} constant to round-off",
                     fontsize=10)
    ax.set_xlabel(f"t [{tunit.name}]")
    ax.set_ylabel(f"energy [{eunit.name}]")
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
              lambda run: configuration_axes(_system(run), run.y)[0].figure, replace=True,
              kinds=(TWO_BODY, NBODY, IN_FIELD))
register_plot("closest_pair", lambda run: _nbody(run) and run.n_bodies >= 2,
              lambda run: closest_pair_axes(_system(run), run.t_s, run.y, shapes=run.shapes,
                                            length_unit=_length_unit(run)).figure,
              replace=True, kinds=(TWO_BODY, NBODY, IN_FIELD))
register_plot("energy_partition", _nbody,
              lambda run: energy_partition_axes(_system(run), run.t_s, run.y).figure,
              replace=True, kinds=(TWO_BODY, NBODY, IN_FIELD, PLANETARY))
register_plot("model_timeline", lambda run: run.plan is not None,
              lambda run: model_timeline_axes(run.plan or {}, float(run.t_s[-1])).figure,
              replace=True)
