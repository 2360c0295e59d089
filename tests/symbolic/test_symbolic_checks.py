"""Exact checks of integrals, involution, conformally Hamiltonian form and invariant measures
on the Chaplygin ball (FORMULAS.md §7) and small independent examples."""

from __future__ import annotations

import pytest
import sympy as sp
from brackets import p_g  # type: ignore[import-not-found]

from poissonkit.errors import DimensionError, InputError
from poissonkit.structure import Bivector, HamiltonianSystem, e3, eps_matrix
from poissonkit.structure.checks import (
    divergence, in_involution, is_conformally_hamiltonian, is_first_integral,
    is_invariant_measure, vanishes,
)

R = sp.Rational


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


@pytest.fixture(scope="module")
def ball():
    """Chaplygin ball, I = (1, 2, 3), d = 1, built from FORMULAS.md §7 (34)–(40)."""
    gam = sp.Matrix(sp.symbols("gamma_x gamma_y gamma_z", real=True))
    M = sp.Matrix(sp.symbols("M_x M_y M_z", real=True))
    d = sp.Integer(1)
    a = [R(1, 2), R(1, 3), R(1, 4)]
    A = sp.diag(*a)
    Ag = A * gam
    g = sp.sqrt(1 - d * _dot(gam, Ag))
    omega = A * M + d * _dot(M, Ag) / g**2 * Ag
    G = eps_matrix(gam)
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = g * G
    mat[3:6, 0:3] = g * G
    mat[3:6, 3:6] = g * eps_matrix(M) - d * _dot(M, Ag) / g * G
    P = Bivector.from_matrix(mat, list(gam) + list(M))
    H1 = _dot(M, omega)
    original = dict(zip(P.coords, list(gam.cross(omega)) + list(M.cross(omega))))
    return dict(P=P, g=g, H1=H1, omega=omega, gam=gam, M=M, original=original, A=A)


def test_ball_original_field_matches_oracle(ball):
    pt = dict(zip(ball["P"].coords, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    X = [sp.nsimplify(sp.radsimp(v.subs(pt))) for v in ball["original"].values()]
    assert X == [R(49, 102), R(29, 102), R(-127, 204), R(-5, 136), R(1, 8), R(39, 68)]


def test_ball_is_conformally_hamiltonian_with_minus_inverse_g(ball):
    P, g, H = ball["P"], ball["g"], ball["H1"] / 2
    res = is_conformally_hamiltonian(ball["original"], P, H, -1 / g)
    assert res, res.failures
    wrong = is_conformally_hamiltonian(ball["original"], P, H, 1 / g)  # time-reversed flow
    assert not wrong
    assert {lab for lab, _ in wrong.failures} == {f"{c}dot" for c in P.coords}


@pytest.mark.slow
def test_ball_integrals_measure_and_involution(ball):
    P, g, gam, M = ball["P"], ball["g"], ball["gam"], ball["M"]
    X = ball["original"]
    integrals = {"H1": ball["H1"], "H2": _dot(M, M), "H3": _dot(gam, gam), "H4": _dot(gam, M)}
    assert is_first_integral(X, integrals)
    not_conserved = is_first_integral(X, {"H1": ball["H1"], "M_x": M[0]})
    assert [lab for lab, _ in not_conserved.failures] == ["X(M_x)"]
    assert is_invariant_measure(X, 1 / g)
    assert not is_invariant_measure(X, g)
    assert in_involution(P, {"H1": ball["H1"], "H2": _dot(M, M)})
    res = in_involution(P, {"H1": ball["H1"], "M_x": M[0], "M_y": M[1]})
    assert "{M_x, M_y}" in [lab for lab, _ in res.failures]


@pytest.mark.slow
def test_checks_accept_a_hamiltonian_system(ball):
    P, g = ball["P"], ball["g"]
    sys_ = HamiltonianSystem(P, ball["H1"] / 2, multiplier=-1 / g, measure=1 / g,
                             original=ball["original"])
    assert is_conformally_hamiltonian(sys_)
    assert is_invariant_measure(sys_)
    assert is_first_integral(sys_, _dot(ball["M"], ball["M"]))
    assert in_involution(sys_, [ball["H1"], _dot(ball["M"], ball["M"])])


def test_p_gf_field_conserves_casimirs_and_divergence_free_measure():
    # P_{g,0} with undefined g (FORMULAS §5): for H = (M, M)/2, X = P dH conserves (gamma, M)
    # and |M|^2; a cheap default-run companion of the slow ball checks
    gam = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    M = sp.symbols("M_x M_y M_z", real=True)
    g = sp.Function("g")(*gam)
    P = p_g(gam, M, g, _dot([sp.diff(g, c) for c in gam], M))
    sys_ = HamiltonianSystem(P, _dot(M, M) / 2)
    assert is_first_integral(sys_, {"C2": _dot(gam, M), "C1": _dot(gam, gam)})
    res = is_first_integral(sys_, {"M_x": M[0]})
    assert not res and res.failures[0][0] == "X(M_x)"
    assert in_involution(P, [_dot(gam, gam), _dot(gam, M), _dot(M, M)])


def test_divergence_of_simple_fields():
    x, y = sp.symbols("x y")
    assert sp.expand(divergence([x**2, x * y], [x, y]) - 3 * x) == 0
    assert divergence({x: -y, y: x}) == 0
    # Lie–Poisson fields are divergence free (e(3) is unimodular)
    P = e3()
    H = _dot(P.coords[3:], P.coords[3:]) / 2 + P.coords[2] ** 3
    assert sp.expand(divergence(HamiltonianSystem(P, H))) == 0


def test_first_integral_modulo_constraint():
    # on the unit circle x^2 + y^2 = 1 the rotation field conserves x^2 + y^2 (trivially) and
    # the field (-y, x) * (x^2 + y^2 - 1) + (1, 0) ... only modulo the constraint
    x, y = sp.symbols("x y")
    c = x**2 + y**2 - 1
    X = {x: -y + c, y: x}
    F = x**2 + y**2
    assert not is_first_integral(X, F)
    assert is_first_integral(X, F, constraints=[c])


def test_vanishes_understands_square_roots_and_functions():
    x = sp.Symbol("x", positive=True)
    f = sp.Function("f")
    assert vanishes(sp.sqrt(x**2 + 1) ** 2 - x**2 - 1)
    assert vanishes(1 / sp.sqrt(x + 1) - sp.sqrt(x + 1) / (x + 1))
    assert not vanishes(sp.sqrt(x + 1) - 1)
    assert vanishes(sp.diff(f(x) ** 2, x) - 2 * f(x) * sp.diff(f(x), x))
    assert vanishes(sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1)


def test_bad_input_is_rejected_with_typed_errors(ball):
    x, y = sp.symbols("x y")
    with pytest.raises(InputError):
        is_first_integral({x: y, y: -x}, "x**2 + y**2")
    with pytest.raises(InputError):
        divergence([x, y])
    with pytest.raises(DimensionError):
        divergence([x, y, 1], [x, y])
    with pytest.raises(InputError):
        in_involution("P", [x])
    with pytest.raises(InputError):
        is_invariant_measure({x: y, y: -x})
    with pytest.raises(InputError):
        is_conformally_hamiltonian(ball["original"], ball["P"], None)
    with pytest.raises(InputError):
        is_first_integral({x: y}, x, constraints=["x - 1"])
