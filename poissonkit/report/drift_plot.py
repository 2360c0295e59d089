"""Invariant drifts on a log axis, with exact zeros drawn honestly.

A log axis cannot show 0. Values that are exactly zero (a conserved quantity the integrator
keeps to the last bit) are drawn as hollow markers ▽ at a stated *floor* — a decade below the
smallest nonzero drift of the figure, but not below :data:`LOWEST_FLOOR` — and the legend says
so; nonzero values under the floor are markers △ there. Nothing is clipped into a line. Only the invariants the system has are drawn (the drifts that
:mod:`poissonkit.numerics.diagnostics` computed for it).
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Mapping

import numpy as np

from poissonkit.numerics.diagnostics import SCALE_FLOOR, Drift
from poissonkit.report.plotkit import figure, thin
from poissonkit.report.summary import Diagnostics

__all__ = ["drift_axes", "drift_floor", "drift_label"]

_COLORS = {"energy_error": "tab:blue", "casimir_drift": "tab:orange",
           "linear_momentum_drift": "tab:purple", "angular_momentum_drift": "tab:green"}
_RELATIVE = {"energy_error": "|ΔH|/|H(0)|", "casimir_drift": "max_k |ΔC_k|/s_k",
             "linear_momentum_drift": "|ΔP|/max|p_i(0)|",
             "angular_momentum_drift": "|Δj|/(Σ|r×p|+Σ|m|)"}
_ABSOLUTE = {"energy_error": "|ΔH|", "casimir_drift": "max_k |ΔC_k|",
             "linear_momentum_drift": "|ΔP|", "angular_momentum_drift": "|Δj|"}
#: The floor never goes lower: a hundredth of double round-off (a cancellation leaving 1e-33
#: would otherwise squash the figure's meaningful decades into a sliver).
LOWEST_FLOOR = 1e-19
#: At most this many zero markers per series (a run of exact zeros stays readable).
MAX_ZERO_MARKERS = 60


def _floored(d: Drift) -> bool:
    """The scale was exactly zero and replaced by :data:`SCALE_FLOOR` (relative = absolute)."""
    scales = d.scale if isinstance(d.scale, tuple) else (d.scale,)
    return all(s == SCALE_FLOOR for s in scales) and d.name != "casimir_drift"


def drift_label(d: Drift) -> str:
    """Legend text: the relative figure, or the absolute one when its scale was zero (e.g.
    ``j(0) = 0``: no ``|Δj|/|j|`` is drawn then)."""
    if _floored(d):
        return f"{_ABSOLUTE.get(d.name, d.name)} (scale 0: absolute, internal units)"
    return _RELATIVE.get(d.name, d.name)


def drift_floor(diag: Diagnostics) -> float:
    """Where exact zeros are drawn: a decade below the smallest nonzero drift, but not below
    :data:`LOWEST_FLOOR` (1e-17 if every drift is exactly zero)."""
    pos = [float(np.min(v[v > 0])) for v in (np.asarray(d.relative) for d in diag.drifts.values())
           if np.any(v > 0)]
    if not pos:
        return 1e-17
    return max(LOWEST_FLOOR, 10.0 ** math.floor(math.log10(min(pos)) - 1))


def drift_axes(diag: Diagnostics, *, ax=None, time_scale: float = 1.0, time_unit: str = "s",
               not_conserved: Mapping[str, str] | None = None):
    """Draw the drifts of ``diag`` on a log axis and return the Axes.

    Parameters
    ----------
    diag
        Diagnostics of a run; every drift in ``diag.drifts`` is drawn, nothing else.
    ax
        Axes to draw on (a new figure when ``None``).
    time_scale
        Factor from ``diag.t`` to ``time_unit``.
    time_unit
        Label of the time axis.
    not_conserved
        ``{quantity: reason}`` of invariants the system does not have (e.g.
        :func:`poissonkit.report.summary.conserved_quantities`: momenta with a fixed body);
        they are left out and named under the legend.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = figure("Invariant drifts", size=(8.4, 4.2))
    else:
        ax.set_title("Invariant drifts", fontsize=10)
    t = np.asarray(diag.t) * time_scale
    skip = dict(not_conserved or {})
    shown = {n: d for n, d in diag.drifts.items() if n.removesuffix("_drift") not in skip}
    floor = drift_floor(Diagnostics(diag.t, shown, diag.angular_momentum))
    marked = {"v": False, "^": False}
    for name, d in shown.items():
        color = _COLORS.get(name)
        y = np.asarray(d.relative, dtype=float)
        tt, yy = thin(t, y)
        # t = 0 is zero by definition: not a finding, not drawn; values under the floor are
        # markers, not a line plunging to 1e-35; a dot on the line keeps isolated samples
        line = np.where(yy >= floor, yy, np.nan)
        line[0] = np.nan
        ax.semilogy(tt, line, color=color, linewidth=0.7, marker=".", markersize=1.5,
                    label=drift_label(d))
        for marker, hit in (("v", y[1:] == 0), ("^", (y[1:] > 0) & (y[1:] < floor))):
            idx = np.flatnonzero(hit) + 1
            if idx.size:
                marked[marker] = True
                idx = idx[::max(1, int(np.ceil(idx.size / MAX_ZERO_MARKERS)))]
                ax.semilogy(t[idx], np.full(idx.size, floor), linestyle="none", marker=marker,
                            markersize=4, markerfacecolor="none", color=color or "0.3")
    if not any(np.any(np.asarray(d.relative) > 0) for d in shown.values()):
        ax.set_ylim(floor / 10, floor * 10)  # only zeros: a log axis needs a range to show
    if marked["v"] or marked["^"]:
        ax.axhline(floor, color="0.5", linewidth=0.6, linestyle=":",
                   label=f"floor {floor:.0e}: markers stand for")
    if marked["v"]:
        ax.plot([], [], "v", markerfacecolor="none", color="0.3", label="  exactly 0")
    if marked["^"]:
        ax.plot([], [], "^", markerfacecolor="none", color="0.3",
                label=f"  nonzero, below {floor:.0e}")
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel("relative drift")
    by_reason: dict[str, list[str]] = {}
    for q, why in skip.items():
        by_reason.setdefault(why, []).append(q.replace("_", " "))
    for why, qs in by_reason.items():  # say what is missing and why, rather than drawing it
        note = f"not an invariant here: {' and '.join(qs)} ({why})"
        ax.plot([], [], " ", label=textwrap.fill(note, 40))
    # outside the axes: a legend never hides a curve
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0)
    return ax
