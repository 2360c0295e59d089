"""Smooth (switched) cutoff: forces are the derivative of the switched energy, and a cluster's
energy no longer jumps when pairs cross the cutoff.

Truth: central finite differences of the energy (independent of the force code).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)
DIPOLE = (C3 - 3 * C1 * C2) / R**3
SOFT = 1 / R**6 - 1 / R**3  # orientation-free: the fast path
#: weak dipoles with a hard core, so a warm cluster neither collapses nor flies apart
GAS = DIPOLE / 20 + 1 / R**9


def lattice_cluster(potential, tops: bool, n_side: int = 4, seed: int = 2, speed: float = 0.3,
                    spacing: float = 1.1):
    rng = np.random.default_rng(seed)
    g = np.arange(n_side, dtype=float) * spacing
    pos = np.array([[x, y, z] for x in g for y in g for z in g])
    pos += rng.uniform(-0.15, 0.15, size=pos.shape)
    n = len(pos)
    bodies = [Body(f"b{k}", 1.0, 1.0 if tops else None) for k in range(n)]
    system = NBodySystem(bodies, [AllPairs(potential)], cutoff=2.0, smooth_cutoff=1.5)
    truncated = NBodySystem(bodies, [AllPairs(potential)], cutoff=2.0)
    p = speed * rng.normal(size=(n, 3))
    if tops:
        nu = rng.normal(size=(n, 3))
        y = system.pack(pos, p, nu, 0.3 * rng.normal(size=(n, 3)), normalize=True)
    else:
        y = system.pack(pos, p)
    return system, truncated, y


@pytest.mark.parametrize("potential, tops", [(DIPOLE, True), (SOFT, False)],
                         ids=["dipoles-general-path", "central-fast-path"])
def test_switched_forces_are_minus_the_energy_gradient(potential, tops):
    system, _, y = lattice_cluster(potential, tops)
    F, _, _ = system.forces(y)
    rng = np.random.default_rng(5)
    h = 1e-6
    for b in rng.choice(system.n_moving, size=6, replace=False):
        for d in range(3):
            yp, ym = y.copy(), y.copy()
            yp[6 * b + d] += h
            ym[6 * b + d] -= h
            fd = -(system.energy(yp) - system.energy(ym)) / (2 * h)
            assert F[b, d] == pytest.approx(fd, rel=1e-6, abs=1e-7 * np.abs(F).max())


@pytest.mark.slow  # two 2000-step runs of a 64-top cluster (~30 s with compilation)
def test_switched_energy_is_continuous_and_conserved_better_than_truncated():
    system, truncated, y = lattice_cluster(GAS, True, speed=0.1, spacing=1.4)
    # a pair just inside the cutoff contributes (almost) nothing with the switch
    two = NBodySystem([Body("a", 1.0, 1.0), Body("b", 1.0, 1.0)], [AllPairs(DIPOLE)],
                      cutoff=2.0, smooth_cutoff=1.5)
    near = two.pack([[0, 0, 0], [2.0 - 1e-6, 0, 0]], np.zeros((2, 3)), [[0, 0, 1]] * 2,
                    np.zeros((2, 3)))
    assert abs(two.forces(near)[2]) < 1e-15
    runs = {}
    for name, s in (("smooth", system), ("truncated", truncated)):
        sol = solve(s, y, 20.0, method="splitting2", step=0.01, save_every=20)
        e = s.energy(sol.y)
        runs[name] = np.abs(e - e[0]).max()
    assert runs["smooth"] < 0.1 * runs["truncated"], runs


def test_smooth_cutoff_needs_a_cutoff_above_it():
    bodies = [Body("a", 1.0), Body("b", 1.0)]
    with pytest.raises(InputError, match="needs a cutoff"):
        NBodySystem(bodies, [AllPairs(SOFT)], smooth_cutoff=1.0)
    with pytest.raises(InputError, match="smooth_cutoff"):
        NBodySystem(bodies, [AllPairs(SOFT)], cutoff=1.0, smooth_cutoff=1.5)
