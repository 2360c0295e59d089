"""The ball rolling in a paraboloid of revolution (survey §6, (104)–(121); FORMULAS.md §13 lists it
as not checked). Independent truths used here: a Newton–Euler model of the ball written below
(reaction force solved numerically from the rolling constraint), the small-oscillation frequency
of a rolling ball in a bowl, energy bounds, and the survey's equations (108) as printed (with
``f = -1/(2c gamma3)`` from §6.4)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from poissonkit_nonholonomic.paraboloid import (
    OriginalFieldSystem,
    ball_on_paraboloid,
    integral_coefficients,
    paraboloid_parts,
    symmetry_field,
)
from scipy.integrate import solve_ivp

from poissonkit.errors import InputError
from poissonkit.numerics.conformal import (
    ConformalIntegrator,
    invariant_drift,
    midpoint_python,
    solve_direct,
)
from poissonkit.structure.checks import is_first_integral, is_invariant_measure
from poissonkit.structure.jacobi import check_jacobi

DEFAULT = {"mu": 0.25, "m": 3.0, "R": 0.5, "c": 0.5, "G": 30.0}


@pytest.fixture(scope="module")
def system():
    return ball_on_paraboloid()


@pytest.fixture(scope="module")
def field(system):
    return dict(zip(system.coords, [system.original[x] for x in system.coords]))


# ------------------------------------------------------------------ independent Newton–Euler
def newton_euler(x, y, omega, mu, m, R, c, G):
    """Rigid ball, centre ``r = (x, y, c(x^2+y^2))``, upward unit normal ``n``, contact point
    ``r - R n`` at rest: ``v = R omega x n``. Unknowns ``omega'`` and the reaction ``N`` from
    ``m v' = N + (0, 0, -G)``, ``mu omega' = (-R n) x N`` and ``v' = R (omega' x n + omega x n')``.
    Returns ``(n, n', v, omega')``."""
    q = np.sqrt(1 + 4 * c**2 * (x**2 + y**2))
    n = np.array([-2 * c * x, -2 * c * y, 1.0]) / q
    v = R * np.cross(omega, n)
    ndot_raw = np.array([-2 * c * v[0], -2 * c * v[1], 0.0])
    ndot = (ndot_raw - n * (n @ ndot_raw)) / q

    def hat(a):
        return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

    A = np.zeros((6, 6))
    b = np.zeros(6)
    # m R (omega' x n) - N = -G e3 - m R omega x n'
    A[:3, :3] = -m * R * hat(n)
    A[:3, 3:] = -np.eye(3)
    b[:3] = np.array([0, 0, -G]) - m * R * np.cross(omega, ndot)
    # mu omega' + R n x N = 0
    A[3:, :3] = mu * np.eye(3)
    A[3:, 3:] = R * hat(n)
    sol = np.linalg.solve(A, b)
    return n, ndot, v, sol[:3]


def to_gamma_M(n, omega, mu, d):
    return n, mu * omega + d * np.cross(n, np.cross(omega, n))


def test_field_matches_an_independent_newton_euler_model_at_random_states(system):
    p = DEFAULT
    d = p["m"] * p["R"] ** 2
    f = OriginalFieldSystem(system)
    rng = np.random.default_rng(5)
    for _ in range(20):
        x, y = rng.uniform(-0.8, 0.8, 2)
        omega = rng.normal(size=3)
        n, ndot, v, omegadot = newton_euler(x, y, omega, p["mu"], p["m"], p["R"], p["c"], p["G"])
        gam, M = to_gamma_M(n, omega, p["mu"], d)
        # M' = mu omega' + d d/dt [n x (omega x n)]
        Mdot = p["mu"] * omegadot + d * (np.cross(ndot, np.cross(omega, n))
                                        + np.cross(n, np.cross(omegadot, n))
                                        + np.cross(n, np.cross(omega, ndot)))
        X = f.rhs(0.0, np.concatenate([gam, M]))
        assert np.allclose(X[:3], ndot, atol=1e-12, rtol=1e-12)
        assert np.allclose(X[3:], Mdot, atol=1e-11, rtol=1e-11)
        # the energy is the mechanical one: mu|omega|^2/2 + m|v|^2/2 + G z
        E = 0.5 * p["mu"] * omega @ omega + 0.5 * p["m"] * v @ v + p["G"] * p["c"] * (x**2 + y**2)
        assert f.energy(np.concatenate([gam, M]))[0] == pytest.approx(E, rel=1e-13)


def test_trajectory_agrees_with_the_newton_euler_integration(system):
    p = DEFAULT
    d = p["m"] * p["R"] ** 2

    def ne_rhs(t, s):
        x, y, omega = s[0], s[1], s[2:]
        _, _, v, omegadot = newton_euler(x, y, omega, p["mu"], p["m"], p["R"], p["c"], p["G"])
        return np.concatenate([v[:2], omegadot])

    s0 = np.array([0.6, -0.2, 0.3, 1.1, -0.7])
    ne = solve_ivp(ne_rhs, (0, 3.0), s0, method="DOP853", rtol=1e-11, atol=1e-11,
                   dense_output=True)
    n0, _, _, _ = newton_euler(*s0[:2], s0[2:], p["mu"], p["m"], p["R"], p["c"], p["G"])
    y0 = np.concatenate(to_gamma_M(n0, s0[2:], p["mu"], d))
    f = OriginalFieldSystem(system)
    ours, _ = solve_direct(system, y0, 3.0, tol=1e-11, backend="python", compiled=f)
    sN = ne.sol(3.0)
    nN, _, _, _ = newton_euler(*sN[:2], sN[2:], p["mu"], p["m"], p["R"], p["c"], p["G"])
    assert np.allclose(ours.y[-1], np.concatenate(to_gamma_M(nN, sN[2:], p["mu"], d)), atol=1e-7)
    # and the centre follows the same path
    assert np.allclose(f.centre(ours.y[-1], p["c"])[0, :2], sN[:2], atol=1e-7)


# ------------------------------------------------------------------ exact symbolic claims
def test_energy_casimir_and_linear_integrals_are_exact_first_integrals(system, field):
    for name, F in [("C", system.casimirs["C=(gamma,gamma)"]), *system.integrals.items()]:
        res = is_first_integral(field, F, coords=system.coords)
        assert res.holds, (name, res.failures[:1])
    # not vacuous: M3 alone, or gamma3^nu (S + gamma3 M3) without the nu/(1-nu) term, is not
    g1, g2, g3, M1, M2, M3 = system.coords
    assert not is_first_integral(field, M3, coords=system.coords).holds
    wrong = sp.sqrt(g3) * (g1 * M1 + g2 * M2 + g3 * M3)
    assert not is_first_integral(field, wrong, coords=system.coords).holds


def test_121_solves_108_as_printed_for_the_paraboloid_for_every_kappa():
    """(108): v1' = f'(v1(mu + g^2 d) - g v2 d)/(f (mu + d)),
    v2' = v1 - f'(1 - g^2)(v1(mu + g^2 d) - g v2 d)/(g f (mu + d)), f = -1/(2 c g)."""
    g, nu, c = sp.symbols("g nu c", positive=True)
    mu = nu**2  # scale: mu + d = 1, kappa = mu = nu^2
    d = 1 - mu
    f = -1 / (2 * c * g)
    fp = sp.diff(f, g)
    co = integral_coefficients(nu**2, g)
    for k in ("1", "2"):
        v1, v2 = co["v1_" + k].subs(sp.sqrt(nu**2), nu), co["v2_" + k].subs(sp.sqrt(nu**2), nu)
        common = v1 * (mu + g**2 * d) - g * v2 * d
        r1 = sp.diff(v1, g) - fp * common / (f * (mu + d))
        r2 = sp.diff(v2, g) - (v1 - fp * (1 - g**2) * common / (g * f * (mu + d)))
        assert sp.simplify(r1) == 0 and sp.simplify(r2) == 0
        # the other reading of the OCR, "v2' = gamma3 v1 - ...", is not solved by (121)
        r2_alt = sp.diff(v2, g) - (g * v1 - fp * (1 - g**2) * common / (g * f * (mu + d)))
        assert sp.simplify(r2_alt) != 0


def test_linear_integrals_for_symbolic_parameters_on_the_sphere():
    """X(J1) = gamma3^nu (nu gamma3'/gamma3 L1 + X(L1)): with mu, m, R, c symbolic, nu^2 = kappa."""
    mu, m, R, c = sp.symbols("mu m R c", positive=True)
    nu = sp.Symbol("nu", positive=True)
    p = paraboloid_parts(mu=mu, m=m, R=R, c=c, G=sp.Symbol("G"))
    coords = p["gamma"] + p["M"]
    X = p["field"]
    g3 = p["gamma"][2]
    J1 = p["J1"].subs(p["nu"], nu)
    L1 = sp.expand(J1 / g3**nu)
    expr = nu * X[2] / g3 * L1 + sum(x * sp.diff(L1, y) for x, y in zip(X, coords))
    num = sp.numer(sp.together(expr))
    # reduce modulo nu^2 = mu/(mu + d)
    rem = sp.rem(sp.Poly(sp.expand(num), nu), sp.Poly((mu + m * R**2) * nu**2 - mu, nu))
    assert sp.expand(rem.as_expr()) == 0


def test_remark_14_J1_J2_is_algebraic_and_quadratic_in_M(system):
    p = paraboloid_parts()
    M = p["M"]
    assert sp.simplify(p["J1"] * p["J2"] - p["H2"]) == 0
    poly = sp.Poly(sp.expand(p["H2"] * p["gamma"][2] ** 2), *M)
    assert poly.is_homogeneous and poly.total_degree() == 2
    assert p["nu"] == sp.Rational(1, 2)  # defaults: kappa = 1/4


def test_invariant_measure_is_gamma3_to_minus_four_and_matches_106(system, field):
    g3 = system.coords[2]
    assert is_invariant_measure(field, g3**-4, coords=system.coords).holds
    for k in (-3, -5, 0):
        assert not is_invariant_measure(field, g3**k, coords=system.coords).holds
    # (106) as reconstructed: rho = f (f - (1 - gamma3^2) f'/gamma3) with f = -1/(2 c gamma3)
    c = system.params["c"]
    f = -1 / (2 * c * g3)
    rho106 = f * (f - (1 - g3**2) * sp.diff(f, g3) / g3)
    assert sp.simplify(rho106 * g3**4) == 1 / (4 * c**2)


def test_field_is_so2_invariant_and_equals_P_dH_for_the_euler_bivector(system, field):
    from poissonkit.structure.checks import check_vanishing

    coords = system.coords
    XS = symmetry_field(coords[:3], coords[3:])
    X = [field[x] for x in coords]
    lie = [sum(XS[j] * sp.diff(X[i], coords[j]) - X[j] * sp.diff(XS[i], coords[j])
               for j in range(6)) for i in range(6)]
    assert check_vanishing(lie, coords=coords, method="random", seed=2).holds
    # [X, gamma1 d/dgamma1] is not zero: the check can fail
    dil = [sp.diff(X[i], coords[0]) * coords[0] - (X[0] if i == 0 else 0) for i in range(6)]
    assert not check_vanishing(dil, coords=coords, method="random", seed=2).holds
    Y = system.structure.matrix * sp.Matrix([sp.diff(system.hamiltonian, x) for x in coords])
    assert check_vanishing([Y[i] - X[i] for i in range(6)], coords=coords, method="random",
                           seed=2).holds


@pytest.mark.slow
def test_euler_bivector_reproduces_the_field_exactly(system):
    from poissonkit.structure.checks import is_conformally_hamiltonian

    assert is_conformally_hamiltonian(system.original, system.structure, system.hamiltonian,
                                      system.multiplier).holds


@pytest.mark.slow
def test_euler_bivector_fails_jacobi_with_gravity(system):
    res = check_jacobi(system.structure, method="random", trials=1, seed=3)
    assert not res.is_poisson


@pytest.mark.slow
def test_euler_bivector_is_poisson_without_gravity():
    s = ball_on_paraboloid(G=0)
    assert check_jacobi(s.structure, method="random", trials=3, seed=3).is_poisson


def test_bad_parameters_are_typed_errors():
    with pytest.raises(InputError, match="does not fit"):
        ball_on_paraboloid(R=1, c=1)
    with pytest.raises(InputError):
        ball_on_paraboloid(mu=-1)
    with pytest.raises(InputError):
        ball_on_paraboloid(c=0)


def test_irrational_nu_keeps_H2_and_drops_transcendental_integrals_by_default():
    s = ball_on_paraboloid(mu=sp.Rational(2, 5), m=1, R=1, c=sp.Rational(1, 4), G=10)
    assert set(s.integrals) == {"H", "H2=J1 J2 (Remark 14)"}
    s2 = ball_on_paraboloid(mu=sp.Rational(2, 5), m=1, R=1, c=sp.Rational(1, 4), G=10,
                            linear_integrals=True)
    assert "J1 (107),(121)" in s2.integrals


# ------------------------------------------------------------------ numerics
def test_midpoint_keeps_invariants_and_agrees_with_dop853(system):
    y0 = np.array([0.3, -0.2, np.sqrt(1 - 0.13), 0.4, 0.9, -0.3])
    ci = ConformalIntegrator(system, y0, backend="python")
    assert ci.sigma == 1
    sol = ci.solve(y0, 3.0, 0.01)
    dr = sol.invariant_drift()
    assert dr["C=(gamma,gamma)"] < 1e-12
    assert dr["H"] < 1e-3 and dr["J1 (107),(121)"] < 1e-3 and dr["J2 (107),(121)"] < 1e-3
    ref, _ = solve_direct(system, y0, 3.0, tol=1e-12, backend="python", compiled=ci.compiled)
    assert np.max(np.abs(sol.y_final - ref.y[-1])) < 1e-3
    assert max(invariant_drift(ci.compiled, ref.y).values()) < 1e-8
    # second order: halving the step divides the error by ~4
    sol2 = ci.solve(y0, 3.0, 0.005)
    e1 = np.max(np.abs(sol.y_final - ref.y[-1]))
    e2 = np.max(np.abs(sol2.y_final - ref.y[-1]))
    assert 3.0 < e1 / e2 < 5.0


def test_near_the_bottom_gamma3_to_one(system):
    """gamma = e3 is the bottom of the bowl (stable equilibrium) where the survey's bracket (110)
    is singular; the field here is regular and the invariants hold."""
    for eps in (1e-7, 0.0):
        y0 = np.array([eps, 0.0, np.sqrt(1 - eps**2), 0.2, -0.1, 0.5])
        f = OriginalFieldSystem(system)
        ref, _ = solve_direct(system, y0, 2.0, tol=1e-12, backend="python", compiled=f)
        assert max(invariant_drift(f, ref.y).values()) < 1e-9
        assert np.min(ref.y[:, 2]) > 0.99  # stays near the bottom
        run = midpoint_python(f, y0, 2.0, 0.01)
        dr = invariant_drift(f, run.y)
        assert dr["C=(gamma,gamma)"] < 1e-13 and dr["H"] < 1e-4


def test_ball_released_at_rest_oscillates_below_its_initial_height(system):
    p = DEFAULT
    f = OriginalFieldSystem(system)
    x0 = 0.3
    g = np.array([-2 * p["c"] * x0, 0.0, 1.0]) / np.sqrt(1 + 4 * p["c"] ** 2 * x0**2)
    y0 = np.concatenate([g, np.zeros(3)])  # at rest: M = 0, where P = X ^ Z / Z(H) is singular
    ref, _ = solve_direct(system, y0, 6.0, tol=1e-11, backend="python", compiled=f)
    r = f.centre(ref.y, p["c"])
    z0 = r[0, 2]
    assert np.max(r[:, 2]) <= z0 + 1e-9  # T >= 0: never above the release height
    assert np.min(r[:, 0]) < -0.25 and np.max(np.abs(r[:, 1])) < 1e-9  # swings across, planar
    # J1 = J2 = 0 at rest and stay so
    assert max(invariant_drift(f, ref.y).values()) < 1e-9


def test_small_oscillation_period_is_that_of_a_rolling_ball_in_a_bowl(system):
    """Centre on a curve of radius rho0 = 1/(2c) at the bottom, rolling v = R omega:
    omega0^2 = (G / rho0) / (m + mu/R^2)."""
    p = DEFAULT
    f = OriginalFieldSystem(system)
    x0 = 1e-3
    g = np.array([-2 * p["c"] * x0, 0.0, 1.0]) / np.sqrt(1 + 4 * p["c"] ** 2 * x0**2)
    y0 = np.concatenate([g, np.zeros(3)])
    w0 = np.sqrt(2 * p["c"] * p["G"] / (p["m"] + p["mu"] / p["R"] ** 2))
    T = 2 * np.pi / w0
    ref, _ = solve_direct(system, y0, 1.25 * T, tol=1e-12, backend="python", compiled=f)
    x = f.centre(ref.y, p["c"])[:, 0]
    t = ref.t
    # first upward zero crossing of x after the start: x(t) = x0 cos(w0 t) crosses at 3T/4
    k = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0][0]
    tc = t[k] - x[k] * (t[k + 1] - t[k]) / (x[k + 1] - x[k])
    assert tc == pytest.approx(0.75 * T, rel=2e-3)


# ------------------------------------------------------------------ rank-4 bracket, Prop. 7
@pytest.mark.slow
def test_rank4_bivector_is_poisson_with_casimirs_C_J1_and_proposition7_holds():
    from poissonkit_nonholonomic.paraboloid import (
        ball_on_paraboloid_rank4,
        proposition7,
    )

    from poissonkit.structure.casimirs import is_casimir

    s = ball_on_paraboloid_rank4()
    assert check_jacobi(s.structure, method="random", seed=1).is_poisson
    for C in s.casimirs.values():
        assert is_casimir(s.structure, C).holds
    ok, detail, _ = proposition7(s)
    assert ok, detail
    # non-vacuous: with the wrong multiplier N the decomposition fails
    from dataclasses import replace

    ok_wrong, _, _ = proposition7(replace(s, multiplier=-s.multiplier))
    assert not ok_wrong


def test_rank4_needs_nu_one_half():
    from poissonkit_nonholonomic.paraboloid import ball_on_paraboloid_rank4

    with pytest.raises(InputError, match="nu = 1/2"):
        ball_on_paraboloid_rank4(mu=sp.Rational(2, 5), m=1, R=1, c=sp.Rational(1, 4))


@pytest.mark.slow
def test_registered_entry_verifies_everything_but_jacobi():
    from poissonkit_nonholonomic.verify import verify_system

    from poissonkit.plugin import system as registry_system

    entry = registry_system("nh.ball_on_paraboloid")
    built = entry.build(**entry.resolve_params({}))
    assert built.params["mu"] == sp.Rational(1, 4)  # floats from the registry become exact
    report = verify_system(built)
    failed = [c["claim"] for c in report["checks"] if not c["ok"]]
    assert failed == ["Jacobi identity [P,P] = 0"]
    assert not any(c["on_constraint_set"] for c in report["checks"])  # identically on R^6
