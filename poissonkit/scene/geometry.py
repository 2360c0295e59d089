"""Shapes of bodies and their gap solver; moved to :mod:`poissonkit.geometry`.

The numerics (contact events) need them, so they live below the numerics layer; this path keeps
working for code that imported them from the scene package.
"""

from poissonkit.geometry import Shape, distance, overlapping, shape_of, support

__all__ = ["Shape", "distance", "overlapping", "shape_of", "support"]
