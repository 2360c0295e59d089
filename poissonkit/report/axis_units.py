"""The units figures and the 3D view label their axes in: one place that chooses them.

Every figure of a run asks :func:`run_axis_units` (or :func:`length_unit_for` /
:func:`time_unit_for` for bare arrays) and divides its SI values by the unit's ``size``; the
label is the unit's ``name``. The choice reads the run's units through
:mod:`poissonkit.report.run_units` and the extent of the data: millimetres for magnets (the
seed's figures), metres, kilometres, astronomical units for planets; seconds, days, years.
Names are unit symbols, never an SI prefix on a number (no "4T" for terametres, read as tesla).

>>> length_unit_for(0.02).name, length_unit_for(7.8e11).name
('mm', 'AU')
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["AU", "DAY", "YEAR", "AxisUnit", "length_unit_for", "run_axis_units",
           "time_unit_for"]

#: The astronomical unit [m] (IAU 2012 B2), the day [s] and the Julian year [s].
AU = 149_597_870_700.0
DAY = 86_400.0
YEAR = 365.25 * DAY

_LENGTHS = (("mm", 1e-3, 0.0), ("m", 1.0, 2.0), ("km", 1e3, 2e4), ("AU", AU, 0.01 * AU))
_TIMES = (("s", 1.0, 0.0), ("day", DAY, 10 * DAY), ("yr", YEAR, 2 * YEAR))


@dataclass(frozen=True)
class AxisUnit:
    """A unit of an axis: its symbol and its SI value.

    Attributes
    ----------
    name
        The symbol in the label (``"mm"``, ``"AU"``, ``"yr"``).
    size
        Its value in SI units (``0.001``; metres per AU; seconds per year).
    """

    name: str
    size: float

    def of(self, values_si: np.ndarray) -> np.ndarray:
        """``values_si`` in this unit."""
        return np.asarray(values_si, dtype=float) / self.size


def _pick(table: tuple[tuple[str, float, float], ...], span: float) -> AxisUnit:
    name, size, _ = table[0]
    for n, s, start in table:
        if np.isfinite(span) and span >= start:
            name, size = n, s
    return AxisUnit(name, size)


def length_unit_for(span_m: float) -> AxisUnit:
    """The length unit for data spanning ``span_m`` metres (largest extent or magnitude)."""
    return _pick(_LENGTHS, abs(float(span_m)))


def time_unit_for(t_end_s: float) -> AxisUnit:
    """The time unit for a run of ``t_end_s`` seconds."""
    return _pick(_TIMES, abs(float(t_end_s)))


def run_axis_units(t_s: np.ndarray, positions_m: np.ndarray | None) -> tuple[AxisUnit, AxisUnit]:
    """``(length, time)`` units of a run's figures from its saved times [s] and positions [m].

    A later scene ``[units]`` table takes precedence here (one place to change).
    """
    t = np.asarray(t_s, dtype=float)
    t_end = float(np.nanmax(np.abs(t))) if t.size else 0.0
    span = 0.0
    if positions_m is not None and np.size(positions_m):
        p = np.asarray(positions_m, dtype=float)
        span = float(np.nanmax(np.abs(p))) if np.isfinite(p).any() else 0.0
    return length_unit_for(span), time_unit_for(t_end)
