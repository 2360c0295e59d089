"""Independent truth for magnet pair forces and torques (test helper, not a test module).

Exact: a uniformly axially magnetised cylinder is two uniformly charged end disks (sigma = ±M);
forces and torques come from a Gauss-Legendre (radius) x trapezoid (angle) quadrature of the
Coulomb interaction of the disk charges (MAGNETS.md §3 describes the method; nothing here uses
poissonkit). Cheap models: the textbook vector dipole formulas, and Coulomb sums over the poles
of a dumbbell (charges ±mu/(2l) at ±l along each axis).
"""

from __future__ import annotations

import math

import numpy as np

MU0 = 4e-7 * math.pi


def _disk_points(center, axis, a, n_r=12, n_t=24):
    x, w = np.polynomial.legendre.leggauss(n_r)
    s = 0.5 * a * (x + 1)
    ws = 0.5 * a * w * s  # area element s ds
    t = 2 * math.pi * np.arange(n_t) / n_t
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    u = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    S, T = np.meshgrid(s, t, indexing="ij")
    W = np.repeat(ws[:, None], n_t, axis=1) * (2 * math.pi / n_t)
    pts = center + (S * np.cos(T))[..., None] * u + (S * np.sin(T))[..., None] * v
    return pts.reshape(-1, 3), W.reshape(-1)


def _charges_cylinder(center, axis, M, a, l, n_r=12, n_t=24):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    out = []
    for sign in (1, -1):
        p, w = _disk_points(np.asarray(center, float) + sign * l * axis, axis, a, n_r, n_t)
        out.append((p, sign * M * w))
    return np.concatenate([o[0] for o in out]), np.concatenate([o[1] for o in out])


def _poles(center, axis, moment, l):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    kappa = moment / (2 * l)
    c = np.asarray(center, float)
    return np.array([c + l * axis, c - l * axis]), np.array([kappa, -kappa])


def _coulomb(p1, q1, p2, q2, center2):
    """Force on charges 2 and torque about center2 (magnetic charges, H-field convention)."""
    d = p2[:, None, :] - p1[None, :, :]
    dist = np.linalg.norm(d, axis=2)
    f = (MU0 / (4 * math.pi)) * (q2[:, None] * q1[None, :] / dist**3)[..., None] * d
    f2 = f.sum(axis=1)
    F = f2.sum(axis=0)
    T = np.cross(p2 - center2, f2).sum(axis=0)
    return F, T


_FT_CACHE: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}


def cylinder_ft(r, nu1, nu2, M, a, l):
    """Exact force on body 2 and torque on body 2 (about its centre); body 1 at the origin."""
    key = (tuple(np.asarray(r, float)), tuple(np.asarray(nu1, float)),
           tuple(np.asarray(nu2, float)), M, a, l)
    if key not in _FT_CACHE:  # the quadrature is the slow part of the tests: compute once
        _FT_CACHE[key] = _cylinder_ft(r, nu1, nu2, M, a, l)
    return _FT_CACHE[key]


def _cylinder_ft(r, nu1, nu2, M, a, l):
    p1, q1 = _charges_cylinder(np.zeros(3), nu1, M, a, l)
    p2, q2 = _charges_cylinder(r, nu2, M, a, l)
    return _coulomb(p1, q1, p2, q2, np.asarray(r, float))


def dumbbell_ft(r, nu1, nu2, moment, l):
    """Force/torque on body 2 for two dumbbells of half-length l (Coulomb sum over poles)."""
    p1, q1 = _poles(np.zeros(3), nu1, moment, l)
    p2, q2 = _poles(r, nu2, moment, l)
    return _coulomb(p1, q1, p2, q2, np.asarray(r, float))


def dipole_ft(r, nu1, nu2, moment):
    """Textbook point-dipole force on 2 and torque on 2: F = grad(m2.B1), T = m2 x B1."""
    r = np.asarray(r, float)
    d = np.linalg.norm(r)
    e = r / d
    m1 = moment * np.asarray(nu1, float) / np.linalg.norm(nu1)
    m2 = moment * np.asarray(nu2, float) / np.linalg.norm(nu2)
    k = MU0 / (4 * math.pi)
    F = 3 * k / d**4 * ((m1 @ e) * m2 + (m2 @ e) * m1 + (m1 @ m2) * e - 5 * (m1 @ e) * (m2 @ e) * e)
    B1 = k * (3 * (m1 @ e) * e - m1) / d**3
    return F, np.cross(m2, B1)


def model_errors(model, r, nu1, nu2, M, a, l):
    """Force and torque error of a cheap model against the exact cylinders.

    Each is relative to the larger of the exact value and the dipole scale (3 k / r^4 for the
    force, k / r^3 for the torque, k = mu0 mu^2 / (4 pi)), so configurations where the exact
    force or torque vanishes by symmetry keep a meaningful measure.
    """
    moment = M * math.pi * a * a * 2 * l
    F0, T0 = cylinder_ft(r, nu1, nu2, M, a, l)
    if model == "dipole":
        F, T = dipole_ft(r, nu1, nu2, moment)
    elif model == "dumbbell":
        F, T = dumbbell_ft(r, nu1, nu2, moment, l)
    elif model == "dumbbell_octupole":
        F, T = dumbbell_ft(r, nu1, nu2, moment, math.sqrt(l * l - 0.75 * a * a))
    elif model == "cylinder":
        return 0.0, 0.0
    else:
        raise ValueError(model)
    d = float(np.linalg.norm(r))
    k = MU0 * moment * moment / (4 * math.pi)
    return (float(np.linalg.norm(F - F0)) / max(float(np.linalg.norm(F0)), 3 * k / d**4),
            float(np.linalg.norm(T - T0)) / max(float(np.linalg.norm(T0)), k / d**3))


def _coulomb_energy(p1, q1, p2, q2):
    d = np.linalg.norm(p2[:, None, :] - p1[None, :, :], axis=2)
    return float((MU0 / (4 * math.pi)) * np.sum(q2[:, None] * q1[None, :] / d))


def cylinder_energy(r, nu1, nu2, M, a, l):
    """Exact interaction energy of two identical cylinders (disk-charge quadrature)."""
    p1, q1 = _charges_cylinder(np.zeros(3), nu1, M, a, l)
    p2, q2 = _charges_cylinder(r, nu2, M, a, l)
    return _coulomb_energy(p1, q1, p2, q2)


def dumbbell_energy(r, nu1, nu2, moment1, l1, moment2=None, l2=None):
    """Energy of two dumbbells (Coulomb sum over the four pole pairs)."""
    p1, q1 = _poles(np.zeros(3), nu1, moment1, l1)
    p2, q2 = _poles(r, nu2, moment1 if moment2 is None else moment2, l1 if l2 is None else l2)
    return _coulomb_energy(p1, q1, p2, q2)


def dipole_energy(r, nu1, nu2, moment1, moment2=None):
    """Textbook U = -m2 . B1(r)."""
    r = np.asarray(r, float)
    d = np.linalg.norm(r)
    e = r / d
    m1 = moment1 * np.asarray(nu1, float) / np.linalg.norm(nu1)
    m2 = (moment1 if moment2 is None else moment2) * np.asarray(nu2, float) / np.linalg.norm(nu2)
    B1 = MU0 / (4 * math.pi) * (3 * (m1 @ e) * e - m1) / d**3
    return float(-(m2 @ B1))
