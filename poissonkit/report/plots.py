"""Two-body figures in the style of seed 000's MATLAB plots (matplotlib, Agg backend).

The seed shows (i) the z-component of the total angular momentum against time ("Total moment
of momentum conservation law"), (ii) the orbital radius on the background of the x-coordinate
("Change of orbital radius on background of x-coordinate changing"), plus the orbit itself. We
add the invariant drifts on a log scale (:mod:`poissonkit.report.drift_plot`). The ``*_axes``
functions draw and return matplotlib Axes (notebooks); the others write one PNG and return its
path. All four are registered in :data:`poissonkit.report.figures.PLOTS` for two-body runs.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import cast

import numpy as np

from poissonkit.contracts import HasEnergy
from poissonkit.report.axis_units import AxisUnit, quantity_unit, run_axis_units
from poissonkit.report.drift_plot import drift_axes
from poissonkit.report.figures import RunData, register_plot
from poissonkit.report.plotkit import (COARSE, caption, constant_to_roundoff, figure, plot_quantity,
                                       samples_per_turn, save, thin)
from poissonkit.report.scene_kind import TWO_BODY
from poissonkit.report.summary import Diagnostics

__all__ = ["angular_momentum_z", "angular_momentum_z_axes", "drifts", "orbit", "orbit_axes",
           "radius_and_x", "radius_and_x_axes", "seed_figures"]


def _axes(ax, title: str):
    if ax is None:
        return figure(title)[1]
    ax.set_title(title, fontsize=10)
    return ax


def angular_momentum_z_axes(t: np.ndarray, jz: np.ndarray, *, ax=None, unit: str = "J s",
                            time_unit: str = "s"):
    """``j_z(t) − j_z(0)`` (seed: total moment of momentum, z-component); returns the Axes.

    Conserved to round-off (a splitting keeps it to the last bits), it is drawn as a flat line
    on a fixed axis and the title says so, instead of autoscaled round-off noise."""
    t, jz = thin(np.asarray(t), np.asarray(jz))
    ax = _axes(ax, "Total angular momentum, z-component")
    plot_quantity(ax, t, jz - jz[0], magnitude=float(np.max(np.abs(jz))), color="tab:blue",
                  linewidth=0.8)
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel(f"j_z(t) - j_z(0) [{unit}]   (j_z(0) = {jz[0]:.10g})")
    return ax


def radius_and_x_axes(t: np.ndarray, r: np.ndarray, *, ax=None, unit: str = "mm",
                      time_unit: str = "s"):
    """Orbital radius ``|r|(t)`` on the background of ``x(t)``; returns the Axes."""
    t, rr = thin(np.asarray(t), np.asarray(r))
    ax = _axes(ax, "Orbital radius on the background of the x-coordinate")
    ax.plot(t, rr[:, 0], color="0.6", linewidth=0.7, label="x")
    radius = np.linalg.norm(rr, axis=1)
    ax.plot(t, radius, color="tab:blue", linewidth=1.0, label="|r|")
    if constant_to_roundoff(radius):  # x sets the scale; say that |r| is flat, not just small
        ax.set_title(f"{ax.get_title()}\n(|r| constant to round-off)", fontsize=10)
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel(f"[{unit}]")
    ax.legend(loc="lower right", fontsize=8)
    return ax


def orbit_axes(r: np.ndarray, *, ax=None, unit: str = "mm"):
    """The relative orbit in the xy-plane; returns the Axes (points, with a caption, when the
    samples are too far apart for the orbit)."""
    (rr,) = thin(np.asarray(r))
    ax = _axes(ax, "Relative orbit r = r2 - r1")
    turns = samples_per_turn(rr)
    if turns < COARSE:
        ax.plot(rr[:, 0], rr[:, 1], ".", color="tab:blue", markersize=3)
        caption(ax.figure, f"Saved too coarsely for the orbit (about {turns:.0f} samples per "
                           "turn): drawn as points, not joined by chords.")
    else:
        ax.plot(rr[:, 0], rr[:, 1], color="tab:blue", linewidth=0.7)
    ax.plot(rr[0, 0], rr[0, 1], "o", color="tab:red", markersize=4, label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.legend(loc="upper right", fontsize=8)
    return ax


def angular_momentum_z(path: str | Path, t: np.ndarray, jz: np.ndarray, *,
                       unit: str = "J s", time_unit: str = "s") -> Path:
    """Write :func:`angular_momentum_z_axes` to ``path``."""
    ax = angular_momentum_z_axes(t, jz, unit=unit, time_unit=time_unit)
    return save(ax.figure, Path(path))


def radius_and_x(path: str | Path, t: np.ndarray, r: np.ndarray, *, unit: str = "mm",
                 time_unit: str = "s") -> Path:
    """Write :func:`radius_and_x_axes` to ``path``."""
    return save(radius_and_x_axes(t, r, unit=unit, time_unit=time_unit).figure, Path(path))


def orbit(path: str | Path, r: np.ndarray, *, unit: str = "mm") -> Path:
    """Write :func:`orbit_axes` to ``path``."""
    return save(orbit_axes(r, unit=unit).figure, Path(path))


def drifts(path: str | Path, diag: Diagnostics, *, time_scale: float = 1.0,
           time_unit: str = "s") -> Path:
    """Write :func:`poissonkit.report.drift_plot.drift_axes` to ``path``."""
    return save(drift_axes(diag, time_scale=time_scale, time_unit=time_unit).figure, Path(path))


def seed_figures(outdir: str | Path, t_si: np.ndarray, r_si: np.ndarray, jz_si: np.ndarray,
                 diag: Diagnostics, time_scale: float) -> Sequence[Path]:
    """All four two-body figures into ``outdir`` (lengths plotted in mm)."""
    out = Path(outdir)
    r_mm = np.asarray(r_si) * 1e3
    return [
        angular_momentum_z(out / "angular_momentum_z.png", t_si, jz_si),
        radius_and_x(out / "radius_and_x.png", t_si, r_mm),
        orbit(out / "orbit.png", r_mm),
        drifts(out / "drifts.png", diag, time_scale=time_scale),
    ]


# ------------------------------------------------------------------ registry entries
def _two_body(run: RunData) -> bool:
    return run.relative is not None


def _units(run: RunData) -> tuple[AxisUnit, AxisUnit]:
    """Length and time units of the run's figures (mm and s for the seed's magnets)."""
    return run_axis_units(run.t_s, run.relative)


def _rel(run: RunData) -> np.ndarray:
    assert run.relative is not None  # guarded by _two_body
    return _units(run)[0].of(run.relative)


def _jz(run: RunData) -> np.ndarray:
    return run.jz if run.jz is not None else np.zeros(len(run.t))


def _jz_figure(run: RunData):
    tunit = _units(run)[1]
    junit = quantity_unit("angular_momentum", _jz(run))
    return angular_momentum_z_axes(tunit.of(run.t_s), junit.of(_jz(run)), unit=junit.name,
                                   time_unit=tunit.name).figure


def _radius_figure(run: RunData):
    lunit, tunit = _units(run)
    return radius_and_x_axes(tunit.of(run.t_s), _rel(run), unit=lunit.name,
                             time_unit=tunit.name).figure


register_plot("angular_momentum_z", _two_body, _jz_figure, replace=True, kinds=(TWO_BODY,))
register_plot("radius_and_x", _two_body, _radius_figure, replace=True, kinds=(TWO_BODY,))
register_plot("orbit", _two_body,
              lambda run: orbit_axes(_rel(run), unit=_units(run)[0].name).figure, replace=True,
              kinds=(TWO_BODY,))


def _drift_figure(run: RunData):
    from poissonkit.report.summary import conserved_quantities

    tunit = run_axis_units(run.t_s, None)[1]
    return drift_axes(run.diag, time_scale=run.time_unit / tunit.size, time_unit=tunit.name,
                      not_conserved=conserved_quantities(cast(HasEnergy, run.system))).figure


register_plot("drifts", lambda run: bool(run.diag.drifts), _drift_figure, replace=True)
