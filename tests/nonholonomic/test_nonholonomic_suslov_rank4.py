"""Suslov problem: the rank-4 bivector (126), Proposition 9, and the potential-case parameters.

Truth used here: the equations (123) and the integrals (124)/(125) of FORMULAS.md §12 (typed in
again below, independently of the plugin), the survey's statements after (126) about the
Casimirs of P' and P'' (seed §7.1), the core's randomized Jacobi check (a separate code path from
the exact claim), sympy's linear solve for the coefficients of Prop. 9, and scipy's DOP853.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from poissonkit_nonholonomic.suslov import (
    RANK4_CLAIMS,
    suslov,
    suslov_potential,
    suslov_prop9,
    suslov_rank4,
    suslov_rank4_casimirs,
    suslov_rank4_jacobi,
    suslov_rank4_parts,
)
from scipy.integrate import solve_ivp

from poissonkit.errors import InputError, ParseError
from poissonkit.plugin import system as registered
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.casimirs import find_casimirs
from poissonkit.structure.jacobi import check_jacobi
from poissonkit.structure.system import HamiltonianSystem

R = sp.Rational


def _field_123(I11, I22, I23):
    """(123) with I13 = 0 (FORMULAS.md §12), order (gamma, omega), as a numpy right-hand side."""
    def rhs(t, y):
        g1, g2, g3, w1, w2, _ = y
        s = I23 * w2
        return [-g3 * w2, g3 * w1, g1 * w2 - g2 * w1, -w2 * s / I11, w1 * s / I22, 0.0]
    return rhs


def _invariants(y, I11, I22, I23):
    """H1, H2 (124) and H4 (125) along the rows of ``y`` (columns are states)."""
    g1, g2, g3, w1, w2, w3 = y
    return np.array([(I11 * w1**2 + I22 * w2**2) / 2, g1**2 + g2**2 + g3**2,
                     I11 * w1 * g1 + I22 * w2 * g2 + I23 * w2 * g3, w3])


# ----------------------------------------------------------------------------- (126)
@pytest.mark.parametrize("I22, I23", [(1, 1), (R(1, 2), R(-2, 5))])
def test_rank4_bivector_126_and_its_pieces_are_poisson(I22, I23):
    s = suslov_rank4(I22=I22, I23=I23)
    ok, detail, _ = suslov_rank4_jacobi(s)
    assert ok, detail
    # the core's randomized check is a separate code path (exact arithmetic at random points)
    p = suslov_rank4_parts(I22, I23)
    for key in ("P1", "P2", "P"):
        res = check_jacobi(Bivector.from_matrix(p[key], p["coords"]), method="random", seed=5)
        assert res.is_poisson, key


def test_rank4_bivector_is_poisson_for_symbolic_inertia():
    I22, I23 = sp.symbols("I22 I23", positive=True)
    ok, detail, _ = suslov_rank4_jacobi(suslov_rank4(I22=I22, I23=I23))
    assert ok, detail


def test_a_wrong_sign_in_the_gamma_omega_block_breaks_jacobi():
    # the check can fail: flip {omega2, gamma_j} of P'' (Casimir H4 is then lost, Jacobi too)
    p = suslov_rank4_parts(1, 1)
    P2 = p["P2"].copy()
    P2[4, 0:3] = -P2[4, 0:3]
    P2[0:3, 4] = -P2[0:3, 4]
    res = check_jacobi(Bivector.from_matrix(P2, p["coords"]), method="random", seed=1)
    assert not res.is_poisson


def test_casimirs_after_126_are_those_the_survey_states():
    """Seed §7.1: P' has H4 and omega_1..3; for P'' "only three of four": H4, H2, omega3;
    P has H4 and omega3 (rank 4)."""
    s = suslov_rank4(I22=1, I23=1)
    ok, detail, _ = suslov_rank4_casimirs(s)
    assert ok, detail
    p = suslov_rank4_parts(1, 1)
    w = p["omega"]
    # find_casimirs finds no other polynomial Casimir of degree <= 2 than the stated ones
    expected = {"P1": {w[0], w[1], w[2], p["H4"]}, "P2": {p["H2"], p["H4"], w[2]},
                "P": {p["H4"], w[2]}}
    for key, want in expected.items():
        found = list(find_casimirs(Bivector.from_matrix(p[key], p["coords"]), 2))
        assert len(found) == len(want), (key, found)
        assert {sp.expand(c) for c in found} == {sp.expand(c) for c in want}, key


def test_coefficients_a_b_may_be_functions_of_the_common_casimirs_only():
    """(126) says a, b are arbitrary functions of the Casimirs of P', P''. With functions of the
    common Casimirs (H4, omega3) a P' + b P'' stays Poisson; a = omega1 (a Casimir of P' only)
    breaks Jacobi: that part of the statement does not verify (docs/nonholonomic/suslov.md)."""
    p = suslov_rank4_parts(1, 1)
    w = p["omega"]

    def poisson(a, b):  # the core's randomized check (exact arithmetic, bound ~1e-29)
        B = Bivector.from_matrix(a * p["P1"] + b * p["P2"], p["coords"])
        return check_jacobi(B, method="random", seed=2).is_poisson

    assert poisson(p["H4"]**2 + 1, w[2] + p["H4"])
    assert not poisson(w[0], 1)


def test_h1_and_h2_are_in_involution_for_p():
    # the survey's closing remark: the level sets of H1, H2 on a leaf are Lagrangian
    p = suslov_rank4_parts(2, 3)
    grad = [sp.Matrix([sp.diff(F, x) for x in p["coords"]]) for F in (p["H1"], p["H2"])]
    assert sp.cancel((grad[0].T * p["P"] * grad[1])[0]) == 0


# ----------------------------------------------------------------------------- Prop. 9
def test_the_field_of_the_parts_is_the_equation_123():
    p = suslov_rank4_parts(1, 2)
    ref = suslov(I11=p["I11"], I22=1, I13=0, I23=2).original  # tested against FORMULAS §12
    assert [sp.simplify(ref[x] - v) for x, v in zip(p["coords"], p["field"])] == [0] * 6


@pytest.mark.parametrize("I22, I23", [(1, 1), (3, R(1, 2))])
def test_proposition_9_with_the_survey_coefficients(I22, I23):
    ok, detail, _ = suslov_prop9(suslov_rank4(I22=I22, I23=I23))
    assert ok, detail


def test_proposition_9_coefficients_are_the_unique_solution():
    """Solve X = a1 P dH1 + a2 P dH2 for a1, a2 with sympy from two components and compare with
    the survey's alpha1, alpha2 (as reconstructed)."""
    I22, I23 = sp.symbols("I22 I23", positive=True)
    p = suslov_rank4_parts(I22, I23)
    P, X = p["P"], p["field"]
    V = [P * sp.Matrix([sp.diff(F, x) for x in p["coords"]]) for F in (p["H1"], p["H2"])]
    a1, a2 = sp.symbols("a1 a2")
    sol = sp.solve([a1 * V[0][3] + a2 * V[1][3] - X[3], a1 * V[0][0] + a2 * V[1][0] - X[0]],
                   [a1, a2], dict=True)[0]
    assert sp.cancel(sol[a1] - p["alpha1"]) == 0
    assert sp.cancel(sol[a2] - p["alpha2"]) == 0


def test_proposition_9_fails_off_the_inertia_condition_with_the_identity():
    s = suslov_rank4(I22=1, I23=1, I11=3)  # I23^2 != (I11 - I22) I22
    ok, detail, _ = suslov_prop9(s)
    assert not ok and "domega_x/dt" in detail
    # the bivectors themselves stay Poisson: only the decomposition needs the condition
    assert suslov_rank4_jacobi(s)[0]


def test_no_single_hamiltonian_of_the_integrals_gives_the_field():
    """alpha1/alpha2 is not a function of (H1, H2, H4, omega3): Jacobian rank 5 at a point, so
    X != N P dH(H1, H2, H4, omega3) and the decomposition of Prop. 9 is needed."""
    p = suslov_rank4_parts(1, 1)
    g, w = p["gamma"], p["omega"]
    funcs = [p["alpha1"] / p["alpha2"], p["H1"], p["H2"], p["H4"], w[2]]
    J = sp.Matrix([[sp.diff(F, x) for x in p["coords"]] for F in funcs])
    pt = dict(zip(g + w, [R(1, 3), R(2, 7), R(-5, 11), R(3, 5), R(-1, 4), 0]))
    assert J.subs(pt).rank() == 5


def _decomposition_rhs(p):
    """alpha1 P dH1 + alpha2 P dH2 through the library's lambdified numerics path."""
    from poissonkit.numerics.conformal import LambdifiedSystem

    B = Bivector.from_matrix(p["P"], p["coords"])
    parts = [LambdifiedSystem(HamiltonianSystem(structure=B, hamiltonian=p[H],
                                                multiplier=p[a]))
             for H, a in (("H1", "alpha1"), ("H2", "alpha2"))]
    return lambda t, y: np.add(parts[0].rhs(t, y), parts[1].rhs(t, y))


def test_decomposition_flow_matches_scipy_integration_of_123():
    I22, I23 = 1.0, 1.0
    I11 = I22 + I23**2 / I22
    p = suslov_rank4_parts(1, 1)
    y0 = np.array([0.6, 0.0, -0.8, 0.2, 0.6, 0.0])  # (gamma, gamma) = 1, H4 = -6/25
    T = 1.0
    ref = solve_ivp(_field_123(I11, I22, I23), (0, T), y0, method="DOP853", rtol=1e-12,
                    atol=1e-12, dense_output=True)
    ts = np.linspace(0, T, 201)
    Y = ref.sol(ts)
    # stay on the regular part: D, h2, H4 and the denominator of alpha1 away from zero
    g1, g2, g3, w1, w2, _ = Y
    assert np.min(np.abs(I23 * g2 - I22 * g3)) > 0.05
    assert np.min(np.abs(I22 * g2 + I23 * g3)) > 0.05
    assert np.min(np.abs(I22 * (w1 * g2 - w2 * g1) + I23 * w1 * g3)) > 0.05
    dec = solve_ivp(_decomposition_rhs(p), (0, T), y0, method="DOP853", rtol=1e-12,
                    atol=1e-12, t_eval=ts)
    assert dec.success
    assert np.max(np.abs(dec.y - Y)) < 1e-9
    inv = _invariants(dec.y, I11, I22, I23)
    assert np.max(np.abs(inv - inv[:, :1])) < 1e-9


def test_registered_hamiltonian_flow_keeps_casimirs_and_h2():
    """The registered system's own flow P dH1 (not the Suslov field) keeps H1, H2, H4, omega3."""
    from poissonkit.numerics.conformal import solve_direct

    s = registered("nh.suslov_rank4").build(**registered("nh.suslov_rank4").resolve_params({}))
    y0 = np.array([0.6, 0.0, -0.8, 0.2, 0.6, 0.0])
    run, _ = solve_direct(s, y0, 0.3, backend="python", tol=1e-12)
    inv = _invariants(run.y.T, 2.0, 1.0, 1.0)
    assert np.max(np.abs(inv - inv[:, :1])) < 1e-9
    assert np.max(np.abs(run.y[-1] - y0)) > 1e-3  # it moved


def test_survey_remark_singularity_is_crossed_by_physical_motions():
    """Seed §7.1 after (126): "the singularity at I23 gamma2 - I22 gamma3 = 0 can never be
    attained in a physical motion". Not confirmed: along (123) omega2 -> 0 and gamma turns about
    e1, so D = I23 gamma2 - I22 gamma3 changes sign (docs/nonholonomic/suslov.md)."""
    I22, I23 = 1.0, 1.0
    I11 = I22 + I23**2 / I22
    y0 = np.array([0.6, 0.48, 0.64, 0.7, -0.9, 0.0])
    sol = solve_ivp(_field_123(I11, I22, I23), (0, 30), y0, method="DOP853", rtol=1e-10,
                    atol=1e-12, dense_output=True)
    D = I23 * sol.sol(np.linspace(0, 30, 3001))[1] - I22 * sol.sol(np.linspace(0, 30, 3001))[2]
    assert np.count_nonzero(np.diff(np.sign(D))) >= 2


def test_rank4_parameters_are_validated():
    with pytest.raises(InputError):
        suslov_rank4(I22=1, I23=0)
    with pytest.raises(InputError):
        suslov_rank4(I22=-1, I23=1)
    with pytest.raises(InputError):
        suslov_rank4(I22=1, I23="1")


def test_rank4_entry_is_registered_with_its_claim_functions():
    entry = registered("nh.suslov_rank4")
    s = entry.build(**entry.resolve_params({"I22": 2.0, "I23": 2.0}))
    assert s.params["I11"] == 4 and s.name == "nh.suslov_rank4"
    assert all(c.__doc__.strip() for c in RANK4_CLAIMS)


# ----------------------------------------------------------------------------- §7.2 parameters
def test_potential_parameter_is_the_parsed_sympy_expression():
    g = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    s = suslov_potential(U="3*gamma_z + gamma_x**2*gamma_y")
    assert isinstance(s.params["U"], sp.Expr)
    assert sp.expand(s.params["U"] - (3 * g[2] + g[0]**2 * g[1])) == 0
    assert s.params["U"] == suslov_potential(U=3 * g[2] + g[0]**2 * g[1]).params["U"]


@pytest.mark.parametrize("bad", ["__import__('os').system('true')", "gamma_x.__class__",
                                 "open('x')"])
def test_potential_strings_go_through_the_allow_list(bad):
    with pytest.raises(ParseError):
        suslov_potential(U=bad)


def test_potential_rejects_non_expressions():
    with pytest.raises(ParseError):
        suslov_potential(U=b"gamma_z")
    with pytest.raises(InputError):
        suslov_potential(U=object())


def test_system_validation_parses_text_with_the_allow_list_only():
    s = suslov_potential()
    # text names the coordinates (parsed, never evaluated) ...
    gx = s.structure.coords[0]
    assert HamiltonianSystem(structure=s.structure, hamiltonian="gamma_x").hamiltonian == gx
    # ... and nothing else
    with pytest.raises(ParseError):
        HamiltonianSystem(structure=s.structure, hamiltonian="gamma_w")
    with pytest.raises(ParseError):
        HamiltonianSystem(structure=s.structure, hamiltonian=0,
                          casimirs={"C": "__import__('os')"})
