"""Which body left which table: a run's non-finite state explained by the fields' regions.

A tabulated field (uniform or adaptive) is NaN outside its region, so a body that leaves it gets
NaN forces and the run stops with a :class:`~poissonkit.errors.NonFiniteStateError` giving a
step and an internal time. :func:`explain_nonfinite` turns that into a
:class:`FieldRegionError` naming the field, the body, its position [m] and the time [s]. The
compiled loops' driver calls it with the last good state, the one before the failing step
(:meth:`poissonkit.numerics.integrators.driver._Run.last_good`): at the failure the state is
NaN, since the kick that read the table outside its region is followed by drifts. A body is at
fault when it is outside the region there, or when its straight path over the failing step ends
outside.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from poissonkit.errors import NonFiniteStateError
from poissonkit.numerics.fields.base import CompiledField


class FieldRegionError(NonFiniteStateError):
    """A body left the region of a tabulated field (a :class:`NonFiniteStateError`, so code that
    catches those still does).

    Attributes
    ----------
    field, body
        The field's and the body's names.
    position
        The body's position [m] in the state the explanation was made from: the last good state
        before the failure when the solver wires it, else the state at the failure.
    time_s
        The time [s] of the failure (``time`` keeps the internal time, as for the base class).
    position_time_s
        The time [s] of :attr:`position` (``time_s`` when it is the state at the failure).
    velocity
        The body's velocity [m/s] there, or ``None`` when not known.
    """

    def __init__(self, step: int, time: float, field: str, body: str,
                 position: Sequence[float], region: tuple[np.ndarray, np.ndarray],
                 time_s: float, position_time_s: float | None = None,
                 velocity: Sequence[float] | None = None) -> None:
        self.field, self.body, self.time_s = field, body, time_s
        self.position = [float(x) for x in position]
        self.position_time_s = time_s if position_time_s is None else float(position_time_s)
        self.velocity = None if velocity is None else [float(v) for v in velocity]
        super().__init__(step, time)
        lo, hi = region
        where = f"it is at {_m(self.position)} m"
        if self.position_time_s != time_s:
            where = f"at t = {self.position_time_s:.6g} s, its last good state, it was at " \
                    f"{_m(self.position)} m"
            if self.velocity is not None:
                where += f" moving at {_m(self.velocity)} m/s"
        self.args = (f"body {body!r} left the region of field {field!r} at t = {time_s:.6g} s: "
                     f"{where}; the table covers {_m(lo)}..{_m(hi)} m; give the field a region "
                     "that contains the motion",)

    def __str__(self) -> str:
        return str(self.args[0])


def _m(xs: Sequence[float] | np.ndarray) -> list[float]:
    """Rounded figures for a message."""
    return [float(f"{float(x):.6g}") for x in xs]


def tabulated_regions(fields: Sequence[CompiledField]
                      ) -> list[tuple[int, CompiledField, np.ndarray, np.ndarray]]:
    """``(index, field, lo, hi)`` of every field with a tabulated region (SI)."""
    out = []
    for k, f in enumerate(fields):
        region = f.info.get("region_m")
        if region is not None:
            out.append((k, f, np.asarray(region[0], float), np.asarray(region[1], float)))
    return out


def reads_tables(system: object) -> bool:
    """Whether ``system`` is an :class:`~poissonkit.numerics.nbody.NBodySystem` with a
    tabulated field (so that a non-finite state may be a body leaving its region)."""
    from poissonkit.numerics.nbody import NBodySystem

    return isinstance(system, NBodySystem) and bool(tabulated_regions(system.fields))


def explain_nonfinite(system: object, y: np.ndarray, error: NonFiniteStateError,
                      span: float = 0.0, y_time: float | None = None) -> NonFiniteStateError:
    """``error`` as a :class:`FieldRegionError` if a body that reads a tabulated field of
    ``system`` (an :class:`~poissonkit.numerics.nbody.NBodySystem`) leaves its region;
    otherwise ``error`` itself.

    Parameters
    ----------
    system
        The system that failed.
    y
        The state at the failure (its positions finite), or the last good state before it.
    error
        The failure.
    span
        Internal time from ``y`` to the failure (0: ``y`` is the state at the failure). A body
        counts as leaving when it is outside the region at ``y`` or its straight path over
        ``span`` (its velocity at ``y``) ends outside.
    y_time
        Internal time of ``y`` (default: the failure's time minus ``span``).
    """
    from poissonkit.numerics.nbody import NBodySystem

    if not isinstance(system, NBodySystem) or not system.fields:
        return error
    regions = tabulated_regions(system.fields)
    if not regions:
        return error
    parts = system.unpack(np.asarray(y, float), si=True)
    r = np.asarray(parts["r"], float).reshape(-1, 3)
    v = _velocities(system, np.asarray(parts["p"], float).reshape(-1, 3))
    coupling = system.data.fields.coupling
    slots = system.data.body_slot
    unit = float(system.scales.time) if system.scales is not None else 1.0
    dt = float(span) * unit
    when = (error.time - span) if y_time is None else y_time
    for k, body in enumerate(system.bodies):
        slot = int(slots[k]) if k < len(slots) else -1
        if body.fixed or not 0 <= slot < len(r) or not np.all(np.isfinite(r[slot])):
            continue
        ahead = r[slot] + v[slot] * dt if dt > 0 and np.all(np.isfinite(v[slot])) else r[slot]
        for f_index, f, lo, hi in regions:
            if coupling[k, f_index] == 0.0:
                continue
            if _outside(r[slot], lo, hi) or _outside(ahead, lo, hi):
                return FieldRegionError(error.step, error.time, f.name, body.name, r[slot],
                                        (lo, hi), error.time * unit, when * unit,
                                        v[slot] if dt > 0 else None)
    return error


def _outside(x: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> bool:
    return bool(np.any(x < lo) or np.any(x > hi))


def _velocities(system: object, p_si: np.ndarray) -> np.ndarray:
    """Velocities [m/s] of the moving bodies from their momenta [SI] (state order)."""
    from poissonkit.numerics.nbody import NBodySystem

    assert isinstance(system, NBodySystem)
    mass = np.asarray(system.data.mass, float)
    if system.scales is not None:
        mass = mass * float(system.scales.mass)
    n = min(len(mass), len(p_si))
    v = np.full_like(p_si, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        v[:n] = p_si[:n] / mass[:n, None]
    return v
