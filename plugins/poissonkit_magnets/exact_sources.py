"""magpylib sources as exact compiled fields: the data layout, the summed kernel, packing.

A field is a list of source records in one float array ``P``::

    P = [n, record_1, …, record_n]
    record = [kind, length, position (3), R (3×3, row-major), parameters…]

``R`` maps the source's own frame to the global one (magpylib's ``orientation``), so the field
at ``r`` is ``B = R b(Rᵀ(r − position))`` and its Jacobian ``R j Rᵀ``, with ``b``, ``j`` the
local closed forms (:mod:`~poissonkit_magnets.exact_local`,
:mod:`~poissonkit_magnets.exact_cuboid`, :mod:`~poissonkit_magnets.exact_cylinder`). A
``Collection`` is the sum of its sources' records. The parameters are magpylib's, in SI: the
polarisation ``J`` [T] of magnets (magpylib derives it from ``magnetization`` when that is
given), the ``moment`` [A m²] of a dipole, ``current`` [A], with magpylib's ``μ0``
(``scipy.constants.mu_0``) for currents and dipoles so that ``B`` agrees with ``getB`` to
round-off.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit

from poissonkit.errors import InputError
from poissonkit.numerics.fields.magnetic import magnetic_kernel
from poissonkit.validation import finite_number, vector3
from poissonkit_magnets.exact_cuboid import cuboid_local
from poissonkit_magnets.exact_cylinder import cylinder_local
from poissonkit_magnets.exact_local import circle_local, dipole_local, polyline_local, sphere_local

#: Record kinds.
DIPOLE, SPHERE, CIRCLE, POLYLINE, CUBOID, CYLINDER = 1, 2, 3, 4, 5, 6
#: magpylib class name -> record kind, for the classes with an exact kernel.
EXACT_CLASSES = {"Dipole": DIPOLE, "Sphere": SPHERE, "Circle": CIRCLE, "Polyline": POLYLINE,
                 "Cuboid": CUBOID, "Cylinder": CYLINDER}
_HEAD = 14


@njit(cache=True, error_model="numpy")
def _local(kind, x, y, z, P, o, out):
    if kind == DIPOLE:
        dipole_local(x, y, z, P, o, out)
    elif kind == SPHERE:
        sphere_local(x, y, z, P, o, out)
    elif kind == CIRCLE:
        circle_local(x, y, z, P, o, out)
    elif kind == POLYLINE:
        polyline_local(x, y, z, P, o, out)
    elif kind == CUBOID:
        cuboid_local(x, y, z, P, o, out)
    elif kind == CYLINDER:
        cylinder_local(x, y, z, P, o, out)


@njit(cache=True, error_model="numpy")
def sources_add(x, y, z, P, out):
    """Add the field and Jacobian of every record of ``P`` (module docstring) to ``out``."""
    n = int(P[0])
    o = 1
    loc = np.empty(12)
    for _ in range(n):
        kind = int(P[o])
        dx = x - P[o + 2]
        dy = y - P[o + 3]
        dz = z - P[o + 4]
        R = P[o + 5:o + 14]
        lx = R[0] * dx + R[3] * dy + R[6] * dz
        ly = R[1] * dx + R[4] * dy + R[7] * dz
        lz = R[2] * dx + R[5] * dy + R[8] * dz
        loc[:] = 0.0
        _local(kind, lx, ly, lz, P, o + _HEAD, loc)
        for i in range(3):
            out[i] += R[3 * i] * loc[0] + R[3 * i + 1] * loc[1] + R[3 * i + 2] * loc[2]
            for j in range(3):
                acc = 0.0
                for k in range(3):
                    for m in range(3):
                        acc += R[3 * i + k] * loc[3 + 3 * k + m] * R[3 * j + m]
                out[3 + 3 * i + j] += acc
        o += int(P[o + 1])


@njit(cache=True, error_model="numpy")
def sources_b(x, y, z, P):
    """``(B, ∂B/∂x)`` (12 numbers) of the sources in ``P`` at ``(x, y, z)``."""
    out = np.zeros(12)
    sources_add(x, y, z, P, out)
    return (out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8], out[9],
            out[10], out[11])


#: The energy kernel ``U = −c ν·B`` of a moment in the exact field of magpylib sources.
EXACT_MAGNET = magnetic_kernel(sources_b)


def magpylib_mu0() -> float:
    """The ``μ0`` magpylib computes with (scipy's CODATA value)."""
    from scipy.constants import mu_0

    return float(mu_0)


def _vec(value: Any, n: int, what: str) -> np.ndarray:
    """A magpylib attribute as ``n`` finite numbers (3-vectors through the shared validator)."""
    if value is None:
        raise InputError(f"magpylib {what} is not set")
    if n == 3:
        return vector3(value, f"magpylib {what}")
    if n == 1:
        return np.array([finite_number(np.asarray(value, dtype=float).reshape(-1)[0],
                                       f"magpylib {what}")])
    out = np.asarray(value, dtype=float).reshape(-1)
    if out.shape != (n,) or not np.all(np.isfinite(out)):
        raise InputError(f"magpylib {what} must be {n} finite numbers, got {value!r}")
    return out


def _parameters(src: Any, kind: int) -> np.ndarray | None:
    name = type(src).__name__
    mu0 = magpylib_mu0()
    if kind == DIPOLE:
        return np.concatenate([_vec(src.moment, 3, f"{name}.moment"), [mu0]])
    if kind == SPHERE:
        return np.concatenate([_vec(src.polarization, 3, f"{name}.polarization"),
                               [_vec(src.diameter, 1, f"{name}.diameter")[0] / 2]])
    if kind == CIRCLE:
        return np.array([_vec(src.current, 1, f"{name}.current")[0],
                         _vec(src.diameter, 1, f"{name}.diameter")[0] / 2, mu0])
    if kind == POLYLINE:
        verts = np.asarray(src.vertices, dtype=float).reshape(-1, 3)
        current = _vec(src.current, 1, f"{name}.current")[0]
        return np.concatenate([[current, mu0, len(verts)], verts.ravel()])
    if kind == CUBOID:
        return np.concatenate([_vec(src.polarization, 3, f"{name}.polarization"),
                               np.abs(_vec(src.dimension, 3, f"{name}.dimension")) / 2])
    pol = _vec(src.polarization, 3, f"{name}.polarization")
    dim = _vec(src.dimension, 2, f"{name}.dimension")
    return np.concatenate([pol, [dim[0] / 2, dim[1] / 2]])


def source_record(src: Any) -> np.ndarray | None:
    """The record of one magpylib source, or ``None`` when it has no exact kernel (another
    class, a path of several positions)."""
    kind = EXACT_CLASSES.get(type(src).__name__)
    if kind is None or type(src).__module__.split(".")[0] != "magpylib":
        return None
    pos = np.asarray(src.position, dtype=float).reshape(-1, 3)
    rot = np.asarray(src.orientation.as_matrix(), dtype=float).reshape(-1, 3, 3)
    if len(pos) != 1 or len(rot) != 1:
        return None
    params = _parameters(src, kind)
    if params is None:
        return None
    return np.concatenate([[float(kind), float(_HEAD + params.size)], pos[0], rot[0].ravel(),
                           params])


def leaf_sources(source: Any) -> list[Any]:
    """The sources of a magpylib ``Collection`` (nested ones flattened), or ``[source]``."""
    children = getattr(source, "sources_all", None)
    return list(children) if children is not None else [source]


def split_sources(source: Any) -> tuple[np.ndarray | None, list[Any], list[str]]:
    """``(P, rest, classes)``: the exact field data of the supported sources of ``source``
    (``None`` if there is none), the sources without an exact kernel, and the classes of the
    exact ones."""
    records = []
    rest = []
    classes = []
    for leaf in leaf_sources(source):
        rec = source_record(leaf)
        if rec is None:
            rest.append(leaf)
        else:
            records.append(rec)
            classes.append(type(leaf).__name__)
    if not records:
        return None, rest, classes
    P = np.concatenate([[float(len(records))], *records])
    return np.ascontiguousarray(P), rest, classes


def evaluate(P: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(B, J)`` of the exact field ``P`` at ``(n, 3)`` points: ``(n, 3)`` and ``(n, 3, 3)``."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.array([sources_b(p[0], p[1], p[2], P) for p in pts]).reshape(-1, 12)
    return out[:, :3], out[:, 3:].reshape(-1, 3, 3)

