"""A magnetic field tabulated to a tolerance over the region a scene needs.

:func:`tabulated_field` chooses the grid from the tolerance: it tabulates on a coarse grid,
measures the interpolation error against the field itself at random points of the region,
and refines (the error falls as ``h⁴`` in the value, ``h³`` in the gradient) until both
relative errors are within the tolerance. The measured errors go into the field's ``info``
(shown in the run summary).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField, FieldRequest
from poissonkit.numerics.fields.magnetic import magnetic_kernel
from poissonkit.numerics.fields.solids import Solid
from poissonkit.numerics.fields.tricubic import evaluate, tabulate, tricubic_field

#: Largest number of grid nodes a tolerance may ask for (24 floats each: 58 MB).
MAX_NODES = 300_000
#: Random points at which the interpolation error is measured.
CHECK_POINTS = 400
#: Default relative tolerance of a tabulated field.
DEFAULT_TOL = 1e-5

#: A table's room for growth: this many times its size (numerics/fields/growth) ...
GROWTH_ROOM = 4
#: ... within this many floats (64 MB): the memory cap of a growing table.
GROWTH_CAP = 1 << 23

#: The energy kernel of a moment in a tabulated field.
TABULATED_MAGNET = magnetic_kernel(tricubic_field)

BField = Callable[[np.ndarray], np.ndarray]


def field_region(request: FieldRequest, region: Sequence[float] | None,
                 centre: Sequence[float], name: str) -> tuple[np.ndarray, np.ndarray]:
    """The box ``(lo, hi)`` [m] to tabulate: ``region`` (6 numbers) if given, else the bodies'
    initial positions padded by half their distance to the source ``centre`` (at least 10 %
    of that distance in every direction)."""
    if region is not None:
        r = np.asarray(region, dtype=float)
        if r.shape != (6,) or not np.all(r[3:] > r[:3]):
            raise InputError(f"{name}: region must be [xmin, ymin, zmin, xmax, ymax, zmax] with "
                             f"max > min, got {list(region)!r}")
        pts = np.asarray(request.points, dtype=float).reshape(-1, 3)
        outside = [p for p in pts if np.any(p < r[:3]) or np.any(p > r[3:])]
        if outside:
            raise InputError(f"{name}: a body that reads the field starts at "
                             f"{outside[0].tolist()} m, outside the region {list(region)!r}; "
                             "enlarge the region (the table covers only it)")
        return r[:3], r[3:]
    pts = np.asarray(request.points, dtype=float).reshape(-1, 3)
    if len(pts) == 0:
        raise InputError(f"{name}: give a region [xmin, ymin, zmin, xmax, ymax, zmax] (m): no "
                         "body reads this field, so the region to tabulate is not known")
    dist = float(np.min(np.linalg.norm(pts - np.asarray(centre, float), axis=1)))
    pad = 0.5 * dist if dist > 0 else 0.5 * float(np.ptp(pts, axis=0).max() or 1.0)
    return pts.min(axis=0) - pad, pts.max(axis=0) + pad


def _fd_jacobian(bfun: BField, pts: np.ndarray, delta: float) -> np.ndarray:
    """Central-difference Jacobians ``∂B_i/∂x_j`` (n, 3, 3) of the field itself."""
    out = np.empty((len(pts), 3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = delta
        out[:, :, j] = (bfun(pts + e) - bfun(pts - e)) / (2 * delta)
    return out


def interpolation_error(P: np.ndarray, bfun: BField, lo: np.ndarray, hi: np.ndarray,
                        seed: int = 0) -> dict[str, float]:
    """Relative errors of the table ``P`` against ``bfun`` at random points of the box: the
    largest ``|ΔB| / max|B|`` (``field``) and ``|ΔJ| / max|J|`` (``gradient``, ``J = ∂B/∂x``
    from central differences of ``bfun``)."""
    rng = np.random.default_rng(seed)
    pts = lo + (hi - lo) * rng.random((CHECK_POINTS, 3))
    b_direct = np.asarray(bfun(pts), dtype=float)
    j_direct = _fd_jacobian(bfun, pts, 1e-5 * float(np.max(hi - lo)))
    b_int, j_int = evaluate(P, pts)
    b_scale = float(np.max(np.linalg.norm(b_direct, axis=1))) or 1.0
    j_scale = float(np.max(np.linalg.norm(j_direct, axis=(1, 2)))) or 1.0
    return {"field": float(np.max(np.linalg.norm(b_int - b_direct, axis=1))) / b_scale,
            "gradient": float(np.max(np.linalg.norm(j_int - j_direct, axis=(1, 2)))) / j_scale,
            "max_B_T": b_scale}


def tabulated_field(name: str, bfun: BField, lo: np.ndarray, hi: np.ndarray, tol: float,
                    info: Mapping[str, Any] | None = None, adaptive: bool = False,
                    solids: Sequence[Solid] = (), grow: bool = True) -> CompiledField:
    """The field ``bfun`` tabulated on the box ``[lo, hi]`` within relative tolerance ``tol``
    (value and gradient), as a magnet's energy field (reads ``moment``).

    ``grow``: the region may grow during a run when a body nears its edge
    (:mod:`poissonkit.numerics.fields.growth`); ``False`` keeps it fixed, and a body leaving
    it stops the run with a typed error naming the field and the body.

    One uniform grid when it fits in :data:`MAX_NODES`; otherwise, if ``adaptive``, an octree
    of the same cells refined where the field varies
    (:func:`~poissonkit.numerics.fields.octree.octree_table`; no accuracy is asked near the
    source's ``solids``).
    """
    if not (math.isfinite(tol) and tol > 0):
        raise InputError(f"{name}: tol must be positive, got {tol!r}")
    extent = hi - lo
    h = float(np.max(extent)) / 4
    while True:
        shape = tuple(int(max(2, math.ceil(e / h - 1e-9) + 1)) for e in extent)
        nodes = int(np.prod(shape))
        if nodes > MAX_NODES and adaptive:
            from poissonkit.numerics.fields.octree import octree_table

            return growable(octree_table(name, bfun, lo, hi, tol, solids, info),
                            lambda a, b: octree_table(name, bfun, a, b, tol, solids, info), grow)
        if nodes > MAX_NODES:
            raise InputError(f"{name}: tolerance {tol:g} needs more than {MAX_NODES} grid nodes "
                             f"over the region {lo.tolist()}..{hi.tolist()} m; loosen tol or "
                             "shrink the region")
        P = tabulate(bfun, lo, hi, shape)  # type: ignore[arg-type]
        err = interpolation_error(P, bfun, lo, hi)
        worst = max(err["field"], err["gradient"])
        if worst <= tol:
            break
        # gradient error ∝ h³: jump close to the needed spacing, at least halve
        h *= min(0.5, 0.9 * (tol / worst) ** (1 / 3))
    report = {**dict(info or {}), "tol": tol, "grid": list(shape), "nodes": nodes,
              "spacing_m": ((hi - lo) / (np.array(shape) - 1)).tolist(),
              "region_m": [lo.tolist(), hi.tolist()],
              "field_error": err["field"], "gradient_error": err["gradient"],
              "max_B_T": err["max_B_T"]}
    return growable(CompiledField(name=name, kernel=TABULATED_MAGNET, data=P, reads="moment",
                                  orientation=True, info=report),
                    lambda a, b: tabulated_field(name, bfun, a, b, tol, info, False, solids),
                    grow)


def growable(built: CompiledField, regrow: Callable[[np.ndarray, np.ndarray], CompiledField],
             grow: bool = True) -> CompiledField:
    """``built`` with its ``regrow`` and the room a regrown table may take in place: up to
    :data:`GROWTH_ROOM` times its size, within :data:`GROWTH_CAP` floats (a table already
    larger, or one asked not to ``grow``, gets no more than its own size: it cannot grow)."""
    size = int(np.asarray(built.data).size)
    room = max(size, min(GROWTH_ROOM * size, GROWTH_CAP)) if grow else size
    return replace(built, regrow=regrow, capacity=room)
