"""Dynamics of the seed 000 scene against independent truth.

* the compiled dumbbell force (magnets plugin) at the orbit state balances the centrifugal force
  of the seed's P_orb (derived in mpmath, seed000's table) — ``ṗ = -1`` in internal units;
* the circular orbit (relative equilibrium, axes normal to the plane) is uniform circular motion
  with angular velocity 1 (internal units): compared with the closed form;
* close approach (pericentre 0.43 l, below the 1.5 l of the hard-case list): with both axes
  normal to the plane the motion is planar central-force motion in
  ``U(r) = K(-2/r + 2/sqrt(r² + 4l²))``; the radial period and the apsidal angle come from
  mpmath quadrature (FORMULAS.md §1, eq. (16) with c' = c'' = 0, c''' = -1) and the integrator
  must land on the next apocentre at that time and angle.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from poissonkit_magnets import seed000
from poissonkit.numerics.solver import solve


def test_compiled_force_balances_centrifugal_force_of_seed_P_orb():
    spec = seed000.default_run()
    f = spec.system.rhs(0.0, spec.y0)
    # internal units: R = 1, P = 1, mu = 1, so the centripetal force is exactly 1
    assert np.allclose(f[0:3], [0, 1, 0], atol=1e-14)
    assert np.allclose(f[3:6], [-1, 0, 0], atol=1e-12)
    assert np.allclose(f[6:], 0, atol=1e-12)  # no torque, axes and spins stay put


@pytest.mark.parametrize("method,step,bound", [("splitting6", 2 * math.pi / 200, 1e-7),
                                               ("splitting8", 2 * math.pi / 200, 1e-8)])
def test_circular_orbit_matches_closed_form(method, step, bound):
    periods = 5
    spec = seed000.default_run(periods=periods, method=method, step=step)
    sol = solve(spec.system, spec.y0, spec.t_end, method=method, step=step, save_every=10)
    t = sol.t
    exact = np.stack([np.cos(t), np.sin(t), 0 * t], axis=1)
    err = np.max(np.linalg.norm(sol.y[:, :3] - exact, axis=1))
    assert err < bound
    # invariants to round-off (structure preservation)
    assert np.max(sol.casimir_drift()) < 1e-13
    j = spec.system.angular_momentum(sol.y)
    assert np.max(np.linalg.norm(j - j[0], axis=1)) / np.linalg.norm(j[0]) < 1e-13


def _planar_truth(momentum_factor: float):
    """Radial period and apsidal angle of the planar orbit, by mpmath quadrature."""
    p = seed000.nondimensional_parameters()
    with mpmath.workdps(30):
        l = mpmath.mpf(p["half_length1"])
        K = mpmath.mpf(p["mu0"]) * (mpmath.mpf(p["moment1"]) / (2 * l)) ** 2 / (4 * mpmath.pi)
        U = lambda r: K * (-2 / r + 2 / mpmath.sqrt(r**2 + 4 * l**2))
        L = mpmath.mpf(momentum_factor)  # r0 = 1, p tangential, mu = 1
        E = L**2 / 2 + U(1)
        g = lambda r: 2 * (E - U(r)) - L**2 / r**2
        rmin = mpmath.findroot(g, (mpmath.mpf("0.1"), mpmath.mpf("0.99")), solver="anderson")
        Tr = 2 * mpmath.quad(lambda r: 1 / mpmath.sqrt(g(r)), [rmin, 1])
        dphi = 2 * mpmath.quad(lambda r: L / r**2 / mpmath.sqrt(g(r)), [rmin, 1])
        return float(rmin), float(Tr), float(dphi)


def test_close_approach_planar_orbit_matches_quadrature():
    rmin, Tr, dphi = _planar_truth(0.8)
    l = seed000.nondimensional_parameters()["half_length1"]
    assert rmin < 1.5 * l  # a close approach in the sense of the hard-case list
    spec = seed000.default_run(momentum_factor=0.8)
    h = Tr / 4000
    sol = solve(spec.system, spec.y0, Tr, method="splitting8", step=h, save_every=4000)
    r, p = sol.y[-1, 0:3], sol.y[-1, 3:6]
    # back at the apocentre after one radial period, turned by the apsidal angle
    assert abs(np.linalg.norm(r) - 1.0) < 1e-9
    assert abs(np.dot(r, p) / np.linalg.norm(r)) < 1e-8  # radial momentum vanishes
    assert abs(math.atan2(r[1], r[0]) % (2 * math.pi) - dphi % (2 * math.pi)) < 1e-8
    assert abs(r[2]) < 1e-14  # planar


def test_close_approach_tilted_keeps_invariants_and_agrees_with_dop853():
    """Tilted close encounter: invariants to round-off, trajectory vs a tight DOP853 solve.

    Stated bounds: Casimirs and |Δj| ≤ 1e-13 (relative to |r×p| + |m'| + |m''|; exact
    sub-flows); relative energy error
    ≤ 1e-10 and final-state difference ≤ 1e-6 (block-relative) after 3 periods at h = T/1000.
    """
    from poissonkit.numerics.workprecision import final_state_error

    spec = seed000.default_run(periods=3, tilt=0.01, momentum_factor=0.8)
    h = 2 * math.pi / 1000
    sol = solve(spec.system, spec.y0, spec.t_end, method="splitting8", step=h, save_every=5)
    d = np.linalg.norm(sol.y[:, :3], axis=1)
    assert d.min() < 0.5  # the encounter happened
    assert np.max(sol.casimir_drift()) < 1e-13
    j = spec.system.angular_momentum(sol.y)
    # round-off scale of j = r x p + m' + m'': the sum of the magnitudes (the spins, |m| ~ 13,
    # nearly cancel in j, so |j| itself would amplify round-off by ~16)
    y0 = sol.y[0]
    scale = np.linalg.norm(np.cross(y0[:3], y0[3:6])) + np.linalg.norm(y0[9:12]) + np.linalg.norm(y0[15:18])
    assert np.max(np.linalg.norm(j - j[0], axis=1)) / scale < 1e-13
    assert np.max(np.abs(sol.energy_error())) < 1e-10
    ref = solve(spec.system, spec.y0, spec.t_end, method="dop853", tol=1e-12)
    assert final_state_error(sol.y[-1], ref.y[-1]) < 1e-6


@pytest.mark.slow
def test_nbody_form_agrees_with_two_body_form():
    y18 = seed000.initial_state(tilt=0.2, spin_ratio=5.0)
    two = seed000.seed_system()
    nb = seed000.nbody_system()
    y24 = seed000.nbody_state(y18)
    f18, f24 = two.rhs(0, y18), nb.rhs(0, y24)
    assert np.allclose(f24[9:12], f18[3:6], atol=1e-12)  # p_2 dot = relative p dot
    assert np.allclose(f24[12:], f18[6:], atol=1e-12)
    T = 2 * math.pi
    a = solve(two, y18, T, method="splitting6", step=T / 400)
    b = solve(nb, y24, T, method="splitting6", step=T / 400)
    r, _ = seed000.relative_orbit(b.y[-1])
    assert np.allclose(r, a.y[-1, :3], atol=1e-10)
