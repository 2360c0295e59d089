"""Typed events located inside the step: collision, geometric contact, escape, closest approach.

Every event has a continuous *event function* ``g(y)`` that is positive while nothing happens:

* :class:`Collision` — smallest centre distance minus ``distance``;
* :class:`Contact` — smallest geometric gap between finite-size bodies (cylinders, balls);
* :class:`Escape` — ``radius`` minus the largest distance from the centre of mass;
* :class:`ClosestApproach` — not terminal: records every local minimum of the smallest centre
  distance that falls below ``distance`` (time and value), the run goes on.

How they are located (see :mod:`poissonkit.numerics.locate`): the compiled time loops
(splitting, midpoint) keep the two previous states and flag a step when ``g`` changed sign, or
when the smallest centre distance has a local minimum among three consecutive step ends that may
dip below the watched distance inside a step (the *grazing* test, see
:func:`~poissonkit.numerics.locate.graze_suspect`). The step is then re-integrated from its start
state with the same method and a shorter step ``s``; the root of ``g`` in ``s`` is bracketed by
bisection until the bracket is shorter than ``time_tol``, and the recorded time is the bracket's
upper end (the first time found with ``g < 0``) with :attr:`EventRecord.time_error` its width.
The bound is on locating the root of the *numerical* trajectory; the integrator's own error adds
to it. The scipy methods hand ``g`` to ``solve_ivp``, which locates sign changes on the dense
output (``time_error`` is then scipy's root-finder tolerance); a dip within one scipy step is
not seen there.

Terminal events stop the integration at the located time, and the last saved state is the state
there. With ``error=True`` a :class:`~poissonkit.errors.CollisionError` /
:class:`~poissonkit.errors.EscapeError` is raised instead of recording the event.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.contracts import (
    HasBodies,
    HasCompiledKernels,
    HasScales,
    HasUnpack,
    System,
)
from poissonkit.errors import CollisionError, EscapeError, InputError
from poissonkit.traits import offers
from poissonkit.validation import positive_number

if TYPE_CHECKING:
    from poissonkit.geometry import Shape

#: Default bisection tolerance on the event time, relative to the step size.
DEFAULT_RELATIVE_TIME_TOL = 1e-9


def _time_tol(value: object, what: str) -> float | None:
    return None if value is None else positive_number(value, f"{what} time_tol")


class _CentreDistanceEvent:
    """What :class:`Collision` and :class:`ClosestApproach` share: both watch the smallest
    centre distance against ``distance`` (checked positive, as is ``time_tol``)."""

    distance: float
    time_tol: float | None

    def __post_init__(self) -> None:
        what = type(self).__name__  # names the event in messages: "Collision distance ..."
        object.__setattr__(self, "distance", positive_number(self.distance, f"{what} distance"))
        object.__setattr__(self, "time_tol", _time_tol(self.time_tol, what))

    @property
    def watch(self) -> float:
        """Centre distance below which the compiled loop hands the step to the locator (and
        the grazing test looks for a dip)."""
        return self.distance

    def value(self, system: HasCompiledKernels, y: np.ndarray) -> float:
        """``g(y)``: smallest centre distance minus ``distance`` (negative inside)."""
        return centre_distance(system, y) - self.distance


@dataclass(frozen=True)
class Collision(_CentreDistanceEvent):
    """Fires when two bodies' centres come closer than ``distance`` (internal length unit).

    Parameters
    ----------
    distance
        Threshold on the smallest centre distance.
    error
        Raise :class:`~poissonkit.errors.CollisionError` instead of recording.
    time_tol
        Bracket width of the located time (internal time); default ``1e-9 × step``.
    """

    distance: float
    error: bool = False
    time_tol: float | None = None
    kind = "collision"
    terminal = True


@dataclass(frozen=True)
class BodyShape:
    """Shape of one body of a system for :class:`Contact` (internal length unit).

    ``radius`` and ``half_length`` > 0 make a solid cylinder about the body's axis ``ν`` (the
    fixed axis for a fixed body, or ``axis`` for a fixed body that is no top, such as a field
    source's solid); only ``radius``: a ball.
    """

    name: str
    radius: float
    half_length: float = 0.0
    axis: tuple[float, float, float] | None = None


@dataclass(frozen=True)
class Contact:
    """Fires when two finite-size bodies touch (geometric gap 0).

    Parameters
    ----------
    shapes
        One :class:`BodyShape` per finite-size body, named as in ``system.bodies``.
    error
        Raise :class:`~poissonkit.errors.CollisionError` instead of recording.
    time_tol
        Bracket width of the located time (internal time); default ``1e-9 × step``.
    """

    shapes: tuple[BodyShape, ...]
    error: bool = False
    time_tol: float | None = None
    kind = "contact"
    terminal = True

    def __post_init__(self) -> None:
        shapes = tuple(self.shapes)
        if len(shapes) < 2:
            raise InputError("Contact needs at least two finite-size bodies")
        for s in shapes:
            positive_number(s.radius, f"Contact shape {s.name!r} radius")
        object.__setattr__(self, "shapes", shapes)
        object.__setattr__(self, "time_tol", _time_tol(self.time_tol, "Contact"))

    @property
    def watch(self) -> float:
        """Centre distance below which two bodies' bounding spheres can touch."""
        b = sorted((math.hypot(s.radius, s.half_length) for s in self.shapes), reverse=True)
        return b[0] + b[1]

    def value(self, system: HasCompiledKernels, y: np.ndarray) -> float:
        """``g(y)``: positive while no two shapes touch, negative once they do.

        Its sign is exact; its value is the gap where cheap — a lower bound (bounding spheres,
        then the capsules around the cylinders) while that is positive, the distance by
        alternating projections otherwise — and, once shapes overlap, minus the overlap of
        their bounding spheres (bisection needs only the sign)."""
        from poissonkit.geometry import shape_of

        pos, axes, fixed = body_frames(system, y)
        index = {name: k for k, name in enumerate(body_names(system))}
        placed = []
        for s in self.shapes:
            k = index.get(s.name)
            if k is None:
                raise InputError(f"Contact: no body named {s.name!r} in the system")
            if fixed[k] and s.axis is not None and not np.any(axes[k]):
                axes[k] = np.asarray(s.axis, dtype=float)
            if s.half_length > 0 and np.any(axes[k]):
                shape = shape_of(pos[k], axes[k], s.radius, s.half_length)
            else:  # no orientation in the state (point mass): its bounding ball, conservatively
                shape = shape_of(pos[k], None, math.hypot(s.radius, s.half_length))
            placed.append((k, s, shape))
        best = math.inf
        if len(placed) > TREE_SHAPES:
            candidates, best = _near_pairs(placed, pos)
        else:
            candidates = ((i, j) for i in range(len(placed)) for j in range(i + 1, len(placed)))
        for i, j in candidates:
            (ki, _, a), (kj, _, b) = placed[i], placed[j]
            if fixed[ki] and fixed[kj]:
                continue
            best = min(best, shape_gap(a, b, float(np.linalg.norm(pos[ki] - pos[kj]))))
        return best

    def touching(self, system: HasCompiledKernels, y: np.ndarray) -> dict[str, Any]:
        """The pair of shapes with the smallest gap at ``y``: their names (``bodies``), the
        gap, and each one's position and axis (internal length; zero axis: none)."""
        pos, axes, fixed = body_frames(system, y)
        index = {name: k for k, name in enumerate(body_names(system))}
        best: tuple[float, str, str] | None = None
        for i, si in enumerate(self.shapes):
            for sj in self.shapes[i + 1:]:
                ki, kj = index[si.name], index[sj.name]
                if fixed[ki] and fixed[kj]:
                    continue
                gap = Contact((si, sj)).value(system, y)
                if best is None or gap < best[0]:
                    best = (gap, si.name, sj.name)
        if best is None:
            return {}
        gap, a, b = best
        return {"bodies": [a, b], "gap": gap,
                "positions": {n: pos[index[n]].tolist() for n in (a, b)},
                "axes": {n: axes[index[n]].tolist() for n in (a, b)}}


#: Shapes beyond which :meth:`Contact.value` finds candidate pairs with a k-d tree (O(N log N))
#: instead of looking at every pair.
TREE_SHAPES = 64


def _near_pairs(placed: list[tuple[int, BodyShape, Shape]], pos: np.ndarray
                ) -> tuple[list[tuple[int, int]], float]:
    """Pairs of ``placed`` whose bounding spheres may be within ``margin`` of each other, and
    ``margin``: a lower bound of the gap of every other pair (the largest bounding radius)."""
    from scipy.spatial import cKDTree

    reach = max(shape.bounding_radius for _, _, shape in placed)
    margin = reach
    centres = pos[[k for k, _, _ in placed]]
    # every pair left out is more than 3 reach apart: its gap exceeds 3 reach - 2 reach
    pairs = cKDTree(centres).query_pairs(2 * reach + margin, output_type="ndarray")
    return [(int(i), int(j)) for i, j in pairs], margin


@dataclass(frozen=True)
class Escape:
    """Fires when a moving body is farther than ``radius`` from the moving bodies' centre of
    mass (two-body form: from the centre of mass of the pair)."""

    radius: float
    error: bool = False
    time_tol: float | None = None
    kind = "escape"
    terminal = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", positive_number(self.radius, "Escape radius"))
        object.__setattr__(self, "time_tol", _time_tol(self.time_tol, "Escape"))

    def value(self, system: HasCompiledKernels, y: np.ndarray) -> float:
        """``g(y)``: ``radius`` minus the largest distance from the centre of mass."""
        return self.radius - float(system.kernels.max_radius(np.ascontiguousarray(y),
                                                             system.data))


@dataclass(frozen=True)
class ClosestApproach(_CentreDistanceEvent):
    """Records (does not stop at) each local minimum of the smallest centre distance below
    ``distance``, located to ``time_tol``."""

    distance: float
    time_tol: float | None = None
    kind = "closest_approach"
    terminal = False
    error = False


Event = Collision | Contact | Escape | ClosestApproach


@dataclass(frozen=True)
class EventRecord:
    """An event that happened.

    Attributes
    ----------
    kind
        ``"collision"``, ``"contact"``, ``"escape"`` or ``"closest_approach"``.
    step
        Index of the step inside which it happened (1-based).
    time
        Located time (internal unit): the first time found with ``g < 0`` (for a closest
        approach: the time of the minimum).
    value
        Smallest centre distance (collision, contact, closest approach) or largest radius
        (escape) at ``time``.
    time_error
        Width of the final bracket: the true root of the numerical trajectory lies in
        ``[time - time_error, time]`` (closest approach: within ``± time_error``).
    detail
        Who: ``bodies`` (names) at fault and, for a collision or an escape, ``distance_m`` and
        ``quantity`` (:func:`name_bodies`); a contact's gap, positions and axes
        (:meth:`Contact.touching`); JSON-ready.
    """

    kind: str
    step: int
    time: float
    value: float
    time_error: float = 0.0
    detail: dict[str, Any] = field(default_factory=dict)


def check_events(events: Sequence[object] | object | None) -> tuple[Event, ...]:
    """Validate an ``events`` sequence; :class:`InputError` for anything unknown."""
    from poissonkit.numerics.fields.contact import SolidContact

    known = (Collision, Contact, Escape, ClosestApproach, SolidContact)
    if events is None:
        return ()
    if isinstance(events, known):
        events = (events,)
    out = tuple(events)  # type: ignore[arg-type]  # a non-iterable fails below as unknown
    for ev in out:
        if not isinstance(ev, known):
            raise InputError(f"events: unknown event {ev!r}; use numerics.events.Collision, "
                             "Contact, Escape, ClosestApproach or "
                             "numerics.fields.contact.SolidContact")
    return out  # type: ignore[return-value]  # each checked above


#: A contact threshold that keeps the compiled loops' event memory without ever flagging.
TRACK_ONLY = 1e-300


def event_thresholds(events: Sequence[object]) -> tuple[float, float, float]:
    """``(contact, escape, watch)`` thresholds of the compiled loops; 0 disables a check.

    ``contact``: centre distance below which a step end is handed to the locator
    (:data:`TRACK_ONLY` for a :class:`~poissonkit.numerics.fields.contact.SolidContact`, which
    the run's driver watches between chunks); ``escape``: radius beyond which it is;
    ``watch``: the grazing test's distance.
    """
    from poissonkit.numerics.fields.contact import SolidContact

    contact = escape = watch = 0.0
    for ev in check_events(events):
        if isinstance(ev, SolidContact):  # no centre distance to watch, but the loops must
            contact = max(contact, TRACK_ONLY)  # keep the previous states for the locator
        if isinstance(ev, (Collision, Contact)):
            contact = max(contact, ev.watch)
        if isinstance(ev, (Collision, Contact, ClosestApproach)):
            watch = max(watch, ev.watch)
        if isinstance(ev, Escape):
            escape = ev.radius if escape == 0.0 else min(escape, ev.radius)
    return contact, escape, watch


def raise_or_record(ev: Event, record: EventRecord, records: list[EventRecord],
                    system: HasCompiledKernels | None = None, state: np.ndarray | None = None
                    ) -> None:
    """Raise the typed error of a terminal event asked as error, or append its record.

    Given the ``system`` and the ``state`` at the event, a contact's record names the two
    bodies that touched and their positions and axes there (:meth:`Contact.touching`); any
    other event's names the bodies at fault and the distance in metres (:func:`name_bodies`),
    and so does its typed error.
    """
    from poissonkit.numerics.fields.contact import SolidContact, with_record_value

    if isinstance(ev, (Contact, SolidContact)) and system is not None and state is not None:
        record = with_record_value(ev, record, system, state)
        record.detail.update(ev.touching(system, state))
    elif system is not None and state is not None:
        name_bodies(record, system, state)
    if ev.error:
        where = (f"at step {record.step} (t = {record.time:.10g} "
                 f"- [0, {record.time_error:.2g}])")
        who = _who(record)
        if ev.kind == "escape":
            raise EscapeError(f"{who or 'a body'} reached distance {record.value:.6g}"
                              f"{_in_metres(record)} {where}")
        what = "touched" if ev.kind == "contact" else \
            f"came within {record.value:.6g}{_in_metres(record)}"
        if isinstance(ev, SolidContact):
            body, field = record.detail["bodies"]
            raise CollisionError(f"body {body!r} touched field {field!r} {where}")
        raise CollisionError(f"{who or 'bodies'} {what} {where}")
    records.append(record)


def name_bodies(record: EventRecord, system: HasCompiledKernels, state: np.ndarray) -> None:
    """Fill the ``detail`` of a collision, closest approach or escape located at ``state``.

    ``bodies``: the pair at the smallest centre distance (collision, closest approach) or the
    moving body farthest from the moving bodies' centre of mass (escape; the two-body form
    names both bodies, whose separation it watches); ``quantity``: what ``value`` measures;
    ``distance_m``: ``value`` in metres (through the system's scales or units). A system
    without body positions gets ``quantity`` and ``distance_m`` only.
    """
    from poissonkit.numerics.units import Scales
    from poissonkit.numerics.unitsystem import units_of

    escape = record.kind == "escape"
    scales = system.scales if offers(system, HasScales) else None
    length = float(scales.length) if isinstance(scales, Scales) else \
        float(units_of(system).to_si(1.0, "length"))
    record.detail.update(quantity="largest distance from the centre of mass" if escape
                         else "smallest centre distance", distance_m=record.value * length)
    if not (offers(system, HasBodies) or offers(system, HasUnpack)):
        return
    names = body_names(system)
    if escape:
        record.detail["bodies"] = list(names) if not offers(system, HasBodies) else \
            [names[_farthest_body(system, state)]]
    else:
        record.detail["bodies"] = [names[k] for k in _closest_pair(system, state)]


def _who(record: EventRecord) -> str:
    """``body 'a'`` or ``bodies 'a' and 'b'`` from a record's ``detail`` (``""`` if none)."""
    names = record.detail.get("bodies") or []
    if len(names) == 1:
        return f"body {names[0]!r}"
    return f"bodies {names[0]!r} and {names[1]!r}" if len(names) == 2 else ""


def _in_metres(record: EventRecord) -> str:
    d = record.detail.get("distance_m")
    return "" if d is None or d == record.value else f" ({d:.6g} m)"


def _closest_pair(system: HasCompiledKernels, y: np.ndarray) -> tuple[int, int]:
    """Indices of the two bodies (not both fixed) with the smallest centre distance, the pair
    :func:`centre_distance` measures (a k-d tree: each moving body's nearest neighbour)."""
    from scipy.spatial import cKDTree

    pos, _, fixed = body_frames(system, y)
    moving = np.flatnonzero(~fixed)
    dist, nb = cKDTree(pos).query(pos[moving], k=2)
    itself = nb[:, 0] == moving  # else another body sits on it, at distance 0 too
    other = np.where(itself, nb[:, 1], nb[:, 0])
    k = int(np.argmin(np.where(itself, dist[:, 1], dist[:, 0])))
    a, b = int(moving[k]), int(other[k])
    return (a, b) if a < b else (b, a)


def _farthest_body(system: HasCompiledKernels, y: np.ndarray) -> int:
    """Index of the moving body farthest from the moving bodies' centre of mass (what
    ``kernels.max_radius`` measures)."""
    pos, _, _ = body_frames(system, y)
    slot = np.asarray(system.data.body_slot)
    moving = np.flatnonzero(slot >= 0)
    mass = np.asarray(system.data.mass)[slot[moving]]
    centre = mass @ pos[moving] / mass.sum()
    return int(moving[np.argmax(np.linalg.norm(pos[moving] - centre, axis=1))])


# ------------------------------------------------------------------ geometry of a state
def centre_distance(system: HasCompiledKernels, y: np.ndarray) -> float:
    """Smallest centre distance between two bodies (not both fixed), internal length."""
    return float(system.kernels.min_distance(np.ascontiguousarray(y), system.data, system.work()))


#: Body names of the two-body (centre-of-mass) form, which has no ``bodies``.
TWO_BODY_NAMES = ("body1", "body2")


def body_names(system: System) -> tuple[str, ...]:
    """Names of a system's bodies (``body1``, ``body2`` for the two-body form)."""
    if offers(system, HasBodies):
        return tuple(b.name for b in system.bodies)
    return TWO_BODY_NAMES


def body_frames(system: HasCompiledKernels, y: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions, axes and fixed flags of every body (internal length).

    N-body systems: moving point masses get a zero axis; fixed bodies their fixed position and
    axis. The two-body form (``r = r2 − r1``, ``ν1``, ``ν2``) places body 1 at the origin,
    which leaves every distance unchanged.
    """
    y = np.asarray(y, dtype=float)
    if not offers(system, HasBodies):
        if not offers(system, HasUnpack):
            raise InputError(f"{type(system).__name__} has neither bodies nor the two-body "
                             "unpack(y): no body positions for shape events")
        u = system.unpack(y)
        return (np.array([np.zeros(3), u["r"]]), np.array([u["nu1"], u["nu2"]]),
                np.zeros(2, dtype=bool))
    n = len(system.bodies)
    d = system.data
    bslot, tslot = d.body_slot, d.top_slot
    nm = d.mass.shape[0]
    pos = np.array(d.fixed_pos, dtype=float).copy()
    axes = np.array(d.fixed_axis, dtype=float).copy()
    fixed = np.array([b.fixed for b in system.bodies], dtype=bool)
    for k in range(n):
        s = int(bslot[k])
        if s >= 0:
            pos[k] = y[6 * s:6 * s + 3]
        t = int(tslot[k])
        if t >= 0:
            q = 6 * nm + 6 * t
            axes[k] = y[q:q + 3]
    return pos, axes, fixed


def _segment_distance(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray, q2: np.ndarray) -> float:
    """Distance between the segments ``p1 q1`` and ``p2 q2`` (clamped closest points, C. Ericson,
    Real-Time Collision Detection, 2005, §5.1.9)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = float(d1 @ d1), float(d2 @ d2), float(d2 @ r)
    c, b = float(d1 @ r), float(d1 @ d2)
    denom = a * e - b * b
    s = min(max((b * f - c * e) / denom, 0.0), 1.0) if denom > 1e-300 * max(a * e, 1.0) else 0.0
    t = (b * s + f) / e if e > 0 else 0.0
    if t < 0.0:
        t, s = 0.0, min(max(-c / a, 0.0), 1.0) if a > 0 else 0.0
    elif t > 1.0:
        t, s = 1.0, min(max((b - c) / a, 0.0), 1.0) if a > 0 else 0.0
    return float(np.linalg.norm((p1 + s * d1) - (p2 + t * d2)))


def ball_cylinder_gap(ball: Shape, cyl: Shape) -> float:
    """Signed gap between a ball and a solid cylinder in closed form: the distance from the
    ball's centre to the cylinder minus the ball's radius (negative once they overlap: then
    minus the centre's depth inside the cylinder minus the radius)."""
    d = ball.center - cyl.center
    z = float(d @ cyl.axis)
    rho = float(np.linalg.norm(d - z * cyl.axis))
    dz = abs(z) - cyl.half_length
    dr = rho - cyl.radius
    if dz <= 0.0 and dr <= 0.0:
        return max(dz, dr) - ball.radius
    return math.hypot(max(dz, 0.0), max(dr, 0.0)) - ball.radius


def shape_gap(a: Shape, b: Shape, centre: float) -> float:
    """Signed gap of two placed shapes (balls, solid cylinders) whose centres are ``centre``
    apart: a lower bound (bounding spheres, then capsules) while that is positive, the
    distance by alternating projections otherwise, and once they overlap minus the overlap of
    their bounding spheres (see :meth:`Contact.value`)."""
    from poissonkit.geometry import distance

    reach = a.bounding_radius + b.bounding_radius
    if centre > reach:
        return centre - reach  # a lower bound is enough far away
    if (a.kind == "cylinder") != (b.kind == "cylinder"):  # a ball and a cylinder: the closed
        return ball_cylinder_gap(b if a.kind == "cylinder" else a,  # form (a fixed solid
                                 a if a.kind == "cylinder" else b)  # under a body, mostly)
    bound = _capsule_gap(a, b)
    if bound > 0:  # the capsules around the cylinders are apart: so are they
        return bound
    d = distance(a, b)
    return d if d > 0 else centre - reach


def _capsule_gap(a: Shape, b: Shape) -> float:
    """Gap between the capsules (axis segment swept by a ball of the radius) around two shapes;
    a lower bound of the shapes' own gap, since each capsule contains its cylinder or ball."""
    def segment(sh: Shape) -> tuple[np.ndarray, np.ndarray]:
        if sh.kind == "cylinder":
            return sh.center - sh.half_length * sh.axis, sh.center + sh.half_length * sh.axis
        return sh.center, sh.center

    (p1, q1), (p2, q2) = segment(a), segment(b)
    return _segment_distance(p1, q1, p2, q2) - a.radius - b.radius
