"""compile_system (any symbolic system) and the implicit midpoint rule."""

from __future__ import annotations

from fractions import Fraction as Fr

import numpy as np
import pytest
import sympy as sp
from numerics_helpers import ORACLE_STATE, orbit_state  # type: ignore[import-not-found]

from poissonkit.errors import InputError
from poissonkit.numerics import compile_system, solve
from poissonkit.structure import HamiltonianSystem, e3


def _heavy_top(multiplier=1):
    P = e3("gamma_M")
    g1, g2, g3, L1, L2, L3 = P.coords
    a = sp.Symbol("a", positive=True)
    H = (L1**2 / 2 + L2**2 / 3 + L3**2 / 4) / 2 + a * g3
    return HamiltonianSystem(
        P, H, multiplier=multiplier, params={"a": 1.0},
        casimirs={"gamma2": g1**2 + g2**2 + g3**2, "area": g1 * L1 + g2 * L2 + g3 * L3},
        name="heavy top")


def test_compiled_field_matches_formulas_e3_oracle():
    # FORMULAS.md §2: at gamma = (2/3, 1/3, 2/3), L = (1, -2, 1/2), A = diag(1/2, 1/3, 1/4),
    # H = (L, A L)/2 + gamma_3:  P0 dH = (-35/72, -1/4, 11/18, -5/12, 13/24, -1/3)
    cs = compile_system(_heavy_top())
    x = np.array([2 / 3, 1 / 3, 2 / 3, 1, -2, 1 / 2])
    expected = [Fr(-35, 72), Fr(-1, 4), Fr(11, 18), Fr(-5, 12), Fr(13, 24), Fr(-1, 3)]
    assert np.max(np.abs(cs.rhs(0, x) - np.array([float(v) for v in expected]))) <= 1e-15
    assert cs.layout == ("gamma_x", "gamma_y", "gamma_z", "M_x", "M_y", "M_z")
    assert "y[0]" in cs.source  # generated code documents the state order


def test_jacobian_matches_finite_differences():
    cs = compile_system(_heavy_top(multiplier=1 / (1 + sp.Symbol("gamma_z", real=True) ** 2 / 4)))
    x = np.array([0.3, -0.4, 0.5, 1.0, 0.2, -0.7])
    J = cs.jacobian(0, x)
    eps = 1e-6
    fd = np.column_stack([(cs.rhs(0, x + eps * e) - cs.rhs(0, x - eps * e)) / (2 * eps)
                          for e in np.eye(6)])
    assert np.allclose(J, fd, rtol=1e-7, atol=1e-8)


def test_missing_parameter_is_a_typed_error():
    hs = _heavy_top()
    with pytest.raises(InputError, match="a"):
        compile_system(HamiltonianSystem(hs.structure, hs.hamiltonian))


@pytest.mark.parametrize("newton", [True, False])
def test_midpoint_keeps_quadratic_casimirs_of_a_conformal_system(newton):
    # conformally Hamiltonian (multiplier N != 1): Casimirs of P are still invariants
    g3 = sp.Symbol("gamma_z", real=True)
    cs = compile_system(_heavy_top(multiplier=1 / (1 + g3**2 / 4)))
    x0 = np.array([0.6, 0.0, 0.8, 1.0, -0.5, 0.3])
    sol = solve(cs, x0, 20.0, "midpoint", step=0.25, options={"newton": newton})
    c = cs.casimirs(sol.y)
    assert np.max(np.abs(c - c[0])) <= 1e-13
    assert np.max(sol.energy_error()) < 1e-2


def test_midpoint_is_second_order():
    cs = compile_system(_heavy_top())
    x0 = np.array([0.6, 0.0, 0.8, 1.0, -0.5, 0.3])
    ref = solve(cs, x0, 2.0, "dop853", tol=1e-13, options={"atol": 1e-14}).y[-1]
    errs = [np.max(np.abs(solve(cs, x0, 2.0, "midpoint", step=h).y[-1] - ref))
            for h in (0.02, 0.01)]
    assert 1.8 <= np.log2(errs[0] / errs[1]) <= 2.3


def test_midpoint_on_the_two_body_system_keeps_casimirs_and_j(dipole_pair):
    sol = solve(dipole_pair, orbit_state(), 3.0, "midpoint", step=0.01)
    assert np.max(sol.casimir_drift()) <= 1e-12
    assert np.max(sol.angular_momentum_drift()) <= 1e-12


@pytest.mark.parametrize("method", ["rk45", "dop853", "radau", "lsoda"])
def test_scipy_adapters_reach_their_tolerance(dipole_pair, method):
    y0 = orbit_state()
    # independent reference: order-8 splitting at a small step
    ref = solve(dipole_pair, y0, 2.0, "splitting8", step=0.01).y[-1]
    sol = solve(dipole_pair, y0, 2.0, method, tol=1e-9)
    assert np.max(np.abs(sol.y[-1] - ref)) < 1e-6
    assert sol.nfev > 0 and sol.summary()["method"] == method


def test_compiled_two_body_field_is_the_oracle_through_compile_system():
    # the symbolic two-body system compiled generically gives the same field as the
    # hand-written two-body kernel (both checked against FORMULAS §1 elsewhere)
    from poissonkit.structure import canonical, direct_sum

    P = direct_sum(("orbit", canonical(3)), ("top1", e3()), ("top2", e3()))
    x = P.coords
    r = sp.Matrix(x[0:3])
    p = sp.Matrix(x[3:6])
    n1, m1, n2, m2 = (sp.Matrix(x[k:k + 3]) for k in (6, 9, 12, 15))
    rn = sp.sqrt(r.dot(r))
    H = p.dot(p) / 4 + sp.Rational(3, 2) * m1.dot(m1) + sp.Rational(5, 2) * m2.dot(m2) \
        + (n1.dot(n2) - 3 * r.dot(n1) * r.dot(n2) / rn**2) / rn**3
    cs = compile_system(HamiltonianSystem(P, H))
    X = cs.rhs(0, ORACLE_STATE)
    assert X[0] == pytest.approx(0.25) and X[12] == pytest.approx(-8.0)
    assert X[3] == pytest.approx(-56 / 3645, rel=1e-14)
