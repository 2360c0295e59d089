"""Jacobi coordinates of point masses (row 0 the centre of mass) and back."""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, error_model="numpy")
def to_jacobi(r, u, m, xj, uj):
    """Inertial positions ``r`` / velocities ``u`` (rows) → Jacobi ``xj``, ``uj``; row 0 = centre
    of mass."""
    n = m.shape[0]
    eta = m[0]
    for d in range(3):
        sx = m[0] * r[0, d]
        su = m[0] * u[0, d]
        eta = m[0]
        for i in range(1, n):
            xj[i, d] = r[i, d] - sx / eta
            uj[i, d] = u[i, d] - su / eta
            sx += m[i] * r[i, d]
            su += m[i] * u[i, d]
            eta += m[i]
        xj[0, d] = sx / eta
        uj[0, d] = su / eta


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def from_jacobi(xj, mfrac, r):
    """Jacobi rows ``xj`` (row 0 = centre of mass) → inertial rows ``r`` (positions or
    velocities alike); ``mfrac[i] = m_i / η_i``.

    With ``R_i`` the centre of mass of bodies ``0 … i``: ``R_{i−1} = R_i − (m_i/η_i) x'_i`` and
    ``r_i = x'_i + R_{i−1}``, from ``R_{n−1}`` = row 0 down (multiplications only).
    """
    n = xj.shape[0]
    for d in range(3):
        R = xj[0, d]
        for i in range(n - 1, 0, -1):
            R -= mfrac[i] * xj[i, d]
            r[i, d] = xj[i, d] + R
        r[0, d] = R


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def jacobi_of_inertial(a, m, inv_eta, aj):
    """Jacobi transform of inertial accelerations (row 0, the centre of mass's, set to 0);
    ``inv_eta[i] = 1/η_i``."""
    n = m.shape[0]
    for d in range(3):
        s = m[0] * a[0, d]
        for i in range(1, n):
            aj[i, d] = a[i, d] - s * inv_eta[i - 1]
            s += m[i] * a[i, d]
        aj[0, d] = 0.0  # internal forces: the centre of mass is not accelerated



def jacobi_of(y: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Jacobi positions and velocities (row 0: centre of mass) of an N-body state ``y``."""
    n = m.shape[0]
    rp = y.reshape(n, 2, 3)
    xj, uj = np.empty((n, 3)), np.empty((n, 3))
    to_jacobi(np.ascontiguousarray(rp[:, 0]), np.ascontiguousarray(rp[:, 1] / m[:, None]),
              m, xj, uj)
    return xj, uj
