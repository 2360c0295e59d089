"""The orientation-free fast path: equal to the general pair loop, and right on a Kepler orbit.

Truths: the general loop (axis terms, torques) on the same scene; the closed-form Kepler
orbit (the shared oracle ``tests/oracles.py``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from oracles import KeplerOrbit  # type: ignore[import-not-found]

from poissonkit.numerics import AllPairs, Body, Interaction, NBodySystem, solve

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)
DIPOLE = 0.3 * (C3 - 3 * C1 * C2) / R**3


def mixed_scene(fast_path: bool) -> tuple[NBodySystem, np.ndarray]:
    """Three magnets (tops, one fixed) and three point masses, all under gravity."""
    rng = np.random.default_rng(11)
    bodies = [Body("m0", 1.0, 2.0), Body("m1", 1.5, 1.0), Body("m2", 0.7, 3.0),
              Body("p0", 2.0), Body("p1", 0.5), Body("p2", 1.2),
              Body("fixed", 3.0, 1.0, fixed=True, position=(0.0, 0.0, -3.0), axis=(0, 0, 1))]
    inter = [AllPairs(DIPOLE, members=["m0", "m1", "m2", "fixed"]),
             AllPairs("gravity", {"G": 1.0}),
             Interaction("p0", "m1", "gravity", {"G": 0.5, "mass1": 4.0})]
    system = NBodySystem(bodies, inter, fast_path=fast_path)
    pos = rng.uniform(-2, 2, size=(7, 3))
    nu = rng.normal(size=(7, 3))
    y = system.pack(pos, rng.normal(size=(7, 3)), nu, rng.normal(size=(7, 3)), normalize=True)
    return system, y


@pytest.mark.slow  # 12-15 s on a cold kernel cache; the default run keeps a smaller sibling
def test_fast_path_equals_general_path_on_a_mixed_magnet_and_point_mass_scene():
    fast, y = mixed_scene(True)
    slow, y2 = mixed_scene(False)
    np.testing.assert_array_equal(y, y2)
    # the fast path really is taken: the orientation-free pairs left the general lists
    assert fast.data.radial_pairs.shape[0] == 1 and fast.data.set_central.tolist() == [0, 1]
    assert slow.data.radial_pairs.shape[0] == 0 and slow.data.set_central.tolist() == [0, 0]
    Ff, Tf, Uf = fast.forces(y)
    Fs, Ts, Us = slow.forces(y)
    scale = np.abs(Fs).max()
    np.testing.assert_allclose(Ff, Fs, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(Tf, Ts, rtol=0, atol=1e-13 * np.abs(Ts).max())
    assert math.isclose(Uf, Us, rel_tol=1e-13)
    np.testing.assert_allclose(fast.rhs(0.0, y), slow.rhs(0.0, y), rtol=0,
                               atol=1e-13 * np.abs(slow.rhs(0.0, y)).max())
    # and a short run agrees step for step (same splitting, same kernels up to round-off)
    a = solve(fast, y, 0.2, method="splitting4", step=0.01)
    b = solve(slow, y, 0.2, method="splitting4", step=0.01)
    np.testing.assert_allclose(a.y[-1], b.y[-1], rtol=0, atol=1e-11 * np.abs(b.y[-1]).max())


def kepler_closed_form(t: float, mu: float, a: float, e: float) -> tuple[np.ndarray, np.ndarray]:
    """Relative position and velocity on an ellipse starting at pericentre (x axis) at t = 0."""
    return KeplerOrbit(mu=mu, a=a, e=e).state(t)


def two_body(m0: float = 1.0, m1: float = 0.25, a: float = 1.0, e: float = 0.6):
    mu = m0 + m1  # G = 1
    x0, v0 = kepler_closed_form(0.0, mu, a, e)
    system = NBodySystem([Body("star", m0), Body("planet", m1)], [AllPairs("gravity", {"G": 1.0})])
    M = m0 + m1
    pos = np.array([-m1 / M * x0, m0 / M * x0])
    vel = np.array([-m1 / M * v0, m0 / M * v0])
    y0 = system.pack(pos, np.array([m0, m1])[:, None] * vel)
    return system, y0, mu


def relative_state(system: NBodySystem, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    u = system.unpack(y)
    m = np.array([b.mass for b in system.bodies])
    return u["r"][1] - u["r"][0], u["p"][1] / m[1] - u["p"][0] / m[0]


def test_two_body_kepler_orbit_matches_the_closed_form():
    system, y0, mu = two_body()
    period = 2 * math.pi / math.sqrt(mu)
    t_end = 3.3 * period
    x_ref, v_ref = kepler_closed_form(t_end, mu, 1.0, 0.6)
    # Wisdom–Holman: for two bodies the Kepler drift is the exact flow (H_I = 0)
    wh = solve(system, y0, t_end, method="wisdom_holman", step=period / 7)
    x, v = relative_state(system, wh.y[-1])
    assert np.abs(x - x_ref).max() < 1e-11 and np.abs(v - v_ref).max() < 1e-11
    # the fast pair loop under a 6th-order splitting converges to the same orbit
    errs = []
    for n in (400, 800):
        sol = solve(system, y0, t_end, method="splitting6", step=t_end / n)
        x, v = relative_state(system, sol.y[-1])
        errs.append(np.abs(x - x_ref).max())
    assert errs[1] < 1e-6 and errs[0] / errs[1] > 2**6 * 0.6
    # centre of mass stays at rest, total momentum zero to round-off
    assert np.abs(system.linear_momentum(sol.y)).max() < 1e-14
