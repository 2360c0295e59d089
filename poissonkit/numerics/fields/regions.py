"""Which body left which table: a run's non-finite state explained by the fields' regions.

A tabulated field (uniform or adaptive) is NaN outside its region, so a body that leaves it gets
NaN forces and the run stops with a :class:`~poissonkit.errors.NonFiniteStateError` giving a
step and an internal time. :func:`explain_nonfinite` turns that into a
:class:`FieldRegionError` naming the field, the body, its position [m] and the time [s], from
the state at the failure (positions stay finite there: the drift that carried the body out was
computed from finite momenta; the NaN comes with the kick that follows).
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
        The body's position [m] at the failure.
    time_s
        The time [s] (``time`` keeps the internal time of the step, as for the base class).
    """

    def __init__(self, step: int, time: float, field: str, body: str,
                 position: Sequence[float], region: tuple[np.ndarray, np.ndarray],
                 time_s: float) -> None:
        self.field, self.body, self.time_s = field, body, time_s
        self.position = [float(x) for x in position]
        super().__init__(step, time)
        lo, hi = region
        self.args = (f"body {body!r} left the region of field {field!r} at t = {time_s:.6g} s: "
                     f"it is at {[round(x, 6) for x in self.position]} m, the table covers "
                     f"{[round(float(x), 6) for x in lo]}..{[round(float(x), 6) for x in hi]} m;"
                     " give the field a region that contains the motion",)

    def __str__(self) -> str:
        return str(self.args[0])


def tabulated_regions(fields: Sequence[CompiledField]
                      ) -> list[tuple[int, CompiledField, np.ndarray, np.ndarray]]:
    """``(index, field, lo, hi)`` of every field with a tabulated region (SI)."""
    out = []
    for k, f in enumerate(fields):
        region = f.info.get("region_m")
        if region is not None:
            out.append((k, f, np.asarray(region[0], float), np.asarray(region[1], float)))
    return out


def explain_nonfinite(system: object, y: np.ndarray, error: NonFiniteStateError
                      ) -> NonFiniteStateError:
    """``error`` as a :class:`FieldRegionError` if a body that reads a tabulated field of
    ``system`` (an :class:`~poissonkit.numerics.nbody.NBodySystem`) is outside its region in
    the state ``y`` at the failure; otherwise ``error`` itself."""
    from poissonkit.numerics.nbody import NBodySystem

    if not isinstance(system, NBodySystem) or not system.fields:
        return error
    regions = tabulated_regions(system.fields)
    if not regions:
        return error
    r = np.asarray(system.unpack(np.asarray(y, float), si=True)["r"], float).reshape(-1, 3)
    coupling = system.data.fields.coupling
    unit = float(system.scales.time) if system.scales is not None else 1.0
    for k, body in enumerate(system.bodies):
        if body.fixed or k >= len(r):
            continue
        for f_index, f, lo, hi in regions:
            if coupling[k, f_index] == 0.0:
                continue
            if np.all(np.isfinite(r[k])) and (np.any(r[k] < lo) or np.any(r[k] > hi)):
                return FieldRegionError(error.step, error.time, f.name, body.name, r[k],
                                        (lo, hi), error.time * unit)
    return error
