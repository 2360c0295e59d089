"""The chaos indicator: MEGNO from two nearby runs.

Known answers: a regular (quasi-periodic) orbit has <Y> -> 2 (Cincotta & Simó 2000) -- the
seed's circular orbit and a Hénon–Heiles orbit at E = 1/12 (regular, Hénon & Heiles 1964);
a chaotic orbit has <Y> ~ λ t / 2, growing with time -- Hénon–Heiles at E = 1/6 in the chaotic
sea, confirmed here independently by a Benettin estimate of the largest Lyapunov exponent with
scipy's DOP853 on the variational equations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from poissonkit.errors import InputError
from poissonkit.sweeps.chaos import megno


@pytest.fixture(scope="module")
def henon_heiles():
    from poissonkit.numerics import compile_system
    from poissonkit.structure import HamiltonianSystem, canonical

    P = canonical(2)
    x, y, px, py = P.coords
    H = (px**2 + py**2) / 2 + (x**2 + y**2) / 2 + x**2 * y - y**3 / 3
    return compile_system(HamiltonianSystem(P, H, name="Hénon–Heiles"))


def hh_state(E, y, py):
    """x = 0 on the surface of section, px > 0 from the energy."""
    return np.array([0.0, y, math.sqrt(2 * E - py**2 - y**2 + 2 * y**3 / 3), py])


def hh_lyapunov(y0, t_end=1000.0, every=1.0):
    """Largest Lyapunov exponent by Benettin's method on the variational equations (scipy)."""
    def f(t, z):
        x, y, px, py = z[:4]
        dx, dy, dpx, dpy = z[4:]
        return [px, py, -x - 2 * x * y, -y - x**2 + y**2,
                dpx, dpy, -(1 + 2 * y) * dx - 2 * x * dy, -2 * x * dx - (1 - 2 * y) * dy]

    z = np.concatenate([y0, [1.0, 0.0, 0.0, 0.0]])
    total = 0.0
    for k in range(int(t_end / every)):
        sol = solve_ivp(f, (k * every, (k + 1) * every), z, method="DOP853", rtol=1e-11,
                        atol=1e-12)
        z = sol.y[:, -1]
        n = np.linalg.norm(z[4:])
        total += math.log(n)
        z[4:] /= n
    return total / t_end


def test_regular_henon_heiles_orbit_gives_two(henon_heiles):
    y = megno(henon_heiles, hh_state(1 / 12, 0.0, 0.0), 1000.0, method="midpoint", step=0.05)
    assert y == pytest.approx(2.0, abs=0.15)


def test_chaotic_henon_heiles_orbit_grows(henon_heiles):
    y0 = hh_state(1 / 6, -0.1, 0.1)
    lam = hh_lyapunov(y0)
    assert lam > 0.02  # independent: a positive Lyapunov exponent, the orbit is chaotic
    short = megno(henon_heiles, y0, 250.0, method="midpoint", step=0.05)
    long = megno(henon_heiles, y0, 1000.0, method="midpoint", step=0.05)
    assert short > 4 and long > 2 * short  # grows about linearly, far from 2
    # <Y> ~ λ t / 2 for chaotic motion: same order of magnitude as the scipy exponent says
    assert 0.25 < long / (lam * 1000.0 / 2) < 4


def test_circular_seed_orbit_is_regular():
    from poissonkit_magnets.seed000_sweep import SeedScene

    scene = SeedScene(periods=20)
    prep = scene.prepare()
    rec = scene.run(prep, {"spin_ratio": 20.0, "tilt": 0.0})
    system, y0, t_end, method, step = rec.megno_inputs
    assert megno(system, y0, t_end, method=method, step=step) == pytest.approx(2.0, abs=0.1)


def test_megno_needs_a_fixed_step(henon_heiles):
    with pytest.raises(InputError, match="fixed step"):
        megno(henon_heiles, hh_state(1 / 12, 0, 0), 10.0, method="dop853", step=None)
