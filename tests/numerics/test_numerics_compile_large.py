"""Code generation for large fields: the Routh sphere on the compiled path.

Truth: FORMULAS.md §11 (Routh sphere oracle), FORMULAS.md §2 (e(3) oracle), exact rational
arithmetic in sympy, mpmath (30 digits) evaluation of the symbolic field, and a high-accuracy
scipy solve of the lambdified field.
"""

from __future__ import annotations

import time
from dataclasses import replace
from fractions import Fraction as Fr

import mpmath
import numpy as np
import pytest
import sympy as sp
from poissonkit_nonholonomic.ball import chaplygin_ball
from poissonkit_nonholonomic.routh import routh_parts, routh_sphere
from scipy.integrate import solve_ivp

from poissonkit.errors import InputError
from poissonkit.numerics import codegen
from poissonkit.numerics.codegen import (
    array_source,
    compile_source,
    is_large,
    jacobian_source,
)
from poissonkit.numerics.conformal import (
    ConformalIntegrator,
    LambdifiedSystem,
    solve_direct,
)
from poissonkit.numerics.system import compile_system
from poissonkit.structure import HamiltonianSystem, e3

# FORMULAS.md §11: R = 2, a = 1/2, m = 3, I1 = 5, I3 = 7, U = 10 gamma3 (routh_sphere defaults)
ROUTH_POINT = np.array([2 / 3, 1 / 3, 2 / 3, 1.0, -2.0, 0.5])
ROUTH_X = [Fr(61435, 870174), Fr(5245, 435087), Fr(-20, 261), Fr(40975358, 12617523),
           Fr(-168233597, 25235046), Fr(7760, 145029)]
Y0 = np.array([0.3, 0.0, np.sqrt(0.91), 0.3, -0.2, 1.0])


@pytest.fixture(scope="module")
def routh():
    hs = routh_sphere()
    return hs, compile_system(hs, field="original")


def _field_mpmath():
    """The Routh field of ``routh_parts`` (no CSE, no codegen), evaluated by mpmath."""
    p = routh_parts()
    coords = list(p["gamma"]) + list(p["M"])
    return sp.lambdify([coords], p["field"], modules="mpmath")


def _random_states(count, seed):
    rng = np.random.default_rng(seed)
    ys = Y0 + rng.normal(scale=0.7, size=(count, 6))
    ys[:, :3] /= np.linalg.norm(ys[:, :3], axis=1)[:, None]
    return ys


# ------------------------------------------------------------------ the Routh sphere compiled
def test_compiled_routh_field_is_the_formulas_oracle(routh):
    _, cs = routh
    expected = np.array([float(v) for v in ROUTH_X])
    got = cs.rhs(0.0, ROUTH_POINT)
    assert np.max(np.abs(got - expected)) <= 1e-14 * np.max(np.abs(expected))


def test_compiled_routh_rhs_matches_the_lambdified_field_at_random_states(routh):
    hs, cs = routh
    f = _field_mpmath()
    L = LambdifiedSystem(hs)  # the python backend: N P dH through the bivector
    for y in _random_states(25, seed=5):
        with mpmath.workdps(30):
            exact = np.array([float(v) for v in f([mpmath.mpf(float(v)) for v in y])])
        scale = np.max(np.abs(exact))
        assert np.max(np.abs(cs.rhs(0.0, y) - exact)) <= 1e-13 * scale
        assert np.max(np.abs(L.rhs(0.0, y) - exact)) <= 1e-12 * scale


def test_compiled_routh_jacobian_matches_mpmath_derivatives(routh):
    _, cs = routh
    f = _field_mpmath()
    for y in _random_states(3, seed=7):
        J = cs.jacobian(0.0, y)
        with mpmath.workdps(45):  # central differences, step 1e-12: error ~1e-24
            h = mpmath.mpf("1e-12")
            for j in range(6):
                up = [mpmath.mpf(float(v)) for v in y]
                down = list(up)
                up[j] += h
                down[j] -= h
                exact = [float((a - b) / (2 * h)) for a, b in zip(f(up), f(down))]
                assert np.allclose(J[:, j], exact, rtol=1e-12, atol=1e-12 * np.max(np.abs(J)))


def test_routh_code_generation_takes_seconds_not_minutes():
    # before: CSE with sympy's pre-optimisation took ~25 s for the right-hand side of P dH and
    # the tree-differentiated Jacobian did not finish in 20 minutes (docs/performance.md)
    hs = routh_sphere()
    start = time.perf_counter()
    cs = compile_system(hs, field="original")
    jacobian_source("jac_gen", cs._coords, cs._field())
    assert time.perf_counter() - start < 30.0


def test_compiled_routh_short_runs_keep_the_integrals(routh):
    hs, cs = routh
    names = cs.integral_names
    # tau-midpoint (N = 1: tau = t): quadratic invariants (gamma, gamma) and the Jellett
    # integral (M, r) are kept to round-off, H and the Routh integral to O(h^2)
    ci = ConformalIntegrator(hs, Y0, field="original")
    sol = ci.solve(Y0, t_end=2.0, step=0.01)
    drift = sol.invariant_drift()
    assert drift["C=(gamma,gamma)"] <= 1e-13
    assert drift[next(n for n in names if "Jellett" in n)] <= 1e-12
    assert drift["H"] <= 1e-4 and drift[next(n for n in names if "Routh" in n)] <= 1e-4
    # DOP853 on the compiled RHS against scipy's DOP853 on the lambdified field
    run = solve_direct(hs, Y0, 2.0, method="dop853", tol=1e-12, compiled=cs)
    f = sp.lambdify([list(hs.coords)], [hs.original[c] for c in hs.coords], modules="math")
    ref = solve_ivp(lambda t, y: f(y), (0.0, 2.0), Y0, method="DOP853", rtol=1e-13, atol=1e-13)
    assert np.max(np.abs(run.y[-1] - ref.y[:, -1])) <= 1e-9
    inv = cs.integrals(run.y)
    assert np.max(np.abs(inv - inv[0])) <= 1e-9
    assert np.allclose(ci.compiled.rhs(0.0, Y0), cs.rhs(0.0, Y0), rtol=1e-15, atol=0)


@pytest.mark.slow
def test_compiled_routh_from_the_bivector_matches_the_oracle():
    # P dH itself (~10^5 tree nodes) through the large-expression path, Jacobian included
    cs = compile_system(routh_sphere())
    expected = np.array([float(v) for v in ROUTH_X])
    assert np.max(np.abs(cs.rhs(0.0, ROUTH_POINT) - expected)) <= 1e-13 * np.max(np.abs(expected))
    ref = compile_system(routh_sphere(), field="original")
    for y in _random_states(5, seed=9):
        assert np.allclose(cs.jacobian(0.0, y), ref.jacobian(0.0, y), rtol=1e-11, atol=1e-11)


# ----------------------------------------------------------------------- choosing the field
def test_original_field_must_exist_and_agree_with_the_bivector():
    hs = routh_sphere()
    g1 = hs.coords[0]
    wrong = dict(hs.original)
    wrong[g1] = wrong[g1] + sp.Rational(1, 1000) * g1
    with pytest.raises(InputError, match="differ"):
        compile_system(replace(hs, original=wrong, name="wrong routh"), field="original")
    with pytest.raises(InputError, match="no original"):
        compile_system(replace(hs, original=None, name="routh without X"), field="original")
    with pytest.raises(InputError, match="field"):
        compile_system(hs, field="expanded")
    with pytest.raises(InputError, match="backend"):
        ConformalIntegrator(hs, Y0, backend="python", field="original")


def test_only_large_fields_take_the_large_path():
    # the other systems keep their code generation unchanged
    for hs in (chaplygin_ball(1, 2, 3, 1), _heavy_top()):
        P, H, N = hs.structure.matrix, hs.hamiltonian, hs.multiplier
        X = [N * sum(P[i, j] * sp.diff(H, x) for j, x in enumerate(hs.coords))
             for i in range(len(hs.coords))]
        assert not is_large(X)
    hs = routh_sphere()
    P, H = hs.structure.matrix, hs.hamiltonian
    X = [sum(P[i, j] * sp.diff(H, x) for j, x in enumerate(hs.coords)) for i in range(6)]
    assert is_large(X)


# ------------------------------------------------- the large code path on small known systems
def _heavy_top(a=1.0, name="heavy top"):
    P = e3("gamma_M")
    g1, g2, g3, L1, L2, L3 = P.coords
    A = sp.Symbol("a", positive=True)
    H = (L1**2 / 2 + L2**2 / 3 + L3**2 / 4) / 2 + A * g3
    return HamiltonianSystem(P, H, params={"a": a}, name=name,
                             casimirs={"gamma2": g1**2 + g2**2 + g3**2})


def test_large_path_reproduces_the_e3_oracle(monkeypatch):
    # FORMULAS.md §2: H = (L, A L)/2 + gamma_3, A = diag(1/2, 1/3, 1/4) at
    # gamma = (2/3, 1/3, 2/3), L = (1, -2, 1/2): P0 dH = (-35/72, -1/4, 11/18, -5/12, 13/24, -1/3)
    monkeypatch.setattr(codegen, "LARGE_TREE", 0)
    cs = compile_system(_heavy_top(name="heavy top, large path"))
    assert cs._large
    x = np.array([2 / 3, 1 / 3, 2 / 3, 1, -2, 1 / 2])
    expected = [Fr(-35, 72), Fr(-1, 4), Fr(11, 18), Fr(-5, 12), Fr(13, 24), Fr(-1, 3)]
    assert np.max(np.abs(cs.rhs(0, x) - np.array([float(v) for v in expected]))) <= 1e-15


def test_large_path_code_is_exact_on_dyadic_data():
    # Euler-Poisson field with dyadic coefficients at dyadic states: every floating-point
    # operation is exact, so the generated program (CSE'd, and its forward-mode Jacobian)
    # must equal sympy's exact rational values bit for bit
    P = e3("gamma_M")
    g1, g2, g3, L1, L2, L3 = P.coords
    H = L1**2 / 2 + L2**2 / 4 + L3**2 / 8 + (g1 * L1 + g3) / 2 + g2**2 * g3 / 4
    coords = P.coords
    X = [sum(P.matrix[i, j] * sp.diff(H, x) for j, x in enumerate(coords)) for i in range(6)]
    rhs = compile_source(array_source("f", coords, X, (6,), large=True), "f")
    jac = compile_source(jacobian_source("j", coords, X, large=True), "j")
    rng = np.random.default_rng(3)
    for _ in range(5):
        y = rng.integers(-16, 17, size=6) / 8.0
        point = {c: sp.Rational(int(v * 8), 8) for c, v in zip(coords, y)}
        exact_f = [float(e.xreplace(point)) for e in X]
        exact_j = [[float(sp.diff(e, c).xreplace(point)) for c in coords] for e in X]
        assert rhs(y, np.empty(6)).tolist() == exact_f
        assert jac(y, np.empty((6, 6))).tolist() == exact_j
