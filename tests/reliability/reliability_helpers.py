"""Systems and states shared by the reliability tests (and the subprocess scripts they run)."""

from __future__ import annotations

import numpy as np
import sympy as sp

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)

#: dipole-dipole energy with mu0 m' m''/(4 pi) = 1 (docs/conventions: c1 = nu1.e, c2 = nu2.e,
#: c3 = nu1.nu2); coaxial aligned dipoles have U = -2/r^3
DIPOLE = (C3 - 3 * C1 * C2) / R**3
#: plus a short-range repulsion, so that bounded, non-colliding orbits exist
BOUND = DIPOLE + R**-6 / 2
#: reduced mass and the two alpha = 1/I of the two-body systems below
MU, ALPHA1, ALPHA2 = 2.0, 3.0, 5.0


def bound_pair():
    """Two tops on a bounded orbit of :data:`BOUND` (centre-of-mass form)."""
    from poissonkit.numerics import TwoBodySystem

    return TwoBodySystem(None, None, ALPHA1, ALPHA2, BOUND, reduced_mass=MU)


def dipole_pair():
    """Two pure dipoles (centre-of-mass form)."""
    from poissonkit.numerics import TwoBodySystem

    return TwoBodySystem(None, None, ALPHA1, ALPHA2, DIPOLE, reduced_mass=MU)


def orbit_state() -> np.ndarray:
    """A bounded, slightly tilted orbit of :func:`bound_pair` (radius about 1)."""
    v = np.sqrt(1.5)
    tilt = 0.05

    def unit(x):
        x = np.asarray(x, dtype=float)
        return x / np.linalg.norm(x)

    r = np.array([1.0, 0.0, 0.0])
    p = np.array([0.0, 2.0 * v, 0.0])
    nu1 = unit([np.cos(tilt), np.sin(tilt), 0.0])
    nu2 = unit([np.cos(tilt), -np.sin(tilt), 0.05])
    m1 = np.array([0.05, 0.0, v / 3])
    m2 = np.array([0.0, -0.05, v / 5])
    return np.concatenate([r, p, nu1, m1, nu2, m2])


#: the long runs of the kill/resume tests, per method: end time, step size, checkpoint interval,
#: saved rows (several seconds of stepping, so that the kill lands mid-run)
KILL_RUNS = {
    "splitting4": {"t_end": 3000.0, "step": 1e-3, "every": 100_000, "save_every": 10_000},
    "midpoint": {"t_end": 1000.0, "step": 1e-3, "every": 20_000, "save_every": 1_000},
}
