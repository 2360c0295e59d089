"""Seed 000 acceptance tests (FORMULAS.md §1, §2): the 18-dim two-top structure, eq. (20),
total angular momentum, the dipole–dipole oracle and the e(3) oracle."""

from __future__ import annotations

import pytest
import sympy as sp

from poissonkit.structure import HamiltonianSystem, canonical, direct_sum, e3
from poissonkit.structure.checks import in_involution, is_first_integral, vanishes

R = sp.Rational
U = sp.Function("U")
mu, a1, a2 = sp.symbols("mu alpha1 alpha2", positive=True)


@pytest.fixture(scope="module")
def two_tops():
    P = direct_sum(("orbit", canonical(3, "r", "p")), ("top1", e3()), ("top2", e3()))
    vec = lambda prefix: sp.Matrix([P.symbol(f"{prefix}_{a}") for a in "xyz"])  # noqa: E731
    return P, vec("orbit.r"), vec("orbit.p"), vec("top1.nu"), vec("top1.m"), vec("top2.nu"), \
        vec("top2.m")


def _invariants(r, nu1, nu2):
    rr = sp.sqrt(r.dot(r))
    e = r / rr
    return rr, e, e.dot(nu1), e.dot(nu2), nu1.dot(nu2)


def _hamiltonian(r, p, nu1, m1, nu2, m2, potential):
    rr, _e, c1, c2, c3 = _invariants(r, nu1, nu2)
    return p.dot(p) / (2 * mu) + a1 * m1.dot(m1) / 2 + a2 * m2.dot(m2) / 2 + potential(rr, c1, c2, c3)


def _name_partials(expr):
    """Replace U(...) and its first partials (Derivative or Subs forms) by symbols U, U_0..U_3.

    sympy writes dU/d(arg k) at composite arguments as ``Subs(Derivative(U(.., xi, ..), xi),
    xi, value)``; both sides of the comparison are normalised the same way.
    """
    names = [sp.Symbol(f"U_{k}") for k in range(4)]

    def repl_subs(s):
        (d, vars_, _pts) = s.args
        f = d.expr
        k = list(f.args).index(vars_[0])
        return names[k]

    expr = expr.replace(lambda e: isinstance(e, sp.Subs) and isinstance(e.args[0], sp.Derivative),
                        repl_subs)
    expr = expr.replace(lambda e: isinstance(e, sp.Derivative) and e.expr.func == U,
                        lambda d: names[list(d.expr.args).index(d.variables[0])])
    return expr.replace(lambda e: getattr(e, "func", None) == U, lambda e: sp.Symbol("U"))


def _vector_form(r, p, nu1, m1, nu2, m2, sign_c3=1):
    """Eq. (20) exactly as printed in FORMULAS.md §1, with U_r, U_c', ... as symbols."""
    Ur, Uc1, Uc2, Uc3 = (sp.Symbol(f"U_{k}") for k in range(4))
    rr, e, c1, c2, _c3 = _invariants(r, nu1, nu2)
    rdot = p / mu
    pdot = -Ur * e - (Uc1 * (nu1 - c1 * e) + Uc2 * (nu2 - c2 * e)) / rr
    nu1dot = a1 * m1.cross(nu1)
    m1dot = Uc1 * e.cross(nu1) - sign_c3 * Uc3 * nu1.cross(nu2)
    nu2dot = a2 * m2.cross(nu2)
    m2dot = Uc2 * e.cross(nu2) + Uc3 * nu1.cross(nu2)
    return sp.Matrix.vstack(rdot, pdot, nu1dot, m1dot, nu2dot, m2dot)


def _zero(expr) -> bool:
    """Exact zero test: |r| becomes a symbol rho with rho**2 = r.r, then polynomial reduction."""
    return vanishes(expr)


def _equal(a, b) -> bool:
    return all(_zero(x - y) for x, y in zip(a, b))


def test_hamiltonian_field_of_two_tops_is_eq_20_for_generic_potential(two_tops):
    P, r, p, nu1, m1, nu2, m2 = two_tops
    H = _hamiltonian(r, p, nu1, m1, nu2, m2, lambda *args: U(*args))
    X = P.hamiltonian_vector_field(H)
    assert X.shape == (18, 1)
    lhs = sp.Matrix([_name_partials(x) for x in X])
    assert _equal(lhs, _vector_form(r, p, nu1, m1, nu2, m2))


def test_flipped_c3_sign_in_eq_20_is_detected(two_tops):
    P, r, p, nu1, m1, nu2, m2 = two_tops
    H = _hamiltonian(r, p, nu1, m1, nu2, m2, lambda *args: U(*args))
    lhs = sp.Matrix([_name_partials(x) for x in P.hamiltonian_vector_field(H)])
    wrong = _vector_form(r, p, nu1, m1, nu2, m2, sign_c3=-1)
    bad = [k for k in range(18) if not _zero(lhs[k] - wrong[k])]
    assert bad == [9, 10, 11]  # exactly the m' components


def test_total_angular_momentum_is_conserved_for_generic_potential(two_tops):
    P, r, p, nu1, m1, nu2, m2 = two_tops
    H = _hamiltonian(r, p, nu1, m1, nu2, m2, lambda *args: U(*args))
    j = r.cross(p) + m1 + m2
    res = is_first_integral(HamiltonianSystem(P, H), {f"j_{a}": j[k] for k, a in enumerate("xyz")})
    assert res.holds, res.failures


def test_total_angular_momentum_brackets_are_so3(two_tops):
    P, r, p, _nu1, m1, _nu2, m2 = two_tops
    j = r.cross(p) + m1 + m2
    for a, b, c in [(0, 1, 2), (1, 2, 0), (2, 0, 1)]:
        assert sp.expand(P.bracket(j[a], j[b]) - j[c]) == 0
    assert not in_involution(P, {"j_x": j[0], "j_y": j[1]})


def test_dipole_dipole_field_matches_oracle(two_tops):
    P, r, p, nu1, m1, nu2, m2 = two_tops
    dipole = lambda rr, c1, c2, c3: (c3 - 3 * c1 * c2) / rr**3  # noqa: E731
    H = _hamiltonian(r, p, nu1, m1, nu2, m2, dipole)
    state = [1, 2, 2, R(1, 2), -1, R(1, 3), 0, 0, 1, R(1, 5), R(2, 5), 1, R(3, 5), R(4, 5), 0,
             -1, R(1, 2), 2]
    point = dict(zip(P.coords, state))
    point.update({mu: 2, a1: 3, a2: 5})
    expected = [R(1, 4), R(-1, 2), R(1, 6), R(-56, 3645), R(-148, 3645), R(-121, 3645),
                R(6, 5), R(-3, 5), 0, R(-2, 81), R(2, 405), 0, -8, 6, R(-11, 2),
                R(4, 405), R(-1, 135), R(4, 405)]
    # X = P dH evaluated exactly at the state (differentiate first, then substitute)
    X = P.matrix.subs(point) * P.gradient(H).subs(point)
    got = [sp.nsimplify(sp.radsimp(x)) for x in X]
    assert got == expected
    assert sp.simplify(H.subs(point)) == R(98567, 6480)
    j = r.cross(p) + m1 + m2
    assert list(j.subs(point)) == [R(28, 15), R(47, 30), 1]
    Xj = [sum(X[i] * sp.diff(jc, x).subs(point) for i, x in enumerate(P.coords)) for jc in j]
    assert [sp.simplify(v) for v in Xj] == [0, 0, 0]


def test_e3_oracle_matrix_and_field():
    P = e3("gamma_M")
    g = sp.Matrix(P.coords[:3])
    L = sp.Matrix(P.coords[3:])
    point = dict(zip(P.coords, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    P0 = [[0, 0, 0, 0, R(2, 3), R(-1, 3)], [0, 0, 0, R(-2, 3), 0, R(2, 3)],
          [0, 0, 0, R(1, 3), R(-2, 3), 0], [0, R(2, 3), R(-1, 3), 0, R(1, 2), 2],
          [R(-2, 3), 0, R(2, 3), R(-1, 2), 0, 1], [R(1, 3), R(-2, 3), 0, -2, -1, 0]]
    assert P.matrix.subs(point) == sp.Matrix(P0)
    A = sp.diag(R(1, 2), R(1, 3), R(1, 4))
    H = (L.T * A * L)[0, 0] / 2 + g[2]
    X = P.hamiltonian_vector_field(H).subs(point)
    assert list(X) == [R(-35, 72), R(-1, 4), R(11, 18), R(-5, 12), R(13, 24), R(-1, 3)]
