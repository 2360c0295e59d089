"""find_casimirs normal form: primitive integers, positive grlex lead, reduced; relations.

Truths used: the invariants of U(1) acting on C^2 with equal weights are |z1|^2, |z2|^2 and
Re, Im of z1 conj(z2), with the one relation (Re)^2 + (Im)^2 = |z1|^2 |z2|^2 (the Hopf map;
classical invariant theory); the Casimirs of so(3), e(3), sl(2) (textbook). The properties are
checked with sympy's own Poly (content, grlex leading coefficient), not with the code under
test.
"""

from __future__ import annotations

import pytest
import sympy as sp

import poissonkit as pk
from poissonkit.structure import Bivector, e3, eps_matrix, find_casimirs, lie_poisson


def _assert_normal(C, coords):
    p = sp.Poly(C, *coords)
    assert p.domain.is_ZZ, C
    assert p.content() == 1, C
    assert p.LC(order="grlex") > 0, C


def _hopf():
    x1, y1, x2, y2, t = sp.symbols("x1 y1 x2 y2 t", real=True)
    V = [-y1, x1, -y2, x2, 0]          # the U(1) rotation of both planes
    W = [0, 0, 0, 0, 1]                # commutes with V, so V ^ W is Poisson
    M = sp.Matrix(5, 5, lambda i, j: V[i] * W[j] - V[j] * W[i])
    return Bivector.from_matrix(M, [x1, y1, x2, y2, t])


@pytest.mark.parametrize("name,degree", [("sl(2)", 2), ("gl(2)", 2), ("so(4)", 2), ("sl(3)", 3),
                                         ("sp(4)", 4), ("su(3)", 3), ("so(3,1)", 2)])
def test_generators_have_primitive_integer_coefficients_and_positive_grlex_lead(name, degree):
    P = lie_poisson(name)
    found = find_casimirs(P, degree)
    assert len(found) > 0
    for C in found:
        _assert_normal(C, P.coords)


def test_textbook_forms_come_out_with_their_textbook_sign_and_scale():
    # gl(2): trace and determinant (was -det); sl(2): x_11^2 + x_12 x_21 = -det X
    g = pk.lie_algebra("gl(2)")
    x11, x12, x21, x22 = g.coords
    assert list(find_casimirs(g.bivector, 2)) == [x11 + x22, x11 * x22 - x12 * x21]
    s = pk.lie_algebra("sl(2)")
    assert list(find_casimirs(s.bivector, 2)) == [sp.expand(-s.matrix.det())]
    assert list(find_casimirs(pk.so3(), 3)) == [sum(m ** 2 for m in pk.so3().coords)]


def test_normal_form_does_not_depend_on_the_scale_or_sign_of_the_bracket():
    for name, d in (("sl(3)", 3), ("so(5)", 4)):
        P = lie_poisson(name)
        assert list(find_casimirs(P * 3, d)) == list(find_casimirs(P, d)) \
            == list(find_casimirs(-P, d))


def test_no_generator_is_a_polynomial_in_lower_degree_ones():
    # so(5) to degree 6: C2, C4; C2^2, C2 C4, C2^3 are not reported
    P = lie_poisson("so(5)")
    found = find_casimirs(P, 4)
    assert [sp.Poly(C, *P.coords).total_degree() for C in found] == [2, 4]
    C2, C4 = found
    # reduced: the leading monomial of C2^2 does not occur in C4
    lead = sp.Poly(C2 ** 2, *P.coords).monoms(order="grlex")[0]
    assert sp.Poly(C4, *P.coords).coeff_monomial(lead) == 0
    # e(3) to degree 6: still the two quadratic ones, and no relation among them
    big = find_casimirs(e3(), 6)
    assert len(big) == 2 and big.relations == ()


def test_relations_among_generators_hopf():
    P = _hopf()
    x1, y1, x2, y2, _t = P.coords
    found = find_casimirs(P, 4)
    assert set(found) == {x1 ** 2 + y1 ** 2, x2 ** 2 + y2 ** 2, x1 * x2 + y1 * y2,
                          x1 * y2 - x2 * y1}
    for C in found:
        _assert_normal(C, P.coords)
    assert len(found.relations) == 1
    R = found.relations[0]
    subs = dict(zip(found.symbols, found.generators))
    assert sp.expand(R.subs(subs)) == 0
    # the Hopf relation, up to the normal form's sign: |z1|^2 |z2|^2 - Re^2 - Im^2
    C = dict(zip(found.generators, found.symbols))
    hopf = C[x1 ** 2 + y1 ** 2] * C[x2 ** 2 + y2 ** 2] - C[x1 * x2 + y1 * y2] ** 2 \
        - C[x1 * y2 - x2 * y1] ** 2
    assert sp.expand(R - hopf) == 0 or sp.expand(R + hopf) == 0
    # below weight 4 the relation cannot be seen
    assert find_casimirs(P, 3).relations == ()


def test_relation_symbols_avoid_coordinate_names():
    P = Bivector.from_matrix(sp.zeros(2, 2), ["C_1", "x"])
    found = find_casimirs(P, 1)
    assert [str(s) for s in found.symbols] == ["_C_1", "_C_2"]


def test_parameters_normal_form():
    # e(3) with the shifted momentum M + k S: Casimir (g, M) + k (g, S); leading coefficient 1
    g = sp.symbols("g1 g2 g3", real=True)
    M = sp.symbols("M1 M2 M3", real=True)
    k = sp.Symbol("k")
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = eps_matrix(g)
    mat[3:6, 0:3] = eps_matrix(g)
    mat[3:6, 3:6] = eps_matrix([m + k * (i + 1) / 2 for i, m in enumerate(M)])
    P = Bivector.from_matrix(mat, g + M)
    found = find_casimirs(P, 2, params=[k])
    assert found[0] == sum(x ** 2 for x in g)
    # cleared of the denominator 2 in the parameter term, primitive over Z[k]
    want = sp.expand(2 * sum(gi * Mi for gi, Mi in zip(g, M)) + k * (g[0] + 2 * g[1] + 3 * g[2]))
    assert sp.expand(found[1] - want) == 0
