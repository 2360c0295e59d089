"""magpylib sources as external fields: declared in a scene or passed from Python.

A scene names the class (an allow-list of magpylib's source classes; user text is never
evaluated) and its own keywords, SI as in magpylib::

    [[fields]]
    source = "magpylib"
    class = "Cylinder"
    params = { polarization = [0.0, 0.0, 1.0], dimension = [0.05, 0.01] }
    position = [0.0, 0.0, 0.0]
    orientation = [0.0, 0.0, 0.0]   # rotation vector [rad], optional

From Python, ``pk.field(source)`` takes any magpylib source or ``Collection``. The field ``B``
is tabulated once over the region the bodies need and interpolated in compiled code
(:mod:`poissonkit.numerics.fields.tabulated`), on a grid chosen from ``tol``; the measured
interpolation error against magpylib is in the field's ``info``.
"""

from __future__ import annotations

import inspect
from collections.abc import Mapping
from typing import Any

import numpy as np

from poissonkit.errors import InputError, UnknownNameError
from poissonkit.numerics.fields.base import CompiledField, FieldRequest
from poissonkit.numerics.fields.tabulated import DEFAULT_TOL, field_region, tabulated_field
from poissonkit.plugin.contributions import ExternalField, Param

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
        When magpylib refuses the values (its message is kept).
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
    rot = None
    if orientation is not None:
        rot = Rotation.from_rotvec(np.asarray(orientation, dtype=float).reshape(3))
    try:
        return cls(position=np.asarray(position, dtype=float).reshape(3), orientation=rot,
                   **kwargs)
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


def _build(params: Mapping[str, Any], request: FieldRequest, source: Any = None
           ) -> CompiledField:
    if source is None:
        tol = float(params.get("tol", request.tol or DEFAULT_TOL))
        centre = np.asarray(params.get("position", (0.0, 0.0, 0.0)), dtype=float)
        lo, hi = field_region(request, params.get("region"), centre, "magpylib")
        key = repr((sorted((k, repr(v)) for k, v in params.items()), tol, lo.tolist(),
                    hi.tolist()))
        if key not in _TABLES:
            if len(_TABLES) >= _MAX_TABLES:
                _TABLES.pop(next(iter(_TABLES)))
            _TABLES[key] = _tabulate(params, request, None)
        return _TABLES[key]
    return _tabulate(params, request, source)


def _tabulate(params: Mapping[str, Any], request: FieldRequest, source: Any
              ) -> CompiledField:
    if source is None:
        if "class" not in params:
            raise InputError("magpylib: give class (one of "
                             f"{', '.join(SOURCE_CLASSES)}) and its params")
        source = make_source(params["class"], params.get("params", {}),
                             params.get("position", (0.0, 0.0, 0.0)), params.get("orientation"))
        described = {"class": params["class"], "params": dict(params.get("params", {}))}
    else:
        if "class" in params or "params" in params:
            raise InputError("magpylib: a source object is given; class and params describe "
                             "one in a scene file, do not give both")
        described = {"class": type(source).__name__}
    tol = float(params.get("tol", request.tol or DEFAULT_TOL))
    centre = np.asarray(source.position, dtype=float).reshape(-1, 3)[-1]
    lo, hi = field_region(request, params.get("region"), centre, "magpylib")
    return tabulated_field("magpylib", field_of(source), lo, hi, tol,
                           info={**described, "source_position_m": centre.tolist()})


MAGPYLIB = ExternalField(
    name="magpylib",
    doc="Field of any magpylib source (magnets, coils, polylines, collections), tabulated over "
        "the region the scene needs to the tolerance tol: U = -mu nu.B on bodies with a moment.",
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
    ),
    reads="moment", orientation=True, build=_build, accepts=is_source, tables=("params",))
