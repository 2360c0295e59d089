"""What a run's system says about its units, its state layout and the two-body distance.

Small readers shared by ``poissonkit run`` (:mod:`poissonkit.commands.run`) and the writers of
its files (:mod:`poissonkit.report.run_output`): each looks at the system through a capability
protocol of :mod:`poissonkit.contracts` and has a neutral answer for a system without it.

Display in the scene's units (figures, the 3D view, progress, messages): :func:`unit_system`
of a run, :func:`scene_time_unit` and :func:`scene_step` for times, and :func:`display_unit`
(+ :func:`axis_label`) for the unit an axis shows SI values of a kind in. Every other value
(trajectory rows, sizes, ``time_unit``) stays internal or SI as before.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from poissonkit.contracts import HasBodies, HasLayout, HasScales, HasUnpack, Trajectory
from poissonkit.numerics.units import Scales
from poissonkit.numerics.unitsystem import SI, UnitSystem
from poissonkit.traits import offers

if TYPE_CHECKING:
    from poissonkit.numerics.runspec import RunSpec


def scales_of(system: object) -> Scales | None:
    """The internal units of ``system`` (:class:`~poissonkit.contracts.HasScales`), ``None``
    for a system in SI units."""
    s = system.scales if offers(system, HasScales) else None
    return s if isinstance(s, Scales) else None


def layout_of(system: object) -> tuple[str, ...]:
    """Names of the state's components (:class:`~poissonkit.contracts.HasLayout`), or ()."""
    return tuple(system.layout) if offers(system, HasLayout) else ()


def time_unit(spec: RunSpec) -> float:
    """The SI value [s] of the run's internal time unit (1 for a run in SI units)."""
    sc = spec.metadata.get("scales") if spec.metadata else None
    if isinstance(sc, dict) and "time" in sc:
        return float(sc["time"])
    s = scales_of(spec.system)
    return float(s.time) if s is not None else 1.0


def trajectory_rows(sol: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """``(t, y)`` of a solution with ``y`` as rows (one state per saved time)."""
    t = np.asarray(sol.t, dtype=float)
    y = np.asarray(sol.y, dtype=float)
    if y.ndim == 2 and y.shape[0] != t.shape[0] and y.shape[1] == t.shape[0]:
        y = y.T
    return t, y


def relative_position(spec: RunSpec, y: np.ndarray) -> np.ndarray | None:
    """Relative position ``r_2 - r_1`` of a two-body run (internal units), or ``None``."""
    system = spec.system
    # bodies in the state (N-body form): the first two moving ones, or the first one
    n_moving = system.n_moving if offers(system, HasBodies) else 0
    if offers(system, HasUnpack) and n_moving == 2:
        r = system.unpack(y)["r"]
        diff: np.ndarray = r[:, 1] - r[:, 0]
        return diff
    if layout_of(system)[:3] and y.shape[1] == 18:  # the seed's centre-of-mass form
        rel: np.ndarray = y[:, 0:3]
        return rel
    if offers(system, HasUnpack) and n_moving >= 1:
        first: np.ndarray = system.unpack(y)["r"][:, 0]
        return first
    return None


# ---------------------------------------------------------------- the scene's units for display

def unit_system(spec: RunSpec | Mapping[str, object] | None) -> UnitSystem:
    """The units the run's scene was written in (``metadata["units"]``, set by
    :func:`poissonkit.scene.build.build_run`), from the run or its metadata mapping (e.g. a
    figure's ``RunData.metadata``, or ``summary.json``'s ``parameters``); SI without them."""
    meta = spec if isinstance(spec, Mapping) or spec is None else spec.metadata
    d = meta.get("units") if meta else None
    return UnitSystem.from_dict(d) if isinstance(d, Mapping) else SI


def scene_time_unit(spec: RunSpec) -> tuple[float, str]:
    """``(factor, label)``: internal time × ``factor`` is time in the scene's unit ``label``
    (``(time_unit(spec), "s")`` for an SI scene): for progress bars, messages, axes."""
    units = unit_system(spec)
    return time_unit(spec) / units.si_per_unit("time"), units.label("time")


def scene_step(spec: RunSpec) -> float | None:
    """The run's fixed step in the scene's time unit (``None``: adaptive)."""
    if spec.step is None:
        return None
    return float(spec.step) * scene_time_unit(spec)[0]


@dataclass(frozen=True)
class DisplayUnit:
    """How to show a quantity on an axis: ``shown = si_value * factor``, labelled ``label``
    (e.g. ``"AU"``, ``"mm"``, ``"10⁶ J"``). Prefixes never collide with unit symbols: SI
    lengths use nm … km and then AU (or a power of ten), never Tm or Gm."""

    label: str
    factor: float

    def __call__(self, si_values: npt.ArrayLike) -> np.ndarray:
        """The values to plot."""
        return np.asarray(si_values, dtype=float) * self.factor


#: SI length units shown, with their size [m]: no prefix beyond km (Tm reads as tesla).
_SI_LENGTHS = (("nm", 1e-9), ("µm", 1e-6), ("mm", 1e-3), ("m", 1.0), ("km", 1e3))
#: SI time units shown for long runs (s and below keep SI prefixes: ms, µs).
_SI_TIMES = (("ns", 1e-9), ("µs", 1e-6), ("ms", 1e-3), ("s", 1.0), ("day", 86400.0),
             ("yr", 365.25 * 86400.0))
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def display_unit(kind: str, si_values: npt.ArrayLike = (), units: UnitSystem = SI
                 ) -> DisplayUnit:
    """The unit to show SI values of ``kind`` in, for the run's units.

    An SI scene gets a prefixed or larger unit fitting the values (lengths: nm … km, then AU
    beyond 10⁶ km; times: ns … s, day, yr); a scene in its own units gets those units
    (``"AU"``, ``"M☉ AU/day"``). Values whose size still lies outside 10⁻³ … 10⁴ get a power
    of ten in the label (``"10⁹ J"``); N-body units are labelled ``L``, ``M``, ``T``.

    Parameters
    ----------
    kind
        A quantity kind (:data:`poissonkit.numerics.unitsystem.DIMENSIONS`: ``"length"``,
        ``"time"``, ``"energy"``, ...).
    si_values
        The values to be shown (SI), which choose the unit; empty: no choice by size.
    units
        The scene's units (:func:`unit_system`).
    """
    v = np.abs(np.asarray(si_values, dtype=float))
    v = v[np.isfinite(v)]
    size = float(v.max()) if v.size else 0.0
    if units.is_si and kind in ("length", "time"):
        table: tuple[tuple[str, float], ...] = _SI_LENGTHS if kind == "length" else _SI_TIMES
        if kind == "length" and size >= 1e9:
            table = (("AU", 149_597_870_700.0),)
        name, unit = table[0]
        for cand, c_unit in table:
            if size >= c_unit or cand == table[0][0]:
                name, unit = cand, c_unit
        return _with_power(name, 1.0 / unit, size)
    return _with_power(units.label(kind), 1.0 / units.si_per_unit(kind), size)


def _with_power(label: str, factor: float, size_si: float) -> DisplayUnit:
    """``label`` with a power of ten (a multiple of 3) when the shown size is outside
    10⁻³ … 10⁴."""
    shown = size_si * factor
    if shown == 0 or 1e-3 <= shown < 1e4:
        return DisplayUnit(label, factor)
    power = 3 * int(math.floor(math.log10(shown) / 3))
    head = f"10{str(power).translate(_SUPERSCRIPT)}"
    return DisplayUnit(f"{head} {label}" if label != "1" else head, factor / 10.0 ** power)


def axis_label(name: str, unit: DisplayUnit) -> str:
    """``"name [unit]"`` (``"name"`` alone for a dimensionless quantity)."""
    return f"{name} [{unit.label}]" if unit.label != "1" else name
