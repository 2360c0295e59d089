"""poissonkit.compat.PoissonGeometry against the installed PyPI package ``poissongeometry`` 1.1.1
(imported as ``poisson.poisson``), on its documented examples and our own cases, and against
independent truths (FORMULAS.md oracles, definitions evaluated directly).

Outputs are compared semantically: both strings are parsed with the allow-list parser and the
difference must be exactly zero.
"""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
import sympy as sp

from poissonkit.compat import PoissonGeometry
from poissonkit.compat._inputs import Reader, is_zero

# The PyPI package is reached through the ``peer`` fixture (tests/compat/conftest.py): without
# it only the comparisons skip (fail under CI); documented examples and oracles still run.

SO3 = {(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}
SL2 = {(1, 2): "-x3", (1, 3): "-x2", (2, 3): "x1"}
# The Schouten oracle of FORMULAS.md §0: Q = [[0, y1 y2, 0], [-y1 y2, 0, y3], [0, -y3, 0]].
Q_ORACLE = {(1, 2): "x1*x2", (2, 3): "x3"}
# A quadratic Poisson bivector and a non-Poisson perturbation of so(3).
QUADRATIC = {(1, 2): "a*x1*x2", (1, 3): "-b*x1*x3", (2, 3): "b*x2*x3"}
NOT_POISSON = {(1, 2): "x3 + x1**2", (1, 3): "-x2", (2, 3): "x1*x2"}
RATIONAL = {(1, 2): "x3/(1 + x1**2)", (1, 3): "-x2/(1 + x1**2)", (2, 3): "x1/(1 + x1**2)"}
# e(3) in the (gamma, L) order of FORMULAS.md §2 on x1..x6.
E3 = {(1, 5): "x3", (1, 6): "-x2", (2, 4): "-x3", (2, 6): "x1", (3, 4): "x2", (3, 5): "-x1",
      (4, 5): "x6", (4, 6): "-x5", (5, 6): "x4"}

BIVECTORS_3D = [SO3, SL2, Q_ORACLE, QUADRATIC, NOT_POISSON, RATIONAL]
FUNCTIONS_3D = ["x1 + x2 + x3", "x1**2 + x2**2 + x3**2", "x1*x2*exp(x3)", "sin(x1)*x2 - x3**3"]
# NumericalPoissonGeometry's documented Hamiltonian; the peer takes ~10 s per call on it.
RATIONAL_H = "1/(x1 - x2) + 1/(x1 - x3) + 1/(x2 - x3)"


def _same(theirs: object, ours: object, dim: int = 3) -> bool:
    """Exact semantic equality of two outputs (strings, dicts of strings, bools)."""
    r = Reader(dim)
    if isinstance(theirs, bool) or isinstance(ours, bool):
        return theirs is ours
    if isinstance(theirs, dict) and isinstance(ours, dict):
        keys = set(theirs) | set(ours)
        return all(is_zero(r.expr(str(theirs.get(k, "0"))) - r.expr(str(ours.get(k, "0"))))
                   for k in keys)
    return is_zero(r.expr(str(theirs)) - r.expr(str(ours)))


# ---------------------------------------------------------------------- documented examples
def test_bivector_to_matrix_equals_peer(peer):
    assert PoissonGeometry(3).bivector_to_matrix(SO3) == peer(3).bivector_to_matrix(SO3)


def test_bivector_to_matrix_matches_documented_example():
    pg = PoissonGeometry(3)
    x1, x2, x3 = sp.symbols("x1:4")
    assert pg.bivector_to_matrix(SO3) == sp.Matrix([[0, x3, -x2], [-x3, 0, x1], [x2, -x1, 0]])
    # the documented LaTeX is of the 3x3 matrix (the package itself prints a padded 4x4 one)
    assert pg.bivector_to_matrix(SO3, latex=True) == sp.latex(pg.bivector_to_matrix(SO3))
    assert pg.bivector_to_matrix(SO3, latex_format=True) == pg.bivector_to_matrix(SO3, latex=True)


def test_sharp_morphism_with_parameters_equals_peer(peer):
    one_form = {(1,): "a1*x1", (2,): "a2*x2", (3,): "a3*x3"}
    assert _same(peer(3).sharp_morphism(SO3, one_form),
                 PoissonGeometry(3).sharp_morphism(SO3, one_form))


def test_sharp_morphism_documented_example_with_parameters():
    one_form = {(1,): "a1*x1", (2,): "a2*x2", (3,): "a3*x3"}
    ours = PoissonGeometry(3).sharp_morphism(SO3, one_form)
    # the docstring's stated result
    assert _same({(1,): "x2*(-a2*x3 + a3*x3)", (2,): "x1*(a1*x3 - a3*x3)",
                  (3,): "x1*x2*(-a1 + a2)"}, ours)


def test_hamiltonian_vf_documented_example_and_sign_against_poissonkit():
    pg = PoissonGeometry(3)
    ours = pg.hamiltonian_vf(SO3, "x1 + x2 + x3")
    assert _same({(1,): "x2 - x3", (2,): "-x1 + x3", (3,): "x1 - x2"}, ours)
    # PoissonGeometry's X_h = {h, .} is minus poissonkit's P dh (conventions.py)
    from poissonkit.structure import Bivector

    P = Bivector.from_components(SO3, pg.coords)
    X = P.hamiltonian_vector_field(sum(pg.coords))
    assert all(is_zero(Reader(3).expr(ours[(i + 1,)]) + X[i]) for i in range(3))


# every bivector with one function by default; the full product is marked slow
_PAIRS = [(b, FUNCTIONS_3D[k % len(FUNCTIONS_3D)]) for k, b in enumerate(BIVECTORS_3D)]
_MORE_PAIRS = [(b, h) for b in BIVECTORS_3D for h in FUNCTIONS_3D if (b, h) not in _PAIRS]


@pytest.mark.parametrize("biv, h", _PAIRS + [pytest.param(b, h, marks=pytest.mark.slow)
                                             for b, h in _MORE_PAIRS])
def test_hamiltonian_vf_equals_peer(biv, h, peer):
    assert _same(peer(3).hamiltonian_vf(biv, h), PoissonGeometry(3).hamiltonian_vf(biv, h))


@pytest.mark.slow
def test_hamiltonian_vf_rational_function_equals_peer(peer):
    assert _same(peer(3).hamiltonian_vf(SO3, RATIONAL_H), PoissonGeometry(3).hamiltonian_vf(SO3, RATIONAL_H))


@pytest.mark.slow
@pytest.mark.parametrize("biv", BIVECTORS_3D[1:])
def test_hamiltonian_vf_rational_function_equals_peer_on_more_bivectors(biv, peer):
    assert _same(peer(3).hamiltonian_vf(biv, RATIONAL_H), PoissonGeometry(3).hamiltonian_vf(biv, RATIONAL_H))


@pytest.mark.parametrize("biv", BIVECTORS_3D)
def test_poisson_bracket_equals_peer(biv, peer):
    pg, th = PoissonGeometry(3), peer(3)
    for f, g in [("x1*x2", "exp(x3)"), ("x1**2 + x2**2 + x3**2", "x2"), ("x1", "x1")]:
        ours = pg.poisson_bracket(biv, f, g)
        assert isinstance(ours, str)
        assert _same(th.poisson_bracket(biv, f, g), ours)


def test_poisson_bracket_documented_example():
    ours = PoissonGeometry(3).poisson_bracket(SO3, "x1 + x2 + x3", "a1*x1 + a2*x2 + a3*x3")
    assert _same("a1*(x2 - x3) - a2*(x1 - x3) + a3*(x1 - x2)", ours)


@pytest.mark.parametrize("biv", BIVECTORS_3D)
def test_casimir_and_kernel_equal_peer(biv, peer):
    pg, th = PoissonGeometry(3), peer(3)
    for K in ["x1**2 + x2**2 + x3**2", "x1**2 - x2**2 + x3**2", "x3", "x1*x2*x3"]:
        assert pg.is_casimir(biv, K) is th.is_casimir(biv, K)
    for form in [{(1,): "x1", (2,): "x2", (3,): "x3"}, {(3,): "1"}, {(1,): "x2", (2,): "-x1"}]:
        assert pg.is_in_kernel(biv, form) is th.is_in_kernel(biv, form)


def test_casimirs_of_so3_and_sl2():
    pg = PoissonGeometry(3)
    assert pg.is_casimir(SO3, "x1**2 + x2**2 + x3**2")
    assert not pg.is_casimir(SO3, "x1**2 - x2**2 + x3**2")
    assert pg.is_casimir(SL2, "x1**2 + x2**2 - x3**2")
    assert pg.is_in_kernel(SO3, {(1,): "x1", (2,): "x2", (3,): "x3"})


def test_one_forms_bracket_documented_example_equals_peer(peer):
    a = {(1,): "a1*x1", (2,): "a2*x2", (3,): "a3*x3"}
    b = {(1,): "b1*x1", (2,): "b2*x2", (3,): "b3*x3"}
    assert _same(peer(3).one_forms_bracket(SO3, a, b), PoissonGeometry(3).one_forms_bracket(SO3, a, b))


def test_one_forms_bracket_documented_example():
    a = {(1,): "a1*x1", (2,): "a2*x2", (3,): "a3*x3"}
    b = {(1,): "b1*x1", (2,): "b2*x2", (3,): "b3*x3"}
    ours = PoissonGeometry(3).one_forms_bracket(SO3, a, b)
    c = "(b1*(a2 - a3) - b2*(a1 - a3) + b3*(a1 - a2))"
    assert _same({(1,): f"-x2*x3*{c}", (2,): f"-x1*x3*{c}", (3,): f"-x1*x2*{c}"}, ours)


@pytest.mark.parametrize("biv", [SO3, Q_ORACLE, pytest.param(RATIONAL, marks=pytest.mark.slow)])
def test_one_forms_bracket_equals_peer_and_exact_forms(biv, peer):
    pg, th = PoissonGeometry(3), peer(3)
    a = {(1,): "x2*x3", (2,): "x1", (3,): "x3**2"}
    b = {(1,): "x3", (2,): "x1*x2", (3,): "1"}
    assert _same(th.one_forms_bracket(biv, a, b), pg.one_forms_bracket(biv, a, b))
    # independent truth: {df, dg}_P = d{f, g}
    r = Reader(3)
    f, g = "x1*x2 + x3", "x2*exp(x1)"
    df = {(i + 1,): str(sp.diff(r.expr(f), x)) for i, x in enumerate(pg.coords)}
    dg = {(i + 1,): str(sp.diff(r.expr(g), x)) for i, x in enumerate(pg.coords)}
    bracket = r.expr(pg.poisson_bracket(biv, f, g))
    d_bracket = {(i + 1,): str(sp.diff(bracket, x)) for i, x in enumerate(pg.coords)}
    assert _same(d_bracket, pg.one_forms_bracket(biv, df, dg))


def test_gauge_transformation_equals_peer(peer):
    P = {(1, 2): "P12", (1, 3): "P13", (2, 3): "P23"}
    lam = {(1, 2): "L12", (1, 3): "L13", (2, 3): "L23"}
    pg, th = PoissonGeometry(3), peer(3)
    ours_biv, ours_det = pg.gauge_transformation(P, lam, det=True)
    th_biv, th_det = th.gauge_transformation(P, lam, det=True)
    assert _same(th_biv, ours_biv) and _same(th_det, ours_det)
    assert _same(th_det, pg.gauge_transformation(P, lam, gauge_biv=False, det=True))
    assert th.gauge_transformation({(1, 2): "1"}, {(1, 2): "-1"}) is False


def test_gauge_transformation_documented_example():
    P = {(1, 2): "P12", (1, 3): "P13", (2, 3): "P23"}
    lam = {(1, 2): "L12", (1, 3): "L13", (2, 3): "L23"}
    pg = PoissonGeometry(3)
    ours_biv, ours_det = pg.gauge_transformation(P, lam, det=True)
    s = "(L12*P12 + L13*P13 + L23*P23 + 1)"
    assert _same({(1, 2): f"P12/{s}", (1, 3): f"P13/{s}", (2, 3): f"P23/{s}"}, ours_biv)
    assert _same(f"{s}**2", ours_det)
    assert pg.gauge_transformation(P, lam, gauge_biv=False) == {}
    assert _same(ours_det, pg.gauge_transformation(P, lam, gauge_biv=False, det=True))


def test_gauge_transformation_singular_returns_false():
    # P = [[0, 1], [-1, 0]], B = [[0, -1], [1, 0]]: B P = I, so det(I - B P) = 0.
    assert PoissonGeometry(2).gauge_transformation({(1, 2): "1"}, {(1, 2): "-1"}) is False


def test_flaschka_ratiu_equals_peer(peer):
    casimirs = ["x1**2 + x2**2 + x3**2", "x4"]
    pg, th = PoissonGeometry(4), peer(4)
    assert _same(th.flaschka_ratiu_bivector(casimirs), pg.flaschka_ratiu_bivector(casimirs), 4)
    ours_b, ours_w = pg.flaschka_ratiu_bivector(casimirs, symplectic_form=True)
    th_b, th_w = th.flaschka_ratiu_bivector(casimirs, symplectic_form=True)
    assert _same(th_b, ours_b, 4) and _same(th_w, ours_w, 4)


def test_flaschka_ratiu_documented_example_and_its_casimirs():
    casimirs = ["x1**2 + x2**2 + x3**2", "x4"]
    pg = PoissonGeometry(4)
    ours = pg.flaschka_ratiu_bivector(casimirs)
    assert _same({(1, 2): "-2*x3", (1, 3): "2*x2", (2, 3): "-2*x1"}, ours, 4)
    # independent truths: Poisson, with the given Casimirs
    assert pg.is_poisson_bivector(ours)
    assert all(pg.is_casimir(ours, K) for K in casimirs)


def test_flaschka_ratiu_in_dimension_5_is_poisson_with_given_casimirs():
    casimirs = ["x1*x2 + x3", "x4**2 + x5", "x1 + x5*x3"]
    pg = PoissonGeometry(5)
    P = pg.flaschka_ratiu_bivector(casimirs)
    assert P and pg.is_poisson_bivector(P)
    assert all(pg.is_casimir(P, K) for K in casimirs)


@pytest.mark.parametrize("biv", [
    SO3, SL2, {(1, 2): "x1"}, {(1, 3): "x1", (2, 3): "x2"}, {(2, 3): "x1"},
    {(1, 3): "-x2", (2, 3): "x1"}, {(1, 3): "x2", (2, 3): "x1"},
    {(1, 2): "x3", (1, 3): "x2", (2, 3): "x1"}, {(1, 3): "x1 + x2", (2, 3): "x2"},
    {(1, 2): "2*x3 + x1", (1, 3): "-x2", (2, 3): "x1 + x3"},
])
def test_linear_normal_form_equals_peer(biv, peer):
    assert _same(peer(3).linear_normal_form_R3(biv), PoissonGeometry(3).linear_normal_form_R3(biv))


def test_linear_normal_forms_random_unimodular_algebras_equal_peer(peer):
    rng = random.Random(7)
    pg, th = PoissonGeometry(3), peer(3)
    x = sp.symbols("x1:4")
    for _ in range(5):
        S = sp.Matrix(3, 3, lambda i, j: rng.randint(-2, 2))
        S = S + S.T
        v = S * sp.Matrix(x)
        biv = {k: str(e) for k, e in {(1, 2): v[2], (1, 3): -v[1], (2, 3): v[0]}.items() if e != 0}
        if biv:
            assert _same(th.linear_normal_form_R3(biv), pg.linear_normal_form_R3(biv))


def test_isomorphic_lie_poisson_documented_example_equals_peer(peer):
    assert peer(3).isomorphic_lie_poisson_R3(SO3, {(1, 2): "x1"}) is False


def test_isomorphic_lie_poisson_documented_example():
    pg = PoissonGeometry(3)
    assert pg.isomorphic_lie_poisson_R3(SO3, {(1, 2): "x1"}) is False
    # so(3) in another basis (x -> 2x, permuted) is isomorphic to so(3); sl(2) is not
    assert pg.isomorphic_lie_poisson_R3(SO3, {(1, 2): "2*x3", (1, 3): "-2*x2", (2, 3): "2*x1"})
    assert not pg.isomorphic_lie_poisson_R3(SO3, SL2)
    # the documented call with explicit "0" entries works here (the package raises Nonlinear)
    assert pg.isomorphic_lie_poisson_R3(SO3, {(1, 2): "x1", (1, 3): "0", (2, 3): "0"}) is False


# ---------------------------------------------------------------------- Schouten calculus
def test_jacobiator_equals_peer(peer):
    assert _same(peer(3).jacobiator(Q_ORACLE), PoissonGeometry(3).jacobiator(Q_ORACLE))


def test_jacobiator_matches_formulas_oracle():
    # FORMULAS.md §0: [Q, Q]^{123} = -2 y1 y3 (= -6 at y = (1, 2, 3)).
    pg = PoissonGeometry(3)
    ours = pg.jacobiator(Q_ORACLE)
    assert _same({(1, 2, 3): "-2*x1*x3"}, ours)
    # FORMULAS.md §0: Q^{ij} = eps_ijk v_k with v = (-y2, y1, 1) has [Q, Q]^{123} = -4.
    assert _same({(1, 2, 3): "-4"}, pg.jacobiator({(1, 2): "1", (1, 3): "-x1", (2, 3): "-x2"}))
    assert pg.jacobiator(SO3) == {}


@pytest.mark.parametrize("biv", BIVECTORS_3D)
def test_is_poisson_bivector_equals_peer(biv, peer):
    assert PoissonGeometry(3).is_poisson_bivector(biv) is peer(3).is_poisson_bivector(biv)


def test_is_poisson_bivector_positive_and_negative_controls():
    pg = PoissonGeometry(3)
    assert pg.is_poisson_bivector(SO3) and pg.is_poisson_bivector(SL2)
    assert pg.is_poisson_bivector(RATIONAL)  # conformal so(3) in dimension 3 stays Poisson
    assert not pg.is_poisson_bivector(Q_ORACLE) and not pg.is_poisson_bivector(NOT_POISSON)
    assert PoissonGeometry(6).is_poisson_bivector(E3)


@pytest.mark.parametrize("biv", [Q_ORACLE, pytest.param(SO3, marks=pytest.mark.slow),
                                 pytest.param(QUADRATIC, marks=pytest.mark.slow)])
@pytest.mark.parametrize("mv", [
    {(1,): "x1**2"}, {(1,): "x1", (2,): "x2", (3,): "x3"}, {(1,): "x2", (2,): "-x1"},
    {(1, 2): "x3**2"}, {(1, 2): "x1*x3", (2, 3): "exp(x1)"}, {(1, 2, 3): "x1*x2*x3"},
])
def test_coboundary_operator_equals_peer(biv, mv, peer):
    assert _same(peer(3).coboundary_operator(biv, mv), PoissonGeometry(3).coboundary_operator(biv, mv))


def test_coboundary_operator_of_function_equals_peer(peer):
    assert _same(peer(3).coboundary_operator(SO3, "x1**2*x3"),
                 PoissonGeometry(3).coboundary_operator(SO3, "x1**2*x3"))


def test_coboundary_operator_of_function_and_documented_example():
    pg = PoissonGeometry(3)
    assert pg.coboundary_operator(SO3, {(1, 2, 3): "x1*x2*x3"}) == {}
    # [P, f] = P df = -X_f (PoissonGeometry's X_f)
    ours = pg.coboundary_operator(SO3, "x1**2*x3")
    minus_x = {k: f"-({v})" for k, v in pg.hamiltonian_vf(SO3, "x1**2*x3").items()}
    assert _same(minus_x, ours)


def test_coboundary_of_bivector_and_trivector_in_dimension_4_equals_peer(peer):
    pg, th = PoissonGeometry(4), peer(4)
    P = {(1, 2): "x3", (3, 4): "x1*x2", (1, 4): "1"}
    A = {(1, 2): "x4", (2, 3): "x1**2"}
    assert _same(th.coboundary_operator(P, A), pg.coboundary_operator(P, A), 4)
    B = {(1, 2, 3): "x4"}
    assert _same(th.coboundary_operator(P, B), pg.coboundary_operator(P, B), 4)


def test_coboundary_of_vector_field_is_minus_lie_derivative():
    # [P, X] = -L_X P (conventions.py); L_X P computed here from its coordinate definition
    pg = PoissonGeometry(3)
    x = pg.coords
    r = Reader(3)
    X = [x[0] ** 2, x[1] * x[2], sp.sin(x[0])]
    P = sp.Matrix(pg.bivector_to_matrix(Q_ORACLE))
    ours = pg.coboundary_operator(Q_ORACLE, {(i + 1,): str(X[i]) for i in range(3)})
    for i in range(3):
        for j in range(i + 1, 3):
            lie = (sum(X[k] * sp.diff(P[i, j], x[k]) for k in range(3))
                   - sum(P[k, j] * sp.diff(X[i], x[k]) + P[i, k] * sp.diff(X[j], x[k])
                         for k in range(3)))
            assert is_zero(r.expr(ours.get((i + 1, j + 1), "0")) + lie)


def test_is_poisson_vf_and_pair_equal_peer(peer):
    pg, th = PoissonGeometry(3), peer(3)
    euler = {(1,): "x1", (2,): "x2", (3,): "x3"}
    assert th.is_poisson_vf(SO3, euler) is False
    assert th.is_poisson_vf(SO3, {(1,): "x2", (2,): "-x1"}) is True
    assert th.is_poisson_pair(QUADRATIC, {(1, 2): "x3**2"}) is True
    assert pg.is_poisson_pair(SO3, {(1, 2): "x1"}) is th.is_poisson_pair(SO3, {(1, 2): "x1"})


def test_is_poisson_vf_and_pair_documented_examples():
    pg = PoissonGeometry(3)
    assert pg.is_poisson_vf(SO3, {(1,): "x1", (2,): "x2", (3,): "x3"}) is False
    assert pg.is_poisson_vf(SO3, {(1,): "x2", (2,): "-x1"}) is True
    # a Hamiltonian vector field is always Poisson
    assert pg.is_poisson_vf(QUADRATIC, pg.hamiltonian_vf(QUADRATIC, "x1*x2 + x3**2"))
    assert pg.is_poisson_pair(QUADRATIC, {(1, 2): "x3**2"}) is True


# ---------------------------------------------------------------------- curl and modular field
def test_curl_fix_shows_the_peer_differentiates_by_the_wrong_coordinate(peer):
    """A = x2 d1^d3, density f = exp(x3): the d1 component of D(A) is -(d3 A + A d3 f / f) = -x2.

    PoissonGeometry 1.1.1 uses d_{x2} f (x2 = the coordinate at the *position* of 3 in (1, 3))
    and gets 0; with f = exp(x2) it gets -x2 where the right answer is 0.
    """
    pg, th = PoissonGeometry(3), peer(3)
    A = {(1, 3): "x2"}
    assert not _same(th.curl_operator(A, "exp(x3)"), pg.curl_operator(A, "exp(x3)"))
    assert not _same(th.curl_operator(A, "exp(x2)"), pg.curl_operator(A, "exp(x2)"))


def test_curl_of_bivector_differentiates_the_density_by_the_right_coordinate():
    # A = x2 d1^d3: D(A)^1 = -(d3 A^{13} + A^{13} d3 f / f), independent of d2 f
    pg = PoissonGeometry(3)
    A = {(1, 3): "x2"}
    assert _same({(1,): "-x2", (3,): "0"}, pg.curl_operator(A, "exp(x3)"))
    assert _same({(1,): "0", (3,): "0"}, pg.curl_operator(A, "exp(x2)"))


def test_curl_of_vector_field_is_weighted_divergence():
    # div_{f Omega} X = (1/f) sum_i d_i (f X^i), for a density that depends on all coordinates
    pg = PoissonGeometry(3)
    r = Reader(3)
    x = pg.coords
    f = sp.exp(x[0] + 2 * x[1] ** 2) * (2 + sp.cos(x[2]))
    X = [x[1] * x[2], x[0] ** 2, sp.sin(x[0] * x[2])]
    ours = pg.curl_operator({(i + 1,): str(X[i]) for i in range(3)}, str(f))
    truth = sum(sp.diff(f * X[i], x[i]) for i in range(3)) / f
    assert is_zero(r.expr(ours) - truth)


def test_modular_vf_is_divergence_of_hamiltonian_fields():
    # Z(g) = div_{f Omega}(X_g) with X_g = -P dg, for several g: an independent definition.
    pg = PoissonGeometry(3)
    r = Reader(3)
    x = pg.coords
    for biv in (SO3, Q_ORACLE):
        for density in ("exp(x3)", "1 + x1**2 + x2**4"):
            f = r.expr(density)
            Z = pg.modular_vf(biv, density)
            for g in (x[0] * x[1], sp.exp(x[2]) + x[0]):
                Xg = [r.expr(v) for v in pg.hamiltonian_vf(biv, str(g)).values()]
                div = sum(sp.diff(f * Xg[i], x[i]) for i in range(3)) / f
                Zg = sum(r.expr(Z.get((i + 1,), "0")) * sp.diff(g, x[i]) for i in range(3))
                assert is_zero(Zg - div)


def test_modular_vf_documented_example():
    ours = PoissonGeometry(3).modular_vf(SO3, "exp(x1 + x2 + x3)")
    assert _same({(1,): "-x2 + x3", (2,): "x1 - x3", (3,): "-x1 + x2"}, ours)


def test_modular_vf_agrees_with_peer_where_the_peer_bug_is_invisible(peer):
    # density exp(x1 + x2 + x3) has equal partials, so the wrong coordinate does not matter
    ours = PoissonGeometry(3).modular_vf(SO3, "exp(x1 + x2 + x3)")
    assert _same(peer(3).modular_vf(SO3, "exp(x1 + x2 + x3)"), ours)


def test_modular_vf_differs_from_peer_on_e3_with_density_exp_x1(peer):
    # e(3) is unimodular, so Z_{f Omega} = Z_Omega - X_f / f = P d log f = column 1 of P.
    pg = PoissonGeometry(6)
    ours = pg.modular_vf(E3, "exp(x1)")
    assert _same({(5,): "-x3", (6,): "x2"}, ours, 6)
    assert not _same(peer(6).modular_vf(E3, "exp(x1)"), ours, 6)


def test_unimodularity_equals_peer(peer):
    pg, th = PoissonGeometry(3), peer(3)
    for biv in (SO3, SL2, {(1, 3): "x1", (2, 3): "x2"}, Q_ORACLE, {(1, 2): "x1*x2"}):
        assert pg.is_unimodular_homogeneous(biv) is th.is_unimodular_homogeneous(biv)
    assert pg.is_unimodular_homogeneous(SO3)
    assert not pg.is_unimodular_homogeneous({(1, 3): "x1", (2, 3): "x2"})


# ---------------------------------------------------------------------- oracles of the reference
def test_hamiltonian_vf_e3_equals_minus_formulas_oracle():
    """FORMULAS.md §2: P0 dH = (-35/72, -1/4, 11/18, -5/12, 13/24, -1/3) at the stated point
    for H = (L, A L)/2 + gamma3, A = diag(1/2, 1/3, 1/4); PoissonGeometry's X_H is -P0 dH."""
    pg = PoissonGeometry(6)
    X = pg.hamiltonian_vf(E3, "x4**2/4 + x5**2/6 + x6**2/8 + x3")
    point = dict(zip(pg.coords, [Fraction(2, 3), Fraction(1, 3), Fraction(2, 3), 1, -2,
                                 Fraction(1, 2)]))
    oracle = [Fraction(-35, 72), Fraction(-1, 4), Fraction(11, 18), Fraction(-5, 12),
              Fraction(13, 24), Fraction(-1, 3)]
    r = Reader(6)
    for i in range(6):
        value = r.expr(X[(i + 1,)]).subs({k: sp.Rational(v) for k, v in point.items()})
        assert value == -sp.Rational(oracle[i])


def test_poisson_bracket_p_gf_formulas_oracle():
    """FORMULAS.md §5, g = 1 + gamma1^2, f = gamma2, phi = 0: {M1, M2} = 731/486 at the point."""
    pg = PoissonGeometry(6)
    g1, g2, g3, M1, M2, M3 = pg.coords
    g, f = 1 + g1 ** 2, g2
    gamma, M = sp.Matrix([g1, g2, g3]), sp.Matrix([M1, M2, M3])
    grad_g = sp.Matrix([sp.diff(g, v) for v in (g1, g2, g3)])
    c = (grad_g.dot(M) - g * f * gamma.dot(M))
    top = {(1, 5): g * g3, (1, 6): -g * g2, (2, 4): -g * g3, (2, 6): g * g1, (3, 4): g * g2,
           (3, 5): -g * g1}
    mm = {(4, 5): g * M3 + c * g3, (4, 6): -(g * M2 + c * g2), (5, 6): g * M1 + c * g1}
    biv = {k: str(v) for k, v in {**top, **mm}.items()}
    at = {g1: sp.Rational(2, 3), g2: sp.Rational(1, 3), g3: sp.Rational(2, 3), M1: 1, M2: -2,
          M3: sp.Rational(1, 2)}
    assert Reader(6).expr(pg.poisson_bracket(biv, "x4", "x5")).subs(at) == sp.Rational(731, 486)
    assert Reader(6).expr(pg.poisson_bracket(biv, "x4", "x6")).subs(at) == sp.Rational(607, 243)
    assert pg.is_casimir(biv, "x1**2 + x2**2 + x3**2")
    assert pg.is_casimir(biv, "x1*x4 + x2*x5 + x3*x6")
    assert pg.is_poisson_bivector(biv)


# ---------------------------------------------------------------------- bigger cases (peer slow)
@pytest.mark.slow
def test_e3_schouten_calculus_equals_peer(peer):
    pg, th = PoissonGeometry(6), peer(6)
    assert pg.is_poisson_bivector(E3) is th.is_poisson_bivector(E3) is True
    assert _same(th.jacobiator(E3), pg.jacobiator(E3), 6)
    X = {(1,): "x2", (2,): "-x1", (4,): "x5", (5,): "-x4"}
    assert pg.is_poisson_vf(E3, X) is th.is_poisson_vf(E3, X) is True
    broken = {**E3, (4, 5): "x6 + x1**2"}
    assert pg.is_poisson_bivector(broken) is th.is_poisson_bivector(broken) is False
    assert _same(th.jacobiator(broken), pg.jacobiator(broken), 6)


@pytest.mark.slow
def test_e3_first_order_operations_equal_peer(peer):
    pg, th = PoissonGeometry(6), peer(6)
    H = "x4**2/4 + x5**2/6 + x6**2/8 + x3*x1"
    assert _same(th.hamiltonian_vf(E3, H), pg.hamiltonian_vf(E3, H), 6)
    assert _same(th.poisson_bracket(E3, H, "x4*x1"), pg.poisson_bracket(E3, H, "x4*x1"), 6)
    assert pg.is_casimir(E3, "x1*x4 + x2*x5 + x3*x6") is th.is_casimir(E3, "x1*x4 + x2*x5 + x3*x6")
    assert _same(th.coboundary_operator(E3, {(1,): "x4"}), pg.coboundary_operator(E3, {(1,): "x4"}), 6)


# ---------------------------------------------------------------------- formats
def test_latex_outputs_are_the_latex_of_the_plain_results():
    pg = PoissonGeometry(3)
    r = Reader(3)
    plain = pg.hamiltonian_vf(SO3, "x1*x2")
    assert pg.hamiltonian_vf(SO3, "x1*x2", latex=True) == sp.latex(
        {k: r.expr(v) for k, v in plain.items()})
    assert pg.poisson_bracket(SO3, "x1", "x2", latex=True) == sp.latex(r.expr("x3"))
    assert pg.jacobiator(Q_ORACLE, latex=True) == sp.latex({(1, 2, 3): r.expr("-2*x1*x3")})
    assert pg.curl_operator({(1,): "x1"}, "1", latex=True) == "1"


def test_variable_prefix_and_attributes_match_peer(peer):
    pg, th = PoissonGeometry(4, variable="y"), peer(4, variable="y")
    assert tuple(map(str, pg.coords)) == tuple(map(str, th.coords)) == ("y1", "y2", "y3", "y4")
    assert pg.coordinates == th.coordinates and pg.dim == th.dim == 4
    P = {(1, 2): "y3", (3, 4): "y1*y2"}
    assert _same(th.hamiltonian_vf(P, "y1*y4"), pg.hamiltonian_vf(P, "y1*y4"), 4)
    out = pg.hamiltonian_vf(P, "y1*y4")
    assert {k: str(v) for k, v in out.items()} == out and out[(2,)] == "y3*y4"
