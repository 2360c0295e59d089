"""The solid shapes of field sources: what a magnet, a coil former or a wire occupies.

A field built from a source with a shape (a magnet, a current loop, a ring base) carries its
:class:`Solid` pieces in :attr:`~poissonkit.numerics.fields.base.CompiledField.solids`. They
serve three readers:

* figures and the 3D view draw them (:func:`field_solids` gives every piece of a system's
  fields with its kind, position, orientation and dimensions, SI);
* a body placed inside one at the start is refused (:func:`check_outside`: the field is valid
  only outside its magnets, and singular on a wire);
* contact events treat the convex pieces (cylinders, balls) as fixed bodies
  (:meth:`Solid.contact_shape`).

Kinds and their ``dimensions`` (metres, degrees for angles):

* ``"cylinder"``: ``radius``, ``height`` (axis: the local ``z``);
* ``"cylinder_segment"``: ``inner_radius``, ``outer_radius``, ``height``, ``phi1``, ``phi2``;
* ``"cuboid"``: ``a``, ``b``, ``c`` (edges along the local ``x``, ``y``, ``z``);
* ``"sphere"``: ``radius``;
* ``"loop"``: ``radius`` (a circular wire in the local ``xy`` plane);
* ``"polyline"``: ``vertices`` (local, a wire);
* ``"mesh"``: ``vertices``, ``faces`` (a closed triangulated body; tetrahedra too).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from poissonkit.errors import InputError

#: Kinds of :class:`Solid` (module docstring).
KINDS = ("cylinder", "cylinder_segment", "cuboid", "sphere", "loop", "polyline", "mesh")
#: Distance [m] from a wire within which a body is said to sit on it.
WIRE_CLEARANCE = 1e-9


@dataclass(frozen=True)
class Solid:
    """One piece of a field source, in SI units.

    Attributes
    ----------
    kind
        One of :data:`KINDS`.
    position
        Centre of the piece [m] (a loop's centre, a polyline's frame origin).
    orientation
        Rotation vector [rad] from the local frame (module docstring) to the global one.
    dimensions
        The kind's dimensions (module docstring).
    field
        Name of the field the piece belongs to (for messages).
    """

    kind: str
    position: tuple[float, float, float]
    orientation: tuple[float, float, float] = (0.0, 0.0, 0.0)
    dimensions: Mapping[str, Any] = field(default_factory=dict)
    field: str = ""

    def rotation(self) -> np.ndarray:
        """The 3×3 matrix of :attr:`orientation` (local → global)."""
        v = np.asarray(self.orientation, dtype=float)
        th = float(np.linalg.norm(v))
        if th == 0.0:
            return np.eye(3)
        k = v / th
        K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
        return np.eye(3) + math.sin(th) * K + (1.0 - math.cos(th)) * (K @ K)

    def local(self, points: npt.ArrayLike) -> np.ndarray:
        """``points`` (n, 3) [m] in the piece's local frame."""
        p = np.asarray(points, dtype=float).reshape(-1, 3) - np.asarray(self.position)
        return p @ self.rotation()

    def axis(self) -> np.ndarray:
        """The local ``z`` axis in the global frame."""
        return self.rotation()[:, 2]

    def inside(self, points: npt.ArrayLike, margin: float = 0.0) -> np.ndarray:
        """True for the points (n, 3) [m] strictly inside the piece grown by ``margin`` [m]
        (a box-like growth, conservative), or on a wire (within ``margin`` or
        :data:`WIRE_CLEARANCE`); a mesh is tested by its bounding box (conservative)."""
        q = self.local(points)
        d = self.dimensions
        m = float(margin)
        rho = np.hypot(q[:, 0], q[:, 1])
        if self.kind == "cylinder":
            return (rho < d["radius"] + m) & (np.abs(q[:, 2]) < d["height"] / 2 + m)
        if self.kind == "cylinder_segment":
            phi = np.degrees(np.arctan2(q[:, 1], q[:, 0]))
            lo, hi = float(d["phi1"]), float(d["phi2"])
            within = ((phi - lo) % 360.0 < (hi - lo)) if hi - lo < 360.0 else np.ones(len(q),
                                                                                   bool)
            if m > 0 and hi - lo < 360.0:  # grown ends: within m of the two end planes too
                within |= np.min([np.abs(_plane_distance(q, a)) for a in (lo, hi)],
                                 axis=0) < m
            return ((rho > d["inner_radius"] - m) & (rho < d["outer_radius"] + m)
                    & (np.abs(q[:, 2]) < d["height"] / 2 + m) & within)
        if self.kind == "cuboid":
            half = np.array([d["a"], d["b"], d["c"]], dtype=float) / 2 + m
            return np.all(np.abs(q) < half, axis=1)
        if self.kind == "sphere":
            return np.linalg.norm(q, axis=1) < d["radius"] + m
        wire = max(m, WIRE_CLEARANCE)
        if self.kind == "loop":
            return np.hypot(rho - d["radius"], q[:, 2]) < wire
        if self.kind == "polyline":
            return _polyline_distance(q, np.asarray(d["vertices"], float)) < wire
        v = np.asarray(d["vertices"], dtype=float)
        return np.all((q > v.min(axis=0) - m) & (q < v.max(axis=0) + m), axis=1)

    def signed_distance(self, points: npt.ArrayLike) -> np.ndarray:
        """Distance [m] of the points (n, 3) [m] from the piece: exact outside, negative
        inside (its magnitude then only a depth estimate: contact events need the sign).

        A wire (``loop``, ``polyline``) is a tube of radius ``wire_radius`` (a dimension,
        default 0: the wire itself); a ``mesh`` is its bounding box (conservative: contact may
        be reported before the mesh is reached, never after)."""
        q = self.local(points)
        d = self.dimensions
        rho = np.hypot(q[:, 0], q[:, 1])
        if self.kind == "sphere":
            return np.linalg.norm(q, axis=1) - float(d["radius"])
        if self.kind == "cylinder":
            r = float(d["radius"])  # (a rectangle symmetric about the axis: ρ = 0 is deep)
            return _rect_distance(rho, q[:, 2], -r, r, float(d["height"]) / 2)
        if self.kind == "cuboid":
            return _box_distance(q, np.array([d["a"], d["b"], d["c"]], dtype=float) / 2)
        if self.kind == "cylinder_segment":
            return _segment_distance_of(q, rho, d)
        wire = float(d.get("wire_radius", 0.0))
        if self.kind == "loop":
            return np.hypot(rho - float(d["radius"]), q[:, 2]) - wire
        if self.kind == "polyline":
            return _polyline_distance(q, np.asarray(d["vertices"], float)) - wire
        v = np.asarray(d["vertices"], dtype=float)
        lo, hi = v.min(axis=0), v.max(axis=0)
        return _box_distance(q - (lo + hi) / 2, (hi - lo) / 2)

    def contact_shape(self) -> tuple[float, float] | None:
        """``(radius, half_length)`` of the convex solid a contact event can use (a cylinder,
        or a ball with half-length 0); ``None`` for other kinds."""
        d = self.dimensions
        if self.kind == "cylinder":
            return float(d["radius"]), float(d["height"]) / 2
        if self.kind == "cylinder_segment" and float(d["phi2"]) - float(d["phi1"]) >= 360.0:
            return float(d["outer_radius"]), float(d["height"]) / 2  # the ring, hole filled
        if self.kind == "sphere":
            return float(d["radius"]), 0.0
        return None

    def describe(self) -> dict[str, Any]:
        """A JSON-ready description (kind, position, orientation, dimensions, field)."""
        dims = {k: (np.asarray(v).tolist() if isinstance(v, (list, tuple, np.ndarray))
                    else float(v)) for k, v in self.dimensions.items()}
        return {"kind": self.kind, "field": self.field, "position_m": list(self.position),
                "orientation_rotvec": list(self.orientation), "dimensions": dims}


def _plane_distance(q: np.ndarray, phi_deg: float) -> np.ndarray:
    """Distance of the local points ``q`` from the half-plane at azimuth ``phi_deg``
    (through the local z axis); points behind the axis count by their distance to it."""
    t = math.radians(phi_deg)
    along = q[:, 0] * math.cos(t) + q[:, 1] * math.sin(t)
    across = -q[:, 0] * math.sin(t) + q[:, 1] * math.cos(t)
    return np.where(along >= 0, np.abs(across), np.hypot(along, across))


def _rect_distance(u: np.ndarray, z: np.ndarray, lo: float, hi: float, half: float
                   ) -> np.ndarray:
    """Signed distance in a half-plane from the rectangle ``lo ≤ u ≤ hi``, ``|z| ≤ half``
    (the cross-section of a cylinder or a ring)."""
    du = np.maximum(lo - u, u - hi)
    dz = np.abs(z) - half
    outside = np.hypot(np.maximum(du, 0.0), np.maximum(dz, 0.0))
    return np.where((du > 0) | (dz > 0), outside, np.maximum(du, dz))


def _box_distance(q: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Signed distance of the points ``q`` from the box ``|q_i| ≤ half_i``."""
    d = np.abs(q) - half
    return np.linalg.norm(np.maximum(d, 0.0), axis=1) + np.minimum(d.max(axis=1), 0.0)


def _segment_distance_of(q: np.ndarray, rho: np.ndarray, d: Mapping[str, Any]) -> np.ndarray:
    """Signed distance from a cylinder segment: within its angular range, from the ring's
    cross-section at the point's azimuth; outside it, from the nearer end face (the distance
    to the cross-section at azimuth ``φ`` grows with the angle between them)."""
    ri, ro, half = float(d["inner_radius"]), float(d["outer_radius"]), float(d["height"]) / 2
    ring = _rect_distance(rho, q[:, 2], ri, ro, half)
    lo, hi = float(d["phi1"]), float(d["phi2"])
    if hi - lo >= 360.0:
        return ring
    phi = np.degrees(np.arctan2(q[:, 1], q[:, 0]))
    within = (phi - lo) % 360.0 <= hi - lo
    ends = []
    for a in (lo, hi):
        t = math.radians(a)
        along = q[:, 0] * math.cos(t) + q[:, 1] * math.sin(t)
        across = -q[:, 0] * math.sin(t) + q[:, 1] * math.cos(t)
        face = np.maximum(_rect_distance(along, q[:, 2], ri, ro, half), 0.0)
        ends.append(np.hypot(across, face))
    end = np.minimum(ends[0], ends[1])
    # inside: no deeper than the distance to an end plane (the sign is what matters)
    return np.where(within, np.where(ring < 0, np.maximum(ring, -end), ring), end)


def _polyline_distance(q: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """Distance of the points ``q`` (n, 3) from the polyline through ``verts``."""
    best = np.full(len(q), np.inf)
    for a, b in zip(verts[:-1], verts[1:], strict=True):
        ab = b - a
        L2 = float(ab @ ab)
        t = np.clip(((q - a) @ ab) / L2, 0.0, 1.0) if L2 > 0 else np.zeros(len(q))
        best = np.minimum(best, np.linalg.norm(q - (a + t[:, None] * ab), axis=1))
    return best


def rotvec_of_axis(axis: npt.ArrayLike) -> tuple[float, float, float]:
    """A rotation vector turning ``e_z`` onto the unit vector along ``axis``."""
    n = np.asarray(axis, dtype=float)
    n = n / np.linalg.norm(n)
    c = float(np.clip(n[2], -1.0, 1.0))
    k = np.cross([0.0, 0.0, 1.0], n)
    s = float(np.linalg.norm(k))
    if s < 1e-15:
        return (0.0, 0.0, 0.0) if c > 0 else (math.pi, 0.0, 0.0)
    v = k / s * math.atan2(s, c)
    return (float(v[0]), float(v[1]), float(v[2]))


def field_solids(fields: Iterable[object]) -> tuple[Solid, ...]:
    """Every solid piece of ``fields`` (built fields, e.g. ``system.fields``), for drawing.

    Examples
    --------
    >>> import poissonkit as pk
    >>> f = pk.field("cylinder", polarization=1.0, radius=0.02, length=0.01).compile()
    >>> [s.kind for s in field_solids([f])]
    ['cylinder']
    """
    from poissonkit.numerics.fields.base import CompiledField

    return tuple(s for f in fields if isinstance(f, CompiledField) for s in f.solids)


def check_outside(solids: Sequence[Solid], names: Sequence[str], points: npt.ArrayLike,
                  unit: str = "m", scale: float = 1.0) -> None:
    """Refuse a body that starts inside a source's solid or on its wire.

    Parameters
    ----------
    solids
        The pieces (:func:`field_solids`).
    names, points
        The bodies' names and SI positions (n, 3) [m].
    unit, scale
        How positions are shown in the message (``position / scale`` in ``unit``).

    Raises
    ------
    InputError
        Naming the field, the body, its position and the piece.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    for s in solids:
        hit = np.nonzero(s.inside(pts))[0]
        if hit.size:
            k = int(hit[0])
            where = "on the wire of" if s.kind in ("loop", "polyline") else "inside"
            raise InputError(f"field {s.field!r}: body {names[k]!r} starts {where} the source "
                             f"({s.kind} at {[round(x / scale, 9) for x in s.position]} {unit}), "
                             f"at {[round(float(x) / scale, 9) for x in pts[k]]} {unit}; the "
                             "field is valid only outside it: move the body out")
