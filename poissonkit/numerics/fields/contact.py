"""Contact of moving bodies with the solids of field sources (magnets, rings, wires).

A field source with a shape (:class:`~poissonkit.numerics.fields.solids.Solid`) is a fixed
body for contact: :class:`SolidContact` is a terminal event whose function ``g(y)`` is the
smallest gap between a moving body and a solid, located inside the step like every other event
(:mod:`poissonkit.numerics.locate`) and recorded as a ``"contact"`` whose ``detail`` names the
body and the field.

The gap: a cylinder or ball solid (:meth:`Solid.contact_shape`) against a body's shape uses the
same pair geometry as body–body contact (:func:`~poissonkit.numerics.events.shape_gap`);
other solids (cuboids, cylinder segments, wires, meshes) use their signed distance
(:meth:`Solid.signed_distance`) from the body's centre minus the radius of the body's bounding
ball (exact for balls and point masses, conservative for a cylinder body).

The compiled time loops watch only centre distances between bodies, so a solid that is no body
would go unseen between chunks; :class:`ChunkGuard` bounds each chunk instead (*conservative
advancement*): a chunk may last only as long as the bodies, at their present speed and
measured acceleration, take to cover half the gap, and the state at a chunk's end is tested
(``g < 0``: the chunk's last step is handed to the locator, as a flagged step is).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.contracts import HasCompiledKernels
from poissonkit.errors import InputError
from poissonkit.numerics.events import BodyShape, body_frames, body_names, shape_gap
from poissonkit.numerics.fields.solids import Solid
from poissonkit.validation import positive_number

if TYPE_CHECKING:
    from poissonkit.numerics.fields.growth import RegionWatch
    from poissonkit.numerics.nbody import NBodySystem

#: Fraction of the gap a chunk may let the fastest body cover (conservative advancement).
GAP_FRACTION = 0.5


@dataclass(frozen=True)
class SolidContact:
    """Fires when a moving body touches a fixed solid of a field source.

    Parameters
    ----------
    bodies
        The moving bodies watched, as :class:`~poissonkit.numerics.events.BodyShape` in the
        internal length unit (``radius = 0``: a point mass, which touches when its centre
        reaches the solid).
    solids
        The solids (SI, :func:`~poissonkit.numerics.fields.solids.field_solids`).
    length
        The system's internal length unit [m] (1 for an SI system).
    error
        Raise :class:`~poissonkit.errors.CollisionError` instead of recording.
    time_tol
        Bracket width of the located time (internal time); default ``1e-9 × step``.
    """

    bodies: tuple[BodyShape, ...]
    solids: tuple[Solid, ...]
    length: float = 1.0
    error: bool = False
    time_tol: float | None = None
    kind = "contact"
    terminal = True

    def __post_init__(self) -> None:
        bodies, solids = tuple(self.bodies), tuple(self.solids)
        if not bodies or not solids:
            raise InputError("SolidContact needs at least one body and one solid")
        for b in bodies:
            if not (isinstance(b.radius, (int, float)) and math.isfinite(b.radius)
                    and b.radius >= 0):
                raise InputError(f"SolidContact body {b.name!r}: radius must be ≥ 0, "
                                 f"got {b.radius!r}")
        object.__setattr__(self, "bodies", bodies)
        object.__setattr__(self, "solids", solids)
        object.__setattr__(self, "length", positive_number(self.length, "SolidContact length"))
        if self.time_tol is not None:
            object.__setattr__(self, "time_tol",
                               positive_number(self.time_tol, "SolidContact time_tol"))

    def gaps(self, system: HasCompiledKernels, y: np.ndarray) -> np.ndarray:
        """``(n_bodies, n_solids)`` signed gaps at ``y`` (internal length)."""
        from poissonkit.geometry import shape_of

        pos, axes, _ = body_frames(system, y)
        index = {name: k for k, name in enumerate(body_names(system))}
        L = self.length
        out = np.empty((len(self.bodies), len(self.solids)))
        for i, b in enumerate(self.bodies):
            k = index.get(b.name)
            if k is None:
                raise InputError(f"SolidContact: no body named {b.name!r} in the system")
            ball = math.hypot(b.radius, b.half_length)
            for j, s in enumerate(self.solids):
                convex = s.contact_shape()
                if convex is None or b.radius == 0:
                    out[i, j] = float(s.signed_distance(pos[k] * L)[0]) / L - ball
                    continue
                r, half = convex[0] / L, convex[1] / L
                centre = np.asarray(s.position, dtype=float) / L
                solid = (shape_of(centre, s.axis(), r, half) if half > 0
                         else shape_of(centre, None, r))
                body = (shape_of(pos[k], axes[k], b.radius, b.half_length)
                        if b.half_length > 0 and np.any(axes[k])
                        else shape_of(pos[k], None, ball))
                out[i, j] = shape_gap(body, solid, float(np.linalg.norm(pos[k] - centre)))
        return out

    def value(self, system: HasCompiledKernels, y: np.ndarray) -> float:
        """``g(y)``: the smallest gap between a watched body and a solid."""
        return float(self.gaps(system, y).min())

    def touching(self, system: HasCompiledKernels, y: np.ndarray) -> dict[str, Any]:
        """The body and the solid with the smallest gap at ``y``: ``bodies`` (the body's name
        and the field's), ``field``, ``solid`` (the piece's description, SI), ``gap`` and the
        body's ``position`` [m]."""
        g = self.gaps(system, y)
        i, j = np.unravel_index(int(np.argmin(g)), g.shape)
        b, s = self.bodies[int(i)], self.solids[int(j)]
        pos, _, _ = body_frames(system, y)
        k = body_names(system).index(b.name)
        return {"bodies": [b.name, s.field], "field": s.field, "solid": s.describe(),
                "gap": float(g[i, j]), "gap_m": float(g[i, j]) * self.length,
                "position_m": (pos[k] * self.length).tolist()}

    def record_value(self, system: HasCompiledKernels, y: np.ndarray) -> float:
        """The value an :class:`~poissonkit.numerics.events.EventRecord` of this event
        carries: the smallest gap (internal length; the bodies' centre distance means nothing
        here, there may be one body only)."""
        return self.value(system, y)


def solid_contact(system: object, bodies: Sequence[BodyShape] | None = None,
                  error: bool = False) -> SolidContact | None:
    """The :class:`SolidContact` of a system's moving bodies with its fields' solids, or
    ``None`` when its fields have no shape.

    Parameters
    ----------
    system
        An :class:`~poissonkit.numerics.nbody.NBodySystem` with fields.
    bodies
        The watched bodies' shapes (internal length); default: every moving body as a point.
    error
        Raise instead of recording.
    """
    from poissonkit.numerics.fields.solids import field_solids
    from poissonkit.numerics.nbody import NBodySystem

    if not isinstance(system, NBodySystem):
        return None
    solids = field_solids(system.fields)
    if not solids:
        return None
    if bodies is None:
        bodies = [BodyShape(b.name, 0.0) for b in system.bodies if not b.fixed]
    length = float(system.scales.length) if system.scales is not None else 1.0
    return SolidContact(tuple(bodies), solids, length, error=error) if bodies else None


def refuse_inside(system: object, y0: np.ndarray) -> None:
    """Refuse a state whose moving bodies start inside a field source's solid or on its wire
    (the field is valid only outside its magnets, and singular on a wire); positions in
    metres. Systems without shaped fields pass.

    Raises
    ------
    InputError
        Naming the field, the body and its position
        (:func:`~poissonkit.numerics.fields.solids.check_outside`).
    """
    from poissonkit.numerics.fields.solids import check_outside, field_solids
    from poissonkit.numerics.nbody import NBodySystem

    if not isinstance(system, NBodySystem) or not system.fields:
        return
    solids = field_solids(system.fields)
    if not solids:
        return
    r = np.asarray(system.unpack(y0, si=True)["r"], dtype=float).reshape(-1, 3)
    slot = np.asarray(system.data.body_slot)  # body → its row of r (moving bodies only)
    moving = [k for k in range(len(system.bodies)) if slot[k] >= 0]
    check_outside(solids, [system.bodies[k].name for k in moving], r[slot[moving]])


class ChunkGuard:
    """What the driver does at chunk boundaries for what the compiled loops cannot see: the
    :class:`SolidContact` events and the growing tables
    (:class:`~poissonkit.numerics.fields.growth.RegionWatch`). ``limit`` before a chunk
    (module docstring), ``after`` once it ran, ``report`` for the run's extras."""

    def __init__(self, system: NBodySystem, events: Sequence[SolidContact],
                 regions: RegionWatch | None = None) -> None:
        self.system: HasCompiledKernels = system  # type: ignore[assignment]
        self.mass = np.asarray(system.data.mass, dtype=float)  # of the momentum slots
        self.events, self.regions = tuple(events), regions
        self.h: float | None = None  # mean step of the last chunk (internal time)
        self.last: tuple[float, np.ndarray] | None = None  # (t, velocities) at its start
        scales = system.scales
        self.time_unit = float(scales.time) if scales is not None else 1.0

    def _velocities(self, y: np.ndarray) -> np.ndarray:
        mass = self.mass
        p = np.asarray(y, dtype=float)[:6 * mass.size].reshape(-1, 6)[:, 3:]
        return p / mass[:, None]

    def _room(self, y: np.ndarray) -> float:
        room = min((ev.value(self.system, y) for ev in self.events), default=math.inf)
        if self.regions is not None and self.regions.watched:
            room = min(room, self.regions.room(y))
        return room

    def limit(self, y: np.ndarray, t: float, max_steps: int) -> int:
        """The most steps the next chunk may take from ``(t, y)``: the fastest body, at its
        speed and the acceleration measured over the last chunk (doubled), covers at most
        :data:`GAP_FRACTION` of the room (the smallest gap to a solid or face of a table)."""
        v = self._velocities(y)
        acc = 0.0
        if self.last is not None and t > self.last[0]:
            acc = float(np.max(np.linalg.norm(v - self.last[1], axis=1))) / (t - self.last[0])
        self.last = (t, v)
        if self.h is None:
            if self.regions is not None and self.regions.watched:  # a resumed run may start
                self.regions.grow(y, t * self.time_unit)  # near or beyond the first table
            return min(max_steps, 1)
        room = self._room(y) * GAP_FRACTION
        if room <= 0:
            return min(max_steps, 1)
        speed = float(np.max(np.linalg.norm(v, axis=1))) if v.size else 0.0
        acc *= 2.0  # the acceleration may grow near a source
        if acc > 0:
            span = (-speed + math.sqrt(speed * speed + 4.0 * acc * room)) / (2.0 * acc)
        else:
            span = room / speed if speed > 0 else math.inf
        steps = span / self.h
        return max(1, min(max_steps, int(steps) if math.isfinite(steps) else max_steps))

    def after(self, y: np.ndarray, t: float, t_before: float, steps: int) -> bool:
        """Grow the tables bodies came near; True if a solid is touched at the chunk's end
        state ``(t, y)`` (``steps`` steps from ``t_before``): its last step holds the
        contact."""
        if steps > 0 and t > t_before:
            self.h = (t - t_before) / steps
        if self.regions is not None and self.regions.watched:
            self.regions.grow(y, t * self.time_unit)
        return any(ev.value(self.system, y) < 0 for ev in self.events)

    def report(self) -> dict[str, Any]:
        """The run's extras: ``field_regrowths`` when a table grew (or could not)."""
        log = self.regions.log if self.regions is not None else []
        return {"field_regrowths": list(log)} if log else {}


def chunk_guard(system: HasCompiledKernels, events: Sequence[object]) -> ChunkGuard | None:
    """The :class:`ChunkGuard` of a run (``None``: no :class:`SolidContact` and no growing
    table)."""
    from poissonkit.numerics.fields.growth import region_watch
    from poissonkit.numerics.nbody import NBodySystem

    if not isinstance(system, NBodySystem):  # solids and tables come with N-body fields
        return None
    solid = [ev for ev in events if isinstance(ev, SolidContact)]
    regions = region_watch(system)
    return ChunkGuard(system, solid, regions) if solid or regions is not None else None


def with_record_value(ev: object, record: Any, system: HasCompiledKernels,
                      y: np.ndarray) -> Any:
    """``record`` with the value of a :class:`SolidContact` (its gap) in place of the centre
    distance the locator puts there."""
    if isinstance(ev, SolidContact):
        return replace(record, value=ev.record_value(system, y))
    return record
