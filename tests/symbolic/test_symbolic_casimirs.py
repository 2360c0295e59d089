"""Rank, singular set and Casimir finding (FORMULAS.md §1, §2, §5, §7, §12)."""

from __future__ import annotations

import pytest
import sympy as sp
from brackets import p_g  # type: ignore[import-not-found]

from poissonkit.errors import DimensionError, InputError, UnknownNameError
from poissonkit.structure import Bivector, canonical, direct_sum, e3, eps_matrix, lie_poisson, so3
from poissonkit.structure.casimirs import (
    SingularSetTooExpensive, find_casimirs, is_casimir, rank, singular_set,
)

R = sp.Rational


def _dot(a, b):
    return sp.expand(sum(x * y for x, y in zip(a, b)))


def _same_span(found, expected) -> bool:
    """Whether two lists of polynomials span the same space (exact linear algebra)."""
    polys = [sp.Poly(sp.expand(p), *sorted(set().union(*(sp.sympify(q).free_symbols
                                                          for q in list(found) + list(expected))),
                                              key=str))
             for p in list(found) + list(expected)]
    monos = sorted({m for p in polys for m in p.monoms()})
    rows = [[p.as_dict().get(m, 0) for m in monos] for p in polys]
    M = sp.Matrix(rows)
    return M[:len(found), :].rank() == M.rank() == M[len(found):, :].rank() == len(expected)


@pytest.fixture(scope="module")
def two_tops():
    return direct_sum(("orbit", canonical(3, "r", "p")), ("top1", e3()), ("top2", e3()))


def _vec(P, prefix):
    return [P.symbol(f"{prefix}_{a}") for a in "xyz"]


# ------------------------------------------------------------------ seed 000 (FORMULAS §1)
def test_two_tops_casimirs_are_the_four_of_formulas_section_1(two_tops):
    P = two_tops
    nu1, m1, nu2, m2 = (_vec(P, n) for n in ("top1.nu", "top1.m", "top2.nu", "top2.m"))
    found = find_casimirs(P, 2)
    expected = [_dot(nu1, nu1), _dot(nu2, nu2), _dot(nu1, m1), _dot(nu2, m2)]
    assert len(found) == 4
    assert set(found) == set(expected)
    for C in expected:
        assert is_casimir(P, C)


def test_two_tops_generic_rank_is_14_and_drops_on_nu_zero(two_tops):
    P = two_tops
    r = rank(P, seed=1)
    assert r == 14 and r.generic
    assert r.error_bound is not None and r.error_bound < 1e-9
    point = {c: 1 for c in P.coords}
    assert rank(P, point) == 14
    for name in ("top1.nu_x", "top1.nu_y", "top1.nu_z"):
        point[name] = 0
    at = rank(P, point)
    assert at == 12 and not at.generic and at.error_bound == 0


def test_two_tops_singular_set_is_union_of_nu_zero(two_tops):
    S = singular_set(two_tops)
    assert S.rank == 14
    P = two_tops
    assert {frozenset(c) for c in S.components} == {
        frozenset(_vec(P, "top1.nu")), frozenset(_vec(P, "top2.nu"))}
    # the single-list form: products vanish exactly on the union
    assert len(S.equations) == 9


def test_total_angular_momentum_is_not_a_casimir(two_tops):
    P = two_tops
    r, p = _vec(P, "orbit.r"), _vec(P, "orbit.p")
    jz = r[0] * p[1] - r[1] * p[0] + P.symbol("top1.m_z") + P.symbol("top2.m_z")
    res = is_casimir(P, jz)
    assert not res
    assert {lab for lab, _ in res.failures} >= {"{orbit.r_x, C}", "{top1.m_x, C}"}


# ------------------------------------------------------------------ Lie–Poisson controls
def test_e3_casimirs_rank_and_singular_set():
    P = e3("gamma_M")
    g, M = P.coords[:3], P.coords[3:]
    assert set(find_casimirs(P, 2)) == {_dot(g, g), _dot(g, M)}
    # products of generators are not reported again
    assert set(find_casimirs(P, 4)) == {_dot(g, g), _dot(g, M)}
    assert rank(P) == 4
    S = singular_set(P)
    assert S.components == (tuple(g),) or set(S.components[0]) == set(g)


def test_so3_and_canonical_casimirs():
    m = so3().coords
    assert list(find_casimirs(so3(), 3)) == [_dot(m, m)]
    assert len(find_casimirs(canonical(2), 3)) == 0
    assert singular_set(canonical(2)).empty


def test_heisenberg_algebra_has_central_casimir():
    # {x, y} = z: the centre z is the only Casimir; rank 2 drops on z = 0
    C = [[[0, 0, 0], [0, 0, 1], [0, 0, 0]], [[0, 0, -1], [0, 0, 0], [0, 0, 0]],
         [[0, 0, 0], [0, 0, 0], [0, 0, 0]]]
    P = lie_poisson(C, ["x", "y", "z"])
    z = P.coords[2]
    assert list(find_casimirs(P, 3)) == [z]
    assert singular_set(P).components == ((z,),)


def test_restricting_variables():
    P = e3()
    nu = P.coords[:3]
    assert list(find_casimirs(P, 2, variables=["nu_x", "nu_y", "nu_z"])) == [_dot(nu, nu)]
    assert len(find_casimirs(P, 2, variables=["m_x", "m_y", "m_z"])) == 0


def test_symbolic_parameters_appear_in_the_answer():
    # e(3) in the shifted momentum M + S (a gyrostat-like shift): Casimir (gamma, M + S)
    g = sp.symbols("g1 g2 g3", real=True)
    M = sp.symbols("M1 M2 M3", real=True)
    S = sp.symbols("S1 S2 S3", real=True)
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = eps_matrix(g)
    mat[3:6, 0:3] = eps_matrix(g)
    mat[3:6, 3:6] = eps_matrix([a + b for a, b in zip(M, S)])
    P = Bivector.from_matrix(mat, g + M)
    found = find_casimirs(P, 2, params=S)
    assert _same_span(found, [_dot(g, g), _dot(g, M) + _dot(g, S)])


# ------------------------------------------------------------------ deformed (survey)
def _p_gf_matrix(gfun, ffun, phi=0):
    """P_{g,f} of FORMULAS.md §5, built from the printed formula."""
    gam = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    M = sp.symbols("M_x M_y M_z", real=True)
    g = gfun(*gam) if callable(gfun) else gfun
    f = ffun(*gam) if callable(ffun) else ffun
    grad = [sp.diff(g, c) for c in gam]
    G = eps_matrix(gam)
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = g * G
    mat[3:6, 0:3] = g * G
    mat[3:6, 3:6] = g * eps_matrix(M) + (_dot(grad, M) - g * f * _dot(gam, M) + phi) * G
    return Bivector.from_matrix(mat, gam + M), gam, M


def test_p_gf_with_undefined_g_f_has_the_two_casimirs():
    P, gam, M = _p_gf_matrix(sp.Function("g"), sp.Function("f"), sp.Function("phi")(
        *sp.symbols("gamma_x gamma_y gamma_z", real=True)))
    assert set(find_casimirs(P, 2)) == {_dot(gam, gam), _dot(gam, M)}
    r = rank(P)
    assert r == 4


def _chaplygin(I, d):
    """P_g of FORMULAS.md §7 (38) from the printed formula, with numbers or symbols."""
    gam = sp.symbols("gamma_x gamma_y gamma_z", real=True)
    M = sp.symbols("M_x M_y M_z", real=True)
    a = [1 / (sp.sympify(Ii) + d) for Ii in I]
    Ag = [ai * gi for ai, gi in zip(a, gam)]
    g = sp.sqrt(1 - d * _dot(gam, Ag))
    return p_g(gam, M, g, -(d * _dot(M, Ag) / g)), gam, M


def test_chaplygin_ball_casimirs_with_sqrt_g():
    P, gam, M = _chaplygin((1, 2, 3), 1)
    assert set(find_casimirs(P, 2)) == {_dot(gam, gam), _dot(gam, M)}
    # (M, M) is an integral of the ball (FORMULAS §7) but not a Casimir
    assert not is_casimir(P, _dot(M, M))
    # exact rank at the oracle point (algebraic numbers, g = sqrt(51)/9)
    pt = dict(zip(gam + M, [R(2, 3), R(1, 3), R(2, 3), 1, -2, R(1, 2)]))
    assert rank(P, pt) == 4


def test_chaplygin_ball_singular_set_is_gamma_zero_or_g_zero():
    P, gam, _M = _chaplygin((1, 2, 3), 1)
    S = singular_set(P)
    (comp,) = S.components
    g2 = 1 - (gam[0] ** 2 / 2 + gam[1] ** 2 / 3 + gam[2] ** 2 / 4)
    # each equation is gamma_i * (12 g^2) up to sign: zero set {gamma = 0} U {g = 0}
    assert len(comp) == 3
    for eq, gi in zip(sorted(comp, key=str), sorted(gam, key=str)):
        assert sp.simplify(eq / (gi * g2)).is_constant()


@pytest.mark.slow
def test_chaplygin_ball_casimirs_with_symbolic_parameters():
    I = sp.symbols("I1 I2 I3", positive=True)
    d = sp.Symbol("d", positive=True)
    P, gam, M = _chaplygin(I, d)
    assert set(find_casimirs(P, 2)) == {_dot(gam, gam), _dot(gam, M)}


def test_casimir_modulo_constraint():
    # on the unit sphere (gamma, gamma) = 1, gamma_x**2 + gamma_y**2 + gamma_z**2 - 1 "is" 0
    P = e3("gamma_M")
    g = P.coords[:3]
    x = P.coords[3]
    C = x * (_dot(g, g) - 1)
    assert not is_casimir(P, C)
    assert is_casimir(P, C, constraints=[_dot(g, g) - 1])


def test_suslov_potential_bracket_casimirs():
    # FORMULAS.md §12 (7.2): I11 = 2, I22 = 1, U = 3 gamma_3 + gamma_1**2 gamma_2;
    # Casimirs E = H1 + U and omega_3; rank 4
    g1, g2, g3, w1, w2, w3 = sp.symbols("g1 g2 g3 w1 w2 w3", real=True)
    I11, I22 = 2, 1
    U = 3 * g3 + g1**2 * g2
    dU = [sp.diff(U, v) for v in (g1, g2, g3)]
    coords = (g1, g2, g3, w1, w2, w3)
    comps = {(1, 3): -w2, (2, 3): w1, (4, 2): dU[2] / I11, (4, 3): -dU[1] / I11,
             (5, 1): -dU[2] / I22, (5, 3): dU[0] / I22}
    mat = sp.zeros(6, 6)
    for (i, j), v in comps.items():
        mat[i - 1, j - 1] = v
        mat[j - 1, i - 1] = -v
    P = Bivector.from_matrix(mat, coords)
    pt = dict(zip(coords, [R(2, 3), R(1, 3), R(2, 3), 1, -2, 0]))
    printed = [[0, 0, 2, 0, 3, 0], [0, 0, 1, R(-3, 2), 0, 0], [-2, -1, 0, R(2, 9), R(-4, 9), 0],
               [0, R(3, 2), R(-2, 9), 0, 0, 0], [-3, 0, R(4, 9), 0, 0, 0], [0, 0, 0, 0, 0, 0]]
    assert P.matrix.subs(pt) == sp.Matrix(printed)
    assert rank(P, pt) == 4
    E = (I11 * w1**2 + I22 * w2**2) / 2 + U
    found = find_casimirs(P, 3)
    assert _same_span(found, [w3, E])
    assert rank(P) == 4


# ------------------------------------------------------------------ bad input
def test_bad_input_is_rejected_with_typed_errors():
    P = e3()
    with pytest.raises(InputError):
        find_casimirs(P, 0)
    with pytest.raises(InputError):
        find_casimirs(P, 2.5)
    with pytest.raises(InputError):
        find_casimirs("not a bivector", 2)
    with pytest.raises(UnknownNameError):
        find_casimirs(P, 2, variables=["nope"])
    with pytest.raises(InputError):
        find_casimirs(P, 2, params=["nu_x"])
    with pytest.raises(DimensionError):
        rank(P, [1, 2, 3])
    with pytest.raises(UnknownNameError):
        rank(P, {"nu_x": 1, "bogus": 2})
    with pytest.raises(InputError):
        rank(P, trials=0)
    with pytest.raises(InputError):
        is_casimir(P, "nu_x**2")
    with pytest.raises(SingularSetTooExpensive):
        singular_set(P, max_minors=3)


def test_library_constructors_agree_with_formulas_and_have_the_casimirs():
    from poissonkit.structure.deformed import chaplygin_ball, p_gf

    ball = chaplygin_ball(I=(1, 2, 3), d=1)
    P, gam, M = _chaplygin((1, 2, 3), 1)
    assert ball.coords == P.coords
    assert all(sp.simplify(a - b) == 0 for a, b in zip(ball.matrix, P.matrix))
    assert set(find_casimirs(ball, 2)) == {_dot(gam, gam), _dot(gam, M)}
    Pgf = p_gf(None, None)
    g2, M2 = Pgf.coords[:3], Pgf.coords[3:]
    assert set(find_casimirs(Pgf, 2)) == {_dot(g2, g2), _dot(g2, M2)}


def test_undeclared_parameters_are_rejected():
    x, y, z = sp.symbols("x y z")
    k = sp.Symbol("k")
    P = Bivector.from_matrix([[0, k * z, 0], [-k * z, 0, 0], [0, 0, 0]], [x, y, z])
    assert list(find_casimirs(P, 1, params=[k])) == [z]
    with pytest.raises(InputError):
        find_casimirs(P, 1, params=["other"])
