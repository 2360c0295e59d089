"""Bi-Hamiltonian tools against independent truth.

* Open Toda lattice in Flaschka variables with the linear and quadratic brackets (Damianou,
  *J. Math. Phys.* 35 (1994); Fernandes 1993): the Lenard–Magri chain of the pencil Casimir
  generates the same algebra as ``tr L^k``, ``k = 1..n``, computed directly from the Lax matrix
  (its linear span equals that of the elementary symmetric functions obtained from the traces
  by Newton's identities).
* Open Toda lattice in canonical ``(q, p)`` with Das–Okubo's second bracket: the recursion
  operator ``N`` has zero Nijenhuis torsion and ``tr N^k = 2 tr L^k`` (eigenvalues of ``N`` are
  those of ``L``, each twice).
* Euler top with the so(3) pencil (second bracket ``eps_ijk dE/dm_k``, Casimir the energy form).
"""

from __future__ import annotations

import time

import pytest
import sympy as sp
from brackets import bivector_of  # type: ignore[import-not-found]

import poissonkit as pk
from poissonkit.structure import Bivector, so3
from poissonkit.structure.bihamiltonian import (
    DegenerateBivectorError,
    involution_both,
    lenard_magri_chain,
    lenard_magri_chains,
    nijenhuis_torsion,
    pencil,
    recursion_operator,
)

LAM = sp.Symbol("lam")


def toda_flaschka(n: int):
    """Linear and quadratic Toda brackets in (a_1..a_{n-1}, b_1..b_n) and the Lax matrix."""
    a = list(sp.symbols(f"a1:{n}"))
    b = list(sp.symbols(f"b1:{n + 1}"))
    X = a + b
    lin, quad = {}, {}
    for i in range(n - 1):
        lin[(a[i], b[i])] = -a[i]
        lin[(a[i], b[i + 1])] = a[i]
        quad[(a[i], b[i])] = -a[i] * b[i]
        quad[(a[i], b[i + 1])] = a[i] * b[i + 1]
        quad[(b[i], b[i + 1])] = 2 * a[i] ** 2
        if i < n - 2:
            quad[(a[i], a[i + 1])] = a[i] * a[i + 1] / 2
    L = sp.diag(*b)
    for i in range(n - 1):
        L[i, i + 1] = L[i + 1, i] = a[i]
    return bivector_of(X, lin), bivector_of(X, quad), L


def _span_rank(polys, coords) -> int:
    """Rank over Q of the coefficient vectors of the polynomials."""
    rows = [sp.Poly(p, *coords).as_dict() for p in polys]
    monos = sorted({m for r in rows for m in r})
    return sp.Matrix([[r.get(m, 0) for m in monos] for r in rows]).rank()


def _same_span(A, B, coords) -> bool:
    rA, rB = _span_rank(A, coords), _span_rank(B, coords)
    return rA == rB == _span_rank(list(A) + list(B), coords)


def _elementary_from_power_sums(p):
    """Newton's identities: e_k from the power sums (k e_k = sum (-1)^(i-1) e_{k-i} p_i)."""
    e = [sp.Integer(1)]
    for k in range(1, len(p) + 1):
        e.append(sp.expand(sum((-1) ** (i - 1) * e[k - i] * p[i - 1] for i in range(1, k + 1)) / k))
    return e[1:]


def _same_algebra(chain_integrals, traces, coords) -> bool:
    """The chain (homogeneous, degrees 1..n) and tr L^k generate the same polynomial algebra:
    compare the linear span of the chain with the elementary symmetric functions of the
    eigenvalues of L, obtained from the traces by Newton's identities (not from a determinant),
    and require the traces to be functionally independent."""
    jac = sp.Matrix([[sp.diff(t, x) for x in coords] for t in traces])
    independent = jac.rank() == len(traces)
    return independent and _same_span(chain_integrals, _elementary_from_power_sums(traces), coords)


@pytest.mark.parametrize("n", [3, 4])
def test_toda_chain_spans_traces_of_lax_powers(n):
    P1, P2, L = toda_flaschka(n)
    assert pk.compatible(P1, P2)
    chain = pk.lenard_magri_chain(P1, P2, (L - LAM * sp.eye(n)).det(), LAM)
    assert chain.check()
    assert chain.in_involution()
    traces = [sp.expand((L ** k).trace()) for k in range(1, n + 1)]
    assert len(chain.integrals) == n
    assert _same_algebra(chain.integrals, traces, P1.coords)
    # the ends of the chain: tr L is the Casimir of P1, det L the Casimir of P2
    assert pk.is_casimir(P1, traces[0])
    assert pk.is_casimir(P2, L.det())


def test_toda_pencil_casimirs_found_automatically():
    n = 3
    P1, P2, L = toda_flaschka(n)
    chains = lenard_magri_chains(P1, P2, n, LAM)
    assert len(chains) == 1
    traces = [sp.expand((L ** k).trace()) for k in range(1, n + 1)]
    assert _same_algebra(chains[0].integrals, traces, P1.coords)
    assert chains[0].in_involution()


def test_chain_span_check_can_fail():
    # a wrong "truth" (tr L^2 replaced by a1**2 + tr L^2) must not give the same algebra
    n = 3
    P1, P2, L = toda_flaschka(n)
    chain = lenard_magri_chain(P1, P2, (L - LAM * sp.eye(n)).det(), LAM)
    wrong = [L.trace(), (L ** 2).trace() + P1.coords[0] ** 2, (L ** 3).trace()]
    assert not _same_algebra(chain.integrals, wrong, P1.coords)


def test_not_a_pencil_casimir_is_refused():
    n = 3
    P1, P2, L = toda_flaschka(n)
    with pytest.raises(pk.PoissonkitError, match="not a Casimir"):
        lenard_magri_chain(P1, P2, (L + LAM * sp.eye(n)).det(), LAM)


def test_incompatible_pair_is_reported():
    P1, _P2, _L = toda_flaschka(3)
    a1, a2, b1, b2, b3 = P1.coords
    Q = bivector_of(list(P1.coords), {(b1, b2): a2, (a1, a2): 1})
    res = pk.compatible(P1, Q, check_poisson=False)
    assert not res and any(lab.startswith("[P1,P2]") for lab, _ in res.failures)


def toda_canonical(n: int):
    q = list(sp.symbols(f"q1:{n + 1}"))
    p = list(sp.symbols(f"p1:{n + 1}"))
    X = q + p
    can = {(q[i], p[i]): 1 for i in range(n)}
    second = {(q[i], p[i]): p[i] for i in range(n)}
    second.update({(q[i], q[j]): -1 for i in range(n) for j in range(i + 1, n)})
    second.update({(p[i + 1], p[i]): sp.exp(q[i] - q[i + 1]) for i in range(n - 1)})
    L = sp.diag(*p)
    for i in range(n - 1):
        L[i, i + 1] = L[i + 1, i] = sp.exp((q[i] - q[i + 1]) / 2)
    return bivector_of(X, can), bivector_of(X, second), L


def test_toda_recursion_operator_canonical():
    n = 3
    P1, P2, L = toda_canonical(n)
    assert pk.compatible(P1, P2)
    N = pk.recursion_operator(P1, P2)
    assert sp.simplify(N * P1.matrix - P2.matrix) == sp.zeros(2 * n)
    assert nijenhuis_torsion(N, P1.coords) == {}
    for k in (1, 2, 3):
        assert sp.simplify((N ** k).trace() - 2 * (L ** k).trace()) == 0


def test_nijenhuis_torsion_detects_a_non_nijenhuis_tensor():
    x, y = sp.symbols("x y")
    N = sp.Matrix([[0, x], [y, 0]])
    assert nijenhuis_torsion(N, (x, y)) != {}


def test_recursion_operator_on_a_leaf():
    P1, P2, _L = toda_flaschka(3)
    with pytest.raises(DegenerateBivectorError):
        recursion_operator(P1, P2)
    a1, a2, b1, b2, b3 = P1.coords
    N = recursion_operator(P1, P2, leaf=["a1", "a2", "b1", "b3"])
    # N P1 = P2 modulo P2(ker P1): ker P1 is spanned by d(b1 + b2 + b3)
    kernel_image = P2.matrix * sp.Matrix([0, 0, 1, 1, 1])
    diff = (N * P1.matrix - P2.matrix).applyfunc(sp.simplify)
    for j in range(5):
        col = diff[:, j]
        assert sp.Matrix.hstack(kernel_image, col).rank(simplify=True) <= 1
    with pytest.raises(DegenerateBivectorError):
        recursion_operator(P1, P2, leaf=["b1", "b2"])  # {b1, b2}_1 = 0: singular block


def euler_top_pencil():
    """so(3) and the second bracket eps_ijk dE/dm_k (its Casimir is the energy form E)."""
    P1 = so3()
    m = P1.coords
    A = sp.symbols("A1:4", positive=True)  # inverse principal moments
    E = sum(Ai * mi ** 2 for Ai, mi in zip(A, m)) / 2
    M2 = sp.Matrix(3, 3, lambda i, j: sum(sp.LeviCivita(i, j, k) * sp.diff(E, m[k])
                                          for k in range(3)))
    return P1, Bivector(m, sp.ImmutableMatrix(M2)), E


def test_euler_top_pencil():
    P1, P2, E = euler_top_pencil()
    m = P1.coords
    assert pk.compatible(P1, P2)
    K = sum(x ** 2 for x in m) / 2
    chain = pk.lenard_magri_chain(P1, P2, E - LAM * K, LAM)
    assert chain.integrals == (sp.expand(E), sp.expand(-K))
    assert chain.in_involution()
    # Euler's equations, with {m_i, m_j} = eps_ijk m_k (x' = P dH = grad H x m):
    # m' = (A m) x m, generated by E with P1 and by -K with P2
    A = [sp.diff(E, x, 2) for x in m]
    euler = sp.Matrix([A[i] * m[i] for i in range(3)]).cross(sp.Matrix(m))
    assert sp.simplify(P1.matrix * P1.gradient(E) - euler) == sp.zeros(3, 1)
    assert sp.simplify(P2.matrix * P2.gradient(-K) - euler) == sp.zeros(3, 1)
    found = lenard_magri_chains(P1, P2, 2, LAM, params=sp.symbols("A1:4", positive=True))
    assert len(found) == 1 and pencil(P1, P2, LAM).matrix.free_symbols >= {LAM}
    assert involution_both(P1, P2, found[0].integrals)


def test_involution_check_can_fail():
    P1, P2, E = euler_top_pencil()
    assert not involution_both(P1, P2, [E, P1.coords[0]])


@pytest.mark.slow
def test_toda_chain_n5():
    n = 5
    t = time.perf_counter()
    P1, P2, L = toda_flaschka(n)
    chain = pk.lenard_magri_chain(P1, P2, (L - LAM * sp.eye(n)).det(), LAM)
    traces = [sp.expand((L ** k).trace()) for k in range(1, n + 1)]
    assert _same_algebra(chain.integrals, traces, P1.coords)
    assert chain.in_involution()
    assert time.perf_counter() - t < 600
