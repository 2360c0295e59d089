"""Shapes of bodies and the overlap test used when a scene is loaded.

A body with ``radius`` and ``length`` is a solid cylinder about its axis; with only ``radius``
a ball; otherwise a point. Two convex shapes overlap iff their distance is 0; the distance is
found by alternating projections (von Neumann), which converges to a closest pair of points of
two disjoint closed convex sets and to a common point of intersecting ones. Projection onto a
cylinder is closed form (clamp the axial and the radial coordinate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


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
        z = float(d @ self.axis)
        radial = d - z * self.axis
        rho = float(np.linalg.norm(radial))
        z = min(max(z, -self.half_length), self.half_length)
        if rho > self.radius:
            radial *= self.radius / rho
        return self.center + z * self.axis + radial


def shape_of(center, axis=None, radius: float = 0.0, half_length: float = 0.0) -> Shape:
    """The shape of a body from its magnet/size attributes (see the module docstring)."""
    c = np.asarray(center, dtype=float)
    if radius > 0 and half_length > 0 and axis is not None:
        a = np.asarray(axis, dtype=float)
        return Shape("cylinder", c, a / np.linalg.norm(a), radius, half_length)
    if radius > 0:
        return Shape("ball", c, None, radius)
    return Shape("point", c)


def distance(a: Shape, b: Shape, iterations: int = 2000, rtol: float = 1e-10) -> float:
    """Distance between two convex shapes (0 if they intersect), by alternating projections."""
    gap = float(np.linalg.norm(a.center - b.center))
    scale = max(a.bounding_radius, b.bounding_radius, gap, 1e-300)
    x = a.project(b.center)
    previous = math.inf
    d = math.inf
    for _ in range(iterations):
        y = b.project(x)
        x = a.project(y)
        d = float(np.linalg.norm(x - y))
        if d <= rtol * scale or abs(previous - d) <= 1e-14 * scale:
            break
        previous = d
    return d if d > rtol * scale else 0.0


def overlapping(a: Shape, b: Shape) -> bool:
    """True if the two shapes share a point (touching counts as overlapping)."""
    if np.linalg.norm(a.center - b.center) > a.bounding_radius + b.bounding_radius:
        return False  # disjoint bounding spheres
    return distance(a, b) == 0.0
