"""The solids of magpylib sources (:class:`~poissonkit.numerics.fields.solids.Solid`): what
each magnet or wire of a source or ``Collection`` occupies, at its position and orientation
(the last of a path)."""

from __future__ import annotations

from typing import Any

import numpy as np

from poissonkit.numerics.fields.solids import Solid
from poissonkit_magnets.exact_sources import leaf_sources


def _dimensions(leaf: Any) -> tuple[str, dict[str, Any]] | None:
    """The kind and dimensions of one magpylib source (``None``: no shape, e.g. a Dipole)."""
    name = type(leaf).__name__
    dim = np.asarray(getattr(leaf, "dimension", np.zeros(0)), dtype=float)
    if name == "Cylinder":
        return "cylinder", {"radius": dim[0] / 2, "height": dim[1]}
    if name == "CylinderSegment":
        return "cylinder_segment", dict(zip(("inner_radius", "outer_radius", "height", "phi1",
                                             "phi2"), dim.tolist(), strict=True))
    if name == "Cuboid":
        return "cuboid", dict(zip("abc", dim.tolist(), strict=True))
    if name == "Sphere":
        return "sphere", {"radius": float(leaf.diameter) / 2}
    if name == "Circle":
        return "loop", {"radius": float(leaf.diameter) / 2}
    if name == "Polyline":
        return "polyline", {"vertices": np.asarray(leaf.vertices, float).tolist()}
    if name == "Tetrahedron":
        v = np.asarray(leaf.vertices, float)
        return "mesh", {"vertices": v.tolist(), "faces": [[0, 1, 2], [0, 1, 3], [0, 2, 3],
                                                          [1, 2, 3]]}
    if name == "TriangularMesh":
        return "mesh", {"vertices": np.asarray(leaf.vertices, float).tolist(),
                        "faces": np.asarray(leaf.faces, int).tolist()}
    return None


def magpylib_solids(source: Any, field: str = "magpylib") -> tuple[Solid, ...]:
    """The solid pieces of a magpylib source or ``Collection`` (sources without a shape, such
    as a ``Dipole``, have none)."""
    out = []
    for leaf in leaf_sources(source):
        kind = _dimensions(leaf)
        if kind is None:
            continue
        pos = np.asarray(leaf.position, dtype=float).reshape(-1, 3)[-1]
        rot = np.asarray(leaf.orientation.as_rotvec(), dtype=float).reshape(-1, 3)[-1]
        out.append(Solid(kind[0], (float(pos[0]), float(pos[1]), float(pos[2])),
                         (float(rot[0]), float(rot[1]), float(rot[2])), kind[1], field=field))
    return tuple(out)
