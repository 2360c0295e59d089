"""Shapes of bodies and the overlap test used when a scene is loaded.

A body with ``radius`` and ``length`` is a solid cylinder about its axis; with only ``radius``
a ball; otherwise a point. Two convex shapes overlap iff their distance is 0; the distance is
found by alternating projections (von Neumann), which converges to a closest pair of points of
two disjoint closed convex sets and to a common point of intersecting ones, checked against the
lower bound of a separating plane (:func:`distance`). Projection onto a cylinder is closed form
(clamp the axial and the radial coordinate). This is the one gap solver of poissonkit (scene
overlap checks, contact events, ``pair_interaction``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike


@dataclass(frozen=True)
class Shape:
    """A convex body shape: ``kind`` is ``"cylinder"``, ``"ball"`` or ``"point"``."""

    kind: str
    center: np.ndarray
    axis: np.ndarray | None = None
    radius: float = 0.0
    half_length: float = 0.0

    @property
    def bounding_radius(self) -> float:
        """Radius of the smallest centred ball containing the shape."""
        return math.hypot(self.radius, self.half_length) if self.kind == "cylinder" else self.radius

    def project(self, x: np.ndarray) -> np.ndarray:
        """The point of the shape closest to ``x``."""
        d = x - self.center
        if self.kind == "point":
            return self.center.copy()
        if self.kind == "ball":
            n = float(np.linalg.norm(d))
            return x.copy() if n <= self.radius else self.center + d * (self.radius / n)
        assert self.axis is not None  # a cylinder has an axis (shape_of)
        z = float(d @ self.axis)
        radial = d - z * self.axis
        rho = float(np.linalg.norm(radial))
        z = min(max(z, -self.half_length), self.half_length)
        if rho > self.radius:
            radial *= self.radius / rho
        closest: np.ndarray = self.center + z * self.axis + radial
        return closest


def shape_of(center: ArrayLike, axis: ArrayLike | None = None, radius: float = 0.0,
             half_length: float = 0.0) -> Shape:
    """The shape of a body from its magnet/size attributes (see the module docstring)."""
    c = np.asarray(center, dtype=float)
    if radius > 0 and half_length > 0 and axis is not None:
        a = np.asarray(axis, dtype=float)
        return Shape("cylinder", c, a / np.linalg.norm(a), radius, half_length)
    if radius > 0:
        return Shape("ball", c, None, radius)
    return Shape("point", c)


def support(shape: Shape, u: np.ndarray) -> float:
    """``max(u · p)`` over the points ``p`` of the shape (its support function)."""
    cu = float(shape.center @ u)
    if shape.kind == "point":
        return cu
    if shape.kind == "ball":
        return cu + shape.radius * float(np.linalg.norm(u))
    z = float(u @ shape.axis)
    return cu + shape.half_length * abs(z) + shape.radius * math.sqrt(max(0.0, float(u @ u) - z * z))


def distance(a: Shape, b: Shape, iterations: int = 5000, rtol: float = 1e-10) -> float:
    """Distance between two convex shapes (0 if they intersect or touch).

    Alternating projections give a pair ``x ∈ a``, ``y ∈ b`` whose distance bounds the gap from
    above; the plane normal to ``x − y`` gives a bound from below (support functions). The
    result is ``|x − y|`` once the two agree within ``rtol × scale`` (``scale``: the larger
    bounding radius or the centre distance), and 0 when ``|x − y| ≤ rtol × scale``; after
    ``iterations`` it is ``|x − y|`` if a separating plane was found, else 0. So a positive
    result always comes with a proof that the shapes are apart (projections alone can stall
    at a small positive distance between overlapping shapes).
    """
    gap = float(np.linalg.norm(a.center - b.center))
    scale = max(a.bounding_radius, b.bounding_radius, gap, 1e-300)
    x = a.project(b.center)
    lower = 0.0
    d = math.inf
    for _ in range(iterations):
        y = b.project(x)
        x = a.project(y)
        w = x - y
        d = float(np.linalg.norm(w))
        if d <= rtol * scale:
            return 0.0
        u = w / d  # from b towards a: min over a of u·p minus max over b of u·q
        lower = max(lower, -support(a, -u) - support(b, u))
        if d - lower <= rtol * scale:
            return d
    return d if lower > 0 else 0.0


def overlapping(a: Shape, b: Shape) -> bool:
    """True if the two shapes share a point (touching counts as overlapping)."""
    if np.linalg.norm(a.center - b.center) > a.bounding_radius + b.bounding_radius:
        return False  # disjoint bounding spheres
    return distance(a, b) == 0.0
