"""Deformed brackets of the survey against the oracle values of FORMULAS.md §5–§10.

Every number below is copied from ``shared/reference/FORMULAS.md`` (section cited per test).
"""

from __future__ import annotations

import pytest
import sympy as sp

from poissonkit.errors import DimensionError, InputError, NotPoissonError
from poissonkit.structure import (
    Bivector,
    canonical,
    canonical_deformation,
    chaplygin_ball,
    chaplygin_gyrostat,
    check_jacobi,
    deform,
    e3,
    p_gf,
    veselova,
    veselova_gyrostat,
)
from poissonkit.structure.deformed import chaplygin_ball_system, gamma_symbols
from poissonkit.structure.jacobi import is_zero_expression

R = sp.Rational
GAMMA = (R(2, 3), R(1, 3), R(2, 3))
M_PT = (1, -2, R(1, 2))


def at(P: Bivector, gamma=GAMMA, second=M_PT) -> sp.Matrix:
    return P.matrix.subs(dict(zip(P.coords, tuple(gamma) + tuple(second)))).applyfunc(sp.radsimp)


def entry(P: Bivector, a: str, b: str, values) -> sp.Expr:
    return sp.radsimp(values[P.index(a), P.index(b)])


def test_p_gf_oracles_section_5():
    P = p_gf("1 + gamma_x^2", "gamma_y", "gamma_z")
    v = at(P)
    assert [entry(P, "M_x", "M_y", v), entry(P, "M_x", "M_z", v), entry(P, "M_y", "M_z", v)] == \
        [R(947, 486), R(553, 243), R(649, 243)]
    assert entry(P, "M_x", "gamma_y", v) == R(26, 27)
    P0 = p_gf(lambda g: 1 + g[0] ** 2, lambda g: g[1])        # phi = 0
    v0 = at(P0)
    assert [entry(P0, "M_x", "M_y", v0), entry(P0, "M_x", "M_z", v0),
            entry(P0, "M_y", "M_z", v0)] == [R(731, 486), R(607, 243), R(541, 243)]


def test_p_gf_reduces_to_e3_and_has_casimirs():
    gamma, M = gamma_symbols()
    assert p_gf(1, 0).matrix == e3("gamma_M").matrix
    P = p_gf(None, None, None)
    for C in (sum(g * g for g in gamma), sum(g * m for g, m in zip(gamma, M))):
        assert all(is_zero_expression(e) for e in P.matrix * P.gradient(C))


def test_canonical_deformation_oracles_section_6():
    P = canonical_deformation(lambda q: 1 + q[0] ** 2)
    v = at(P, GAMMA, (1, -2, R(1, 2)))
    assert entry(P, "q_x", "p_x", v) == R(13, 9)
    assert [entry(P, "p_x", "p_y", v), entry(P, "p_x", "p_z", v), entry(P, "p_y", "p_z", v)] == \
        [R(8, 3), R(-2, 3), 0]
    q, p = P.coords[:3], P.coords[3:]
    M = sp.Matrix(q).cross(sp.Matrix(p))
    point = dict(zip(P.coords, GAMMA + (1, -2, R(1, 2))))
    assert list(M.subs(point)) == [R(3, 2), R(1, 3), R(-5, 3)]
    assert P.bracket(M[0], M[1]).subs(point) == R(-29, 27)


def test_canonical_deformation_is_push_forward_of_canonical():
    # (q, p) -> (q, g(q) p): P = J P0 J^T (FORMULAS.md §6), checked for an undefined g
    P = canonical_deformation()
    q, p = P.coords[:3], P.coords[3:]
    g = sp.Function("g")(*q)
    Q = canonical(3).subs({}).matrix
    image = list(q) + [g * pi for pi in p]
    J = sp.Matrix(image).jacobian(q + p)
    pushed = (J * Q * J.T).subs({pi: pi / g for pi in p}, simultaneous=True)
    assert all(sp.expand(e) == 0 for e in (pushed - P.matrix))


def test_chaplygin_ball_oracles_section_7():
    P = chaplygin_ball(I=(1, 2, 3), d=1)
    v = at(P)
    s = sp.sqrt(51)
    assert [entry(P, "gamma_x", "M_y", v), entry(P, "gamma_x", "M_z", v),
            entry(P, "gamma_y", "M_z", v)] == [2 * s / 27, -s / 27, 2 * s / 27]
    assert [entry(P, "M_x", "M_y", v), entry(P, "M_x", "M_z", v), entry(P, "M_y", "M_z", v)] == \
        [5 * s / 153, 143 * s / 612, 3 * s / 34]


def test_chaplygin_ball_is_p_g0_section_7():
    gamma, M = gamma_symbols()
    a = sp.symbols("a1:4", positive=True)
    d = sp.Symbol("d", positive=True)
    g = sp.sqrt(1 - d * sum(ai * gi ** 2 for ai, gi in zip(a, gamma)))
    diff = chaplygin_ball(a=a, d=d).matrix - p_gf(g, 0).matrix
    assert all(is_zero_expression(e) for e in diff)


def test_chaplygin_ball_and_gyrostat_flow_oracles_section_7():
    point = dict(zip(gamma_symbols()[0] + gamma_symbols()[1], GAMMA + M_PT))
    ball = chaplygin_ball_system(I=(1, 2, 3), d=1)
    X = [sp.radsimp(e.subs(point)) for e in ball.vector_field()]
    assert X == [R(49, 102), R(29, 102), R(-127, 204), R(-5, 136), R(1, 8), R(39, 68)]
    assert sp.radsimp((2 * ball.hamiltonian).subs(point)) == R(133, 68)
    gyro = chaplygin_ball_system(I=(1, 2, 3), d=1, S=(1, 0, -1))
    Xs = [sp.radsimp(e.subs(point)) for e in gyro.vector_field()]
    assert Xs == [R(49, 102), R(29, 102), R(-127, 204), R(-91, 136), R(-89, 136), R(-1, 17)]
    # the representation reproduces the original equations (34)/(49) identically
    for system in (ball, gyro):
        X = system.vector_field()
        assert all(is_zero_expression(X[i] - system.original[c])
                   for i, c in enumerate(system.coords))


def test_gyrostat_casimir_and_jacobi_section_7():
    P = chaplygin_gyrostat()
    gamma, M = gamma_symbols()
    S = sp.symbols("S1:4", real=True)
    C = sum(g * (m + s) for g, m, s in zip(gamma, M, S))
    assert all(is_zero_expression(e) for e in P.matrix * P.gradient(C))
    assert check_jacobi(P, method="exact").is_poisson


def test_veselova_oracles_section_9():
    K_PT = (1, 2, -1)
    s2 = sp.sqrt(2)
    for P in (veselova(a=(1, 2, 3), b=R(2, 3)), veselova(a=(1, 2, 3))):  # b = (gamma, K) = 2/3
        v = at(P, GAMMA, K_PT)
        assert [entry(P, "K_x", "K_y", v), entry(P, "K_x", "K_z", v), entry(P, "K_y", "K_z", v)] \
            == [-11 * s2 / 9, -17 * s2 / 9, 7 * s2 / 9]
        assert entry(P, "K_x", "gamma_y", v) == 2 * s2 / 3
    b = sp.Symbol("b")
    assert check_jacobi(veselova(b=b), method="exact").is_poisson
    assert check_jacobi(veselova(), method="exact").is_poisson


def test_veselova_gyrostat_oracles_section_10():
    P = veselova_gyrostat(a=(1, 2, 3), k=(1, 1, 0))
    v = at(P, GAMMA, (1, 2, -1))
    s2 = sp.sqrt(2)
    assert [entry(P, "K_x", "K_y", v), entry(P, "K_x", "K_z", v), entry(P, "K_y", "K_z", v)] == \
        [-14 * s2 / 9, -49 * s2 / 18, 13 * s2 / 9]
    assert entry(P, "K_x", "gamma_y", v) == 2 * s2 / 3
    assert check_jacobi(veselova_gyrostat(), method="exact").is_poisson


def test_deform_declares_and_checks():
    P = e3("gamma_M")
    gamma = P.coords[:3]
    Q = sp.zeros(6, 6)
    Q[3:6, 3:6] = sp.Matrix([[0, gamma[2], -gamma[1]], [-gamma[2], 0, gamma[0]],
                             [gamma[1], -gamma[0], 0]])          # Remark 5 with phi = 1
    assert deform(P, Q).dim == 6
    bad = sp.zeros(6, 6)
    bad[3, 4], bad[4, 3] = P.coords[3] ** 2, -P.coords[3] ** 2
    with pytest.raises(NotPoissonError):
        deform(P, bad)
    assert deform(P, bad, check=False).matrix[3, 4] == P.coords[5] + P.coords[3] ** 2
    with pytest.raises(DimensionError):
        deform(P, sp.zeros(3, 3))


def test_bad_input_is_typed():
    with pytest.raises(InputError):
        p_gf("1 + M_x")                     # g must be a function of gamma only
    with pytest.raises(InputError):
        p_gf(lambda g: sp.Symbol("M_x", real=True))
    with pytest.raises(InputError):
        chaplygin_ball(I=(1, 2, 3), a=(1, 2, 3))
    with pytest.raises(DimensionError):
        chaplygin_ball(I=(1, 2))
    with pytest.raises(InputError):
        veselova(b=gamma_symbols(("gamma", "K"))[0][0])
    with pytest.raises(InputError):
        p_gf(names=("gamma", "gamma"))
    with pytest.raises(InputError):
        p_gf("__import__('os').system('echo x')")
