"""Tables that grow: a tabulated field's region follows the bodies that read it.

A tabulated field (uniform or adaptive) covers a box; outside it the field is NaN. During a run
:class:`RegionWatch` looks, at chunk boundaries, at every moving body that reads a growable
field (:attr:`~poissonkit.numerics.fields.base.CompiledField.regrow`): once a body is within
:data:`EDGE_FRACTION` of the box's extent from a face, the box is grown on that side by
:data:`GROW_FRACTION` of its extent, the field is re-tabulated over it (same tolerance, same
kind of table) and written in place into the system's field data, in the room reserved for it
(:attr:`~poissonkit.numerics.fields.base.CompiledField.capacity`, the memory cap). Each growth
is recorded (``field``, ``time``, ``old``, ``new`` boxes [m]). A table that cannot grow (the
new one needs more room or more nodes than allowed) is recorded as such and left alone: a body
that leaves it gets the typed error of :mod:`~poissonkit.numerics.fields.regions`.

The chunk guard (:class:`~poissonkit.numerics.fields.contact.ChunkGuard`) keeps chunks short
enough that no body crosses a face within one: :meth:`RegionWatch.room` is the distance to the
nearest face. Between two tables the interpolants differ by at most their tolerance: a body's
energy then steps by that much (the run's energy error is of the order of the table's stated
accuracy).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField

#: A body closer to a face than this fraction of the box's extent (along that axis) grows it.
EDGE_FRACTION = 0.1
#: How far a face moves out when it grows, as a fraction of the box's extent.
GROW_FRACTION = 0.5


class RegionWatch:
    """The growable tables of a system and the bodies that read them (module docstring)."""

    def __init__(self, system: Any, watched: list[tuple[int, list[int]]]) -> None:
        self.system = system
        self.watched = watched  # (field index, indices of the moving bodies that read it)
        self.log: list[dict[str, Any]] = []
        d = system.scales
        self.length = float(d.length) if d is not None else 1.0

    def _box(self, f: int) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = self.system.fields[f].info["region_m"]
        return np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)

    def _positions(self, y: np.ndarray) -> np.ndarray:
        return np.asarray(self.system.unpack(np.asarray(y, float), si=True)["r"],
                          dtype=float).reshape(-1, 3)

    def room(self, y: np.ndarray) -> float:
        """Smallest distance (internal length) from a watched body to a face of its table."""
        r = self._positions(y)
        best = np.inf
        for f, bodies in self.watched:
            lo, hi = self._box(f)
            p = r[bodies]
            best = min(best, float(np.min(np.minimum(p - lo, hi - p))))
        return max(best, 0.0) / self.length

    def grow(self, y: np.ndarray, t_seconds: float) -> None:
        """Grow every table a watched body is near the face of (module docstring)."""
        r = self._positions(y)
        for item in list(self.watched):
            f, bodies = item
            lo, hi = self._box(f)
            new_lo, new_hi = _grown(lo, hi, r[bodies])
            if np.array_equal(new_lo, lo) and np.array_equal(new_hi, hi):
                continue
            entry: dict[str, Any] = {"field": self.system.fields[f].name, "time": t_seconds,
                                     "old": [lo.tolist(), hi.tolist()],
                                     "new": [new_lo.tolist(), new_hi.tolist()]}
            reason = self._replace(f, new_lo, new_hi)
            if reason is not None:
                entry.update(grown=False, reason=reason)
                self.watched.remove(item)  # left alone: a body leaving it gets the typed error
            self.log.append(entry)

    def _replace(self, f: int, lo: np.ndarray, hi: np.ndarray) -> str | None:
        """Re-tabulate field ``f`` over ``[lo, hi]`` in place; why not, or ``None``."""
        old: CompiledField = self.system.fields[f]
        assert old.regrow is not None
        try:
            new = old.regrow(lo, hi)
        except InputError as exc:
            return str(exc)
        fd = self.system.data.fields
        start, stop = int(fd.offsets[f]), int(fd.offsets[f + 1])
        data = np.asarray(new.data, dtype=float).ravel()
        if new.kernel is not old.kernel:
            return "the grown table needs another kind of table"
        if data.size > stop - start:
            return (f"the grown table needs {data.size * 8 / 1e6:.1f} MB, more than the "
                    f"{(stop - start) * 8 / 1e6:.1f} MB reserved for it")
        fd.params[start:start + data.size] = data
        fd.params[start + data.size:stop] = 0.0
        fields = list(self.system.fields)
        fields[f] = replace(new, regrow=old.regrow, capacity=old.capacity, solids=old.solids,
                            info={**dict(old.info), **dict(new.info)})
        self.system.fields = tuple(fields)
        return None


def _grown(lo: np.ndarray, hi: np.ndarray, points: np.ndarray,
           most: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """The box ``[lo, hi]`` grown, face by face, until every point is farther than
    :data:`EDGE_FRACTION` of the extent from each face (at most ``most`` growths: a resumed
    run may start outside the first table)."""
    lo, hi = lo.copy(), hi.copy()
    for _ in range(most):
        extent = hi - lo
        low = np.any(points - lo < EDGE_FRACTION * extent, axis=0)
        high = np.any(hi - points < EDGE_FRACTION * extent, axis=0)
        if not (low.any() or high.any()):
            break
        lo = np.where(low, lo - GROW_FRACTION * extent, lo)
        hi = np.where(high, hi + GROW_FRACTION * extent, hi)
    return lo, hi


def region_watch(system: object) -> RegionWatch | None:
    """The :class:`RegionWatch` of a system's growable tables (``None``: none)."""
    from poissonkit.numerics.nbody import NBodySystem

    if not isinstance(system, NBodySystem) or not system.fields:
        return None
    coupling = np.asarray(system.data.fields.coupling)
    offsets = system.data.fields.offsets
    slot = np.asarray(system.data.body_slot)  # body → its row in unpack(y)["r"]
    watched = []
    for f, fld in enumerate(system.fields):
        if fld.regrow is None or "region_m" not in fld.info:
            continue
        if int(offsets[f + 1] - offsets[f]) <= np.asarray(fld.data).size:
            continue  # no room reserved: it cannot grow
        bodies = [int(slot[k]) for k in range(len(system.bodies))
                  if slot[k] >= 0 and coupling[k, f] != 0.0]
        if bodies:
            watched.append((f, bodies))
    return RegionWatch(system, watched) if watched else None
