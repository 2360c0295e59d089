"""Standard invariants of the classical Lie algebras, computed in a sparse polynomial ring.

The generators (traces of powers, Pfaffians, and for the Euclidean algebras the contracted
invariants below) are polynomials with thousands of terms for ``so(7)`` or ``sp(6)``; expanding
matrix powers as sympy expressions takes tens of seconds, whereas the same products in
:mod:`sympy.polys.rings` (dicts of exponent tuples) take a fraction of a second. Only the
final polynomials are converted back to sympy expressions.

Traces: ``tr X^p = sum_ij (X^a)_ij (X^b)_ji`` with ``a + b = p`` and ``a, b <= ceil(p / 2)``, so
only half the powers are formed. Pfaffians: expansion along the first row, memoised on the
remaining index set.

Euclidean algebras ``e(n) = so(n) x R^n``: with ``M`` the rotation part (antisymmetric,
``M_ij = m_ij``) and ``nu`` the translation part, let ``Y = [[M, nu], [-nu^T, 0]]``. The
invariants of ``so(n + 1)`` at ``(M, nu / eps)`` have, as ``eps -> 0``, leading terms that are
invariants of the contraction ``e(n)`` (Inönü–Wigner): the principal ``2k``-minors of ``Y``
containing the last index, i.e. ``D_k = e_2k(Y) - e_2k(M)`` (``e_j`` the sum of principal
``j``-minors, computed from traces by Newton's identities), ``k = 1 .. floor(n / 2)``, and for
odd ``n`` the Pfaffian ``Pf(Y)`` (whose square is the top ``D``). Their number
``floor((n + 1) / 2)`` is the index of ``e(n)`` (``dim - rank`` of the Lie–Poisson bracket);
``D_1 = |nu|^2`` and, for ``n = 3``, ``Pf(Y) = -(nu, m)``. Each is proved a Casimir in the tests.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import sympy as sp
from sympy.polys.rings import PolyElement, PolyRing

if TYPE_CHECKING:
    from poissonkit.structure.lie_algebras import LieAlgebra

__all__ = [
    "euclid_invariants", "pfaffian_invariant", "ring_matrix", "ring_pfaffian", "ring_traces",
    "traces_invariants",
]

_RMatrix = list[list[PolyElement]]


def _ring(coords: Sequence[sp.Symbol], entries: Sequence[sp.Expr]) -> PolyRing:
    """Polynomial ring over QQ, or over QQ<I> if an entry is complex (``u(n)``, ``su(n)``)."""
    complex_ = any(e.has(sp.I) for e in entries)
    return PolyRing(list(coords), sp.QQ_I if complex_ else sp.QQ)


def _linear(R: PolyRing, e: sp.Expr) -> PolyElement:
    """A linear form in the ring's generators (entries of ``X`` are linear in the coordinates)."""
    if e == 0:
        return R.zero
    pos = {s: k for k, s in enumerate(R.symbols)}
    n = len(pos)
    out = R.zero
    for term in sp.Add.make_args(sp.expand(e)):
        c, s = term.as_independent(*R.symbols, as_Add=False)
        mono = [0] * n
        mono[pos[s]] = 1
        out += R({tuple(mono): R.domain.from_sympy(c)})
    return out


def ring_matrix(X: sp.MatrixBase, coords: Sequence[sp.Symbol]) -> _RMatrix:
    """``X`` (entries linear in ``coords``) as a list of rows of ring elements."""
    R = _ring(coords, list(X))
    return [[_linear(R, X[i, j]) for j in range(X.cols)] for i in range(X.rows)]


def _matmul(A: _RMatrix, B: _RMatrix, zero: PolyElement) -> _RMatrix:
    n, m, p = len(A), len(B), len(B[0])
    out = []
    for i in range(n):
        row = []
        for j in range(p):
            acc = zero
            for k in range(m):
                if A[i][k] and B[k][j]:
                    acc += A[i][k] * B[k][j]
            row.append(acc)
        out.append(row)
    return out


def ring_traces(X: _RMatrix, powers: Sequence[int]) -> dict[int, PolyElement]:
    """``{p: tr X^p}`` for the given powers ``p >= 1``."""
    zero = X[0][0].ring.zero
    n = len(X)
    top = max(powers)
    half = (top + 1) // 2
    pw: dict[int, _RMatrix] = {1: X}
    for k in range(2, half + 1):
        pw[k] = _matmul(pw[k - 1], X, zero)
    out = {}
    for p in powers:
        a = (p + 1) // 2
        b = p - a
        if b == 0:
            out[p] = sum((X[i][i] for i in range(n)), zero)
            continue
        A, B = pw[a], pw[b]
        out[p] = sum((A[i][j] * B[j][i] for i in range(n) for j in range(n)
                      if A[i][j] and B[j][i]), zero)
    return out


def ring_pfaffian(A: _RMatrix, idx: Sequence[int] | None = None) -> PolyElement:
    """Pfaffian of the principal submatrix ``A[idx, idx]`` (antisymmetric; all of ``A`` default).

    Expansion along the first row: ``Pf = sum_j (-1)^(j+1) A_0j Pf(A without rows 0, j)``.
    """
    zero = A[0][0].ring.zero
    memo: dict[tuple[int, ...], PolyElement] = {}

    def pf(s: tuple[int, ...]) -> PolyElement:
        if not s:
            return zero + 1
        if len(s) % 2:
            return zero
        if s in memo:
            return memo[s]
        out = zero
        first = s[0]
        for j in range(1, len(s)):
            a = A[first][s[j]]
            if a:
                rest = s[1:j] + s[j + 1:]
                term = a * pf(rest)
                out = out + term if j % 2 else out - term
        memo[s] = out
        return out

    return pf(tuple(range(len(A))) if idx is None else tuple(idx))


def _as_expr(p: PolyElement) -> sp.Expr:
    # over QQ as_expr is already the expanded canonical form (an expand costs 2x the rest);
    # over QQ<I> coefficients such as 2 + 0*I need the expand to become plain numbers
    return p.as_expr() if p.ring.domain.is_QQ else sp.expand(p.as_expr())


def traces_invariants(powers: Sequence[int], label: str = "X",
                      of: Callable[[sp.Matrix], sp.Matrix] = lambda X: X
                      ) -> Callable[[LieAlgebra], dict[str, sp.Expr]]:
    """``alg -> {"tr(label^p)": tr(of(X)^p)}``, ``X = alg.matrix``, computed in the ring."""
    def inv(alg: LieAlgebra) -> dict[str, sp.Expr]:
        if not powers:
            return {}
        X = ring_matrix(of(sp.Matrix(alg.matrix)), alg.coords)
        tr = ring_traces(X, sorted(powers))
        return {f"tr({label}^{p})": _as_expr(tr[p]) for p in sorted(powers)}
    return inv


def pfaffian_invariant(alg: LieAlgebra, eta: Sequence[int]) -> sp.Expr:
    """``Pf(X eta)`` of ``so(p, q)``, ``X = alg.matrix``, computed in the ring."""
    X = sp.Matrix(alg.matrix) * sp.diag(*eta)
    return _as_expr(ring_pfaffian(ring_matrix(X, alg.coords)))


def _newton_elementary(p: dict[int, PolyElement], top: int, one: PolyElement
                       ) -> list[PolyElement]:
    """``e_0 .. e_top`` from the power sums ``p[1..top]``: ``k e_k = sum (-1)^(i-1) e_{k-i} p_i``.

    Over QQ the division by ``k`` is exact.
    """
    e = [one]
    for k in range(1, top + 1):
        acc = one * 0
        for i in range(1, k + 1):
            if p.get(i):
                t = e[k - i] * p[i]
                acc = acc + t if i % 2 else acc - t
        e.append(acc.quo_ground(k))
    return e


def euclid_invariants(trans: Sequence[int], rot_pairs: Sequence[tuple[int, int, int, int]],
                      n: int) -> Callable[[LieAlgebra], dict[str, sp.Expr]]:
    """The ``floor((n + 1) / 2)`` contracted invariants of ``e(n)`` / ``se(n)`` (module notes).

    Parameters
    ----------
    trans
        Indices of the translation coordinates ``nu_1 .. nu_n`` in ``alg.coords``.
    rot_pairs
        ``(coordinate index, i, j, sign)``: the rotation coordinate is ``sign * M_ij``.
    n
        The dimension of the translations.

    Returns
    -------
    callable
        ``alg -> {"D_k": ..., "Pf(Y)": ...}`` for ``k = 2 .. floor(n / 2)`` and, for odd ``n``,
        the Pfaffian (``D_1 = |nu|^2`` is named by the caller).
    """
    def inv(alg: LieAlgebra) -> dict[str, sp.Expr]:
        R = PolyRing(list(alg.coords), sp.QQ)
        gens = R.gens
        Y = [[R.zero] * (n + 1) for _ in range(n + 1)]
        for c, i, j, sign in rot_pairs:
            Y[i][j] = gens[c] * sign
            Y[j][i] = -gens[c] * sign
        for i, c in enumerate(trans):
            Y[i][n] = gens[c]
            Y[n][i] = -gens[c]
        M = [row[:n] for row in Y[:n]]
        top = 2 * (n // 2)
        out: dict[str, sp.Expr] = {}
        if top >= 4:
            powers = list(range(2, top + 1, 2))
            eY = _newton_elementary(ring_traces(Y, powers), top, R.one)
            eM = _newton_elementary(ring_traces(M, powers), top, R.one)
            for k in range(2, n // 2 + 1):
                out[f"D_{k}"] = _as_expr(eY[2 * k] - eM[2 * k])
        if n % 2:
            out["Pf(Y)"] = _as_expr(ring_pfaffian(Y))
        return out
    return inv
