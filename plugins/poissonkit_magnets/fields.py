"""Axisymmetric bodies given by their magnetic scalar potential, and the seed's eqs. (17), (18).

``H = -grad psi`` (so ``B = -mu0 grad psi`` outside magnets). A body of revolution with axis
``nu1`` at the origin has ``psi(rho, z)`` in cylindrical coordinates about its axis.

* Uniformly magnetised cylinder (docs/magnets.md): two charged end disks decomposed into rings,
  ``psi_disk = (sigma/pi) int_0^a s K(m)/sqrt((rho+s)^2+(z-z0)^2) ds`` (Gauss–Legendre), or the
  odd axial multipole series ``psi = (1/4pi) sum q_n P_n(cos theta)/r^(n+1)`` far away
  (``r > 3 sqrt(l^2+a^2)``), with ``q_n`` the cylinder's exact axial moments.
* Circular current loop: ``H`` in closed form (elliptic integrals, docs/magnets.md); the loop's
  ``psi`` is the solid angle ``I Omega/(4 pi)`` (multivalued), so only ``grad psi`` is provided.

Pair models built on these (body 1 = the field source, body 2 = the probe):

* (17) dipole ``mu nu2`` at ``r e``: ``U = mu0 mu nu2 . grad psi`` (= ``-m.B``), i.e.
  ``mu0 mu (psi_r c2 + psi_z c3)`` in the seed's non-orthogonal pair ``(|x|, x.nu1)``.
* (18) dumbbell (half-length ``l``, charge ``kappa = mu/(2l)``) at ``r e``:
  ``U = mu0 kappa sum_eps eps psi(r e + eps l nu2)``.

Forces and torques use the analytic gradient / Hessian of ``psi``; the partials follow from them.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from poissonkit_magnets._geometry import canonical_frame, partials_from_vectors
from poissonkit_magnets._special import ellipke, gauss_legendre_unit, ring_hess

#: Ring nodes for the disk integrals of psi (Gauss–Legendre on [0, a]).
N_RING = 24
#: Highest odd multipole order of the far-field series.
N_MULTIPOLE = 41


@njit(cache=True)
def cylinder_axial_moments(m: float, a: float, l: float, nmax: int) -> np.ndarray:
    """Axial multipoles ``q_n`` (n = 0..nmax, zero for even n) of a cylinder (two disks).

    ``q_n = int sigma r'^n P_n(cos theta') dA'`` over both end disks (``sigma = +-m`` at
    ``z0 = +-l``), with the solid harmonic
    ``r^n P_n = sum_k (-1)^k n! / (4^k k!^2 (n-2k)!) z^(n-2k) s^(2k)`` integrated over the disk
    radius ``s`` in closed form. Checked: ``q1 = mu``, ``q3 = mu (l^2 - 3a^2/4)``,
    ``q5 = mu (l^4 - 5/2 l^2 a^2 + 5/8 a^4)`` (docs/magnets.md).
    """
    q = np.zeros(nmax + 1)
    for n in range(1, nmax + 1, 2):
        total = 0.0
        for k in range(0, n // 2 + 1):
            # r^n P_n(cos) of a point (s, z0), averaged over angle: sum over k of
            # c_{n,k} z0^(n-2k) s^(2k) with c = (-1)^k n! / (4^k k!^2 (n-2k)!)
            c = (-1.0) ** k * math.exp(math.lgamma(n + 1.0) - k * math.log(4.0)
                                       - 2.0 * math.lgamma(k + 1.0) - math.lgamma(n - 2.0 * k + 1.0))
            # int_0^a s^(2k) 2 pi s ds = 2 pi a^(2k+2)/(2k+2)
            area_moment = 2.0 * math.pi * a ** (2 * k + 2) / (2.0 * k + 2.0)
            # two disks: +m at +l and -m at -l (odd n: contributions add)
            total += c * area_moment * (l ** (n - 2 * k) - (-l) ** (n - 2 * k))
        q[n] = m * total
    return q


@njit(cache=True)
def _disk_rings(rho: float, zz: float, a: float, sx: np.ndarray, sw: np.ndarray) -> np.ndarray:
    """``int_0^a s (f, f_rho, f_z, f_rhorho, f_rhoz, f_zz)(rho, zz; s) ds`` by Gauss–Legendre.

    Close to the disk (``|zz| < a``) the ring kernel peaks at ``s = rho``; the interval is then
    split there so that each panel sees only a one-sided peak.
    """
    acc = np.zeros(6)
    if 0.0 < rho < a and abs(zz) < a:
        lo = np.array([0.0, rho])
        hi = np.array([rho, a])
        npanel = 2
    else:
        lo = np.array([0.0, 0.0])
        hi = np.array([a, a])
        npanel = 1
    for j in range(npanel):
        width = hi[j] - lo[j]
        for k in range(sx.shape[0]):
            s = lo[j] + width * sx[k]
            f, fr, fz, frr, frz, fzz = ring_hess(rho, zz, s)
            ws = sw[k] * width * s
            acc[0] += ws * f
            acc[1] += ws * fr
            acc[2] += ws * fz
            acc[3] += ws * frr
            acc[4] += ws * frz
            acc[5] += ws * fzz
    return acc


@njit(cache=True)
def cylinder_psi_local(rho: float, z: float, m: float, a: float, l: float, sx: np.ndarray,
                       sw: np.ndarray) -> tuple[float, float, float, float, float, float]:
    """``psi`` of a cylinder and ``(psi_rho, psi_z, psi_rhorho, psi_rhoz, psi_zz)`` by rings."""
    out = np.zeros(6)
    for i in range(2):
        sg = 1.0 if i == 0 else -1.0
        out += (sg * m / math.pi) * _disk_rings(rho, z - sg * l, a, sx, sw)
    return out[0], out[1], out[2], out[3], out[4], out[5]


@njit(cache=True)
def multipole_psi_local(rho: float, z: float, q: np.ndarray
                        ) -> tuple[float, float, float, float, float, float]:
    """``psi = (1/4pi) sum q_n P_n(u)/r^(n+1)`` (u = z/r) and its cylindrical derivatives."""
    r2 = rho * rho + z * z
    r = math.sqrt(r2)
    u = z / r
    nmax = q.shape[0] - 1
    # Legendre P_n(u) and derivatives by recurrence
    p_prev, p = 1.0, u
    dp_prev, dp = 0.0, 1.0
    ddp_prev, ddp = 0.0, 0.0
    psi = 0.0
    g_r = 0.0   # d/dr at fixed u
    g_u = 0.0   # d/du at fixed r
    g_rr = 0.0
    g_ru = 0.0
    g_uu = 0.0
    for n in range(1, nmax + 1):
        if n > 1:
            p_new = ((2 * n - 1) * u * p - (n - 1) * p_prev) / n
            dp_new = dp_prev + (2 * n - 1) * p
            ddp_new = ddp_prev + (2 * n - 1) * dp
            p_prev, p = p, p_new
            dp_prev, dp = dp, dp_new
            ddp_prev, ddp = ddp, ddp_new
        if q[n] != 0.0:
            c = q[n] / (4.0 * math.pi) * r ** (-(n + 1))
            psi += c * p
            g_r += -(n + 1) * c * p / r
            g_u += c * dp
            g_rr += (n + 1) * (n + 2) * c * p / r2
            g_ru += -(n + 1) * c * dp / r
            g_uu += c * ddp
    # chain rule (r, u) -> (rho, z): r_rho = rho/r, r_z = z/r, u_rho = -z rho/r^3, u_z = rho^2/r^3
    r_rho = rho / r
    r_z = z / r
    u_rho = -z * rho / (r2 * r)
    u_z = rho * rho / (r2 * r)
    psi_rho = g_r * r_rho + g_u * u_rho
    psi_z = g_r * r_z + g_u * u_z
    # second derivatives of r and u
    r_rhorho = z * z / (r2 * r)
    r_zz = rho * rho / (r2 * r)
    r_rhoz = -rho * z / (r2 * r)
    u_rhorho = -z / (r2 * r) + 3.0 * z * rho * rho / (r2 * r2 * r)
    u_zz = -3.0 * rho * rho * z / (r2 * r2 * r)
    u_rhoz = -rho / (r2 * r) + 3.0 * z * z * rho / (r2 * r2 * r)

    def second(ra, rb, ua, ub, rab, uab):
        return (g_rr * ra * rb + g_ru * (ra * ub + ua * rb) + g_uu * ua * ub
                + g_r * rab + g_u * uab)

    prr = second(r_rho, r_rho, u_rho, u_rho, r_rhorho, u_rhorho)
    prz = second(r_rho, r_z, u_rho, u_z, r_rhoz, u_rhoz)
    pzz = second(r_z, r_z, u_z, u_z, r_zz, u_zz)
    return psi, psi_rho, psi_z, prr, prz, pzz


@njit(cache=True)
def loop_psi_local(rho: float, z: float, current: float, a: float
                   ) -> tuple[float, float]:
    """``(psi_rho, psi_z) = -(H_rho, H_z)`` of a loop of radius ``a`` (current right-handed
    about +z) at the origin; closed form of docs/magnets.md divided by mu0."""
    p = (a + rho) ** 2 + z * z
    qd = (a - rho) ** 2 + z * z
    m = 4.0 * a * rho / p
    k, e = ellipke(m)
    sq = math.sqrt(p)
    hz = current / (2.0 * math.pi * sq) * (k + (a * a - rho * rho - z * z) / qd * e)
    if rho > 1e-9 * a:
        hr = current * z / (2.0 * math.pi * rho * sq) * (-k + (a * a + rho * rho + z * z) / qd * e)
    else:
        hr = 0.0
    return -hr, -hz


@njit(cache=True)
def _to_cartesian(d: np.ndarray, nu: np.ndarray, pr: float, pz: float, prr: float,
                  prz: float, pzz: float) -> tuple[np.ndarray, np.ndarray]:
    """Gradient and Hessian in Cartesian coordinates of an axisymmetric ``psi(rho, z)``."""
    z = d[0] * nu[0] + d[1] * nu[1] + d[2] * nu[2]
    rv = d - z * nu
    rho = math.sqrt(rv[0] ** 2 + rv[1] ** 2 + rv[2] ** 2)
    grad = pz * nu
    # the 3×3 products written out (np.outer/np.eye would pull numba's linalg overloads into
    # the compile); element by element the same operations in the same order
    hess = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            hess[i, j] = pzz * (nu[i] * nu[j])
    if rho > 0.0:
        rh = rv / rho
        grad = grad + pr * rh
        g = pr / rho if rho > 1e-7 * math.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2) else prr
        for i in range(3):
            for j in range(3):
                e = 1.0 if i == j else 0.0
                hess[i, j] += prr * (rh[i] * rh[j]) + prz * (rh[i] * nu[j] + nu[i] * rh[j])
                hess[i, j] += g * (e - rh[i] * rh[j] - nu[i] * nu[j])
    else:
        for i in range(3):
            for j in range(3):
                e = 1.0 if i == j else 0.0
                hess[i, j] += prr * (e - nu[i] * nu[j])
    return grad, hess


@njit(cache=True)
def cylinder_psi_cartesian(d: np.ndarray, nu: np.ndarray, m: float, a: float, l: float,
                           sx: np.ndarray, sw: np.ndarray, q: np.ndarray
                           ) -> tuple[float, np.ndarray, np.ndarray]:
    """``psi``, its gradient and Hessian at offset ``d`` from a cylinder with axis ``nu``.

    Uses the multipole series beyond ``3 sqrt(l^2 + a^2)`` (orders up to 41: truncation
    ~3^-42, i.e. below rounding), the ring decomposition inside.
    """
    z = d[0] * nu[0] + d[1] * nu[1] + d[2] * nu[2]
    rv = d - z * nu
    rho = math.sqrt(rv[0] ** 2 + rv[1] ** 2 + rv[2] ** 2)
    if rho * rho + z * z > 9.0 * (l * l + a * a):
        psi, pr, pz, prr, prz, pzz = multipole_psi_local(rho, z, q)
    else:
        psi, pr, pz, prr, prz, pzz = cylinder_psi_local(rho, z, m, a, l, sx, sw)
    grad, hess = _to_cartesian(d, nu, pr, pz, prr, prz, pzz)
    return psi, grad, hess


@njit(cache=True)
def dipole_cylinder_core(r: float, c1: float, c2: float, c3: float, m1: float, a1: float,
                         l1: float, moment2: float, mu0: float, n_ring: int
                         ) -> tuple[float, float, float, float, float]:
    """Seed eq. (17): dipole (body 2) in the field of a cylinder (body 1); ``(U, partials)``."""
    sx, sw = gauss_legendre_unit(n_ring)
    q = cylinder_axial_moments(m1, a1, l1, N_MULTIPOLE)
    e, nu1, nu2 = canonical_frame(c1, c2, c3)
    x = r * e
    psi, grad, hess = cylinder_psi_cartesian(x, nu1, m1, a1, l1, sx, sw, q)
    k = mu0 * moment2
    u = k * (nu2[0] * grad[0] + nu2[1] * grad[1] + nu2[2] * grad[2])
    force = -k * (hess @ nu2)
    torque2 = -k * np.cross(nu2, grad)  # m x B with B = -mu0 grad psi
    torque1 = -torque2 - np.cross(x, force)
    ur, u1, u2, u3 = partials_from_vectors(r, c1, c2, e, nu1, nu2, force, torque1, torque2)
    return u, ur, u1, u2, u3


@njit(cache=True)
def dumbbell_cylinder_core(r: float, c1: float, c2: float, c3: float, m1: float, a1: float,
                           l1: float, moment2: float, half_length2: float, mu0: float,
                           n_ring: int) -> tuple[float, float, float, float, float]:
    """Seed eq. (18) (with its factor eps): dumbbell (body 2) in a cylinder's field."""
    sx, sw = gauss_legendre_unit(n_ring)
    q = cylinder_axial_moments(m1, a1, l1, N_MULTIPOLE)
    e, nu1, nu2 = canonical_frame(c1, c2, c3)
    x = r * e
    kap = mu0 * moment2 / (2.0 * half_length2)
    u = 0.0
    force = np.zeros(3)
    torque2 = np.zeros(3)
    for i in range(2):
        eps = 1.0 if i == 0 else -1.0
        arm = eps * half_length2 * nu2
        psi, grad, hess = cylinder_psi_cartesian(x + arm, nu1, m1, a1, l1, sx, sw, q)
        u += eps * kap * psi
        fpole = -eps * kap * grad  # pole charge eps*kappa in H = -grad psi
        force += fpole
        torque2 += np.cross(arm, fpole)
    torque1 = -torque2 - np.cross(x, force)
    ur, u1, u2, u3 = partials_from_vectors(r, c1, c2, e, nu1, nu2, force, torque1, torque2)
    return u, ur, u1, u2, u3
