"""Pair geometry shared by the compiled models.

A configuration given by its invariants ``(r, c1, c2, c3)`` (see :mod:`poissonkit.conventions`)
is realised in a canonical frame: body 1 at the origin, ``e = z``, ``nu1`` in the x-z plane.
Models that are computed as vector integrals (exact cylinders, field models, loops) return the
force on body 2 and both torques; :func:`partials_from_vectors` turns these into the partials
``(U_r, U_c1, U_c2, U_c3)`` by inverting the architecture's formulas

    F  = -[U_r e + U_c1 (nu1 - c1 e)/r + U_c2 (nu2 - c2 e)/r]
    T2 = U_c2 e x nu2 + U_c3 nu1 x nu2,      T1 = U_c1 e x nu1 + U_c3 nu2 x nu1

in the least-squares sense. Where ``e, nu1, nu2`` are coplanar one combination of the angular
partials (along the gradient of the Gram determinant) does not act on any force or torque; the
minimum-norm solution is returned there, which reproduces F, T1 and T2 exactly.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def canonical_frame(c1: float, c2: float, c3: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit vectors ``(e, nu1, nu2)`` with the given cosines (``e = z``, ``nu1`` in x-z)."""
    e = np.array([0.0, 0.0, 1.0])
    s1 = math.sqrt(max(0.0, 1.0 - c1 * c1))
    nu1 = np.array([s1, 0.0, c1])
    if s1 > 1e-12:
        x2 = (c3 - c1 * c2) / s1
    else:
        x2 = math.sqrt(max(0.0, 1.0 - c2 * c2))
    y2 = math.sqrt(max(0.0, 1.0 - c2 * c2 - x2 * x2))
    nu2 = np.array([x2, y2, c2])
    nu2 /= math.sqrt(nu2[0] ** 2 + nu2[1] ** 2 + nu2[2] ** 2)
    return e, nu1, nu2


@njit(cache=True)
def perpendicular_pair(nu: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors ``u, w`` with ``(u, w, nu)`` right-handed orthonormal."""
    if abs(nu[0]) < 0.9:
        a = np.array([1.0, 0.0, 0.0])
    else:
        a = np.array([0.0, 1.0, 0.0])
    u = a - (a[0] * nu[0] + a[1] * nu[1] + a[2] * nu[2]) * nu
    u /= math.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
    w = np.cross(nu, u)
    return u, w


@njit(cache=True)
def partials_from_vectors(r: float, c1: float, c2: float, e: np.ndarray, nu1: np.ndarray,
                          nu2: np.ndarray, force: np.ndarray, torque1: np.ndarray,
                          torque2: np.ndarray) -> tuple[float, float, float, float]:
    """``(U_r, U_c1, U_c2, U_c3)`` reproducing ``force`` (on 2) and both torques."""
    a = np.zeros((9, 4))
    b = np.zeros(9)
    t1 = np.cross(e, nu1)
    t2 = np.cross(e, nu2)
    t12 = np.cross(nu1, nu2)
    for k in range(3):
        # force rows times r so that every unknown (r U_r, U_c1, U_c2, U_c3) is an energy
        a[k, 0] = e[k]
        a[k, 1] = nu1[k] - c1 * e[k]
        a[k, 2] = nu2[k] - c2 * e[k]
        b[k] = -force[k] * r
        a[3 + k, 2] = t2[k]
        a[3 + k, 3] = t12[k]
        b[3 + k] = torque2[k]
        a[6 + k, 1] = t1[k]
        a[6 + k, 3] = -t12[k]
        b[6 + k] = torque1[k]
    x = np.linalg.lstsq(a, b, 1e-10)[0]
    return x[0] / r, x[1], x[2], x[3]
