"""Tricubic Hermite tabulation of a vector field, and its compiled evaluation with gradient.

On each cell of a regular grid the interpolant is the tricubic polynomial matching, at the
8 corners, the value and the derivatives ``∂x, ∂y, ∂z, ∂xy, ∂xz, ∂yz, ∂xyz`` of each
component (F. Lekien, J. Marsden, Int. J. Numer. Meth. Eng. 63 (2005) 455), written here in
tensor form with the 1-D cubic Hermite basis. It is C¹ over the whole grid and its error is
``O(h⁴)`` in the value and ``O(h³)`` in the gradient. The gradient returned is the exact
derivative of the interpolant, so an energy built on it is conserved by its own forces.

The nodal derivatives come from the field itself by central differences on a ``3×3×3``
stencil of half-width ``δ = h/200`` about each node (truncation ``O(δ²)``, rounding
``ε (h/δ)³`` relative, both far below the interpolation error).

Data layout ``P`` (float64): ``[x0, y0, z0, hx, hy, hz, nx, ny, nz]`` then the node table of
shape ``(nx, ny, nz, 8, 3)`` in C order, derivative ``∂^(i,j,k)`` at index ``i + 2j + 4k``,
pre-multiplied by ``hx^i hy^j hz^k``. Outside the grid the evaluation returns NaN (a run that
leaves the tabulated region stops with non-finite values).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numba
import numpy as np

HEADER = 9
#: δ / h of the central differences that give the nodal derivatives.
STENCIL = 1.0 / 200.0
#: Nodes whose stencils are evaluated in one call of the field.
CHUNK = 20_000


def tabulate(bfun: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray,
             shape: tuple[int, int, int]) -> np.ndarray:
    """The data array ``P`` of the field ``bfun`` ((n, 3) points → (n, 3) values) on the grid
    of ``shape`` nodes spanning the box ``[lo, hi]`` (module docstring)."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    n = np.array(shape, dtype=int)
    h = (hi - lo) / (n - 1)
    axes = [lo[d] + h[d] * np.arange(n[d]) for d in range(3)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    table = node_table(bfun, nodes, h)
    head = np.concatenate([lo, h, n.astype(float)])
    return np.ascontiguousarray(np.concatenate([head, table.ravel()]))


def node_table(bfun: Callable[[np.ndarray], np.ndarray], nodes: np.ndarray, h: np.ndarray
               ) -> np.ndarray:
    """The nodal data ``(n, 8, 3)`` of ``bfun`` at ``nodes`` (n, 3) for cells of size ``h``
    (3,): the value and the derivatives ``∂^(i,j,k)`` pre-multiplied by ``h^(i,j,k)``, by
    central differences of half-width ``STENCIL h`` (module docstring)."""
    delta = STENCIL * h
    offs = np.array([(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)],
                    dtype=float)
    # 1-D stencils: value (0, 1, 0), derivative (-1, 0, 1)/(2δ) times h (unit cell)
    w = [np.array([[0.0, 1.0, 0.0], [-0.5, 0.0, 0.5]]) * np.array([[1.0], [h[d] / delta[d]]])
         for d in range(3)]
    table = np.empty((len(nodes), 8, 3))
    for start in range(0, len(nodes), CHUNK):  # bounded memory: 27 points per node
        part = nodes[start:start + CHUNK]
        pts = part[:, None, :] + offs[None, :, :] * delta[None, None, :]
        vals = np.asarray(bfun(pts.reshape(-1, 3)), dtype=float).reshape(len(part), 3, 3, 3, 3)
        for k in range(2):
            for j in range(2):
                for i in range(2):
                    table[start:start + len(part), i + 2 * j + 4 * k, :] = np.einsum(
                        "a,b,c,nabcq->nq", w[0][i], w[1][j], w[2][k], vals)
    return table


@numba.njit(cache=True, error_model="numpy", inline="always")
def _basis(u):
    """Cubic Hermite basis on [0, 1]: values and derivatives of (h00, h01, h10, h11)."""
    u2 = u * u
    u3 = u2 * u
    return (2.0 * u3 - 3.0 * u2 + 1.0, -2.0 * u3 + 3.0 * u2, u3 - 2.0 * u2 + u, u3 - u2,
            6.0 * u2 - 6.0 * u, -6.0 * u2 + 6.0 * u, 3.0 * u2 - 4.0 * u + 1.0, 3.0 * u2 - 2.0 * u)


@numba.njit(cache=True, error_model="numpy", inline="always")
def grid_coordinates(x, y, z, P):
    """``(tx, ty, tz, hx, hy, hz, nx, ny, nz)``: the point in units of the grid whose header
    ``[x0, y0, z0, hx, hy, hz, nx, ny, nz]`` starts ``P`` (this table's and the octree's), the
    spacings and the counts."""
    hx = P[3]
    hy = P[4]
    hz = P[5]
    return ((x - P[0]) / hx, (y - P[1]) / hy, (z - P[2]) / hz, hx, hy, hz, int(P[6]), int(P[7]),
            int(P[8]))


@numba.njit(cache=True, error_model="numpy", inline="always")
def _cell(t, n):
    """Cell index and local coordinate of ``t`` (in cells) on an axis of ``n`` nodes
    (``-1`` outside)."""
    if not (t >= 0.0 and t <= n - 1.0):
        return -1, 0.0
    i = int(math.floor(t))
    if i > n - 2:
        i = n - 2
    return i, t - i


@numba.njit(cache=True, error_model="numpy", inline="always")
def hermite_patch(P, origin, sa, sb, sc, u, v, w, hx, hy, hz):
    """``(B, ∂B/∂x)`` (12 numbers) of one cell at local coordinates ``(u, v, w)`` in
    ``[0, 1]³``: the corner ``(a, b, c)``'s nodal data start at ``origin + a sa + b sb + c sc``
    in ``P`` (8 derivatives × 3 components, module docstring), the cell's size is
    ``(hx, hy, hz)``."""
    bu = _basis(u)
    bv = _basis(v)
    bw = _basis(w)
    # basis of corner a, kind i (0 value, 1 derivative): index 2 i + a; derivative at + 4
    out = np.zeros(12)
    for c in range(2):
        for k in range(2):
            fz = bw[2 * k + c]
            dz = bw[4 + 2 * k + c] / hz
            for b in range(2):
                for j in range(2):
                    fy = bv[2 * j + b]
                    dy = bv[4 + 2 * j + b] / hy
                    for a in range(2):
                        base = origin + a * sa + b * sb + c * sc
                        for i in range(2):
                            fx = bu[2 * i + a]
                            dx = bu[4 + 2 * i + a] / hx
                            wv = fx * fy * fz
                            wx = dx * fy * fz
                            wy = fx * dy * fz
                            wz = fx * fy * dz
                            q = base + (i + 2 * j + 4 * k) * 3
                            for comp in range(3):
                                val = P[q + comp]
                                out[comp] += wv * val
                                out[3 + 3 * comp] += wx * val
                                out[4 + 3 * comp] += wy * val
                                out[5 + 3 * comp] += wz * val
    return (out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8], out[9],
            out[10], out[11])


@numba.njit(cache=True, error_model="numpy")
def tricubic_field(x, y, z, P):
    """``(B, ∂B/∂x)`` of the tabulated field at ``(x, y, z)``: 3 values, then the Jacobian
    ``J_ij = ∂B_i/∂x_j`` row by row (12 numbers); NaN outside the grid."""
    tx, ty, tz, hx, hy, hz, nx, ny, nz = grid_coordinates(x, y, z, P)
    ix, u = _cell(tx, nx)
    iy, v = _cell(ty, ny)
    iz, w = _cell(tz, nz)
    if ix < 0 or iy < 0 or iz < 0:
        nan = math.nan
        return (nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan)
    origin = HEADER + (((ix * ny + iy) * nz + iz) * 8) * 3
    return hermite_patch(P, origin, ny * nz * 24, nz * 24, 24, u, v, w, hx, hy, hz)


def evaluate(P: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``B`` (n, 3) and Jacobians (n, 3, 3) of the table ``P`` at ``points`` (n, 3)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.array([tricubic_field(p[0], p[1], p[2], P) for p in pts]).reshape(-1, 12)
    return out[:, :3], out[:, 3:].reshape(-1, 3, 3)
