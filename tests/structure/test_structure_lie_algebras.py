"""Classical Lie algebras by name: brackets, coordinates, pairing and standard invariants.

Truths used: the textbook brackets of gl(n) (``[E_ij, E_kl] = d_jk E_il - d_li E_kj``), so(n) and
the Heisenberg algebra written out by hand below; the seeds' e(3), so(3) and se(3) blocks; the
degrees of the basic invariants (exponents + 1) of the classical algebras (Humphreys,
*Introduction to Lie algebras and representation theory*, §22; Bourbaki, Lie Groups ch. VI
Plates): A_{n-1} = sl(n): 2..n; B_m = so(2m+1): 2, 4, .., 2m; D_m = so(2m): 2, 4, .., 2m-2 and m;
C_n = sp(2n): 2, 4, .., 2n; gl(n) adds degree 1.
"""

from __future__ import annotations

import random

import pytest
import sympy as sp
from sympy.polys.matrices import DomainMatrix

import poissonkit as pk
from poissonkit.errors import InputError, PoissonkitError, UnknownNameError
from poissonkit.structure import check_jacobi, e3, find_casimirs, is_casimir, se3, so3
from poissonkit.structure.lie_algebras import LIE_ALGEBRA_NAMES, lie_algebra, pfaffian

SMALL = ["gl(1)", "gl(2)", "gl(3)", "sl(2)", "sl(3)", "so(2)", "so(3)", "so(4)", "so(5)",
         "so(2,1)", "so(3,1)", "so(2,2)", "sp(2)", "sp(4)", "u(1)", "u(2)", "u(3)", "su(2)",
         "su(3)", "e(2)", "e(3)", "e(4)", "se(3)", "se(4)", "heisenberg(1)", "heisenberg(2)"]


# ------------------------------------------------------------------ the existing blocks
def test_so3_e3_se3_by_name_are_the_existing_blocks():
    assert pk.lie_poisson("so(3)") == so3()
    assert pk.lie_poisson("e(3)") == e3()
    assert pk.lie_poisson("se(3)") == se3()
    assert lie_algebra("so(3,0)").bivector == so3()
    # the hat map: X = hat(m), so X w = m x w
    m = so3().coords
    w = sp.Matrix(sp.symbols("w1:4"))
    assert (lie_algebra("so(3)").matrix * w - sp.Matrix(m).cross(w)).expand() == sp.zeros(3, 1)


@pytest.mark.parametrize("name", ["gl(3)", "so(4)", "sp(4)", "su(2)", "se(4)", "heisenberg(2)"])
def test_structure_constant_form_gives_the_same_bivector(name):
    g = lie_algebra(name)
    assert pk.lie_poisson(g.structure_constants, g.coords) == g.bivector
    C = g.structure_constants  # [E_a, E_b] = sum_c C[a][b][c] E_c, in the stated basis
    for a in range(g.dim):
        for b in range(g.dim):
            comm = g.basis[a] * g.basis[b] - g.basis[b] * g.basis[a]
            assert (comm - sum((C[a][b][c] * g.basis[c] for c in range(g.dim)),
                               sp.zeros(*comm.shape))).expand() == sp.zeros(*comm.shape)


@pytest.mark.parametrize("name", SMALL)
def test_every_family_is_poisson(name):
    assert check_jacobi(pk.lie_poisson(name))


# ------------------------------------------------------------------ brackets by hand
def test_gl_bracket_is_the_textbook_one():
    n = 3
    P = pk.lie_poisson("gl(3)")
    x = {(i, j): P.symbol(f"x_{i + 1}{j + 1}") for i in range(n) for j in range(n)}
    d = lambda a, b: int(a == b)  # noqa: E731
    for (i, j), xij in x.items():
        for (k, l), xkl in x.items():
            assert P.bracket(xij, xkl) == d(j, k) * x[i, l] - d(l, i) * x[k, j]


@pytest.mark.parametrize("n", [4, 5])
def test_so_bracket_is_the_textbook_one(n):
    P = pk.lie_poisson(f"so({n})")

    def m(i, j):
        if i == j:
            return 0
        return P.symbol(f"m_{i + 1}{j + 1}") if i < j else -P.symbol(f"m_{j + 1}{i + 1}")
    d = lambda a, b: int(a == b)  # noqa: E731
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    for i, j in pairs:
        for k, l in pairs:
            want = d(j, k) * m(i, l) - d(i, k) * m(j, l) - d(j, l) * m(i, k) + d(i, l) * m(j, k)
            assert sp.expand(P.bracket(m(i, j), m(k, l)) - want) == 0


def test_heisenberg_bracket():
    P = pk.lie_poisson("heisenberg(2)")
    q1, q2, p1, p2, z = P.coords
    assert [P.bracket(q1, p1), P.bracket(q2, p2), P.bracket(q1, p2), P.bracket(q1, q2)] == \
        [z, z, 0, 0]
    assert all(P.bracket(z, c) == 0 for c in P.coords)


def test_so_p_q_boosts_by_hand():
    # so(2,1), basis B_12 = E_12 - E_21, B_13 = E_13 + E_31, B_23 = E_23 + E_32:
    # [B_13, B_23] = E_12 - E_21 = B_12 (two boosts close on a rotation, with the sign
    # opposite to so(3)), [B_12, B_13] = -(E_23 + E_32) = -B_23
    P = pk.lie_poisson("so(2,1)")
    m12, m13, m23 = P.coords
    assert P.bracket(m13, m23) == m12 and P.bracket(m12, m13) == -m23
    assert P.bracket(m12, m23) == m13


# ------------------------------------------------------------------ coordinates and pairing
_KAPPA = {"gl": 1, "sl": 1, "so": sp.Rational(1, 2), "sp": sp.Rational(1, 2),
          "u": sp.Rational(1, 2), "su": sp.Rational(1, 2)}


@pytest.mark.parametrize("name", ["gl(3)", "sl(3)", "so(4)", "so(3)", "so(2,2)", "sp(4)",
                                  "u(3)", "su(3)"])
def test_coordinates_are_the_documented_pairing(name):
    """x_a = kappa Re tr(X^H E_a) (poissonkit.conventions), and X lies in g."""
    g = lie_algebra(name)
    kappa = _KAPPA[name.split("(")[0]]
    X = g.matrix
    for x, E in zip(g.coords, g.basis):
        assert sp.expand(kappa * sp.re(sp.expand((X.H * E).trace()))) == x
    # X is a real combination of the basis: the basis spans g
    c = sp.symbols(f"c0:{g.dim}", real=True)
    sol = sp.solve(list(X - sum((ci * E for ci, E in zip(c, g.basis)), sp.zeros(*X.shape))), c,
                   dict=True)
    assert sol and all(v.free_symbols <= set(g.coords) for v in sol[0].values())


def test_documented_matrix_entries():
    sl = lie_algebra("sl(3)")
    x = {s.name: s for s in sl.coords}
    assert sl.matrix[2, 2] == -x["x_11"] - x["x_22"] and sl.matrix[0, 1] == x["x_12"]
    so = lie_algebra("so(4)")
    assert so.matrix[0, 1] == so.coords[0] and so.matrix[1, 0] == -so.coords[0]
    sp4 = lie_algebra("sp(4)")
    J = sp.Matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-1, 0, 0, 0], [0, -1, 0, 0]])
    assert (sp4.matrix.T * J + J * sp4.matrix).expand() == sp.zeros(4, 4)
    u = lie_algebra("u(2)")
    H = (-sp.I * u.matrix).expand()   # Hermitian, H_12 = s_12 + i a_12
    s11, s12, s22, a12 = u.coords
    assert H == sp.Matrix([[s11, s12 + sp.I * a12], [s12 - sp.I * a12, s22]])


# ------------------------------------------------------------------ invariants
@pytest.mark.parametrize("name", SMALL)
def test_standard_invariants_poisson_commute_with_every_coordinate(name):
    g = lie_algebra(name)
    inv = g.invariants()
    assert inv
    for label, C in inv.items():
        assert C != 0 and not C.has(sp.I), label
        assert is_casimir(g.bivector, C), (name, label)


def _random_point(g, rng):
    return {x: sp.Rational(rng.randint(-50, 50), rng.randint(1, 9)) for x in g.coords}


def _trace_gradient(g, k, pt):
    """d tr(X^k)/dx_a = k tr(X^(k-1) dX/dx_a), exactly at a rational point (no expansion)."""
    X = g.matrix.subs(pt)
    Xk = X ** (k - 1)
    return [k * (Xk * g.matrix.diff(x)).trace() for x in g.coords]


def _pfaffian_gradient(g, eta, pt):
    """d Pf(A)/dx_a = Pf(A) tr(A^-1 dA/dx_a) / 2 with A = X eta (A invertible at the point)."""
    A = (g.matrix * sp.diag(*eta)).subs(pt)
    Ainv, pf = A.inv(), pfaffian(A)
    return [pf * (Ainv * (g.matrix * sp.diag(*eta)).diff(x)).trace() / 2 for x in g.coords]


LITERATURE = (
    [("gl(%d)" % n, list(range(1, n + 1))) for n in range(1, 6)]
    + [("sl(%d)" % n, list(range(2, n + 1))) for n in range(2, 6)]
    + [("so(%d)" % (2 * m + 1), list(range(2, 2 * m + 1, 2))) for m in (1, 2)]
    + [("so(%d)" % (2 * m), sorted(list(range(2, 2 * m - 1, 2)) + [m])) for m in (1, 2)]
    + [("sp(%d)" % (2 * n), list(range(2, 2 * n + 1, 2))) for n in range(1, 5)]
    + [pytest.param("sp(10)", [2, 4, 6, 8, 10], marks=pytest.mark.slow)]  # ~30 s
)


@pytest.mark.parametrize("name,degrees", LITERATURE + [("so(6)", [2, 3, 4]),
                                                     ("so(3,2)", [2, 4]), ("so(3,3)", [2, 3, 4])])
def test_invariant_degrees_match_the_literature_and_form_a_full_independent_set(name, degrees):
    """At a random rational point: every invariant's gradient is in the kernel of P, the
    gradients are independent and their number is the corank of P (so no Casimir is missing
    from an algebraically independent set), and the degrees are the textbook ones.

    A random point of a 10^3-wide grid passes a false identity with probability <= deg/10^3 per
    polynomial (Schwartz–Zippel); the seed is fixed.
    """
    g = lie_algebra(name)
    rng = random.Random(2026)
    pt = _random_point(g, rng)
    P = g.bivector.matrix.subs(pt)
    fam = name.split("(")[0]
    if fam in ("gl", "sl"):
        first = 1 if fam == "gl" else 2
        grads = {k: _trace_gradient(g, k, pt) for k in range(first, g.matrix.rows + 1)}
    elif fam == "sp":
        grads = {k: _trace_gradient(g, k, pt) for k in range(2, g.matrix.rows + 1, 2)}
    else:  # so(p, q)
        n = g.matrix.rows
        grads = {k: _trace_gradient(g, k, pt) for k in range(2, n if n % 2 == 0 else n + 1, 2)}
        if n % 2 == 0:
            p = int(name.split("(")[1].split(",")[0].rstrip(")"))
            eta = [1] * p + [-1] * (n - p)
            grads["Pf"] = _pfaffian_gradient(g, eta, pt)
    G = sp.Matrix([grads[k] for k in grads]).T
    Pq, Gq = (DomainMatrix.from_Matrix(M).convert_to(sp.QQ) for M in (P, G))
    assert (Pq * Gq).is_zero_matrix
    assert Gq.rank() == len(grads) == g.dim - Pq.rank()
    got = sorted(k if k != "Pf" else g.matrix.rows // 2 for k in grads)
    assert got == degrees
    if g.dim <= 10:  # the expanded invariants have the same degrees
        assert sorted(sp.Poly(C, *g.coords).total_degree() for C in g.invariants().values()) \
            == degrees


# ------------------------------------------------------------------ Casimirs found
def _in_algebra(C, gens, coords, deg):
    """Whether C is a polynomial in gens (span of their products of degree <= deg)."""
    prods = [sp.Integer(1)]
    frontier = [(sp.Integer(1), 0, 0)]
    degs = [sp.Poly(g, *coords).total_degree() for g in gens]
    while frontier:
        new = []
        for p, d, start in frontier:
            for k in range(start, len(gens)):
                if d + degs[k] <= deg:
                    q = sp.expand(p * gens[k])
                    prods.append(q)
                    new.append((q, d + degs[k], k))
        frontier = new
    polys = [sp.Poly(p, *coords) for p in prods + [C]]
    monos = sorted({m for p in polys for m in p.monoms()})
    M = sp.Matrix([[p.coeff_monomial(m) for m in monos] for p in polys])
    return M.rank() == M[:-1, :].rank()


@pytest.mark.parametrize("name,degree,degrees", [
    ("so(3)", 2, [2]), ("so(4)", 2, [2, 2]), ("so(5)", 4, [2, 4]), ("so(6)", 3, [2, 3]),
    ("sl(2)", 2, [2]), ("sl(3)", 3, [2, 3]), ("sl(4)", 4, [2, 3, 4]),
    ("gl(2)", 2, [1, 2]), ("gl(3)", 3, [1, 2, 3]), ("sp(2)", 2, [2]), ("sp(4)", 4, [2, 4]),
    ("u(2)", 2, [1, 2]), ("su(3)", 3, [2, 3]), ("so(3,1)", 2, [2, 2]), ("e(3)", 2, [2, 2]),
    ("se(3)", 2, [2, 2]), ("e(2)", 2, [2]), ("heisenberg(2)", 2, [1]),
])
def test_found_casimirs_have_the_literature_degrees_and_generate_the_standard_invariants(
        name, degree, degrees):
    g = lie_algebra(name)
    found = find_casimirs(g.bivector, degree)
    assert [sp.Poly(C, *g.coords).total_degree() for C in found] == degrees
    assert found.relations == ()
    for label, C in g.invariants().items():
        if sp.Poly(C, *g.coords).total_degree() <= degree:
            assert _in_algebra(C, list(found), g.coords, degree), label
    for C in found:  # and conversely: found ones are polynomials in the standard ones
        assert _in_algebra(C, list(g.invariants().values()), g.coords, degree)


@pytest.mark.slow
@pytest.mark.parametrize("name,degree,degrees", [("gl(4)", 4, [1, 2, 3, 4]),
                                                 ("sp(6)", 4, [2, 4])])
def test_found_casimirs_of_larger_algebras(name, degree, degrees):
    g = lie_algebra(name)
    found = find_casimirs(g.bivector, degree)
    assert [sp.Poly(C, *g.coords).total_degree() for C in found] == degrees
    for C in found:
        assert _in_algebra(C, list(g.invariants().values()), g.coords, degree)


# ------------------------------------------------------------------ errors
@pytest.mark.parametrize("bad", ["so5", "so(5", "foo(3)", "sl(2,1)", "g2", "", "so(-1)"])
def test_unknown_names_list_the_accepted_ones(bad):
    with pytest.raises(UnknownNameError) as err:
        pk.lie_poisson(bad)
    assert "so(p,q)" in str(err.value) and "heisenberg(n)" in str(err.value)
    assert set(err.value.available) == set(LIE_ALGEBRA_NAMES)


@pytest.mark.parametrize("bad", ["sp(3)", "sl(1)", "so(1)", "so(1,0)", "su(1)", "e(1)",
                                 "gl(0)", "heisenberg(0)", "gl(30)"])
def test_bad_sizes_are_typed_errors_naming_the_ranges(bad):
    with pytest.raises(InputError) as err:
        pk.lie_algebra(bad)
    assert "sp(2n) n>=1" in str(err.value) or "dimension" in str(err.value)


def test_other_bad_input():
    with pytest.raises(PoissonkitError):
        pk.lie_algebra(5)
    with pytest.raises(InputError, match="dimension 3"):
        pk.lie_poisson("so(3)", ["a", "b"])
    g = pk.lie_algebra("so(3)", ["a", "b", "c"])
    assert [str(c) for c in g.coords] == ["a", "b", "c"]
    assert g.bivector.bracket(*g.bivector.coords[:2]) == g.bivector.coords[2]


def test_names_are_case_and_space_tolerant_and_cached():
    assert pk.lie_algebra(" SO( 3 , 1 ) ").bivector == pk.lie_poisson("so(3,1)")
    assert pk.lie_algebra("so(4)") is pk.lie_algebra("so(4)")
    assert repr(pk.lie_algebra("sp(4)")) == "LieAlgebra('sp(4)', dim=10)"
    assert isinstance(pk.lie_algebra("sp(4)"), pk.LieAlgebra)
