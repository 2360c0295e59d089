"""Closed-form field of a diametrally polarised cylinder (magpylib ``Cylinder``) and its Jacobian.

Lengths in units of the radius, magnetisation ``M`` along local ``x`` (the transverse
polarisation's azimuth is rotated out), half length ``z₀``. The side carries the charge
``σ = M cos φ'``, so ``H = −∇ψ`` with ``ψ = x h(s, z)``, ``s = ρ²``; ``B = μ0 H`` outside and
``μ0 H + J`` inside. Writing ``g = h``, ``G1 = 2 h_s``, ``G2 = 4 h_ss``::

    ∇ψ  = (g + x² G1, x y G1, x g_z)
    ∇∇ψ: xx = 3x G1 + x³ G2, xy = y G1 + x²y G2, yy = x G1 + x y² G2,
         xz = g_z + x² ∂_z G1, yz = x y ∂_z G1, zz = x g_zz

* **Off the axis** (``ρ ≥ 0.3 √(1 + ζ²)``, ``ζ`` the axial distance beyond the nearer end): ``∂_ρ(ρ g)`` and ``g`` are magpylib's closed form (Caciagli
  et al., J. Magn. Magn. Mater. 456 (2018) 423, with ``K``, ``E`` and ``Π`` through Bulirsch's
  ``cel``); every ``z``-derivative is a difference over the end planes of the charged-ring
  integral ``∫ cos φ' dφ'/|r − r'|``, i.e. ``g_z = Q(ρ, z + z₀) − Q(ρ, z − z₀)`` with
  ``Q = (8/π) S(m)/p^{3/2}`` (:func:`poissonkit_magnets.exact_loop.s_of_m`), and Laplace's
  equation gives ``G2 = −(4 G1 + g_zz)/ρ²``.
* **Near the axis** (``ρ < 0.3 √(1 + ζ²)``), where those differences cancel (near the axis as
  ``1/ρ⁴``, far along it as ``z⁵``), the axis series
  ``h = Σ_k a_k(z) s^k`` with ``a_k = (−1)^k a₀^{(2k)}/(4^k k! (k+1)!)`` (Laplace) and
  ``a₀ = [u(z + z₀) − u(z − z₀)]/4``, ``u(ζ) = ζ/√(1 + ζ²)`` — the charges sit at ``ρ = 1``
  only, so the series converges like ``(ρ²/(1 + ζ²))^k``; 20 terms reach round-off. The derivatives of
  ``u`` are those of ``R⁻³ = −∂_ρ(1/r)`` at ``ρ = 1`` (derivatives of Legendre polynomials).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from poissonkit_magnets.exact_loop import cel, ellipke_c, s_of_m

_AXIS_RHO = 0.3
_TERMS = 20


@njit(cache=True, error_model="numpy")
def _u_derivs(zeta: float, nmax: int) -> np.ndarray:
    """``u^{(n)}(ζ)``, ``n = 0..nmax``, of ``u = ζ/√(1 + ζ²)``:
    ``u^{(n)} = (−1)^{n−1} (n−1)! P'_n(t) / R^{n+2}`` (``R = √(1 + ζ²)``, ``t = ζ/R``; the
    ``n``-th derivative of ``R⁻³ = −∂_ρ(1/r)`` at ``ρ = 1``), with ``P'_n`` from the
    cancellation-free ``P'_{n+1} = P'_{n−1} + (2n + 1) P_n``."""
    r = math.sqrt(1.0 + zeta * zeta)
    t = zeta / r
    out = np.empty(nmax + 1)
    out[0] = t
    p_prev, p = 1.0, t          # P_{n−1}, P_n
    dp_prev, dp = 0.0, 1.0      # P'_{n−1}, P'_n (n = 1)
    fact = 1.0                  # (n − 1)!
    rp = r * r * r              # R^{n+2}
    for n in range(1, nmax + 1):
        if n > 1:
            fact *= n - 1
            dp_prev, dp = dp, dp_prev + (2 * n - 1) * p
            p_prev, p = p, ((2 * n - 1) * t * p - (n - 1) * p_prev) / n
            rp *= r
        out[n] = (-1.0) ** (n - 1) * fact * dp / rp
    return out


@njit(cache=True, error_model="numpy")
def _axis_series(s: float, z: float, z0: float):
    """``(g, G1, G2, g_z, ∂_z G1, g_zz)`` by the axis series (module docstring)."""
    nmax = 2 * _TERMS + 2
    up = _u_derivs(z + z0, nmax)
    um = _u_derivs(z - z0, nmax)
    g = 0.0
    hs = 0.0
    hss = 0.0
    hz = 0.0
    hsz = 0.0
    hzz = 0.0
    c = 1.0  # (−1)^k / (4^k k! (k+1)!)
    p0 = 1.0  # s^k
    p1 = 0.0  # s^(k−1)
    p2 = 0.0  # s^(k−2)
    for k in range(_TERMS):
        if k > 0:
            c *= -1.0 / (4.0 * k * (k + 1))
            p2 = p1
            p1 = p0
            p0 = p0 * s
        d0 = 0.25 * (up[2 * k] - um[2 * k])
        if k == 0 and (z + z0) * (z - z0) > 0.0:  # u(a) − u(b) without cancellation
            ra = math.sqrt(1.0 + (z + z0) ** 2)
            rb = math.sqrt(1.0 + (z - z0) ** 2)
            d0 = z * z0 / (ra * rb * ((z + z0) * rb + (z - z0) * ra))
        d1 = 0.25 * (up[2 * k + 1] - um[2 * k + 1])
        d2 = 0.25 * (up[2 * k + 2] - um[2 * k + 2])
        g += c * d0 * p0
        hz += c * d1 * p0
        hzz += c * d2 * p0
        hs += k * c * d0 * p1
        hsz += k * c * d1 * p1
        hss += k * (k - 1) * c * d0 * p2
    return g, 2.0 * hs, 4.0 * hss, hz, 2.0 * hsz, hzz


@njit(cache=True, error_model="numpy")
def _s_prime(m: float, m1: float) -> float:
    """``dS/dm`` of ``S(m) = ((1 − m/2)K − E)/m²``."""
    if m < 0.5:
        # S = π/2 Σ_{n≥2} t_n m^{n−2}, t_n = 2n c_n/(2n−1) − c_{n−1}/2
        c_prev = 0.25
        total = 0.0
        mp = 1.0
        for n in range(2, 80):
            c = c_prev * ((n - 0.5) / n) ** 2
            if n >= 3:
                term = (n - 2) * (2.0 * n * c / (2.0 * n - 1.0) - 0.5 * c_prev) * mp
                total += term
                if abs(term) < 1e-18 * abs(total):
                    break
                mp *= m
            c_prev = c
        return 0.5 * math.pi * total
    k, e = ellipke_c(m1)
    dk = (e - m1 * k) / (2.0 * m * m1)
    de = (e - k) / (2.0 * m)
    s = ((1.0 - 0.5 * m) * k - e) / (m * m)
    return (-0.5 * k + (1.0 - 0.5 * m) * dk - de) / (m * m) - 2.0 * s / m


@njit(cache=True, error_model="numpy")
def _q_family(rho: float, zeta: float) -> tuple[float, float, float]:
    """``(Q, ∂Q/∂ρ, ∂Q/∂ζ)`` of ``Q = (8/π) S(m)/p^{3/2}``, ``p = (1 + ρ)² + ζ²``,
    ``m = 4ρ/p`` (radius 1)."""
    p = (1.0 + rho) ** 2 + zeta * zeta
    m = 4.0 * rho / p
    m1 = ((1.0 - rho) ** 2 + zeta * zeta) / p
    s = s_of_m(m, m1)
    ds = _s_prime(m, m1)
    p32 = p * math.sqrt(p)
    k = 8.0 / math.pi
    m_r = 4.0 * (1.0 - rho * rho + zeta * zeta) / (p * p)
    m_z = -8.0 * rho * zeta / (p * p)
    q = k * s / p32
    q_r = k * (ds * m_r / p32 - 3.0 * s * (1.0 + rho) / (p * p32))
    q_z = k * (ds * m_z / p32 - 3.0 * s * zeta / (p * p32))
    return q, q_r, q_z


@njit(cache=True, error_model="numpy")
def _closed_form(r: float, z: float, z0: float) -> tuple[float, float]:
    """``(∂_ρ(ρ g), g)`` off the axis: magpylib's ``magnet_cylinder_diametral_Hfield``
    (general case, ``M = 1``, ``φ = 0`` and ``π/2``)."""
    zp = z + z0
    zm = z - z0
    zp2 = zp * zp
    zm2 = zm * zm
    r2 = r * r
    rp = r + 1.0
    rm = r - 1.0
    ap2 = zp2 + rm * rm
    am2 = zm2 + rm * rm
    ap = math.sqrt(ap2)
    am = math.sqrt(am2)
    argp = -4.0 * r / ap2
    argm = -4.0 * r / am2
    if rm == 0.0:
        argc = 1e16
        one_over_rm = 0.0
    else:
        argc = -4.0 * r / (rm * rm)
        one_over_rm = 1.0 / rm
    ellk_p, elle_p = ellipke_c(1.0 - argp)
    ellk_m, elle_m = ellipke_c(1.0 - argm)
    ellpi_p = cel(math.sqrt(1.0 - argp), 1.0 - argc, 1.0, 1.0)
    ellpi_m = cel(math.sqrt(1.0 - argm), 1.0 - argc, 1.0, 1.0)
    x1 = (-zm * am * elle_m + zp * ap * elle_p + zm / am * (2.0 + zm2) * ellk_m
          - zp / ap * (2.0 + zp2) * ellk_p
          + (zm / am * ellpi_m - zp / ap * ellpi_p) * rp * (r2 + 1.0) * one_over_rm)
    x2 = (zm * am * elle_m - zp * ap * elle_p - zm / am * (2.0 + zm2 + 2.0 * r2) * ellk_m
          + zp / ap * (2.0 + zp2 + 2.0 * r2) * ellk_p + zm / am * rp * rp * ellpi_m
          - zp / ap * rp * rp * ellpi_p)
    k = 1.0 / (4.0 * math.pi * r2)
    return x1 * k, x2 * k


@njit(cache=True, error_model="numpy")
def _derivatives(x: float, y: float, z: float, z0: float):
    """``(g, G1, G2, g_z, ∂_z G1, g_zz)`` at a point (radius 1, ``M = 1`` along ``x``)."""
    s = x * x + y * y
    rho = math.sqrt(s)
    zeta = max(0.0, abs(z) - z0)  # axial distance to the nearer end plane (0 between them)
    if s < _AXIS_RHO * _AXIS_RHO * (1.0 + zeta * zeta):
        return _axis_series(s, z, z0)
    f_r, g = _closed_form(rho, z, z0)
    qp, qp_r, qp_z = _q_family(rho, z + z0)
    qm, qm_r, qm_z = _q_family(rho, z - z0)
    g1 = (f_r - g) / s
    g_zz = qp_z - qm_z
    g2 = -(4.0 * g1 + g_zz) / s
    return g, g1, g2, qp - qm, (qp_r - qm_r) / rho, g_zz


@njit(cache=True, error_model="numpy")
def cylinder_diametral_add(x, y, z, jx, jy, a, h, out):
    """Field and Jacobian of a cylinder (radius ``a``, half length ``h``) with the transverse
    polarisation ``(jx, jy)`` [T], added to ``out``."""
    jt = math.sqrt(jx * jx + jy * jy)
    c = jx / jt
    sn = jy / jt
    # the frame where J is along x, lengths in radii
    xs = (c * x + sn * y) / a
    ys = (-sn * x + c * y) / a
    zs = z / a
    g, g1, g2, gz, g1z, gzz = _derivatives(xs, ys, zs, h / a)
    grad = (g + xs * xs * g1, xs * ys * g1, xs * gz)
    hxx = 3.0 * xs * g1 + xs ** 3 * g2
    hxy = ys * g1 + xs * xs * ys * g2
    hyy = xs * g1 + xs * ys * ys * g2
    hxz = gz + xs * xs * g1z
    hyz = xs * ys * g1z
    hzz = xs * gzz
    hess = ((hxx, hxy, hxz), (hxy, hyy, hyz), (hxz, hyz, hzz))
    inside = xs * xs + ys * ys <= 1.0 and abs(zs) <= h / a
    bl = (-jt * grad[0] + (jt if inside else 0.0), -jt * grad[1], -jt * grad[2])
    rot = ((c, -sn, 0.0), (sn, c, 0.0), (0.0, 0.0, 1.0))  # back to the cylinder's frame
    for i in range(3):
        out[i] += rot[i][0] * bl[0] + rot[i][1] * bl[1] + rot[i][2] * bl[2]
        for j in range(3):
            acc = 0.0
            for k in range(3):
                for m in range(3):
                    acc += rot[i][k] * hess[k][m] * rot[j][m]
            out[3 + 3 * i + j] += -jt * acc / a
