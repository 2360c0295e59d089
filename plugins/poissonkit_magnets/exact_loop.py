"""The field of a circular current loop, accurate up to the wire, and its derivatives.

The same closed forms as :func:`poissonkit_magnets.exact_fields.loop_local` (Jackson §5.5),
but the complete elliptic integrals take the complementary parameter ``m₁ = 1 − m = q/p``
computed without cancellation (``q = (a − ρ)² + z²``, ``p = (a + ρ)² + z²``), so that the
relative accuracy stays at round-off close to the wire, where ``m → 1`` (magpylib's ``cel``
does the same). Used by the exact ``Circle`` and by the Jacobian of the ``Cylinder``; also
Bulirsch's general complete elliptic integral ``cel`` as magpylib evaluates it.
"""

from __future__ import annotations

import math

from numba import njit

_SERIES_M = 0.1
_CEL_TOL = 1e-8  # Bulirsch's AGM converges quadratically: sqrt(eps) ends it at round-off


@njit(cache=True, error_model="numpy")
def ellipke_c(m1: float) -> tuple[float, float]:
    """``(K(m), E(m))`` from ``m₁ = 1 − m`` by the AGM of ``1`` and ``√m₁``."""
    a = 1.0
    b = math.sqrt(m1)
    total = 0.5 * (1.0 - m1)
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


@njit(cache=True, error_model="numpy")
def _small_m_series(m: float) -> tuple[float, float, float]:
    """``(K'(m), E'(m), T(m))`` by their power series (``m < 0.1``), with
    ``T = ((1 − m/2)E − (1 − m)K)/m²``."""
    c_prev = 1.0
    e_prev = 1.0
    t = 0.0
    de = 0.0
    dk = 0.0
    mp = 1.0
    c = 1.0
    for n in range(1, 40):
        c *= ((n - 0.5) / n) ** 2
        e_n = -c / (2.0 * n - 1.0)
        mn1 = m ** (n - 1)
        de += n * e_n * mn1
        dk += n * c * mn1
        if n >= 2:
            t += (e_n - 0.5 * e_prev - c + c_prev) * mp
            mp *= m
        c_prev = c
        e_prev = e_n
    h = 0.5 * math.pi
    return h * dk, h * de, h * t


@njit(cache=True, error_model="numpy")
def loop_fields(rho: float, z: float, mu0i: float, a: float
                ) -> tuple[float, float, float, float, float, float]:
    """``(B_ρ, B_z, B_ρ/ρ, ∂B_z/∂ρ, ∂B_z/∂z, ∂B_ρ/∂ρ)`` of a loop of radius ``a`` about +z at
    the origin carrying ``μ0 I = mu0i``."""
    cc = mu0i / (2.0 * math.pi)
    p = (a + rho) ** 2 + z * z
    q = (a - rho) ** 2 + z * z
    m = 4.0 * a * rho / p
    m1 = q / p
    k, e = ellipke_c(m1)
    if m < _SERIES_M:
        dk, de, t = _small_m_series(m)
    else:
        dk = (e - m1 * k) / (2.0 * m * m1)
        de = (e - k) / (2.0 * m)
        t = ((1.0 - 0.5 * m) * e - m1 * k) / (m * m)
    sp = math.sqrt(p)
    w = a * a - rho * rho - z * z
    f = w / q
    g = k + f * e
    bz = cc * g / sp
    br_rho = 16.0 * cc * a * a * z * t / (p * sp * q)
    m_r = 4.0 * a * (a * a - rho * rho + z * z) / (p * p)
    m_z = -8.0 * a * rho * z / (p * p)
    f_r = (-2.0 * rho * q + w * 2.0 * (a - rho)) / (q * q)
    f_z = (-2.0 * z * q - w * 2.0 * z) / (q * q)
    g_r = dk * m_r + f_r * e + f * de * m_r
    g_z = dk * m_z + f_z * e + f * de * m_z
    bz_r = cc * (g_r / sp - g * (a + rho) / (p * sp))
    bz_z = cc * (g_z / sp - g * z / (p * sp))
    br_r = -bz_z - br_rho
    return rho * br_rho, bz, br_rho, bz_r, bz_z, br_r


@njit(cache=True, error_model="numpy")
def s_of_m(m: float, m1: float) -> float:
    """``S(m) = ((1 − m/2) K(m) − E(m))/m²`` (``m₁ = 1 − m``; series below ``m = 0.5``)."""
    if m < 0.5:
        # (1 − m/2)K − E = π/2 Σ_n (2n c_n/(2n−1) − c_{n−1}/2) mⁿ, c_n = ((2n−1)!!/(2n)!!)²
        c = 0.25
        total = 0.0
        mp = 1.0
        for n in range(2, 80):
            c_prev, c = c, c * ((n - 0.5) / n) ** 2
            term = (2.0 * n * c / (2.0 * n - 1.0) - 0.5 * c_prev) * mp
            total += term
            if abs(term) < 1e-18 * abs(total):
                break
            mp *= m
        return 0.5 * math.pi * total
    k, e = ellipke_c(m1)
    return ((1.0 - 0.5 * m) * k - e) / (m * m)


@njit(cache=True, error_model="numpy")
def cel(kc: float, p: float, c: float, s: float) -> float:
    """Bulirsch's ``cel(k_c, p, c, s) = ∫₀^{π/2} (c cos²t + s sin²t) / ((cos²t + p sin²t)
    √(cos²t + k_c² sin²t)) dt`` (``k_c ≠ 0``), as magpylib evaluates it."""
    if p > 0.0:
        p = math.sqrt(p)
        s /= p
    else:
        f = kc * kc
        q = 1.0 - f
        g = 1.0 - p
        f -= p
        q *= s - c * p
        p = math.sqrt(f / g)
        c = (c - s) / g
        s = -q / (g * g * p) + c * p
    em = 1.0
    qc = abs(kc)
    kk = qc
    for _ in range(60):
        g = kk / p
        c, s = c + s / p, 2.0 * (s + c * g)
        p += g
        g = em
        em += qc
        if abs(g - qc) <= g * _CEL_TOL:
            break
        qc = 2.0 * math.sqrt(kk)
        kk = em * qc
    return 0.5 * math.pi * (s + c * em) / (em * (em + p))
