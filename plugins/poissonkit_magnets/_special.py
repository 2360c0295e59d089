"""Compiled special functions: complete elliptic integrals and the field of a charged ring.

Elliptic integrals take the parameter ``m = k**2`` (as scipy's ``ellipk(m)``). ``K`` and ``E``
come from the arithmetic-geometric mean; the derivatives ``K'(m)``, ``K''(m)`` use the power
series of ``2F1(1/2, 1/2; 1; m)`` for small ``m`` (where the closed forms cancel) and the closed
forms / Legendre's equation elsewhere.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_HALF_PI = 0.5 * math.pi
_SMALL_M = 0.1


@njit(cache=True)
def ellipke(m: float) -> tuple[float, float]:
    """``(K(m), E(m))`` for ``0 <= m < 1`` by the AGM (relative accuracy ~1e-16)."""
    a = 1.0
    b = math.sqrt(1.0 - m)
    c2 = m
    total = 0.5 * m  # sum of 2^(n-1) c_n^2, c_0^2 = m
    p = 0.5
    for _ in range(40):
        an = 0.5 * (a + b)
        cn = 0.5 * (a - b)
        b = math.sqrt(a * b)
        a = an
        p *= 2.0
        c2 = cn * cn
        total += p * c2
        if c2 < 1e-34 * a * a:
            break
    k = math.pi / (2.0 * a)
    return k, k * (1.0 - total)


@njit(cache=True)
def ellipk_derivs(m: float) -> tuple[float, float, float, float]:
    """``(K, E, K'(m), K''(m))``, stable for small ``m``."""
    k, e = ellipke(m)
    if m < _SMALL_M:
        # K = pi/2 sum c_n m^n, c_n = ((1/2)_n / n!)^2; 30 terms give 1e-30 at m = 0.1
        c = 1.0
        d1 = 0.0
        d2 = 0.0
        mp1 = 1.0  # m^(n-1)
        mp2 = 0.0  # m^(n-2)
        for n in range(1, 32):
            c *= ((n - 0.5) / n) ** 2
            d1 += n * c * mp1
            if n >= 2:
                d2 += n * (n - 1) * c * mp2
            mp2 = mp1
            mp1 *= m
        return k, e, _HALF_PI * d1, _HALF_PI * d2
    km = (e - (1.0 - m) * k) / (2.0 * m * (1.0 - m))
    # Legendre's equation m(1-m)K'' + (1-2m)K' - K/4 = 0
    kmm = (0.25 * k - (1.0 - 2.0 * m) * km) / (m * (1.0 - m))
    return k, e, km, kmm


@njit(cache=True)
def ellipk_d1(m: float) -> tuple[float, float]:
    """``(K, K'(m))``, stable for small ``m`` (cheaper than :func:`ellipk_derivs`)."""
    k, e = ellipke(m)
    if m < _SMALL_M:
        c = 1.0
        d1 = 0.0
        mp1 = 1.0
        for n in range(1, 32):
            c *= ((n - 0.5) / n) ** 2
            term = n * c * mp1
            d1 += term
            if term < 1e-17 * d1:
                break
            mp1 *= m
        return k, _HALF_PI * d1
    return k, (e - (1.0 - m) * k) / (2.0 * m * (1.0 - m))


@njit(cache=True)
def ring_grad(rho: float, z: float, s: float) -> tuple[float, float, float]:
    """``f = K(m)/D`` of a ring of radius ``s`` and its ``(d/drho, d/dz)``.

    ``D = sqrt((rho+s)^2 + z^2)``, ``m = 4 rho s / D^2``. A ring carrying total charge ``q``
    has scalar potential ``q f / (2 pi^2)`` (so that ``int dphi / |x - x'| = 4 f``).
    """
    p = (rho + s) ** 2 + z * z
    d = math.sqrt(p)
    m = 4.0 * rho * s / p
    k, km = ellipk_d1(m)
    mr = 4.0 * s / p - 8.0 * rho * s * (rho + s) / (p * p)
    mz = -8.0 * rho * s * z / (p * p)
    inv_d3 = 1.0 / (p * d)
    f = k / d
    fr = km * mr / d - k * (rho + s) * inv_d3
    fz = km * mz / d - k * z * inv_d3
    return f, fr, fz


@njit(cache=True)
def ring_hess(rho: float, z: float, s: float) -> tuple[float, float, float, float, float, float]:
    """``f = K(m)/D`` (see :func:`ring_grad`), its gradient and second derivatives.

    Returns ``(f, f_rho, f_z, f_rhorho, f_rhoz, f_zz)``.
    """
    p = (rho + s) ** 2 + z * z
    d = math.sqrt(p)
    m = 4.0 * rho * s / p
    k, e, km, kmm = ellipk_derivs(m)
    pr = 2.0 * (rho + s)
    pz = 2.0 * z
    p2 = p * p
    p3 = p2 * p
    # m = 4 rho s / P and its derivatives (P_rr = P_zz = 2, P_rz = 0)
    mr = 4.0 * s / p - 4.0 * rho * s * pr / p2
    mz = -4.0 * rho * s * pz / p2
    mrr = -8.0 * s * pr / p2 - 8.0 * rho * s / p2 + 8.0 * rho * s * pr * pr / p3
    mzz = -8.0 * rho * s / p2 + 8.0 * rho * s * pz * pz / p3
    mrz = -4.0 * s * pz / p2 + 8.0 * rho * s * pr * pz / p3
    # D = sqrt(P)
    dr = (rho + s) / d
    dz = z / d
    drr = z * z / (p * d)
    dzz = (rho + s) ** 2 / (p * d)
    drz = -(rho + s) * z / (p * d)
    f = k / d
    fr = km * mr / d - k * dr / p
    fz = km * mz / d - k * dz / p
    frr = (kmm * mr * mr / d + km * mrr / d - 2.0 * km * mr * dr / p
           - k * drr / p + 2.0 * k * dr * dr / (p * d))
    fzz = (kmm * mz * mz / d + km * mzz / d - 2.0 * km * mz * dz / p
           - k * dzz / p + 2.0 * k * dz * dz / (p * d))
    frz = (kmm * mr * mz / d + km * mrz / d - km * mr * dz / p - km * mz * dr / p
           - k * drz / p + 2.0 * k * dr * dz / (p * d))
    return f, fr, fz, frr, frz, fzz


@njit(cache=True)
def gauss_legendre_unit(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on ``[0, 1]`` (Newton on ``P_n``, compiled so that
    kernels take only scalar parameters)."""
    x = np.empty(n)
    w = np.empty(n)
    for i in range(n):
        t = math.cos(math.pi * (i + 0.75) / (n + 0.5))
        dp = 1.0
        for _ in range(100):
            p0 = 1.0
            p1 = t
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * t * p1 - (k - 1) * p0) / k
            if n == 1:
                p0, p1 = 1.0, t
            dp = n * (t * p1 - p0) / (t * t - 1.0)
            dt = p1 / dp
            t -= dt
            if abs(dt) < 1e-16:
                break
        x[i] = 0.5 * (1.0 - t)
        w[i] = 1.0 / ((1.0 - t * t) * dp * dp)
    return x, w


@njit(cache=True)
def hyp2f1_maxwell(m: float) -> float:
    """``2F1(3/2, 3/2; 3; m)`` for ``0 <= m < 1`` (series; closed form via K, E near 1)."""
    if m < 0.5:
        term = 1.0
        total = 1.0
        for n in range(0, 200):
            term *= (1.5 + n) * (1.5 + n) / ((3.0 + n) * (n + 1.0)) * m
            total += term
            if abs(term) < 1e-17 * total:
                break
        return total
    # M = mu0 sqrt(ab)[(2/k - k)K - 2E/k] = (pi/16) mu0 sqrt(ab) k^3 2F1  =>  2F1 from K, E
    k, e = ellipke(m)
    kk = math.sqrt(m)
    return ((2.0 / kk - kk) * k - 2.0 * e / kk) * 16.0 / (math.pi * kk ** 3)
