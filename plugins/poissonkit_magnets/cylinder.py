"""Exact interaction of two uniformly, axially magnetised cylinders.

A cylinder of radius ``a``, height ``2 l`` and magnetisation ``M`` along ``nu`` is exactly two
uniformly charged end disks, ``sigma = +M`` at ``+l nu`` and ``-M`` at ``-l nu`` (docs/magnets.md).
The energy of the four disk pairs is ``U = mu0 sum int_disk1 sigma1 psi2 dA``, where the scalar
potential of a disk of body 2 is reduced to a 1-D integral over rings,

    psi_disk(rho, z) = (sigma / pi) int_0^a s K(m) / sqrt((rho + s)^2 + z^2) ds,

so the whole quadrature is 3-D: Gauss–Legendre in ``s`` for the rings of each disk of body 2,
Gauss–Legendre in radius times the trapezoid rule in angle over each disk of body 1. Forces and
torques are the same integrals with the analytic gradient of ``psi`` (differentiation under the
integral sign), so U, F, T1 and T2 are consistent to rounding; the partials
``(U_r, U_c1, U_c2, U_c3)`` follow from them (:func:`partials_from_vectors`).

Accuracy is limited by the smoothness of ``psi2`` over the disks of body 1: it is at the 1e-10
level whenever the smallest gap between end disks of different bodies is at least about half the
larger radius (e.g. coaxial cylinders of radius 1.25 mm with a 2 mm face gap), and degrades
when end faces nearly touch (see docs/magnets.md for measurements).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from poissonkit_magnets._geometry import canonical_frame, partials_from_vectors, perpendicular_pair
from poissonkit_magnets._special import gauss_legendre_unit, ring_grad

#: Default quadrature: radial nodes per disk of body 1 and per ring integral, angular nodes.
N_RADIAL = 12
N_ANGULAR = 24


@njit(cache=True)
def pair_nodes(distance: float, a_max: float, n_max: int) -> int:
    """Radial node count for one pair of end disks whose centres are ``distance`` apart.

    Gauss–Legendre with ``n`` nodes integrates the multipole expansion of ``1/|x - y|`` up to
    degree ``2n - 1``; its terms fall like ``(a/D)^k``, so ``n ~ 7.5 / log10(D/a)`` reaches
    ~1e-15 of that pair's share. Close pairs (``D < 4a``) keep ``n_max``.
    """
    ratio = distance / a_max
    if ratio < 4.0:
        return n_max
    n = int(math.ceil(7.5 / math.log10(ratio)))
    return max(4, min(n_max, n))


@njit(cache=True)
def cylinder_vectors(r: float, c1: float, c2: float, c3: float, m1: float, m2: float,
                     a1: float, a2: float, l1: float, l2: float, mu0: float, n_radial: int,
                     n_angular: int
                     ) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                np.ndarray, np.ndarray]:
    """Energy, force on body 2, torques on bodies 1 and 2 (about their centres), and the frame.

    Body 1 sits at the origin; ``e = z`` (see :func:`canonical_frame`). For each of the four
    pairs of end disks, up to ``n_radial`` Gauss–Legendre nodes are used radially on the disk of
    body 1 and for the ring integral over the disk of body 2, and up to ``n_angular`` trapezoid
    nodes in angle (fewer for distant disk pairs, see :func:`pair_nodes`).
    """
    e, nu1, nu2 = canonical_frame(c1, c2, c3)
    rvec = r * e
    u1, w1 = perpendicular_pair(nu1)
    energy = 0.0
    grad_sum = np.zeros(3)
    torque_sum = np.zeros(3)
    a_max = max(a1, a2)
    for i1 in range(2):
        sg1 = 1.0 if i1 == 0 else -1.0
        centre1 = sg1 * l1 * nu1
        for i2 in range(2):
            sg2 = 1.0 if i2 == 0 else -1.0
            centre2 = rvec + sg2 * l2 * nu2
            dc = centre2 - centre1
            n = pair_nodes(math.sqrt(dc[0] ** 2 + dc[1] ** 2 + dc[2] ** 2), a_max, n_radial)
            na = max(8, (n_angular * n) // n_radial)
            tx, tw = gauss_legendre_unit(n)
            dphi = 2.0 * math.pi / na
            scale = sg2 * m2 * a2 / math.pi
            for ir in range(n):
                t = a1 * tx[ir]
                wr = sg1 * m1 * a1 * a1 * tx[ir] * tw[ir] * dphi * mu0
                for ip in range(na):
                    phi = (ip + 0.5) * dphi
                    cp = math.cos(phi)
                    sp_ = math.sin(phi)
                    x0 = centre1[0] + t * (cp * u1[0] + sp_ * w1[0])
                    x1 = centre1[1] + t * (cp * u1[1] + sp_ * w1[1])
                    x2 = centre1[2] + t * (cp * u1[2] + sp_ * w1[2])
                    d0 = x0 - centre2[0]
                    d1 = x1 - centre2[1]
                    d2 = x2 - centre2[2]
                    z = d0 * nu2[0] + d1 * nu2[1] + d2 * nu2[2]
                    rv0 = d0 - z * nu2[0]
                    rv1 = d1 - z * nu2[1]
                    rv2 = d2 - z * nu2[2]
                    rho = math.sqrt(rv0 * rv0 + rv1 * rv1 + rv2 * rv2)
                    f_acc = 0.0
                    fr_acc = 0.0
                    fz_acc = 0.0
                    for k in range(n):
                        s = a2 * tx[k]
                        f, fr, fz = ring_grad(rho, z, s)
                        ws = tw[k] * s
                        f_acc += ws * f
                        fr_acc += ws * fr
                        fz_acc += ws * fz
                    # grad psi = psi_rho rho_hat + psi_z nu2 (psi_rho = 0 on the axis)
                    gx = scale * fz_acc * nu2[0]
                    gy = scale * fz_acc * nu2[1]
                    gz = scale * fz_acc * nu2[2]
                    if rho > 0.0:
                        cr = scale * fr_acc / rho
                        gx += cr * rv0
                        gy += cr * rv1
                        gz += cr * rv2
                    energy += wr * scale * f_acc
                    grad_sum[0] += wr * gx
                    grad_sum[1] += wr * gy
                    grad_sum[2] += wr * gz
                    torque_sum[0] += wr * (x1 * gz - x2 * gy)
                    torque_sum[1] += wr * (x2 * gx - x0 * gz)
                    torque_sum[2] += wr * (x0 * gy - x1 * gx)
    force = grad_sum.copy()  # F2 = -grad_{r2} U = +mu0 sum int sigma1 grad psi2
    torque1 = -torque_sum
    torque2 = -torque1 - np.cross(rvec, force)  # exact angular-momentum balance
    return energy, force, torque1, torque2, e, nu1, nu2


@njit(cache=True)
def cylinder_core(r: float, c1: float, c2: float, c3: float, m1: float, m2: float, a1: float,
                  a2: float, l1: float, l2: float, mu0: float, n_radial: int,
                  n_angular: int) -> tuple[float, float, float, float, float]:
    """``(U, U_r, U_c1, U_c2, U_c3)`` of two exact cylinders (``l`` = half-heights)."""
    u, force, t1, t2, e, nu1, nu2 = cylinder_vectors(r, c1, c2, c3, m1, m2, a1, a2, l1, l2,
                                                      mu0, n_radial, n_angular)
    ur, uc1, uc2, uc3 = partials_from_vectors(r, c1, c2, e, nu1, nu2, force, t1, t2)
    return u, ur, uc1, uc2, uc3
