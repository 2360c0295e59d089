"""Figures of bodies in external fields: height and axis tilt against time.

One body over a magnet (the Levitron, a magnet over a magpylib cylinder) has no orbit and no
partner: what matters is how high it hovers and how far its axis tilts. :func:`height_tilt_axes`
draws both for every moving body, along the axis of the first field source with a shape
(:mod:`poissonkit.report.source_shapes`; vertical ``z`` without one). The registry entry at the
bottom draws it for runs of kind ``"in_field"`` (:mod:`poissonkit.report.scene_kind`).
"""

from __future__ import annotations

import numpy as np

from poissonkit.numerics.nbody import NBodySystem
from poissonkit.report.axis_units import run_axis_units
from poissonkit.report.figures import RunData, register_plot
from poissonkit.report.plotkit import (COARSE, caption, figure, layout, plot_quantity,
                                       samples_per_turn, thin)
from poissonkit.report.scene_kind import IN_FIELD
from poissonkit.report.source_shapes import source_shapes

__all__ = ["height_tilt_axes"]

#: Most bodies drawn one line each (then the figure is clutter).
MAX_LINES = 10


def height_tilt_axes(system: NBodySystem, t_s: np.ndarray, y: np.ndarray, *, axes=None):
    """Height along the field's axis and tilt of each top's axis from it, against time.

    Parameters
    ----------
    system
        The system (its first field source with a shape gives the axis, else ``z``).
    t_s
        Saved times [s].
    y
        Saved states (internal units), one row per time.
    axes
        Two matplotlib Axes to draw into (height, tilt); default a new figure.

    Returns
    -------
    numpy.ndarray of two matplotlib Axes
        A quantity constant to round-off is drawn flat and its title says so; sampling too
        coarse for the precession of the axis is drawn as points and the caption says so.
    """
    from poissonkit.report.nbody_plots import axes_of_tops, positions_si

    new = axes is None
    if axes is None:
        fig, axs = figure("Height and axis tilt", nrows=2, size=(6.4, 5.6))
        axes = axs[:, 0]
    fig = axes[0].figure
    t_s, yy = thin(np.asarray(t_s), np.atleast_2d(y))
    shapes = source_shapes(system)
    ref = np.asarray(shapes[0].axis if shapes else (0.0, 0.0, 1.0))
    base = float(np.dot(shapes[0].centre, ref) + shapes[0].length / 2) if shapes else 0.0
    moving = [i for i, b in enumerate(system.bodies) if not b.fixed][:MAX_LINES]
    pos = positions_si(system, yy)
    lunit, tunit = run_axis_units(t_s, pos[:, moving] - base * ref)
    t = tunit.of(t_s)
    nu = axes_of_tops(system, yy)
    turns = min((samples_per_turn(v - np.outer(v @ ref, ref)) for v in nu.values()),
                default=float("inf"))
    coarse = turns < COARSE
    ax_h, ax_t = axes
    ax_h.set_title("Height" + (" above the source's top face" if shapes else ""), fontsize=9)
    for i in moving:
        plot_quantity(ax_h, t, lunit.of(pos[:, i] @ ref - base), coarse=coarse,
                      color=f"C{i % 10}", linewidth=0.9, label=system.bodies[i].name)
    ax_h.set_ylabel(f"height [{lunit.name}]")
    ax_t.set_title("Tilt of the axis ν from the field's axis line", fontsize=9)
    for i, v in nu.items():
        if i in moving:
            # from the axis line, either way: a top may hover with its moment down
            cos = np.abs(v @ ref) / np.linalg.norm(v, axis=1)
            tilt = np.degrees(np.arccos(np.clip(cos, 0.0, 1.0)))
            plot_quantity(ax_t, t, tilt, coarse=coarse, color=f"C{i % 10}", linewidth=0.9,
                          label=system.bodies[i].name)
    if not nu:
        ax_t.text(0.5, 0.5, "no tops: point bodies have no axis", ha="center",
                  transform=ax_t.transAxes, fontsize=8)
    ax_t.set_ylabel("tilt [deg]")
    for ax in axes:
        ax.set_xlabel(f"t [{tunit.name}]")
        if len(moving) > 1 and ax.get_legend_handles_labels()[0]:
            ax.legend(loc="best", fontsize=7)
    if coarse:
        caption(fig, f"Sampled too coarsely for the precession (about {turns:.0f} samples per "
                     "turn of the axis): drawn as points, not joined; save more often "
                     "(save_dt) to see the motion between them.")
    if new:  # titles and labels of the two panels apart (saving lays it out again)
        layout(fig)
    return axes


def _in_field(run: RunData) -> bool:
    return isinstance(run.system, NBodySystem)


def _draw(run: RunData):
    assert isinstance(run.system, NBodySystem)  # guarded by _in_field
    return height_tilt_axes(run.system, run.t_s, run.y)[0].figure


register_plot("height_tilt", _in_field, _draw, kinds=(IN_FIELD,), replace=True)
