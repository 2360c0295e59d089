"""Schouten bracket, Lie derivative, Lichnerowicz coboundary and multivector bookkeeping.

Independent truths: the oracle values of FORMULAS.md §0, the survey's eq. (4) written out as a
plain loop (not the graded formula the module uses), the Lie derivative of a bivector written
componentwise, and the poissongeometry package.
"""

from __future__ import annotations

import itertools

import pytest
import sympy as sp

from poissonkit.errors import DimensionError, InputError, PoissonkitError
from poissonkit.structure import Bivector, e3, eps_matrix, so3
from poissonkit.structure.schouten import (
    Multivector,
    are_compatible,
    is_poisson_vector_field,
    jacobiator,
    lichnerowicz,
    multivector_from_dict,
    schouten_bracket,
    wedge,
)

y = sp.symbols("y1:4", real=True)


def q_oracle() -> Bivector:
    """``Q`` of FORMULAS.md §0."""
    return Bivector.from_matrix([[0, y[0] * y[1], 0], [-y[0] * y[1], 0, y[2]], [0, -y[2], 0]], y)


def survey_eq4(A: Bivector, B: Bivector, i: int, j: int, k: int) -> sp.Expr:
    """``[A,B]^{ijk} = -sum_m (B^{mk} d_m A^{ij} + A^{mk} d_m B^{ij}) + cyclic`` (survey (4))."""
    x = A.coords
    total = 0
    for a, b, c in ((i, j, k), (j, k, i), (k, i, j)):
        for m in range(A.dim):
            total -= B.matrix[m, c] * sp.diff(A.matrix[a, b], x[m])
            total -= A.matrix[m, c] * sp.diff(B.matrix[a, b], x[m])
    return sp.expand(total)


def test_oracle_values_of_formulas_section_0():
    Q = q_oracle()
    S = schouten_bracket(Q, Q)
    assert sp.expand(S.component(0, 1, 2) + 2 * y[0] * y[2]) == 0
    assert S.component(0, 1, 2).subs({y[0]: 1, y[1]: 2, y[2]: 3}) == -6
    assert sp.expand(jacobiator(Q).component(0, 1, 2) + y[0] * y[2]) == 0
    eps_v = Bivector.from_matrix(eps_matrix([-y[1], y[0], 1]), y)
    assert schouten_bracket(eps_v, eps_v).component(0, 1, 2) == -4
    assert schouten_bracket(so3(), so3()).is_zero()


def test_bivector_bracket_matches_survey_eq4_on_random_polynomial_bivectors():
    x = sp.symbols("x1:5", real=True)
    rng = __import__("random").Random(7)

    def rand_biv():
        mat = sp.zeros(4, 4)
        for i, j in itertools.combinations(range(4), 2):
            e = sum(rng.randint(-2, 2) * x[a] * x[b] for a in range(4) for b in range(a, 4)
                    if rng.random() < 0.3) + rng.randint(-1, 1) * x[rng.randrange(4)]
            mat[i, j], mat[j, i] = e, -e
        return Bivector.from_matrix(mat, x)

    A, B = rand_biv(), rand_biv()
    S = schouten_bracket(A, B)
    for i, j, k in itertools.combinations(range(4), 3):
        assert sp.expand(S.component(i, j, k) - survey_eq4(A, B, i, j, k)) == 0
    # graded symmetry of two bivectors: [A, B] = [B, A]
    assert (S - schouten_bracket(B, A)).is_zero()


def test_bivector_with_vector_field_is_minus_lie_derivative():
    P = q_oracle()
    X = [y[1] * y[2], y[0] ** 2, y[0] - y[2]]
    x = P.coords
    S = schouten_bracket(P, Multivector.vector_field(X, x))
    for i, j in itertools.combinations(range(3), 2):
        # (L_X P)^{ij} = X^m d_m P^{ij} - P^{mj} d_m X^i - P^{im} d_m X^j
        lie = sum(X[m] * sp.diff(P.matrix[i, j], x[m]) - P.matrix[m, j] * sp.diff(X[i], x[m])
                  - P.matrix[i, m] * sp.diff(X[j], x[m]) for m in range(3))
        assert sp.expand(S.component(i, j) + lie) == 0


def test_vector_vector_is_lie_bracket_and_function_pairing():
    X = Multivector.vector_field([y[1], -y[0], 0], y)
    Y = Multivector.vector_field([y[0] * y[2], 0, y[1]], y)
    Z = schouten_bracket(X, Y)
    for i in range(3):
        expected = sum(X.component(m) * sp.diff(Y.component(i), y[m])
                       - Y.component(m) * sp.diff(X.component(i), y[m]) for m in range(3))
        assert sp.expand(Z.component(i) - expected) == 0
    f = y[0] ** 2 * y[2]
    assert sp.expand(schouten_bracket(X, Multivector.function(f, y)).component()
                     - (y[1] * 2 * y[0] * y[2])) == 0


def test_lichnerowicz_of_function_is_hamiltonian_field_and_squares_to_zero():
    P = e3()
    H = sum(c ** 2 for c in P.coords[3:]) / 2 + P.coords[2]
    XH = lichnerowicz(P, H)
    expected = P.hamiltonian_vector_field(H)
    assert all(sp.expand(XH.component(i) - expected[i]) == 0 for i in range(6))
    assert lichnerowicz(P, XH).is_zero()          # d_P^2 H = 0 for Poisson P
    assert is_poisson_vector_field(P, XH)
    assert lichnerowicz(P, P).is_zero()           # d_P P = [P, P] = 0


def test_poisson_vector_fields_and_compatibility():
    P = so3()
    m = P.coords
    # the Euler (radial) field scales a linear bracket: not a Poisson vector field
    assert not is_poisson_vector_field(P, list(m))
    # rotations are symmetries of so(3)
    assert is_poisson_vector_field(P, [m[1], -m[0], 0])
    # so(3) is compatible with every frozen bracket P(a) (constant)
    frozen = P.subs({m[0]: 1, m[1]: 2, m[2]: 3})
    assert are_compatible(P, frozen)
    Q = Bivector.from_matrix(q_oracle().matrix.subs(dict(zip(y, m))), m)
    assert not are_compatible(P, Q)


def test_compatibility_agrees_with_poissongeometry():
    poisson = pytest.importorskip("poisson.poisson")
    pg = poisson.PoissonGeometry(3)
    cases = [({(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}, {(1, 2): "1", (1, 3): "2"}),
             ({(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}, {(1, 2): "x1*x2", (2, 3): "x3"}),
             ({(1, 2): "x3"}, {(2, 3): "x1**2"})]
    x = sp.symbols("x1:4", real=True)
    for a, b in cases:
        A = Bivector.from_components(a, x)
        B = Bivector.from_components(b, x)
        assert are_compatible(A, B) == pg.is_poisson_pair(a, b)


def test_multivector_sign_handling_and_errors():
    x = sp.symbols("x1:5", real=True)
    T = Multivector(3, x, {(2, 0, 1): x[3]})
    assert T.components == {(0, 1, 2): x[3]}       # (2,0,1) is an even permutation
    assert T.component(1, 0, 2) == -x[3]
    assert T.component(0, 0, 2) == 0
    assert T.subs({x[3]: 5}).component(0, 1, 2) == 5
    with pytest.raises(InputError):
        Multivector(2, x, {(1, 1): x[0]})
    with pytest.raises(DimensionError):
        Multivector(2, x, {(0, 7): 1})
    with pytest.raises(DimensionError):
        Multivector(2, x, {(0, 1, 2): 1})
    with pytest.raises(InputError):
        Multivector(2, x, {(0, 1): 1, (1, 0): 2})
    with pytest.raises(DimensionError):
        schouten_bracket(so3(), e3())
    with pytest.raises(DimensionError):
        T.component(0, 1)
    with pytest.raises(InputError):
        multivector_from_dict({(0, 1): "x1"}, x)
    with pytest.raises(InputError):
        multivector_from_dict({(1, 2): "x1", (1, 2, 3): "x2"}, x)
    with pytest.raises(PoissonkitError):
        multivector_from_dict({(1, 2): "y9"}, x)
    assert isinstance(wedge(Multivector.vector_field([1, 0, 0, 0], x),
                            Multivector.vector_field([0, x[0], 0, 0], x)).component(0, 1), sp.Expr)


def test_bivector_bad_input_is_typed():
    x = sp.symbols("x1:4", real=True)
    with pytest.raises(InputError):
        Bivector.from_matrix([[0, 1, 0], [1, 0, 0], [0, 0, 0]], x)      # not antisymmetric
    with pytest.raises(DimensionError):
        Bivector.from_matrix([[0, 1], [-1, 0]], x)                      # wrong size
    with pytest.raises(InputError):
        Bivector.from_components({(1, 1): "x1"}, x)                     # repeated index
    with pytest.raises(DimensionError):
        Bivector.from_components({(0, 1): "x1"}, x)                     # zero index (1-based)
    with pytest.raises(PoissonkitError):
        Bivector.from_components({(1, 2): "z"}, x)                      # unknown symbol
    plain = sp.Symbol("x1")                                              # not the real x1
    with pytest.raises(InputError):
        Bivector.from_matrix([[0, plain, 0], [-plain, 0, 0], [0, 0, 0]], ["x1", "x2", "x3"])


def test_strings_are_never_sympified():
    evil = "__import__('os').system('echo pwned')"
    x = sp.symbols("x1:3", real=True)
    with pytest.raises(PoissonkitError):
        Multivector(2, x, {(0, 1): evil})
    with pytest.raises(PoissonkitError):
        Multivector.function(evil, x)
    with pytest.raises(PoissonkitError):
        Bivector.from_matrix([[0, evil], [evil, 0]], x)
    with pytest.raises(PoissonkitError):
        Bivector.from_components({(1, 2): evil}, x)
    from poissonkit.structure import lie_poisson
    with pytest.raises(PoissonkitError):
        lie_poisson([[[evil] * 2] * 2] * 2)
