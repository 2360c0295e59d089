"""Figures of planetary runs: orbits about the primary, orbital elements against time.

A planetary run (:data:`~poissonkit.report.scene_kind.PLANETARY`: point masses under gravity,
one dominant) is drawn in the frame of its primary, the heaviest body: each orbit in the
primary's ``xy`` plane, in astronomical units for planets. Saved states too far apart for an
orbit (fewer than :data:`~poissonkit.report.plotkit.COARSE` per revolution) are drawn as points,
not joined by chords that would turn the orbit into a spirograph, and the caption says so.
Orbital elements are drawn only when the run carries them (:attr:`RunData.elements`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from poissonkit.numerics.nbody import NBodySystem
from poissonkit.report.axis_units import run_axis_units
from poissonkit.report.figures import RunData, register_plot
from poissonkit.report.plotkit import COARSE, caption, figure, layout, samples_per_turn, thin
from poissonkit.report.scene_kind import PLANETARY

__all__ = ["elements_axes", "orbits_axes"]


def _primary(system: NBodySystem) -> int:
    return int(np.argmax([b.mass for b in system.bodies]))


def orbits_axes(system: NBodySystem, y: np.ndarray, *, ax=None):
    """Orbits of every body about the primary (the heaviest body), in its ``xy`` plane.

    Returns
    -------
    matplotlib.axes.Axes
    """
    from poissonkit.report.nbody_plots import positions_si

    p = _primary(system)
    title = f"Orbits about {system.bodies[p].name} (xy plane)"
    new = ax is None
    ax = ax if ax is not None else figure(title, size=(6.4, 5.6))[1]
    (rows,) = thin(np.atleast_2d(y), limit=4000)
    pos = positions_si(system, rows)
    rel = pos - pos[:, p:p + 1]
    unit, _ = run_axis_units(np.zeros(1), rel)
    coarse = []
    for i, b in enumerate(system.bodies):
        if i == p:
            continue
        xy = unit.of(rel[:, i, :2])
        turns = samples_per_turn(rel[:, i])
        if turns < COARSE:
            coarse.append((b.name, turns))
            ax.plot(xy[:, 0], xy[:, 1], ".", color=f"C{i % 10}", markersize=2.5, label=b.name)
        else:
            ax.plot(xy[:, 0], xy[:, 1], color=f"C{i % 10}", linewidth=0.7, label=b.name)
        ax.plot(xy[-1, 0], xy[-1, 1], "o", color=f"C{i % 10}", markersize=4)
    ax.plot(0, 0, "*", color="goldenrod", markersize=10, label=system.bodies[p].name)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x − x_{system.bodies[p].name} [{unit.name}]")
    ax.set_ylabel(f"y − y_{system.bodies[p].name} [{unit.name}]")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0)
    if coarse:
        names = ", ".join(n for n, _ in coarse)
        counts = ", ".join(f"{k:.0f}" for _, k in coarse)
        caption(ax.figure, f"Saved too coarsely for the orbits of {names} ({counts} samples per "
                           "revolution): drawn as points, not joined; save more often (save_dt) "
                           "to draw them as lines.")
    if new:
        layout(ax.figure)
    return ax


#: Elements drawn, with their axis labels ("a" is scaled to the length unit).
_ELEMENTS = (("a", "a"), ("e", "e"), ("inc", "inc [deg]"))


def elements_axes(t_s: np.ndarray, elements: Mapping[str, np.ndarray],
                  names: list[str], *, axes=None):
    """Semi-major axis, eccentricity and inclination of each body against time.

    Parameters
    ----------
    t_s
        Saved times [s].
    elements
        ``{"a": (n, k) [m], "e": (n, k), "inc": (n, k) [rad]}`` for ``k`` bodies (others
        ignored; a missing one is not drawn).
    names
        The ``k`` body names.

    Returns
    -------
    list of matplotlib Axes
    """
    shown = [(k, label) for k, label in _ELEMENTS if k in elements]
    if axes is None:
        _, axs = figure("Orbital elements", nrows=max(1, len(shown)),
                        size=(6.4, 1.2 + 1.6 * len(shown)))
        axes = list(axs[:, 0])
    _, tunit = run_axis_units(t_s, None)
    t = tunit.of(t_s)
    for ax, (key, label) in zip(axes, shown):
        v = np.asarray(elements[key], dtype=float).reshape(len(t), -1)
        if key == "a":
            unit, _ = run_axis_units(t_s, np.column_stack([v.ravel()] * 3))
            v, label = unit.of(v), f"a [{unit.name}]"
        elif key == "inc":
            v = np.degrees(v)
        for k in range(v.shape[1]):
            ax.plot(t, v[:, k], color=f"C{k % 10}", linewidth=0.8,
                    label=names[k] if k < len(names) else None)
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.set_ylabel(label)
        ax.set_xlabel(f"t [{tunit.name}]")
    if axes:
        axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
    return axes


def _planetary(run: RunData) -> bool:
    return isinstance(run.system, NBodySystem)


def _orbits(run: RunData):
    assert isinstance(run.system, NBodySystem)  # guarded by _planetary
    return orbits_axes(run.system, run.y).figure


def _elements(run: RunData):
    assert isinstance(run.system, NBodySystem) and run.elements is not None
    p = _primary(run.system)
    names = [b.name for i, b in enumerate(run.system.bodies) if i != p]
    return elements_axes(run.t_s, run.elements, names)[0].figure


register_plot("orbits", _planetary, _orbits, kinds=(PLANETARY,), replace=True)
register_plot("elements", lambda run: _planetary(run) and run.elements is not None, _elements,
              kinds=(PLANETARY,), replace=True)
