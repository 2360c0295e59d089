"""The random-point method of the field checks (``method="random"``, exact arithmetic with exact
square roots at seeded random rational points): agreement with the exact method, genuine
counterexamples, the sphere constraint, reproducibility and typed errors.

Independent truth: the exact symbolic method of the same checks, the oracle values of
FORMULAS.md §7 (Chaplygin ball) and §9 (Veselova, Prop. 4), and mpmath evaluation at 50 digits
of the counterexamples reported."""

from __future__ import annotations

import mpmath
import pytest
import sympy as sp

from poissonkit.errors import InputError, ParseError
from poissonkit.structure import HamiltonianSystem, e3
from poissonkit.structure.checks import (
    check_vanishing,
    in_involution,
    is_conformally_hamiltonian,
    is_first_integral,
    is_invariant_measure,
)
from poissonkit.structure.deformed import chaplygin_ball, chaplygin_ball_system
from poissonkit.structure.randompoints import (
    RandomPointError,
    RandomPoints,
    sphere_parametrization,
)

R = sp.Rational
x, y, z = sp.symbols("x y z", real=True)
SPHERE = x**2 + y**2 + z**2 - 1


def _dot(a, b):
    return sum(p * q for p, q in zip(a, b))


def _heavy_top():
    P = e3()
    nu, m = P.coords[:3], P.coords[3:]
    H = _dot(m, m) / 2 + nu[2]
    return P, nu, m, HamiltonianSystem(P, H)


def _at(expr, point):
    """mpmath value (50 digits) of ``expr`` at a reported point: independent of the evaluator."""
    with mpmath.workdps(50):
        return mpmath.mpf(sp.N(expr.xreplace(point), 50))


# ---------------------------------------------------------------------- agreement with exact
def test_heavy_top_integrals_agree_with_exact_and_failures_are_real_points():
    _, nu, m, S = _heavy_top()
    candidates = {"(nu,m)": _dot(nu, m), "(nu,nu)": _dot(nu, nu), "m_z": m[2],
                  "m_x": m[0], "nu_x m_y": nu[0] * m[1]}
    for name, F in candidates.items():
        exact = is_first_integral(S, F)
        rand = is_first_integral(S, F, method="random", seed=5)
        assert rand.holds == exact.holds, name
        assert rand.method == "random" and exact.method == "exact"
        if rand.holds:
            assert 0 < rand.false_positive_bound < 1e-9 and rand.point is None
        else:
            # the reported value is X(F) at the reported point, recomputed symbolically
            (label, value), = rand.failures
            residual = exact.failures[0][1]
            assert label == "X(F)" and value != 0
            assert sp.nsimplify(residual.xreplace(rand.point)) == value
            assert rand.false_positive_bound == 0.0


def test_involution_and_conformal_form_agree_with_exact():
    P, nu, m, S = _heavy_top()
    H = S.hamiltonian
    good = [H, _dot(nu, m), m[2], _dot(nu, nu)]
    assert in_involution(P, good) and in_involution(P, good, method="random", seed=2)
    bad = in_involution(P, {"H": H, "m_x": m[0]}, method="random", seed=2)
    assert not bad and not in_involution(P, {"H": H, "m_x": m[0]})
    assert bad.failures[0][0] == "{H, m_x}"
    # Euler-Poisson equations by hand: xdot = {x, H}, {m_i, nu_j} = eps_ijk nu_k
    X = P.hamiltonian_vector_field(H)
    ok = is_conformally_hamiltonian(dict(zip(P.coords, X)), P, H, method="random", seed=3)
    wrong = is_conformally_hamiltonian(dict(zip(P.coords, -X)), P, H, method="random", seed=3)
    assert ok and not wrong
    assert not is_conformally_hamiltonian(dict(zip(P.coords, -X)), P, H)
    assert {lab for lab, _ in wrong.failures} == {f"{c}dot" for c, e in zip(P.coords, X) if e != 0}


def test_chaplygin_ball_with_square_root_agrees_with_exact():
    """FORMULAS.md §7: X(H_i) = 0, div(g^{-1} X) = 0, X = -g^{-1} P_g dH, all with
    g = sqrt(1 - d (gamma, A gamma)); a wrong density (g, 1) and a wrong sign fail."""
    S = chaplygin_ball_system(I=(1, 2, 3), d=1)
    gam, M = S.coords[:3], S.coords[3:]
    g = 1 / S.measure
    for F in [*S.integrals.values(), _dot(gam, gam), _dot(gam, M)]:
        assert is_first_integral(S, F, method="random", seed=11)
    assert not is_first_integral(S, M[0], method="random", seed=11)
    assert is_invariant_measure(S, method="random", seed=11)
    X = S.vector_field()
    for rho in (g, sp.Integer(1)):
        exact = is_invariant_measure(S, rho)
        rand = is_invariant_measure(S, rho, method="random", seed=11)
        assert not exact and not rand
        # a genuine counterexample: div(rho X) (sympy derivatives) at the point, by mpmath
        div = sum(sp.diff(rho * X[i], S.coords[i]) for i in range(6))
        assert abs(_at(div, rand.point) - _at(rand.failures[0][1], {})) < 1e-30
        assert abs(_at(rand.failures[0][1], {})) > 1e-6
    assert is_conformally_hamiltonian(S, method="random", seed=11)
    flipped = {k: -v for k, v in S.original.items()}
    assert not is_conformally_hamiltonian(flipped, S.structure, S.hamiltonian, S.multiplier,
                                          method="random", seed=11)


def test_random_points_reproduce_the_chaplygin_oracle_values_exactly():
    """FORMULAS.md §7 oracle at gamma = (2/3,1/3,2/3), M = (1,-2,1/2): exact square roots."""
    P = chaplygin_ball(I=(1, 2, 3), d=1)
    c = P.coords
    at = dict(zip(c, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    pts = RandomPoints(c, parametrization=at, seed=0)   # a constant "parametrisation" = a point
    s51 = sp.sqrt(51)
    assert pts.value(P.matrix[0, 4]) == 2 * s51 / 27
    assert pts.value(P.matrix[3, 5]) == 143 * s51 / 612
    S = chaplygin_ball_system(I=(1, 2, 3), d=1)
    X = S.vector_field()
    assert [pts.value(e) for e in X] == [R(49, 102), R(29, 102), R(-127, 204), R(-5, 136),
                                         R(1, 8), R(39, 68)]


# ---------------------------------------------------------------------- square roots
def test_square_roots_are_handled_exactly():
    a = sp.sqrt(x**2 + 1)
    assert check_vanishing([a**2 - x**2 - 1, 1 / a - a / (x**2 + 1),
                            sp.sqrt(2 * x**2 + 2) - sp.sqrt(2) * a,       # dependent radicals
                            sp.sqrt(8) * a - 2 * sp.sqrt(2 * x**2 + 2),
                            1 / (1 + a) - (a - 1) / x**2],                  # inverse of a surd
                           method="random", seed=1)
    res = check_vanishing({"r": a - 1, "s": sp.sqrt(x**2 + 2) - a}, method="random", seed=1)
    assert not res and {lab for lab, _ in res.failures} == {"r", "s"}
    for lab, val in res.failures:
        assert abs(_at(val, {})) > 1e-20
    # a perfect-square radicand: sqrt((x-1/2)^2) = x - 1/2 only for x > 1/2; a counterexample
    # has x < 1/2 (the value there is exact and rational)
    sq = check_vanishing(sp.sqrt(x**2 - x + R(1, 4)) - (x - R(1, 2)), method="random", seed=4,
                         trials=8)
    assert not sq and sq.point[x] < R(1, 2)
    assert sq.failures[0][1] == 1 - 2 * sq.point[x]
    # sympy writes sqrt(x**2) = Abs(x) for real x: evaluated exactly too
    assert not check_vanishing(sp.sqrt(x**2) - x, method="random", seed=4, trials=8)


def test_points_outside_the_domain_are_skipped_and_counted():
    u = R(1, 100) - x**2   # real only for |x| < 1/10
    res = check_vanishing(sp.sqrt(u) * sp.sqrt(u + x**2) - sp.sqrt(u * (u + x**2)),
                          method="random", seed=2)
    assert res and "outside the domain skipped" in res.note
    with pytest.raises(RandomPointError, match="defined"):
        check_vanishing(sp.sqrt(-1 - x**2) - 1, method="random", seed=1)


# ---------------------------------------------------------------------- constraint surfaces
def test_sphere_constraint_parametrised_and_recognised():
    assert not check_vanishing(SPHERE, method="random", seed=1)
    assert check_vanishing(SPHERE, constraints=[SPHERE], method="random", seed=1)
    par = sphere_parametrization(x, y, z)
    res = check_vanishing([x**4 + y**2 * x**2 + z**2 * x**2 - x**2], constraints=[SPHERE],
                          parametrization=par, method="random", seed=1)
    assert res.holds and "constraint surface" in res.note
    with pytest.raises(InputError, match="does not satisfy"):
        check_vanishing(x, constraints=[SPHERE], parametrization={x: 1, y: 1, z: 1},
                        method="random")
    with pytest.raises(InputError, match="parametrization"):
        check_vanishing(x, constraints=[x**3 + y**3 - 1], method="random")
    # a linear constraint is solved for one coordinate
    assert check_vanishing(x * y - y * (1 - z), constraints=[x + z - 1], method="random",
                           seed=3)


def test_prop4_veselova_equals_chaplygin_g_only_on_the_sphere():
    """FORMULAS.md §9, Prop. 4/(68): with a^Ves = 1 - d a^Chap, g_Ves = g_Chap on (gamma,gamma)=1
    (exactly checked there through the same stereographic parametrisation)."""
    aC = [R(1, 2), R(1, 3), R(1, 4)]
    d = 1
    aV = [1 - d * a for a in aC]
    g = (x, y, z)
    gV = sp.sqrt(sum(aV[i] * g[i] ** 2 for i in range(3)))
    gC = sp.sqrt(1 - d * sum(aC[i] * g[i] ** 2 for i in range(3)))
    on = check_vanishing(gV - gC, constraints=[SPHERE], method="random", seed=9)
    off = check_vanishing(gV - gC, method="random", seed=9)
    assert on and not off
    # the exact method proves the squares equal on the sphere (it cannot pick the branch of
    # sqrt: gV + gC is not in the ideal either, so it refutes gV - gC = 0 there)
    assert check_vanishing(gV**2 - gC**2, constraints=[SPHERE])
    assert abs(_at(gV - gC, off.point) - _at(off.failures[0][1], {})) < 1e-30


def test_first_integral_on_the_sphere_only():
    """e(3) with H = (m, m)/2 + nu_z: F = m_x (nu,nu) - m_x is zero on |nu| = 1 only."""
    _, nu, m, S = _heavy_top()
    F = m[0] * (_dot(nu, nu) - 1)
    assert not is_first_integral(S, F, method="random", seed=1)
    on = is_first_integral(S, F, constraints=[_dot(nu, nu) - 1], method="random", seed=1)
    assert on and on.holds == is_first_integral(S, F, constraints=[_dot(nu, nu) - 1]).holds


# ---------------------------------------------------------------------- points, seeds, bounds
def test_seeded_runs_are_reproducible():
    _, nu, m, S = _heavy_top()
    a = is_first_integral(S, m[0], method="random", seed=123)
    b = is_first_integral(S, m[0], method="random", seed=123)
    c = is_first_integral(S, m[0], method="random", seed=124)
    assert a.point == b.point and a.failures == b.failures and a.note == b.note
    assert c.point != a.point
    fresh = is_first_integral(S, _dot(nu, m), method="random")
    seed = int(fresh.note.split("seed ")[1].split(",")[0])
    assert is_first_integral(S, _dot(nu, m), method="random", seed=seed).note == fresh.note


def test_shared_points_object_and_assumptions():
    P, nu, m, S = _heavy_top()
    pts = RandomPoints(P, trials=2, seed=8)
    r1 = is_first_integral(S, _dot(nu, m), method="random", points=pts)
    r2 = in_involution(P, [S.hamiltonian, _dot(nu, m)], method="random", points=pts)
    assert r1 and r2 and r1.trials == r2.trials == 2
    # positive symbols get positive values: sympy simplified sqrt(k**2) to k
    k = sp.Symbol("k", positive=True)
    assert check_vanishing(sp.sqrt(k**2) - k, method="random", seed=1, trials=10)


def test_auto_method_proves_small_inputs_exactly():
    _, nu, m, S = _heavy_top()
    assert is_first_integral(S, _dot(nu, m), method="auto").method == "exact"
    f = sp.Function("f")
    assert check_vanishing(f(x) - f(x), method="auto").method == "exact"


# ---------------------------------------------------------------------- typed errors
def test_bad_input_gives_typed_errors():
    P, nu, m, S = _heavy_top()
    with pytest.raises(InputError, match="unknown method"):
        is_first_integral(S, m[0], method="fast")
    with pytest.raises(InputError, match="trials"):
        is_first_integral(S, m[0], method="random", trials=0)
    with pytest.raises(InputError, match="seed"):
        is_first_integral(S, m[0], method="random", seed="one")
    with pytest.raises(RandomPointError, match="undefined function"):
        check_vanishing(sp.Function("g")(x) - 1, method="random", seed=1)
    with pytest.raises(RandomPointError, match="method='exact'"):
        check_vanishing(sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1, method="random", seed=1)
    with pytest.raises(RandomPointError, match="roots"):
        check_vanishing(x ** R(1, 3), method="random", seed=1)
    with pytest.raises(ParseError):
        check_vanishing("x - x", method="random")
    with pytest.raises(InputError, match="RandomPoints"):
        is_first_integral(S, m[0], method="random", points="pts")
    pts = RandomPoints(P, seed=1)
    with pytest.raises(InputError, match="constraints differ"):
        is_first_integral(S, m[0], constraints=[_dot(nu, nu) - 1], method="random", points=pts)
    with pytest.raises(InputError, match="through itself"):
        RandomPoints((x, y), parametrization={x: y + 1, y: x - 1})
    assert issubclass(RandomPointError, InputError)


# ---------------------------------------------------------------------- plugin claims on the core
def test_plugin_claims_run_on_check_vanishing_and_detect_wrong_equations():
    """The non-holonomic plugin's BMF (55) and Veselova (58)->(62) claims (FORMULAS.md §8, §9)
    go through check_vanishing(method="random"): true as built, false with a counterexample
    point when the claimed equations are perturbed."""
    from dataclasses import replace

    from poissonkit_nonholonomic import ball, claims, veselova

    bmf = ball.chaplygin_ball_sphere_bmf(1, 2, 3, 1)
    ok, detail, method = claims.bmf_decomposition(bmf)
    assert ok and "false-positive bound" in method
    gx = bmf.coords[0]
    bad = replace(bmf, original={**bmf.original, gx: 2 * bmf.original[gx]})
    ok, detail, _ = claims.bmf_decomposition(bad)
    assert not ok and detail.startswith("component gamma_xdot") and " at " in detail
    ves = veselova.veselova()
    assert claims.veselova_pushforward(ves)[0]
    K1 = ves.coords[3]
    bad = replace(ves, original={**ves.original, K1: ves.original[K1] + ves.coords[0]})
    ok, detail, _ = claims.veselova_pushforward(bad)
    assert not ok and "K_xdot" in detail
