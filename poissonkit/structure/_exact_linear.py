"""Exact sparse linear algebra for the Hamiltonisation search (:mod:`.hamiltonize`).

Rows are ``{column: value}`` dicts over an exact field ``K`` (``QQ`` or ``QQ(parameters)``);
the elimination is sympy's sparse :class:`~sympy.polys.matrices.DomainMatrix` reduced echelon
form, so no floating point and no ``simplify`` are involved.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from sympy.polys.matrices import DomainMatrix

#: Elimination method of DomainMatrix.rref: Gauss-Jordan with division keeps the sparse rows
#: of these systems short (fraction-free elimination grows the entries).
RREF_METHOD = "GJ"


@dataclass(frozen=True)
class LinearSolution:
    """Affine solution family ``u = u0 + sum_t tau_t v_t`` of ``A u = b``.

    Attributes
    ----------
    consistent
        Whether ``A u = b`` has a solution.
    particular
        ``{column: value}`` of ``u0`` (pivot columns only; free columns are 0).
    directions
        One ``{column: value}`` per free column ``f``: the null-space vector with ``u_f = 1``.
    free
        The free columns, in the order of ``directions``.
    rank
        Rank of ``A``.
    """

    consistent: bool
    particular: dict[int, object]
    directions: tuple[dict[int, object], ...]
    free: tuple[int, ...]
    rank: int


def solve_sparse(rows: Sequence[dict[int, object]], rhs: Sequence[object], ncols: int,
                 K) -> LinearSolution:
    """Solve ``A u = b`` exactly (``A`` given by sparse rows, ``b`` by ``rhs``) over ``K``."""
    data = {}
    for r, (row, b) in enumerate(zip(rows, rhs)):
        d = {c: v for c, v in row.items() if v}
        if b:
            d[ncols] = b
        if d:
            data[len(data)] = d
    if not data:
        free = tuple(range(ncols))
        return LinearSolution(True, {}, tuple({f: K.one} for f in free), free, 0)
    M = DomainMatrix(data, (len(data), ncols + 1), K)
    R, pivots = M.rref(method=RREF_METHOD)
    if ncols in pivots:
        return LinearSolution(False, {}, (), (), len(pivots) - 1)
    sdm = R.rep.to_sdm()
    pivot_set = set(pivots)
    free = tuple(c for c in range(ncols) if c not in pivot_set)
    particular: dict[int, object] = {}
    directions: dict[int, dict[int, object]] = {f: {f: K.one} for f in free}
    for r, p in enumerate(pivots):
        row = sdm.get(r, {})
        if row.get(ncols):
            particular[p] = row[ncols]
        for c, v in row.items():
            if c != p and c != ncols:
                directions[c][p] = -v
    return LinearSolution(True, particular, tuple(directions[f] for f in free), free,
                          len(pivots))


def nullspace_sparse(rows: Sequence[dict[int, object]], ncols: int, K) -> LinearSolution:
    """The null space of ``A``, as a :class:`LinearSolution` with ``u0 = 0``."""
    return solve_sparse(rows, [K.zero] * len(rows), ncols, K)


def inconsistency_certificate(rows: Sequence[dict[int, object]], rhs: Sequence[object],
                              ncols: int, K) -> dict[int, object] | None:
    """A vector ``y`` with ``y^T A = 0`` and ``y^T b = 1`` (proof that ``A u = b`` is unsolvable).

    Solves the transposed system ``[A^T; b^T] y = (0, ..., 0, 1)``; returns ``{row: y_row}``
    (only non-zero entries) or ``None`` if ``A u = b`` is solvable after all.
    """
    nrows = len(rows)
    cols: dict[int, dict[int, object]] = {}
    for r, row in enumerate(rows):
        for c, v in row.items():
            if v:
                cols.setdefault(c, {})[r] = v
    trows = [cols.get(c, {}) for c in range(ncols)]
    trows.append({r: b for r, b in enumerate(rhs) if b})
    trhs = [K.zero] * ncols + [K.one]
    sol = solve_sparse(trows, trhs, nrows, K)
    if not sol.consistent:
        return None
    return dict(sol.particular)


def check_certificate(rows: Sequence[dict[int, object]], rhs: Sequence[object], ncols: int,
                      y: dict[int, object], K) -> bool:
    """Whether ``y^T A = 0`` and ``y^T b != 0`` (independent re-check of a certificate)."""
    acc: dict[int, object] = {}
    for r, w in y.items():
        for c, v in rows[r].items():
            acc[c] = acc.get(c, K.zero) + w * v
    if any(v for v in acc.values()):
        return False
    total = K.zero
    for r, w in y.items():
        total += w * rhs[r]
    return bool(total)
