"""Circular current loops and superconducting rings (docs/magnets.md).

* Mutual inductance of two coaxial loops (Maxwell), evaluated in the hypergeometric form
  ``M = (pi/16) mu0 sqrt(ab) k^3 2F1(3/2, 3/2; 3; k^2)``, which has no cancellation at small ``k``
  (Maxwell's elliptic form loses ~1e-12 relative at d = 10 a).
* Arbitrary placements: the Neumann double line integral
  ``M = mu0/(4 pi) oint oint dl1 . dl2 / |x1 - x2|`` with the trapezoid rule in both angles
  (spectrally accurate for separated loops); force and torque on loop 2 from
  ``F = I2 oint dl2 x B1``, ``T2 = I2 oint (x2 - r2) x (dl2 x B1)`` with Biot–Savart ``B1``.
* Dipole in a loop's field: ``U = -m . B_loop``, ``F = grad(m . B)``, ``T = m x B``, with ``B``
  from the Biot–Savart integral over the loop (validated against the closed elliptic form).

Loops carry their current right-handed about their axis ``nu``. A loop of constant current has
pair energy ``-I1 I2 M`` (the mechanical potential at fixed currents). A superconducting ring
keeps its flux ``Phi`` instead; two rings have ``U = Phi^T L^-1 Phi / 2`` with
``L = [[L1, M], [M, L2]]``, so currents follow the configuration, ``I = L^-1 Phi``, and
``dU/dM = -I1 I2``. The self-inductance of a thin ring of radius ``a`` and wire radius ``b``
is ``L = mu0 a (ln(8a/b) - 2)`` (surface current, ``b << a``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from poissonkit_magnets._geometry import canonical_frame, partials_from_vectors, perpendicular_pair
from poissonkit_magnets._special import hyp2f1_maxwell

#: Default number of trapezoid nodes along each loop.
N_LOOP = 96


@njit(cache=True)
def mutual_inductance_coaxial(a: float, b: float, d: float, mu0: float) -> float:
    """Mutual inductance of coaxial loops of radii ``a``, ``b`` at axial distance ``d`` (H)."""
    m = 4.0 * a * b / ((a + b) ** 2 + d * d)
    return math.pi / 16.0 * mu0 * math.sqrt(a * b) * m ** 1.5 * hyp2f1_maxwell(m)


def self_inductance(radius: float, wire_radius: float, mu0: float = 4e-7 * math.pi) -> float:
    """Thin-ring self-inductance ``mu0 a (ln(8a/b) - 2)`` (H), valid for ``b << a``."""
    if not 0 < wire_radius < radius / 4:
        raise ValueError(f"thin-ring formula needs 0 < wire_radius < radius/4, got "
                         f"wire_radius={wire_radius}, radius={radius}")
    return mu0 * radius * (math.log(8.0 * radius / wire_radius) - 2.0)


@njit(cache=True)
def _loop_points(centre: np.ndarray, nu: np.ndarray, a: float, n: int
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Trapezoid nodes on a loop and the tangents ``dl/dphi`` times ``2 pi / n``."""
    u, w = perpendicular_pair(nu)
    pts = np.empty((n, 3))
    dls = np.empty((n, 3))
    h = 2.0 * math.pi / n
    for i in range(n):
        phi = i * h
        c = math.cos(phi)
        s = math.sin(phi)
        for k in range(3):
            pts[i, k] = centre[k] + a * (c * u[k] + s * w[k])
            dls[i, k] = a * h * (-s * u[k] + c * w[k])
    return pts, dls


@njit(cache=True)
def loop_dipole_vectors(r: float, c1: float, c2: float, c3: float, current1: float,
                        radius1: float, moment2: float, mu0: float, n: int
                        ) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                   np.ndarray, np.ndarray]:
    """Energy, force on the dipole, torques on loop and dipole, and the frame."""
    e, nu1, nu2 = canonical_frame(c1, c2, c3)
    x = r * e
    mvec = moment2 * nu2
    pts, dls = _loop_points(np.zeros(3), nu1, radius1, n)
    kf = mu0 * current1 / (4.0 * math.pi)
    b = np.zeros(3)
    grad_mb = np.zeros(3)
    for i in range(n):
        d = x - pts[i]
        q2 = d[0] ** 2 + d[1] ** 2 + d[2] ** 2
        q = math.sqrt(q2)
        inv3 = 1.0 / (q2 * q)
        tx = np.cross(dls[i], d)
        b += kf * tx * inv3
        # m . (dl x d) = (m x dl) . d ; its gradient in x
        mt = np.cross(mvec, dls[i])
        mtd = mt[0] * d[0] + mt[1] * d[1] + mt[2] * d[2]
        grad_mb += kf * (mt * inv3 - 3.0 * mtd * d * inv3 / q2)
    energy = -(mvec[0] * b[0] + mvec[1] * b[1] + mvec[2] * b[2])
    force = grad_mb
    torque2 = np.cross(mvec, b)
    torque1 = -torque2 - np.cross(x, force)
    return energy, force, torque1, torque2, e, nu1, nu2


@njit(cache=True)
def loop_dipole_core(r: float, c1: float, c2: float, c3: float, current1: float, radius1: float,
                     moment2: float, mu0: float, n: int) -> tuple[float, float, float, float, float]:
    """``(U, U_r, U_c1, U_c2, U_c3)`` of a dipole (body 2) in a loop's field (body 1)."""
    u, f, t1, t2, e, nu1, nu2 = loop_dipole_vectors(r, c1, c2, c3, current1, radius1, moment2,
                                                     mu0, n)
    ur, u1, u2, u3 = partials_from_vectors(r, c1, c2, e, nu1, nu2, f, t1, t2)
    return u, ur, u1, u2, u3


@njit(cache=True)
def loop_loop_vectors(r: float, c1: float, c2: float, c3: float, radius1: float,
                      radius2: float, mu0: float, n: int
                      ) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                 np.ndarray, np.ndarray]:
    """Mutual inductance and, for unit currents, force on loop 2 and torques on both loops."""
    e, nu1, nu2 = canonical_frame(c1, c2, c3)
    x = r * e
    p1, d1 = _loop_points(np.zeros(3), nu1, radius1, n)
    p2, d2 = _loop_points(x, nu2, radius2, n)
    k = mu0 / (4.0 * math.pi)
    mutual = 0.0
    force = np.zeros(3)
    torque2 = np.zeros(3)
    for j in range(n):
        b0 = 0.0
        b1 = 0.0
        b2 = 0.0
        for i in range(n):
            d0 = p2[j, 0] - p1[i, 0]
            d1_ = p2[j, 1] - p1[i, 1]
            d2_ = p2[j, 2] - p1[i, 2]
            q2 = d0 * d0 + d1_ * d1_ + d2_ * d2_
            q = math.sqrt(q2)
            mutual += (d1[i, 0] * d2[j, 0] + d1[i, 1] * d2[j, 1] + d1[i, 2] * d2[j, 2]) / q
            inv3 = 1.0 / (q2 * q)
            # Biot-Savart: dl1 x d / |d|^3
            b0 += (d1[i, 1] * d2_ - d1[i, 2] * d1_) * inv3
            b1 += (d1[i, 2] * d0 - d1[i, 0] * d2_) * inv3
            b2 += (d1[i, 0] * d1_ - d1[i, 1] * d0) * inv3
        b = k * np.array([b0, b1, b2])
        fj = np.cross(d2[j], b)
        force += fj
        torque2 += np.cross(p2[j] - x, fj)
    mutual *= k
    torque1 = -torque2 - np.cross(x, force)
    return mutual, force, torque1, torque2, e, nu1, nu2


@njit(cache=True)
def loops_core(r: float, c1: float, c2: float, c3: float, current1: float, current2: float,
               radius1: float, radius2: float, mu0: float, n: int
               ) -> tuple[float, float, float, float, float]:
    """Two loops at constant currents: ``U = -I1 I2 M`` and its partials."""
    mut, f, t1, t2, e, nu1, nu2 = loop_loop_vectors(r, c1, c2, c3, radius1, radius2, mu0, n)
    ii = current1 * current2
    ur, u1, u2, u3 = partials_from_vectors(r, c1, c2, e, nu1, nu2, ii * f, ii * t1, ii * t2)
    return -ii * mut, ur, u1, u2, u3


@njit(cache=True)
def superconducting_core(r: float, c1: float, c2: float, c3: float, flux1: float, flux2: float,
                         radius1: float, radius2: float, self1: float, self2: float, mu0: float,
                         n: int) -> tuple[float, float, float, float, float]:
    """Two flux-conserving rings: ``U = Phi^T L^-1 Phi / 2`` minus its value at infinity."""
    mut, f, t1, t2, e, nu1, nu2 = loop_loop_vectors(r, c1, c2, c3, radius1, radius2, mu0, n)
    det = self1 * self2 - mut * mut
    i1 = (self2 * flux1 - mut * flux2) / det
    i2 = (self1 * flux2 - mut * flux1) / det
    energy = 0.5 * (flux1 * i1 + flux2 * i2) - 0.5 * (flux1 ** 2 / self1 + flux2 ** 2 / self2)
    # dU/dM = -I1 I2, so forces and torques are those of loops carrying the present currents
    ii = i1 * i2
    ur, u1, u2, u3 = partials_from_vectors(r, c1, c2, e, nu1, nu2, ii * f, ii * t1, ii * t2)
    return energy, ur, u1, u2, u3


@njit(cache=True)
def ring_currents(r: float, c1: float, c2: float, c3: float, flux1: float, flux2: float,
                  radius1: float, radius2: float, self1: float, self2: float, mu0: float,
                  n: int) -> tuple[float, float]:
    """Currents ``I = L^-1 Phi`` of two superconducting rings in this configuration."""
    mut = loop_loop_vectors(r, c1, c2, c3, radius1, radius2, mu0, n)[0]
    det = self1 * self2 - mut * mut
    return (self2 * flux1 - mut * flux2) / det, (self1 * flux2 - mut * flux1) / det
