"""The shapes of a system's field sources, for drawing: magnets, rings, current loops.

:func:`source_shapes` is the one adapter between the compiled fields of a system
(:attr:`~poissonkit.numerics.fields.base.CompiledField.info`, what each field says it was built
from) and the figures: a ``cylinder`` field (radius, length, position, axis), a
``current_loop`` (radius, position, axis), a ``magpylib`` source declared by class and
``dimension`` (Cylinder, CylinderSegment, Cuboid, Sphere, Circle) become
:class:`SourceShape` objects. Fields without a shape (gravity, a uniform field, a magpylib
object passed from Python without its dimensions) are skipped. Two coaxial cylinders of
opposite polarisation, the inner one inside the outer (the Levitron's exact base), are one
ring. :func:`outline` and :func:`mesh` give the geometry to draw, in metres.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from poissonkit.contracts import HasExternalFields
from poissonkit.numerics.fields.base import CompiledField
from poissonkit.traits import offers

__all__ = ["SourceShape", "mesh", "outline", "source_shapes"]

_Z = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class SourceShape:
    """A field source to draw (SI).

    Attributes
    ----------
    kind
        ``"cylinder"`` (solid or, with ``inner_radius``, a ring), ``"loop"`` (a current loop of
        ``radius``), ``"box"`` (``size`` along x, y, z), ``"sphere"``.
    label
        What the legend says (``"ring magnet (cylinder fields)"``, ``"magpylib Cuboid"``).
    centre, axis
        Centre [m] and unit symmetry axis.
    radius, inner_radius, length
        Outer and inner radius, full length along the axis [m] (cylinders, rings, loops,
        spheres use ``radius``).
    size
        Edge lengths of a box [m].
    """

    kind: str
    label: str
    centre: tuple[float, float, float]
    axis: tuple[float, float, float] = _Z
    radius: float = 0.0
    inner_radius: float = 0.0
    length: float = 0.0
    size: tuple[float, float, float] = (0.0, 0.0, 0.0)


def source_shapes(system: object) -> list[SourceShape]:
    """The drawable sources of ``system``'s external fields (empty for none).

    Parameters
    ----------
    system
        Any system; its fields are read through
        :class:`~poissonkit.contracts.HasExternalFields`.
    """
    if not offers(system, HasExternalFields):
        return []
    fields = system.external_fields
    shapes: list[SourceShape] = []
    for f in fields if isinstance(fields, Sequence) else ():
        if isinstance(f, CompiledField):
            shape = _shape(f.name, f.info)
            if shape is not None:
                shapes.append(shape)
    return _rings(shapes)


def _num(info: Mapping[str, object], key: str, default: float = 0.0) -> float:
    v = info.get(key, default)
    return float(v) if isinstance(v, (int, float)) else default


def _vec(v: object, default: tuple[float, float, float]) -> tuple[float, float, float]:
    a = np.asarray(v if v is not None else default, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        return default
    return (float(a[0]), float(a[1]), float(a[2]))


def _shape(name: str, info: Mapping[str, object]) -> SourceShape | None:
    if name == "cylinder":
        pol = _num(info, "polarization_T", 1.0)
        return SourceShape("cylinder", "cylinder magnet" + (" (−)" if pol < 0 else ""),
                           _vec(info.get("position_m"), (0, 0, 0)), _unit(info.get("axis")),
                           radius=_num(info, "radius_m"), length=_num(info, "length_m"))
    if name == "current_loop":
        return SourceShape("loop", "current loop", _vec(info.get("position_m"), (0, 0, 0)),
                           _unit(info.get("axis")), radius=_num(info, "radius_m"))
    if name == "magpylib":
        return _magpylib(info)
    return None


def _unit(axis: object) -> tuple[float, float, float]:
    a = np.asarray(_vec(axis, _Z))
    n = float(np.linalg.norm(a))
    return _Z if n == 0 else (float(a[0] / n), float(a[1] / n), float(a[2] / n))


def _magpylib(info: Mapping[str, object]) -> SourceShape | None:
    """A magpylib source declared by class and ``dimension`` (``diameter`` for spheres and
    circles); orientation is not in the field's info: the source's own z-axis is taken."""
    cls = str(info.get("class", ""))
    params = info.get("params")
    if not isinstance(params, Mapping):
        return None
    centre = _vec(info.get("source_position_m"), (0.0, 0.0, 0.0))
    label = f"magpylib {cls}"
    dim = np.asarray(params.get("dimension", ()), dtype=float).reshape(-1)
    if cls == "Cylinder" and dim.size == 2:
        return SourceShape("cylinder", label, centre, radius=float(dim[0]) / 2,
                           length=float(dim[1]))
    if cls == "CylinderSegment" and dim.size == 5:
        return SourceShape("cylinder", label, centre, radius=float(dim[1]),
                           inner_radius=float(dim[0]), length=float(dim[2]))
    if cls == "Cuboid" and dim.size == 3:
        return SourceShape("box", label, centre, size=_vec(dim, (0, 0, 0)))
    diameter = params.get("diameter")
    if cls in ("Sphere", "Circle") and isinstance(diameter, (int, float)):
        return SourceShape("sphere" if cls == "Sphere" else "loop", label, centre,
                           radius=float(diameter) / 2)
    return None


def _rings(shapes: list[SourceShape]) -> list[SourceShape]:
    """Merge an inner "(−)" cylinder into the coaxial outer one it hollows: a ring."""
    out = list(shapes)
    for inner in [s for s in shapes if s.kind == "cylinder" and s.label.endswith("(−)")]:
        for k, outer in enumerate(out):
            if (outer.kind == "cylinder" and not outer.label.endswith("(−)")
                    and outer.inner_radius == 0 and np.allclose(outer.centre, inner.centre)
                    and np.allclose(outer.axis, inner.axis) and inner.radius < outer.radius
                    and np.isclose(outer.length, inner.length)):
                out[k] = replace(outer, inner_radius=inner.radius,
                                 label="ring magnet (two cylinder fields)")
                out.remove(inner)
                break
    return out


def _frame(axis: Sequence[float]) -> np.ndarray:
    z = np.asarray(axis, dtype=float)
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _circle(radius: float, z: float, n: int) -> np.ndarray:
    phi = np.linspace(0, 2 * np.pi, n + 1)
    return np.column_stack([radius * np.cos(phi), radius * np.sin(phi), np.full(n + 1, z)])


_BREAK = np.full((1, 3), np.nan)


def outline(shape: SourceShape, n: int = 48, *,
            seen_along: Sequence[float] | np.ndarray | None = None) -> np.ndarray:
    """Edges of ``shape`` as one polyline ``(m, 3)`` [m], pieces separated by NaN rows: the
    end circles and four generators of a cylinder (and its bore), the circle of a loop, the
    twelve edges of a box, three great circles of a sphere. ``seen_along``: the direction a
    projection looks along; a cylinder then gets only the two generators of its silhouette
    (the others would project onto its middle)."""
    if shape.kind == "box":
        h = np.asarray(shape.size) / 2
        c = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * h
        edges = [(0, 1), (0, 2), (0, 4), (1, 3), (1, 5), (2, 3), (2, 6), (3, 7), (4, 5),
                 (4, 6), (5, 7), (6, 7)]
        local = np.vstack([np.vstack([c[a], c[b], _BREAK[0]]) for a, b in edges])
        return local + np.asarray(shape.centre)
    if shape.kind == "sphere":
        ring = _circle(shape.radius, 0.0, n)
        pieces = [ring, _BREAK, ring[:, [0, 2, 1]], _BREAK, ring[:, [2, 0, 1]]]
        return np.vstack(pieces) + np.asarray(shape.centre)
    half = shape.length / 2
    pieces = []
    for r in (shape.radius, shape.inner_radius):
        if r <= 0:
            continue
        if shape.kind == "loop":
            pieces += [_circle(r, 0.0, n), _BREAK]
            continue
        pieces += [_circle(r, -half, n), _BREAK, _circle(r, half, n), _BREAK]
        for phi in _generators(shape.axis, seen_along):
            p = np.array([r * np.cos(phi), r * np.sin(phi)])
            pieces += [np.array([[*p, -half], [*p, half]]), _BREAK]
    local = np.vstack(pieces)
    return local @ _frame(shape.axis).T + np.asarray(shape.centre)


def _generators(axis: Sequence[float], seen_along: Sequence[float] | np.ndarray | None
                ) -> list[float]:
    """Angles (in the cylinder's frame) of the generators to draw."""
    if seen_along is None:
        return [0.0, np.pi / 2, np.pi, 3 * np.pi / 2]
    frame = _frame(axis)
    side = np.cross(np.asarray(axis, dtype=float), np.asarray(seen_along, dtype=float))
    if np.linalg.norm(side) < 1e-12:  # seen end-on: the circles are the silhouette
        return []
    local = frame.T @ side
    phi = float(np.arctan2(local[1], local[0]))
    return [phi, phi + np.pi]


def mesh(shape: SourceShape, n: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """A closed triangle mesh of ``shape``: vertices ``(v, 3)`` [m] and triangles ``(t, 3)``.

    A loop is a thin torus-like band (1 % of its radius thick), a ring a hollow cylinder.
    """
    if shape.kind == "box":
        h = np.asarray(shape.size) / 2
        v = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * h
        tris = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                         [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
        return v + np.asarray(shape.centre), tris
    if shape.kind == "sphere":
        lat = np.linspace(0, np.pi, n // 2 + 1)
        lon = np.linspace(0, 2 * np.pi, n, endpoint=False)
        v = shape.radius * np.stack([np.outer(np.sin(lat), np.cos(lon)),
                                     np.outer(np.sin(lat), np.sin(lon)),
                                     np.outer(np.cos(lat), np.ones_like(lon))], -1).reshape(-1, 3)
        return v + np.asarray(shape.centre), _grid_tris(len(lat), n)
    outer, inner = shape.radius, shape.inner_radius
    half = shape.length / 2
    if shape.kind == "loop":
        inner, half = 0.97 * outer, 0.015 * outer
    # a tube: outer wall, top annulus, inner wall (or the axis), bottom annulus
    profile = [(outer, -half), (outer, half), (inner, half), (inner, -half), (outer, -half)]
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    v = np.array([[r * np.cos(p), r * np.sin(p), z] for r, z in profile for p in phi])
    v = v @ _frame(shape.axis).T + np.asarray(shape.centre)
    return v, _grid_tris(len(profile), n)


def _grid_tris(rows: int, n: int) -> np.ndarray:
    """Triangles of a band of ``rows`` rings of ``n`` points each (rings closed around)."""
    tris = []
    for i in range(rows - 1):
        for j in range(n):
            a, b = i * n + j, i * n + (j + 1) % n
            tris += [(a, b, a + n), (b, b + n, a + n)]
    return np.array(tris, dtype=int)
