"""magpylib sources as external fields: declared in a scene or passed from Python.

A scene names the class (an allow-list of magpylib's source classes; user text is never
evaluated) and its own keywords, SI as in magpylib::

    [[fields]]
    source = "magpylib"
    class = "Cylinder"
    params = { polarization = [0.0, 0.0, 1.0], dimension = [0.05, 0.01] }
    position = [0.0, 0.0, 0.0]
    orientation = [0.0, 0.0, 0.0]   # rotation vector [rad], optional

From Python, ``pk.field(source)`` takes any magpylib source or ``Collection``.

The classes with a closed form in :mod:`poissonkit_magnets.exact_sources` (``Dipole``,
``Sphere``, ``Circle``, ``Polyline``, ``Cuboid``, ``Cylinder`` with any polarisation) are
evaluated exactly by compiled kernels: no region, no tolerance, no set-up. Any other source is
tabulated once over the region the bodies need and interpolated in compiled code
(:mod:`poissonkit.numerics.fields.tabulated`), on a grid chosen from ``tol``; the measured
interpolation error against magpylib is in the field's ``info``. A ``Collection`` mixing both
is the exact sum of its supported sources plus a table of the others. ``mode = "table"``
tabulates everything (the behaviour before exact kernels), ``mode = "exact"`` refuses a source
without a kernel.
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics.fields.base import CompiledField, FieldRequest
from poissonkit.numerics.fields.tabulated import DEFAULT_TOL, field_region, tabulated_field
from poissonkit.plugin.contributions import ExternalField, Param
from poissonkit.validation import vector3
from poissonkit_magnets.exact_sources import EXACT_MAGNET, split_sources
from poissonkit_magnets.source_solids import magpylib_solids

#: magpylib source classes a scene may name: class name -> (subpackage, attribute).
SOURCE_CLASSES: dict[str, tuple[str, str]] = {
    "Cuboid": ("magnet", "Cuboid"),
    "Cylinder": ("magnet", "Cylinder"),
    "CylinderSegment": ("magnet", "CylinderSegment"),
    "Sphere": ("magnet", "Sphere"),
    "Tetrahedron": ("magnet", "Tetrahedron"),
    "TriangularMesh": ("magnet", "TriangularMesh"),
    "Circle": ("current", "Circle"),
    "Polyline": ("current", "Polyline"),
    "TriangleSheet": ("current", "TriangleSheet"),
    "TriangleStrip": ("current", "TriangleStrip"),
    "Dipole": ("misc", "Dipole"),
    "Triangle": ("misc", "Triangle"),
}
#: Keywords the scene gives outside ``params`` (or that are not physics).
_RESERVED = {"self", "position", "orientation", "style", "kwargs", "children",
             "override_parent"}
#: Keywords holding integer indices.
_INTEGER_KEYS = {"faces", "triangles"}


def _magpylib():
    try:
        import magpylib
    except ImportError:
        raise InputError("magpylib fields need magpylib: pip install magpylib") from None
    return magpylib


def source_class(name: str) -> type:
    """The magpylib class ``name`` from the allow-list (:data:`SOURCE_CLASSES`)."""
    if name not in SOURCE_CLASSES:
        raise UnknownNameError("magpylib source class", name, SOURCE_CLASSES)
    sub, attr = SOURCE_CLASSES[name]
    return getattr(getattr(_magpylib(), sub), attr)


def source_keywords(cls: type) -> list[str]:
    """The physical keywords of a magpylib source class (its constructor's, without
    position, orientation and style)."""
    sig = inspect.signature(cls.__init__)
    return [p.name for p in sig.parameters.values()
            if p.name not in _RESERVED and p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]


def make_source(name: str, params: Mapping[str, Any], position: Any = (0.0, 0.0, 0.0),
                orientation: Any = None) -> Any:
    """A magpylib source from a class name and its keywords (SI), placed and rotated.

    Raises
    ------
    UnknownNameError
        For a class outside the allow-list or a keyword the class does not take.
    InputError
        When ``params`` is empty, ``position`` or ``orientation`` is not three numbers, or
        magpylib refuses the values (its message is kept).
    """
    from scipy.spatial.transform import Rotation

    cls = source_class(name)
    allowed = source_keywords(cls)
    kwargs: dict[str, Any] = {}
    for key, value in params.items():
        if key not in allowed:
            raise UnknownNameError(f"keyword of magpylib {name}", key, allowed)
        arr = np.asarray(value, dtype=float)
        kwargs[key] = arr.astype(int) if key in _INTEGER_KEYS else (
            float(arr) if arr.ndim == 0 else arr)
    if not kwargs:
        raise InputError(f"magpylib {name}: params is missing or empty; give its keywords "
                         f"({', '.join(allowed)}), e.g. params = {{ {allowed[0]} = ... }}")
    where = vector3(position, f"magpylib {name}: position [m]")
    rot = None
    if orientation is not None:
        rot = Rotation.from_rotvec(vector3(orientation, f"magpylib {name}: orientation "
                                           "(a rotation vector [rad])"))
    try:
        return cls(position=where, orientation=rot, **kwargs)
    except Exception as exc:  # magpylib's own input errors: keep the message, type it
        raise InputError(f"magpylib {name}: {type(exc).__name__}: {exc}") from None


def is_source(obj: object) -> bool:
    """True for a magpylib source (a class of :data:`SOURCE_CLASSES`) or ``Collection``."""
    try:
        import magpylib
    except ImportError:
        return False
    classes = tuple(source_class(n) for n in SOURCE_CLASSES) + (magpylib.Collection,)
    return isinstance(obj, classes)


def field_of(source: Any) -> Any:
    """``B(points)`` [T] of a magpylib source: (n, 3) positions [m] → (n, 3)."""
    def bfun(points: np.ndarray) -> np.ndarray:
        out = np.asarray(source.getB(np.asarray(points, dtype=float)), dtype=float)
        return out.reshape(-1, 3)
    return bfun


#: Tables of declared sources already built in this process (a sweep builds its scene once
#: per point): key -> field. Bounded, oldest dropped first.
_TABLES: dict[str, CompiledField] = {}
_MAX_TABLES = 8
#: How a source is evaluated: exact kernels where they exist (else a table), only tables, or
#: only exact kernels.
MODES = ("auto", "table", "exact")


def _declared(params: Mapping[str, Any], source: Any) -> tuple[Any, dict[str, Any]]:
    """The magpylib source of a field and what a report says it was built from."""
    if source is None:
        if "class" not in params:
            raise InputError("magpylib: give class (one of "
                             f"{', '.join(SOURCE_CLASSES)}) and its params")
        source = make_source(params["class"], params.get("params", {}),
                             params.get("position", (0.0, 0.0, 0.0)), params.get("orientation"))
        return source, {"class": params["class"], "params": dict(params.get("params", {}))}
    if "class" in params or "params" in params:
        raise InputError("magpylib: a source object is given; class and params describe "
                         "one in a scene file, do not give both")
    return source, {"class": type(source).__name__}


def _build(params: Mapping[str, Any], request: FieldRequest, source: Any = None
           ) -> CompiledField:
    mode = params.get("mode", "auto")
    if mode not in MODES:
        raise UnknownNameError("magpylib field mode", mode, MODES)
    source, described = _declared(params, source)
    built = _evaluated(params, request, source, described, mode, declared="class" in params)
    return replace(built, solids=magpylib_solids(source))


def _evaluated(params: Mapping[str, Any], request: FieldRequest, source: Any,
               described: dict[str, Any], mode: str, declared: bool) -> CompiledField:
    """The field of ``source``: exact kernels, a table, or both (module docstring)."""
    centre = np.asarray(source.position, dtype=float).reshape(-1, 3)[-1]
    described["source_position_m"] = centre.tolist()
    if mode == "table":
        return _cached(params, request, source, described, declared)
    P, rest, classes = split_sources(source)
    if rest and mode == "exact":
        names = sorted({type(r).__name__ for r in rest})
        raise InputError(f"magpylib: no exact kernel for {', '.join(names)} (exact kernels: "
                         "Dipole, Sphere, Circle, Polyline, Cuboid, Cylinder); use "
                         "mode = 'auto' to tabulate them")
    if P is None:
        return _cached(params, request, source, described, declared)
    info = {**described, "exact": True, "exact_sources": classes}
    unused = [k for k in ("tol", "region", "grow") if k in params]
    if not rest:
        if unused:
            info["unused"] = unused  # an exact field has no table to tune
        return CompiledField("magpylib", EXACT_MAGNET, P, reads="moment", orientation=True,
                             info=info)
    from poissonkit_magnets.exact_mixed import mixed_field

    table = _cached(params, request, _Sum(rest), {"class": "Collection"}, declared)
    return mixed_field(P, table, {**info, "tabulated_sources":
                                  [type(r).__name__ for r in rest]})


class _Sum:
    """The sources a table covers (those of a collection without an exact kernel)."""

    def __init__(self, sources: list[Any]) -> None:
        self.sources = sources
        self.position = sources[0].position
        self.sources_all = sources  # its solids are those of its sources

    def getB(self, points: np.ndarray) -> np.ndarray:
        return sum(np.asarray(s.getB(points), dtype=float).reshape(-1, 3)
                   for s in self.sources)


def _cached(params: Mapping[str, Any], request: FieldRequest, source: Any,
            described: Mapping[str, Any], declared: bool) -> CompiledField:
    """A table of ``source`` (reused for a source declared in a scene)."""
    tol = float(params.get("tol", request.tol or DEFAULT_TOL))
    centre = np.asarray(source.position, dtype=float).reshape(-1, 3)[-1]
    lo, hi = field_region(request, params.get("region"), centre, "magpylib")
    where = {"adaptive": True, "solids": magpylib_solids(source),
             "grow": bool(params.get("grow", True))}
    if not declared:
        return tabulated_field("magpylib", field_of(source), lo, hi, tol, info=described,
                               **where)
    key = repr((sorted((k, repr(v)) for k, v in params.items()), tol, lo.tolist(),
                hi.tolist(), described.get("class")))
    if key not in _TABLES:
        if len(_TABLES) >= _MAX_TABLES:
            _TABLES.pop(next(iter(_TABLES)))
        _TABLES[key] = tabulated_field("magpylib", field_of(source), lo, hi, tol,
                                       info=described, **where)
    return _TABLES[key]


MAGPYLIB = ExternalField(
    name="magpylib",
    doc="Field of any magpylib source (magnets, coils, polylines, collections): exact compiled "
        "kernels for Dipole, Sphere, Circle, Polyline, Cuboid and Cylinder, other "
        "sources tabulated over the region the scene needs to the tolerance tol: "
        "U = -mu nu.B on bodies with a moment.",
    params=(
        Param("class", "str", "magpylib source class (Cylinder, Cuboid, Circle, Polyline, ...)",
              optional=True),
        Param("position", "vector", "position of the source [m]", (0.0, 0.0, 0.0), unit="m"),
        Param("orientation", "vector", "rotation vector of the source [rad]", unit="rad",
              optional=True),
        Param("tol", "float", "relative interpolation tolerance of B and its gradient",
              positive=True, optional=True),
        Param("region", "vector", "box to tabulate [xmin, ymin, zmin, xmax, ymax, zmax] [m] "
              "(default: the bodies' initial positions, padded)", unit="m", optional=True),
        Param("mode", "str", "auto (exact kernels where they exist, else a table), table or "
              "exact", "auto"),
        Param("grow", "bool", "a table's region grows when a body nears its edge (false: it "
              "stays, and a body leaving it stops the run)", True),
    ),
    reads="moment", orientation=True, build=_build, accepts=is_source, tables=("params",))
