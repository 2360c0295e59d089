"""Pin every convention stated in poissonkit/conventions.py against FORMULAS.md §0–§2."""

from __future__ import annotations

import math
import random

import sympy as sp

from poissonkit import conventions
from poissonkit.structure import Bivector, e3, eps_matrix, so3

R = sp.Rational


def test_bivector_matrix_holds_the_brackets_of_coordinates():
    P = e3("gamma_M")
    n = P.dim
    for i in range(n):
        for j in range(n):
            assert P.bracket(P.coords[i], P.coords[j]) == P.matrix[i, j]


def test_bracket_is_dF_P_dG_and_antisymmetric():
    P = e3()
    x = P.coords
    rng = random.Random(7)
    F = sum(rng.randint(-3, 3) * x[i] * x[j] for i in range(6) for j in range(i, 6))
    G = x[0] ** 3 + x[4] * x[5] - 2 * x[3]
    manual = sum(P.matrix[i, j] * sp.diff(F, x[i]) * sp.diff(G, x[j])
                 for i in range(6) for j in range(6))
    assert sp.expand(P.bracket(F, G) - manual) == 0
    assert sp.expand(P.bracket(F, G) + P.bracket(G, F)) == 0


def test_hamiltonian_vector_field_is_plus_P_dH_with_e3_oracle():
    # FORMULAS.md §2: {x, H} = P0 dH = (-35/72, -1/4, 11/18, -5/12, 13/24, -1/3)
    assert conventions.HAMILTONIAN_SIGN == 1
    P = e3("gamma_M")
    g, L = P.coords[:3], P.coords[3:]
    H = (L[0] ** 2 / 2 + L[1] ** 2 / 3 + L[2] ** 2 / 4) / 2 + g[2]
    pt = dict(zip(P.coords, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    expected = [R(-35, 72), R(-1, 4), R(11, 18), R(-5, 12), R(13, 24), R(-1, 3)]
    X = P.hamiltonian_vector_field(H).subs(pt)
    assert list(X) == expected
    eom = P.equations_of_motion(H)
    assert [eom[c].subs(pt) for c in P.coords] == expected
    assert [P.bracket(c, H).subs(pt) for c in P.coords] == expected
    # the multiplier multiplies: X = N P dH
    assert list(P.hamiltonian_vector_field(H, multiplier=-2).subs(pt)) == [-2 * v for v in expected]


def test_space_frame_equations_of_seed_000():
    # xdot = {x, H}: mdot = dH/dm x m + dH/dnu x nu, nudot = dH/dm x nu (conventions, seed 000)
    P = e3()
    nu, m = sp.Matrix(P.coords[:3]), sp.Matrix(P.coords[3:])
    H = (m.T * sp.diag(1, 2, 3) * m)[0, 0] / 2 + nu[0] * nu[2] ** 2
    dHdm = sp.Matrix([sp.diff(H, c) for c in m])
    dHdnu = sp.Matrix([sp.diff(H, c) for c in nu])
    X = P.hamiltonian_vector_field(H)
    assert (X[:3, 0] - dHdm.cross(nu)).expand() == sp.zeros(3, 1)
    assert (X[3:, 0] - dHdm.cross(m) - dHdnu.cross(nu)).expand() == sp.zeros(3, 1)


def test_eps_matrix_convention():
    v = sp.Matrix(sp.symbols("v1 v2 v3"))
    w = sp.Matrix(sp.symbols("w1 w2 w3"))
    E = eps_matrix(v)
    # FORMULAS.md §0 prints [v]_eps = [[0, v3, -v2], [-v3, 0, v1], [v2, -v1, 0]]
    assert E == sp.Matrix([[0, v[2], -v[1]], [-v[2], 0, v[0]], [v[1], -v[0], 0]])
    assert (E * w - w.cross(v)).expand() == sp.zeros(3, 1)
    for i in range(3):
        for j in range(3):
            assert E[i, j] == sum(sp.LeviCivita(i, j, k) * v[k] for k in range(3))


def test_e3_orderings_and_brackets():
    for order, (a, b) in [("nu_m", ("nu", "m")), ("gamma_M", ("gamma", "M"))]:
        P = e3(order)
        assert P.names == tuple(f"{a}_{x}" for x in "xyz") + tuple(f"{b}_{x}" for x in "xyz")
        pos, mom = P.coords[:3], P.coords[3:]
        for i in range(3):
            for j in range(3):
                eps = [sp.LeviCivita(i, j, k) for k in range(3)]
                assert P.bracket(mom[i], mom[j]) == sum(e * c for e, c in zip(eps, mom))
                assert P.bracket(mom[i], pos[j]) == sum(e * c for e, c in zip(eps, pos))
                assert P.bracket(pos[i], pos[j]) == 0
    # the two orderings are the same bracket (same matrix up to renaming)
    assert e3("nu_m").matrix.subs(dict(zip(e3("nu_m").coords, e3("gamma_M").coords)),
                                  simultaneous=True) == e3("gamma_M").matrix


def test_schouten_sign_gives_twice_the_jacobiator_on_formulas_oracle():
    from poissonkit.structure import schouten

    assert conventions.SCHOUTEN_JACOBI_FACTOR == 2
    y = sp.symbols("y1 y2 y3")
    Q = Bivector.from_matrix([[0, y[0] * y[1], 0], [-y[0] * y[1], 0, y[2]], [0, -y[2], 0]], y)
    QQ = schouten.schouten_bracket(Q, Q)
    jac = schouten.jacobiator(Q)
    assert sp.expand(QQ.component(0, 1, 2) + 2 * y[0] * y[2]) == 0
    assert QQ.component(0, 1, 2).subs(dict(zip(y, (1, 2, 3)))) == -6
    assert sp.expand(jac.component(0, 1, 2) + y[0] * y[2]) == 0
    # Q^{ij} = eps_ijk v_k with v = (-y2, y1, 1): [Q, Q]^{123} = -4
    V = Bivector.from_matrix(eps_matrix([-y[1], y[0], 1]), y)
    assert sp.expand(schouten.schouten_bracket(V, V).component(0, 1, 2)) == -4
    assert schouten.schouten_bracket(so3(), so3()).is_zero()


def test_mu0_is_four_pi_times_1e_minus_7():
    assert conventions.MU0 == 4e-7 * math.pi
    assert math.isclose(conventions.MU0, 1.2566370614359173e-06, rel_tol=0, abs_tol=1e-22)


def test_pair_invariant_names():
    assert conventions.PAIR_INVARIANTS == ("r", "c1", "c2", "c3")


# --- e(n) invariants (issue 34): names and values pinned against determinants computed here
def _euclid_Y(alg, n):
    nu = [alg.bivector.symbol(f"nu_{i}") for i in range(1, n + 1)]
    Y = sp.zeros(n + 1)
    for i in range(n):
        for j in range(i + 1, n):
            Y[i, j] = alg.bivector.symbol(f"m_{i + 1}{j + 1}")
            Y[j, i] = -Y[i, j]
        Y[i, n], Y[n, i] = nu[i], -nu[i]
    return Y


def test_euclid_invariant_names_and_values():
    from itertools import combinations

    from poissonkit.structure.lie_algebras import lie_algebra

    assert conventions.EUCLID_INVARIANTS == ("|nu|^2", "D_{k}", "Pf(Y)")
    assert set(lie_algebra("e(3)").invariants()) == {"|nu|^2", "(nu, m)"}
    assert set(lie_algebra("se(3)").invariants()) == {"|P|^2", "(L, P)"}
    for n, names in ((4, {"|nu|^2", "D_2"}), (5, {"|nu|^2", "D_2", "Pf(Y)"})):
        alg = lie_algebra(f"e({n})")
        inv = alg.invariants()
        assert set(inv) == names
        Y = _euclid_Y(alg, n)
        # D_k: the principal 2k-minors of Y containing the last index, summed (k = 1: |nu|^2)
        for k, name in ((1, "|nu|^2"), (2, "D_2")):
            minors = sum(Y.extract(list(s) + [n], list(s) + [n]).det(method="berkowitz")
                         for s in combinations(range(n), 2 * k - 1))
            assert sp.expand(minors - inv[name]) == 0, name
        if n % 2:
            assert sp.expand(inv["Pf(Y)"] ** 2 - Y.det(method="berkowitz")) == 0


def test_text_names_mean_only_what_is_declared():
    """conventions, "Text expressions": I, E, S, N, pi are symbols when declared; undeclared,
    pi is the constant and the others are refused (I never silently becomes sqrt(-1))."""
    import pytest

    from poissonkit.errors import ParseError
    from poissonkit.structure.parsing import parse_expression

    x = sp.Symbol("x", real=True)
    assert conventions.UNDECLARED_NAMES == ("I", "E", "S", "N")
    assert conventions.TEXT_CONSTANTS == ("pi",)
    for name in conventions.UNDECLARED_NAMES:
        with pytest.raises(ParseError, match=f"{name!r} is not declared"):
            parse_expression(f"{name}*x", [x])
        e = parse_expression(f"{name}*x", [x], params=[name])
        assert e.free_symbols == {x, sp.Symbol(name, real=True)}  # a real symbol, not sympy's
    assert parse_expression("I**2", [x], params=["I"]) != -1
    assert parse_expression("pi*x", [x]) == sp.pi * x
    assert parse_expression("pi*x", [x], params=["pi"]).free_symbols == {
        x, sp.Symbol("pi", real=True)}


def test_text_accepts_unicode_and_keyword_parameter_names():
    from poissonkit.structure.parsing import parse_expression

    x = sp.Symbol("x", real=True)
    alpha, lam = sp.Symbol("α", real=True), sp.Symbol("lambda", real=True)
    assert parse_expression("α*x**2 + lambda*x", [x], params=["α", "lambda"]) == \
        alpha * x ** 2 + lam * x
    # the same names in a bracket written as text
    P = Bivector.from_components({(1, 2): "lambda*x3", (2, 3): "α*x1", (1, 3): "-x2"},
                                 ["x1", "x2", "x3"], params=["α", "lambda"])
    assert lam in P.matrix.free_symbols and alpha in P.matrix.free_symbols


def test_decimals_in_text_are_exact_rationals():
    from poissonkit.structure.parsing import parse_expression

    x = sp.Symbol("x", real=True)
    assert conventions.EXACT_DECIMALS is True
    assert parse_expression("0.1*x", [x]) == R(1, 10) * x
    assert parse_expression("2.5e-3 + 1.25", [x]) == R(1, 400) + R(5, 4)
    assert parse_expression("0.1 + 0.2", [x]) == R(3, 10)  # not 0.30000000000000004
    assert parse_expression("0.1*x", [x], exact=False) == sp.Float(0.1) * x
    assert parse_expression("3*x", [x]) == 3 * x
