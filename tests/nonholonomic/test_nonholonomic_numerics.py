"""Physical-time integration through the time change dtau = |N| dt (poissonkit.numerics.conformal),
against high-accuracy direct solves (scipy DOP853, tol 1e-12)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import sympy as sp
from poissonkit_nonholonomic.ball import chaplygin_ball, chaplygin_ball_sphere_bmf
from poissonkit_nonholonomic.routh import routh_sphere
from poissonkit_nonholonomic.veselova import veselova

from poissonkit.errors import InputError, IntegrationError
from poissonkit.numerics.conformal import (
    ConformalIntegrator,
    LambdifiedSystem,
    invariant_drift,
    midpoint_python,
    solve_direct,
    time_change,
)

Y_BALL = np.array([0.0, 0.6, 0.8, 1.0, -0.5, 0.2])


@pytest.fixture(scope="module")
def ball_setup():
    s = chaplygin_ball(1, 2, 3, 1)
    ci = ConformalIntegrator(s, Y_BALL, backend="python")
    ref, _ = solve_direct(s, Y_BALL, 8.0, tol=1e-12, backend="python")
    return s, ci, ref


def test_time_change_of_the_chaplygin_ball_is_dt_equals_g_dtau():
    s = chaplygin_ball(1, 2, 3, 1)
    sigma, clock = time_change(s, Y_BALL)
    assert sigma == -1
    g = 1 / -s.multiplier
    assert sp.simplify(clock - g) == 0


def test_conformal_midpoint_converges_with_order_two_to_the_physical_flow(ball_setup):
    s, ci, ref = ball_setup
    errs = [np.max(np.abs(ci.solve(Y_BALL, 8.0, h).y_final - ref.y[-1])) for h in (0.04, 0.02)]
    assert errs[1] < 2e-4
    assert 3.2 < errs[0] / errs[1] < 4.8


def test_conformal_midpoint_keeps_casimirs_to_roundoff_and_energy_to_order_h2(ball_setup):
    s, ci, ref = ball_setup
    sol = ci.solve(Y_BALL, 8.0, 0.02)
    drift = sol.invariant_drift()
    assert drift["H3=(gamma,gamma)"] < 1e-12
    assert drift["H4=(gamma,M)"] < 1e-12
    assert drift["H2=(M,M)"] < 1e-12  # quadratic integral: kept by the midpoint rule too
    assert 1e-10 < drift["H1=(M,omega)"] < 1e-5  # not quadratic: O(h^2), bounded
    # the physical clock is increasing and ends exactly at t_end
    assert np.all(np.diff(sol.t) > 0) and sol.t[-1] == 8.0
    # the direct high-accuracy run conserves them as well (independent check of the claims)
    ref_drift = invariant_drift(ci.compiled, ref.y)
    assert max(ref_drift.values()) < 1e-9


def test_veselova_conformal_run_conserves_its_integrals():
    s = veselova(1, 2, 3)
    y0 = np.array([0.0, 0.6, 0.8, 0.4, -0.3, 0.5])
    sol = ConformalIntegrator(s, y0, backend="python").solve(y0, 5.0, 0.02)
    d = sol.invariant_drift()
    assert d["H3=(gamma,gamma)"] < 1e-12 and d["H4=(gamma,K)"] < 1e-12 and d["H2=(K,K)"] < 1e-12
    assert d["H1=(K,A_g K)"] < 1e-4  # O(h^2) with h = 0.02
    ref, _ = solve_direct(s, y0, 5.0, tol=1e-12, backend="python")
    assert np.max(np.abs(sol.y_final - ref.y[-1])) < 1e-3


def _tau_flow(system, y, tau, h=0.005):
    """The Hamiltonian flow in tau: dx/dtau = sigma P dH (sigma from the multiplier's sign)."""
    sigma, _ = time_change(system, y)
    tau_sys = LambdifiedSystem(replace(system, multiplier=sp.Integer(sigma)))
    return midpoint_python(tau_sys, np.asarray(y, float), tau, h).y[-1], tau_sys


def test_chaplygin_veselova_equivalence_numerically():
    """Prop. 4: with a^Ves = 1 - d a^Chap and K = M the two systems share the bracket on
    (gamma,gamma) = 1 and H^Ves = H2 - d H1^Chap; hence (i) each flow keeps the other's
    integrals (same invariant tori) and (ii) in the Hamiltonian time tau the flows commute.
    They are not the same trajectories: the Hamiltonians differ."""
    d = 1
    ch = chaplygin_ball(1, 2, 3, d)  # a^Chap = (1/2, 1/3, 1/4)
    ves = veselova(sp.Rational(1, 2), sp.Rational(2, 3), sp.Rational(3, 4))
    y0 = Y_BALL
    L_ch, L_ves = LambdifiedSystem(ch), LambdifiedSystem(ves)
    # (i) the Veselova trajectory stays on the Chaplygin torus
    sol = ConformalIntegrator(ves, y0, backend="python").solve(y0, 4.0, 0.01)
    ch_ints = L_ch.integrals(sol.y[:-1])
    assert np.max(np.abs(ch_ints - ch_ints[0])) < 1e-5
    # the Veselova energy equals H2 - d H1 on this trajectory
    h_ves = L_ves.integrals(sol.y[:-1])[:, 0]
    assert np.allclose(h_ves, ch_ints[:, 1] - d * ch_ints[:, 0], atol=1e-9)
    # (ii) commuting tau-flows
    a, _ = _tau_flow(ch, y0, 0.7)
    ab, _ = _tau_flow(ves, a, 0.5)
    b, _ = _tau_flow(ves, y0, 0.5)
    ba, _ = _tau_flow(ch, b, 0.7)
    assert np.max(np.abs(ab - ba)) < 1e-5
    assert np.max(np.abs(a - b)) > 1e-2  # the flows themselves differ


def test_routh_sphere_near_the_axis_gamma3_to_one():
    """gamma3 -> 1 is where the survey's rank-4 bracket of a body of revolution degenerates; the
    Euler-field representation used here is regular there and the midpoint run keeps (gamma,
    gamma) and the bilinear Jellett integral to round-off."""
    s = routh_sphere()
    for eps in (1e-7,):
        y0 = np.array([eps, 0.0, np.sqrt(1 - eps**2), 0.3, -0.2, 1.0])
        ci = ConformalIntegrator(s, y0, backend="python")
        assert ci.sigma == 1
        sol = ci.solve(y0, 2.0, 0.01)
        d = sol.invariant_drift()
        assert d["C=(gamma,gamma)"] < 1e-12
        assert d["J1=(M,r) (Jellett)"] < 1e-11
        assert d["J2=g omega3 (Routh)"] < 1e-3 and d["H"] < 1e-2
        ref, _ = solve_direct(s, y0, 2.0, tol=1e-12, backend="python", compiled=ci.compiled)
        assert np.max(np.abs(sol.y_final - ref.y[-1])) < 1e-3
        assert max(invariant_drift(ci.compiled, ref.y).values()) < 1e-8


def test_bmf_direct_run_conserves_integrals_and_time_change_singular_where_s_vanishes():
    s = chaplygin_ball_sphere_bmf(1, 2, 3, 1)
    L = LambdifiedSystem(s)
    ref, _ = solve_direct(s, Y_BALL, 5.0, tol=1e-12, backend="python", compiled=L)
    assert max(invariant_drift(L, ref.y).values()) < 1e-9
    # N = d/(g s) and s = det(B + 2d gamma^ gamma^) changes sign on the sphere (FORMULAS.md §8:
    # s = 4d^2 (gamma,B gamma) - 2d((trB E - B) gamma, B gamma) + det B = -5 at e1, 3 at e3), so the
    # time change dt = (g s / d) dtau degenerates on s = 0, e.g. at (sqrt6/4, 0, sqrt10/4)
    sign_e1, _ = time_change(s, [1, 0, 0, 1, 0, 0])
    sign_e3, clock = time_change(s, [0, 0, 1, 1, 0, 0])
    assert sign_e1 != sign_e3
    ci = ConformalIntegrator(s, [0, 0, 1, 1, 0, 0], backend="python")
    assert abs(ci.clock(np.array([np.sqrt(6) / 4, 0, np.sqrt(10) / 4, 1, 0, 0]))[0]) < 1e-12


def test_bad_arguments_are_typed_errors(ball_setup):
    s, ci, _ = ball_setup
    with pytest.raises(InputError):
        ci.solve(Y_BALL, -1.0, 0.01)
    with pytest.raises(InputError):
        ci.solve(Y_BALL, 1.0, 0.0)
    with pytest.raises(InputError):
        ConformalIntegrator(s, Y_BALL, backend="gpu")
    with pytest.raises(IntegrationError):
        midpoint_python(ci.compiled, Y_BALL, 50.0, 50.0)


@pytest.mark.slow
def test_compiled_path_matches_the_python_path(ball_setup):
    s, ci, ref = ball_setup
    cc = ConformalIntegrator(s, Y_BALL, backend="compiled")
    a = cc.solve(Y_BALL, 8.0, 0.02)
    b = ci.solve(Y_BALL, 8.0, 0.02)
    assert np.max(np.abs(a.y_final - b.y_final)) < 1e-10
    direct = solve_direct(s, Y_BALL, 8.0, method="dop853", tol=1e-12)
    assert np.max(np.abs(direct.y[-1] - ref.y[-1])) < 1e-8
