"""The units figures and the 3D view label their axes in: one place that chooses them.

Every figure of a run asks :func:`run_axis_units` (or :func:`length_unit_for` /
:func:`time_unit_for` for bare arrays) and divides its SI values by the unit's ``size``; the
label is the unit's ``name``. The choice reads the run's units through
:mod:`poissonkit.report.run_units` and the extent of the data: millimetres for magnets (the
seed's figures), metres, kilometres, astronomical units for planets; seconds, days, years.
Names are unit symbols, never an SI prefix on a number (no "4T" for terametres, read as tesla).

A scene with a ``[units]`` table is drawn in its own units (``AU`` and ``yr``, with a power of
ten when the values lie far from 1; ``L`` and ``T`` for N-body units): pass ``units``, or draw
inside :func:`scene_units` (what :func:`~poissonkit.report.figures.write_figures` does with the
run's units, so every registered figure follows them). SI scenes keep the choice above.

>>> length_unit_for(0.02).name, length_unit_for(7.8e11).name
('mm', 'AU')
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

import numpy as np

from poissonkit.numerics.unitsystem import SI, UnitSystem

__all__ = ["AU", "DAY", "YEAR", "AxisUnit", "dataset_units", "length_unit_for",
           "quantity_unit", "run_axis_units", "scene_units", "time_unit_for"]

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


#: The units of the scene whose figures are being drawn (:func:`scene_units`).
_SCENE_UNITS: ContextVar[UnitSystem] = ContextVar("poissonkit_scene_units", default=SI)


@contextmanager
def scene_units(units: UnitSystem) -> Iterator[None]:
    """Inside, figures choose their axis units from ``units`` (a scene's ``[units]``)."""
    token = _SCENE_UNITS.set(units)
    try:
        yield
    finally:
        _SCENE_UNITS.reset(token)


def dataset_units(attrs: Mapping[object, object]) -> UnitSystem:
    """The units a trajectory dataset's values are in, from its attributes (``units_length``,
    ``units_time``, ``units_mass``, ``units_G`` of
    :func:`~poissonkit.report.trajectory.unit_attributes`); SI without them."""
    names = [attrs.get(f"units_{k}") for k in ("length", "time", "mass")]
    if not all(isinstance(n, str) for n in names):
        return SI
    if names == ["L", "T", "M"]:
        return UnitSystem(G=float(attrs.get("units_G", 1.0)))  # type: ignore[arg-type]
    return UnitSystem(str(names[0]), str(names[1]), str(names[2]))


def _in_scene_units(kind: str, size_si: float, units: UnitSystem) -> AxisUnit:
    """The scene's own unit of ``kind`` (with a power of ten for values far from 1)."""
    from poissonkit.report.run_units import display_unit

    shown = display_unit(kind, [size_si], units)
    base = units.si_per_unit(kind)
    power = round(float(np.log10(1.0 / (shown.factor * base))))  # the label's power of ten
    return AxisUnit(shown.label, base * 10.0 ** power)


def _pick(table: tuple[tuple[str, float, float], ...], span: float) -> AxisUnit:
    name, size, _ = table[0]
    for n, s, start in table:
        if np.isfinite(span) and span >= start:
            name, size = n, s
    return AxisUnit(name, size)


def length_unit_for(span_m: float, units: UnitSystem | None = None) -> AxisUnit:
    """The length unit for data spanning ``span_m`` metres (largest extent or magnitude), in
    the scene's ``units`` (default: those of :func:`scene_units`, else SI)."""
    units = _SCENE_UNITS.get() if units is None else units
    if not units.is_si:
        return _in_scene_units("length", abs(float(span_m)), units)
    return _pick(_LENGTHS, abs(float(span_m)))


def time_unit_for(t_end_s: float, units: UnitSystem | None = None) -> AxisUnit:
    """The time unit for a run of ``t_end_s`` seconds, in the scene's ``units`` (default:
    those of :func:`scene_units`, else SI)."""
    units = _SCENE_UNITS.get() if units is None else units
    if not units.is_si:
        return _in_scene_units("time", abs(float(t_end_s)), units)
    return _pick(_TIMES, abs(float(t_end_s)))


def run_axis_units(t_s: np.ndarray, positions_m: np.ndarray | None,
                   units: UnitSystem | None = None) -> tuple[AxisUnit, AxisUnit]:
    """``(length, time)`` units of a run's figures from its saved times [s] and positions [m]
    (SI values whatever the scene's units).

    ``units``: the scene's units (default: those of :func:`scene_units`, else SI); a scene in
    its own units gets them, an SI scene the unit fitting the data (mm for magnets, AU for
    planets; s, day, yr).
    """
    t = np.asarray(t_s, dtype=float)
    t_end = float(np.nanmax(np.abs(t))) if t.size else 0.0
    span = 0.0
    if positions_m is not None and np.size(positions_m):
        p = np.asarray(positions_m, dtype=float)
        span = float(np.nanmax(np.abs(p))) if np.isfinite(p).any() else 0.0
    return length_unit_for(span, units), time_unit_for(t_end, units)


#: The SI unit figures of an SI scene label each other kind with.
_SI_LABELS = {"energy": "J", "angular_momentum": "J s", "momentum": "kg m/s", "mass": "kg",
              "velocity": "m/s"}


def quantity_unit(kind: str, values_si: np.ndarray, units: UnitSystem | None = None
                  ) -> AxisUnit:
    """The unit of an axis showing SI values of ``kind`` (``"energy"``,
    ``"angular_momentum"``, ...): the SI unit for an SI scene (``J``, ``J s``), else the scene's
    own (``M☉ AU²/yr²``, with a power of ten for values far from 1)."""
    units = _SCENE_UNITS.get() if units is None else units
    if units.is_si:
        return AxisUnit(_SI_LABELS.get(kind) or units.label(kind), 1.0)
    v = np.abs(np.asarray(values_si, dtype=float))
    v = v[np.isfinite(v)]
    return _in_scene_units(kind, float(v.max()) if v.size else 0.0, units)
