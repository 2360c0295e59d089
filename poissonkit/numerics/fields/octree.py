"""Adaptive tables: an octree of tricubic Hermite cells, refined where the field varies.

A magnet's field varies on the scale of the distance to it, so one uniform grid fine enough
near the magnet is wastefully fine far away and, at ``tol = 1e-5`` over centimetres, does not
fit in memory. :func:`octree_table` starts from a coarse grid of cells over the region and
splits a cell into its 8 octants while the cell's interpolant misses the field, at random test
points inside it, by more than the tolerance; each leaf is the cell of the uniform table
(:func:`~poissonkit.numerics.fields.tricubic.hermite_patch`: the tricubic Hermite polynomial of
the value and the derivatives ``∂x, ∂y, ∂z, ∂xy, ∂xz, ∂yz, ∂xyz`` at its 8 corners, from the
field itself, :func:`~poissonkit.numerics.fields.tricubic.node_table`).

Leaves of the same size share their corner data, so the interpolant is C¹ across them, and
its gradient is the exact derivative of its value everywhere: inside a leaf the energy is
conserved by its forces. Where a leaf meets a smaller one the two interpolants differ by at
most their interpolation errors: the field is continuous there to the tolerance, and a body
crossing such a face sees an energy step of that size (a run's energy error is then of the
order of the table's stated accuracy, not of round-off).

Errors are relative to the largest ``|B|`` and ``|∂B/∂x|`` found in the region outside the
source's solids (the measure of the uniform table). They are asked only farther than ``skin``
from the solids: inside a magnet the field is not wanted (bodies stop at its surface), and on
its surface and edges the field is not smooth. The final errors are measured at fresh random
points of the region (outside the skin) and reported in the field's ``info``.

Data layout ``P``: ``[x0, y0, z0, hx, hy, hz, nx, ny, nz, n_tree, leaf_start]`` (the region's
corner, the root cells' size and counts), then the tree: one entry per node, root cells first
in C order; an entry ``e ≥ 0`` is the index of the node's first of 8 children (octant
``a + 2b + 4c``), ``e < 0`` the leaf number ``−e − 1``; then 192 numbers per leaf (corner
``a + 2b + 4c`` at offset ``24 (a + 2b + 4c)``, each as a node of the uniform table, its
derivatives pre-multiplied by the leaf's size). Outside the region the evaluation is NaN.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numba
import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField
from poissonkit.numerics.fields.magnetic import magnetic_kernel
from poissonkit.numerics.fields.solids import Solid
from poissonkit.numerics.fields.tricubic import (grid_coordinates, hermite_patch,
                                                 node_table)

HEAD = 11
LEAF = 192
#: Deepest split of a root cell (its size / 2¹⁰).
MAX_DEPTH = 10
#: Most leaves of a table (192 floats each: 300 MB).
MAX_LEAVES = 200_000
#: Random test points per cell and level.
TESTS = 8
#: A cell is split when its measured error exceeds this fraction of the tolerance (the test
#: points sample the cell; the margin covers what they miss).
SAFETY = 0.5
#: Default distance [m] from the source's solids within which no accuracy is asked.
DEFAULT_SKIN = 1e-3
#: Fresh random points of the final error measurement.
CHECK_POINTS = 4000

BField = Callable[[np.ndarray], np.ndarray]
_CORNERS = np.array([(a, b, c) for c in (0, 1) for b in (0, 1) for a in (0, 1)], dtype=np.int64)


@numba.njit(cache=True, error_model="numpy")
def octree_field(x, y, z, P):
    """``(B, ∂B/∂x)`` (12 numbers, as the uniform table's) of the leaf holding the point;
    NaN outside the region."""
    tx, ty, tz, hx, hy, hz, nx, ny, nz = grid_coordinates(x, y, z, P)
    if not (0.0 <= tx <= nx and 0.0 <= ty <= ny and 0.0 <= tz <= nz):
        nan = math.nan
        return (nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan)
    ix = min(int(math.floor(tx)), nx - 1)
    iy = min(int(math.floor(ty)), ny - 1)
    iz = min(int(math.floor(tz)), nz - 1)
    u = tx - ix
    v = ty - iy
    w = tz - iz
    e = P[HEAD + (ix * ny + iy) * nz + iz]
    while e >= 0.0:
        a = 1 if u >= 0.5 else 0
        b = 1 if v >= 0.5 else 0
        c = 1 if w >= 0.5 else 0
        u = 2.0 * u - a
        v = 2.0 * v - b
        w = 2.0 * w - c
        hx *= 0.5
        hy *= 0.5
        hz *= 0.5
        e = P[HEAD + int(e) + a + 2 * b + 4 * c]
    origin = int(P[10]) + int(-e - 1.0) * LEAF
    return hermite_patch(P, origin, 24, 48, 96, u, v, w, hx, hy, hz)


#: The energy kernel of a moment in an octree table.
OCTREE_MAGNET = magnetic_kernel(octree_field)


@numba.njit(cache=True, error_model="numpy")
def _cells_at(D, which, uvw, h):
    """``(B, J)`` rows (m, 12) of the cells ``which`` (leaf data ``D``, 192 per cell) at local
    coordinates ``uvw`` (m, 3), cells of size ``h``."""
    out = np.empty((which.shape[0], 12))
    for t in range(which.shape[0]):
        r = hermite_patch(D, which[t] * LEAF, 24, 48, 96, uvw[t, 0], uvw[t, 1], uvw[t, 2],
                          h[0], h[1], h[2])
        for q in range(12):
            out[t, q] = r[q]
    return out


def _jacobian(bfun: BField, pts: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """Central differences ``∂B_i/∂x_j`` (n, 3, 3), step ``delta`` (n,) per point."""
    out = np.empty((len(pts), 3, 3))
    for j in range(3):
        e = np.zeros((len(pts), 3))
        e[:, j] = delta
        out[:, :, j] = (bfun(pts + e) - bfun(pts - e)) / (2 * delta[:, None])
    return out


def _clear(solids: Sequence[Solid], pts: np.ndarray, skin: float) -> np.ndarray:
    """Points farther than ``skin`` from every solid (a box-like growth, conservative)."""
    keep = np.ones(len(pts), dtype=bool)
    for s in solids:
        keep &= ~s.inside(pts, skin)
    return keep


class _Builder:
    """The octree of one field, level by level (module docstring)."""

    def __init__(self, name: str, bfun: BField, lo: np.ndarray, hi: np.ndarray, tol: float,
                 solids: Sequence[Solid], skin: float, seed: int) -> None:
        self.name, self.bfun, self.lo, self.tol = name, bfun, lo, tol
        self.solids, self.skin = solids, skin
        self.rng = np.random.default_rng(seed)
        extent = hi - lo
        self.cells = np.array([max(1, math.ceil(e / (float(np.max(extent)) / 4) - 1e-9))
                               for e in extent], dtype=np.int64)
        self.h0 = extent / self.cells
        self.scales = self._scales(lo, hi)
        n_root = int(np.prod(self.cells))
        self.tree: list[float] = [0.0] * n_root
        self.leaves: list[np.ndarray] = []
        self.unresolved = 0

    def _scales(self, lo: np.ndarray, hi: np.ndarray) -> tuple[float, float]:
        pts = lo + (hi - lo) * self.rng.random((CHECK_POINTS, 3))
        pts = pts[_clear(self.solids, pts, self.skin)]
        if len(pts) == 0:
            raise InputError(f"{self.name}: the region holds no point farther than "
                             f"{self.skin:g} m from the source; enlarge it")
        b = np.asarray(self.bfun(pts), float).reshape(-1, 3)
        j = _jacobian(self.bfun, pts, np.full(len(pts), 1e-4 * float(np.min(self.h0))))
        return (float(np.max(np.linalg.norm(b, axis=1))) or 1.0,
                float(np.max(np.linalg.norm(j, axis=(1, 2)))) or 1.0)

    def level(self, depth: int, coords: np.ndarray, slots: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
        """Tabulate the cells ``coords`` (integer, at ``depth``) stored in tree ``slots``;
        keep the good ones as leaves, return the children of the others."""
        h = self.h0 / 2.0 ** depth
        corners = (coords[:, None, :] + _CORNERS[None, :, :]).reshape(-1, 3)
        nodes, index = np.unique(corners, axis=0, return_inverse=True)
        data = node_table(self.bfun, self.lo + nodes * h, h)[index.ravel()]
        D = np.ascontiguousarray(data.reshape(len(coords), LEAF).ravel())
        err = self._errors(D, coords, h)
        split = err > SAFETY * self.tol
        if depth == MAX_DEPTH:
            self.unresolved += int(np.count_nonzero(split))
            split[:] = False
        for k in np.nonzero(~split)[0]:
            self.tree[int(slots[k])] = -(len(self.leaves) + 1.0)
            self.leaves.append(D[k * LEAF:(k + 1) * LEAF])
        if len(self.leaves) > MAX_LEAVES:
            raise InputError(f"{self.name}: tolerance {self.tol:g} needs more than "
                             f"{MAX_LEAVES} cells of an adaptive table; loosen tol or shrink "
                             "the region")
        parents = np.nonzero(split)[0]
        child_slots = np.empty((len(parents), 8), dtype=np.int64)
        for n, k in enumerate(parents):
            self.tree[int(slots[k])] = float(len(self.tree))
            child_slots[n] = np.arange(len(self.tree), len(self.tree) + 8)
            self.tree.extend([0.0] * 8)
        children = (2 * coords[parents][:, None, :] + _CORNERS[None, :, :]).reshape(-1, 3)
        return children, child_slots.ravel()

    def _errors(self, D: np.ndarray, coords: np.ndarray, h: np.ndarray) -> np.ndarray:
        """Largest relative error of each cell's interpolant at its test points."""
        which = np.repeat(np.arange(len(coords)), TESTS)
        uvw = self.rng.random((len(which), 3))
        pts = self.lo + (coords[which] + uvw) * h
        keep = _clear(self.solids, pts, self.skin)
        which, uvw, pts = which[keep], uvw[keep], pts[keep]
        err = np.zeros(len(coords))
        if len(pts) == 0:
            return err
        got = _cells_at(D, which, np.ascontiguousarray(uvw), h)
        b = np.asarray(self.bfun(pts), float).reshape(-1, 3)
        j = _jacobian(self.bfun, pts, np.full(len(pts), 1e-4 * float(np.min(h))))
        e = np.maximum(np.linalg.norm(got[:, :3] - b, axis=1) / self.scales[0],
                       np.linalg.norm(got[:, 3:].reshape(-1, 3, 3) - j, axis=(1, 2))
                       / self.scales[1])
        np.maximum.at(err, which, e)
        return err

    def data(self) -> np.ndarray:
        head = np.concatenate([self.lo, self.h0, self.cells.astype(float),
                               [float(len(self.tree)), float(HEAD + len(self.tree))]])
        return np.ascontiguousarray(np.concatenate([head, np.asarray(self.tree),
                                                    *self.leaves]))


def octree_table(name: str, bfun: BField, lo: np.ndarray, hi: np.ndarray, tol: float,
                 solids: Sequence[Solid] = (), info: Mapping[str, Any] | None = None,
                 skin: float = DEFAULT_SKIN, seed: int = 0) -> CompiledField:
    """The field ``bfun`` over the box ``[lo, hi]`` as an octree table (module docstring)
    within relative tolerance ``tol`` (value and gradient), as a magnet's energy field (reads
    ``moment``).

    Parameters
    ----------
    name
        The field's name (messages, the built field).
    bfun
        ``B(points)`` [T]: (n, 3) positions [m] → (n, 3).
    lo, hi
        The region [m].
    tol
        Relative tolerance (module docstring).
    solids
        The source's solids: no accuracy is asked within ``skin`` [m] of them.
    info
        What the report should also show.

    Raises
    ------
    InputError
        If the table would need more than :data:`MAX_LEAVES` cells.
    """
    if not (math.isfinite(tol) and tol > 0):
        raise InputError(f"{name}: tol must be positive, got {tol!r}")
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    b = _Builder(name, bfun, lo, hi, tol, solids, skin, seed)
    coords = np.array([(i, j, k) for i in range(b.cells[0]) for j in range(b.cells[1])
                       for k in range(b.cells[2])], dtype=np.int64)
    slots = np.arange(len(coords), dtype=np.int64)
    depth = 0
    while len(coords):
        coords, slots = b.level(depth, coords, slots)
        depth += 1
    P = b.data()
    measured = table_error(P, bfun, lo, hi, solids, skin, b.scales, seed + 1)
    report = {**dict(info or {}), "tol": tol, "adaptive": "octree", "cells": len(b.leaves),
              "depth": depth - 1, "nodes": 8 * len(b.leaves), "memory_MB": P.nbytes / 1e6,
              "region_m": [lo.tolist(), hi.tolist()], "accurate_beyond_m": skin,
              "unresolved_cells": b.unresolved, **measured,
              "max_B_T": b.scales[0]}
    return CompiledField(name=name, kernel=OCTREE_MAGNET, data=P, reads="moment",
                         orientation=True, info=report)


def evaluate(P: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``B`` (n, 3) and Jacobians (n, 3, 3) of the octree table ``P`` at ``points`` (n, 3)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.array([octree_field(p[0], p[1], p[2], P) for p in pts]).reshape(-1, 12)
    return out[:, :3], out[:, 3:].reshape(-1, 3, 3)


def table_error(P: np.ndarray, bfun: BField, lo: np.ndarray, hi: np.ndarray,
                solids: Sequence[Solid], skin: float, scales: tuple[float, float],
                seed: int) -> dict[str, float]:
    """Relative errors of the table ``P`` at fresh random points of the region farther than
    ``skin`` from the solids: ``field_error`` (``|ΔB|/max|B|``) and ``gradient_error``."""
    rng = np.random.default_rng(seed)
    pts = lo + (hi - lo) * rng.random((CHECK_POINTS, 3))
    pts = pts[_clear(solids, pts, skin)]
    B, J = evaluate(P, pts)
    b = np.asarray(bfun(pts), float).reshape(-1, 3)
    j = _jacobian(bfun, pts, np.full(len(pts), 1e-6 * float(np.max(hi - lo))))
    return {"field_error": float(np.max(np.linalg.norm(B - b, axis=1))) / scales[0],
            "gradient_error": float(np.max(np.linalg.norm(J - j, axis=(1, 2)))) / scales[1]}
