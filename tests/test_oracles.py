"""The shared oracles (``tests/oracles.py``) against independent checks: a DOP853 solve of the
equations of motion written out here at rtol 1e-13, the conservation laws, the defining
equation, and (Kepler) a second, independent formulation in 40-digit arithmetic."""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import (
    KeplerOrbit,
    euler_top,
    euler_top_period,
    free_top_axis,
    kepler_step_mp,
    solve_kepler,
)
from scipy.integrate import solve_ivp

TIGHT = {"method": "DOP853", "rtol": 1e-13, "atol": 1e-15}


@pytest.mark.parametrize("e", [0.0, 0.3, 0.9, 0.999, 0.999999])
def test_kepler_equation_is_solved_to_round_off_for_any_mean_anomaly(e):
    M = np.linspace(-60.0, 60.0, 20001)
    E = solve_kepler(M, e)
    assert np.all(np.abs(E - e * np.sin(E) - M) <= 8 * np.finfo(float).eps * (1 + np.abs(M)))
    assert np.all(np.diff(E) > 0)  # E(M) is increasing
    with pytest.raises(ValueError):
        solve_kepler(0.5, 1.0)


ORBITS = [KeplerOrbit(mu=1.3, a=1.2, e=0.7, inclination=0.4, node=1.0, periapsis=2.0,
                      mean_anomaly=0.5),
          KeplerOrbit(mu=1.0, a=1.0, e=0.9, mean_anomaly=math.pi),
          KeplerOrbit(mu=1.001, a=1.0, e=0.3)]


@pytest.mark.parametrize("orbit", ORBITS, ids=["inclined", "apocentre", "pericentre"])
def test_kepler_orbit_matches_a_tight_numerical_solve_and_keeps_its_invariants(orbit):
    x0, v0 = orbit.state(0.0)
    ts = np.linspace(0.0, 1.5 * orbit.period, 31)

    def rhs(_t, y):
        return np.r_[y[3:], -orbit.mu * y[:3] / np.linalg.norm(y[:3]) ** 3]

    ref = solve_ivp(rhs, (0.0, ts[-1]), np.r_[x0, v0], t_eval=ts, **TIGHT).y.T
    x, v = orbit.state(ts)
    assert np.abs(np.c_[x, v] - ref).max() < 1e-9 * max(1.0, np.abs(ref).max())
    energy = 0.5 * (v**2).sum(-1) - orbit.mu / np.linalg.norm(x, axis=-1)
    assert np.abs(energy - orbit.energy).max() < 1e-13 * abs(orbit.energy) * 10
    h = np.cross(x, v)
    assert np.abs(h - orbit.angular_momentum).max() < 1e-13 * 10
    # periodic, and the documented start: pericentre on +x, apocentre on -x
    x1, v1 = orbit.state(orbit.period)
    assert np.allclose(x1, x0, atol=1e-13) and np.allclose(v1, v0, atol=1e-12)


def test_kepler_orbit_agrees_with_the_universal_variable_step_in_40_digits():
    orbit = ORBITS[0]
    x0, v0 = orbit.state(0.0)
    for t in (0.3, 5.0, 17.0, -2.5):
        xm, vm = kepler_step_mp(x0, v0, orbit.mu, t)
        x, v = orbit.state(t)
        assert np.abs(xm - x).max() < 5e-14 and np.abs(vm - v).max() < 5e-14
    # a hyperbola: energy kept, there and back is the identity
    xh, vh = np.array([1.0, 0.0, 0.0]), np.array([0.0, 2.0, 0.3])
    x, v = kepler_step_mp(xh, vh, 1.0, 7.0)
    assert math.isclose(0.5 * v @ v - 1 / np.linalg.norm(x), 0.5 * vh @ vh - 1.0, rel_tol=1e-14)
    xb, vb = kepler_step_mp(x, v, 1.0, -7.0)
    assert np.allclose(xb, xh, atol=1e-13) and np.allclose(vb, vh, atol=1e-13)


def test_barycentric_bodies_keep_the_centre_of_mass_at_rest():
    m0, m1 = 1.0, 0.25
    x, v = ORBITS[0].bodies(m0, m1, np.array([0.0, 1.0]))
    assert x.shape == (2, 2, 3)
    assert np.abs(m0 * x[:, 0] + m1 * x[:, 1]).max() < 1e-15
    assert np.abs(m0 * v[:, 0] + m1 * v[:, 1]).max() < 1e-15
    assert np.allclose(x[:, 1] - x[:, 0], ORBITS[0].state(np.array([0.0, 1.0]))[0])


def test_free_top_axis_precesses_about_the_angular_momentum():
    m, inertia = np.array([0.3, -0.4, 1.2]), 0.7
    nu0 = np.array([1.0, 0.2, -0.1]) / np.linalg.norm([1.0, 0.2, -0.1])
    ts = np.linspace(0.0, 4.0, 9)
    ref = solve_ivp(lambda _t, n: np.cross(m / inertia, n), (0.0, 4.0), nu0, t_eval=ts,
                    **TIGHT).y.T
    nu = free_top_axis(nu0, m, inertia, ts)
    assert np.abs(nu - ref).max() < 1e-11
    assert np.allclose(np.linalg.norm(nu, axis=-1), 1.0, atol=1e-15)
    assert np.allclose(nu @ m, nu0 @ m, atol=1e-15)


def test_euler_top_matches_a_tight_numerical_solve_in_both_regimes():
    rng = np.random.default_rng(1)
    regimes = set()
    for _ in range(40):  # random states and axis orders: both signs, both separatrix sides
        m0 = rng.standard_normal(3)
        inertia = rng.permutation([1.0, 2.0, 3.0]) * rng.uniform(0.5, 2.0)
        regimes.add(m0 @ m0 > (m0 @ (m0 / inertia)) * np.sort(inertia)[1])
        ts = np.linspace(0.0, 3.0, 7)
        ref = solve_ivp(lambda _t, m: np.cross(m, m / inertia), (0.0, 3.0), m0,  # noqa: B023
                        t_eval=ts, **TIGHT).y.T
        m = euler_top(m0, inertia, ts)
        assert np.abs(m - ref).max() < 1e-10 * max(1.0, np.abs(m0).max())
        assert np.allclose((m**2).sum(-1), m0 @ m0, rtol=1e-13)
        assert np.allclose((m**2 / inertia).sum(-1), m0 @ (m0 / inertia), rtol=1e-13)
    assert regimes == {True, False}
    m0, inertia = np.array([0.2, 1.0, 0.4]), np.array([1.0, 2.0, 3.0])
    assert np.allclose(euler_top(m0, inertia, euler_top_period(m0, inertia)), m0, atol=1e-12)
    with pytest.raises(ValueError):
        euler_top(m0, np.array([1.0, 1.0, 2.0]), 1.0)
