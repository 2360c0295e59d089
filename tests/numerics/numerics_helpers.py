"""Helpers of the numerics tests: potentials written out from FORMULAS.md §1 (not from the
magnets plugin, which is tested separately), and small systems shared by several tests so that
numba compiles each kernel once per session."""

from __future__ import annotations

import numpy as np
import sympy as sp

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)

#: FORMULAS.md §1 dipole–dipole potential with mu0 mu' mu''/(4 pi) = 1.
DIPOLE = (C3 - 3 * C1 * C2) / R**3


def dumbbell(l1, l2, k1, k2, mu0=4 * sp.pi):
    """FORMULAS.md §1 eq. (16): charges eps k at +-l along each axis (half-lengths l)."""
    U = 0
    for e1 in (1, -1):
        for e2 in (1, -1):
            R2 = R**2 + l1**2 + l2**2 + 2 * R * (e2 * l2 * C2 - e1 * l1 * C1) - 2 * e1 * e2 * l1 * l2 * C3
            U += e1 * e2 / sp.sqrt(R2)
    return mu0 * k1 * k2 / (4 * sp.pi) * U


#: FORMULAS.md §1 oracle state (r, p, nu', m', nu'', m'').
ORACLE_STATE = np.array([1, 2, 2, 1 / 2, -1, 1 / 3, 0, 0, 1, 1 / 5, 2 / 5, 1, 3 / 5, 4 / 5, 0,
                         -1, 1 / 2, 2], dtype=float)


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


#: dipole pair plus a short-range repulsion, so that bound, non-colliding orbits exist
#: (pure dipole-dipole circular orbits are unstable, like every r^-3 attraction)
BOUND = DIPOLE + R**-6 / 2


def orbit_state(tilt=0.05, spin=1.0):
    """A bounded two-top orbit of ``BOUND`` (mu = 2, alpha = 3, 5), radius within 1 +- 3 %.

    Head-to-tail axes near e; V_r(1) = 6 - 3 = 3 gives the circular momentum p = 2 sqrt(3/2);
    the spins make the axes co-rotate with the orbit (alpha |m| = orbital rate).
    """
    v = np.sqrt(1.5)
    r = np.array([1.0, 0.0, 0.0])
    p = np.array([0.0, 2.0 * v, 0.0])
    nu1 = unit([np.cos(tilt), np.sin(tilt), 0.0])
    nu2 = unit([np.cos(tilt), -np.sin(tilt), 0.05])
    m1 = spin * np.array([0.05, 0.0, v / 3])
    m2 = spin * np.array([0.0, -0.05, v / 5])
    return np.concatenate([r, p, nu1, m1, nu2, m2])


def assert_invariants_at_roundoff(system, sol, tol=1e-13):
    """Casimirs (|ν| = 1, (ν, m)), total angular and linear momentum of an N-body solution kept
    to ``tol``; the momenta relative to the size of the summed terms (the round-off of the
    sums themselves)."""
    assert np.max(sol.casimir_drift()) <= tol
    assert np.all(np.abs(system.casimirs(sol.y)[:, 0::2] - 1) <= tol)
    parts = system.unpack(sol.y)
    j = system.angular_momentum(sol.y)
    j_scale = (np.linalg.norm(np.cross(parts["r"], parts["p"]), axis=-1).sum(-1)
               + np.linalg.norm(parts["m"], axis=-1).sum(-1)).max()
    assert np.max(np.linalg.norm(j - j[0], axis=1)) <= tol * j_scale
    P = system.linear_momentum(sol.y)
    p_scale = np.linalg.norm(parts["p"], axis=-1).sum(-1).max()
    assert np.max(np.linalg.norm(P - P[0], axis=1)) <= tol * p_scale


def assert_energy_without_drift(sol):
    """A long run's energy error bounded (below 1e-3) with no secular growth (its last tenth
    within twice its first tenth), and the Casimirs and angular momentum at round-off."""
    err = sol.energy_error()
    first, last = err[: len(err) // 10].max(), err[-len(err) // 10:].max()
    assert err.max() < 1e-3
    assert last < 2.0 * first + 1e-12, (first, last)  # no secular growth
    assert np.max(sol.casimir_drift()) <= 1e-12
    assert np.max(sol.angular_momentum_drift()) <= 1e-12
