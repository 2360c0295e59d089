"""Casimirs of a linear (Lie–Poisson) bracket, one graded piece at a time.

For ``{x_a, x_b} = sum_c C_ab^c x_c`` with rational ``C`` the Casimir condition
``{x_a, C} = 0`` respects two gradings of the polynomial algebra:

* the degree: ``{x_a, S^d} ⊂ S^d``;
* every grading of the Lie algebra itself, ``w(c) = w(a) + w(b)`` whenever ``C_ab^c != 0``,
  extended additively to monomials: ``{x_a, S_w} ⊂ S_{w + w(a)}``. Over ``Z`` these are the
  weights of a torus of automorphisms (the roots for ``sl(n)``, ``sp(2n)`` in their standard
  bases); over ``Z/2`` they are commuting involutive automorphisms (for ``so(n)`` in the basis
  ``m_ij`` the reflections of the axes, which separate the Pfaffian from the traces).

If ``C = sum_w C_w`` is a Casimir, ``{x_a, C_w}`` lie in distinct graded pieces for distinct
``w``, so each ``C_w`` is a Casimir: the null space splits into one small sparse system per
(degree, weight), built directly from the structure constants (no symbolic expansion). All
gradings are found as null spaces: over ``QQ`` for ``Z`` and by bitmask elimination for
``Z/2``.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from fractions import Fraction
from itertools import combinations_with_replacement
from math import gcd

import sympy as sp
from sympy.polys.matrices import DomainMatrix
from sympy.polys.orderings import grlex
from sympy.polys.rings import PolyElement, PolyRing

from poissonkit.structure.bivector import Bivector

__all__: list[str] = []

# P[i][j] = [(c, coefficient)]: {x_i, x_j} = sum coefficient * x_c
_Linear = list[list[list[tuple[int, Fraction]]]]


def linear_terms(B: Bivector) -> _Linear | None:
    """The structure constants of ``B`` if every entry is a rational linear form, else None."""
    n = B.dim
    pos = {c: k for k, c in enumerate(B.coords)}
    out: _Linear = [[[] for _ in range(n)] for _ in range(n)]
    for i in range(n):
        for j in range(n):
            e = B.matrix[i, j]
            if e == 0:
                continue
            if not e.free_symbols <= set(pos):
                return None
            for term in sp.Add.make_args(sp.expand(e)):
                coeff, sym = term.as_coeff_Mul()
                if sym not in pos or not coeff.is_Rational:
                    return None
                out[i][j].append((pos[sym], Fraction(int(coeff.p), int(coeff.q))))
    return out


def _constraints(P: _Linear) -> list[dict[int, int]]:
    rows = []
    n = len(P)
    for a in range(n):
        for b in range(a + 1, n):
            for c, _v in P[a][b]:
                r: dict[int, int] = defaultdict(int)
                r[a] += 1
                r[b] += 1
                r[c] -= 1
                rows.append({k: v for k, v in r.items() if v})
    return rows


def _z_weights(rows: list[dict[int, int]], n: int) -> list[tuple]:
    """Per coordinate, its weights in a basis of the Z-gradings (rational tuples)."""
    if not rows:
        return [(k,) for k in range(n)]  # abelian: every coordinate its own grading
    M = DomainMatrix({i: {c: sp.QQ(v) for c, v in r.items()} for i, r in enumerate(rows)},
                     (len(rows), n), sp.QQ)
    N = M.nullspace().to_Matrix()
    return [tuple(Fraction(int(N[k, a].p), int(N[k, a].q)) for k in range(N.rows))
            for a in range(n)]


def _z2_weights(rows: list[dict[int, int]], n: int) -> list[int]:
    """Per coordinate, a bitmask of its weights in a basis of the Z/2-gradings."""
    ech: dict[int, int] = {}  # pivot column -> row bitmask (reduced)
    for r in rows:
        mask = 0
        for c, v in r.items():
            if v % 2:
                mask ^= 1 << c
        for p, row in ech.items():
            if mask >> p & 1:
                mask ^= row
        if not mask:
            continue
        p = mask.bit_length() - 1
        for q in list(ech):
            if ech[q] >> p & 1:
                ech[q] ^= mask
        ech[p] = mask
    free = [c for c in range(n) if c not in ech]
    basis = []
    for f in free:  # null vector: x_f = 1, pivots from their rows
        v = 1 << f
        for p, row in ech.items():
            if row >> f & 1:
                v |= 1 << p
        basis.append(v)
    return [sum(1 << k for k, v in enumerate(basis) if v >> a & 1) for a in range(n)]


def _inner(P: _Linear, w: Sequence[Fraction]) -> bool:
    """Whether the grading ``w`` is ``ad`` of an element: ``{x_h, x_a} = w_a x_a`` for all ``a``.

    Then every Casimir ``C`` has ``sum_w w C_w = {x_h, C} = 0``: only weight ``0`` can occur.
    """
    n = len(P)
    rows: dict[tuple[int, int], dict[int, object]] = {}
    for b in range(n):  # {x_h, x_a} = sum_b h_b {x_b, x_a} = sum_b h_b sum_c C_ba^c x_c
        for a in range(n):
            for c, v in P[b][a]:
                rows.setdefault((a, c), {})[b] = sp.QQ(v.numerator, v.denominator)
    keys = sorted(set(rows) | {(a, a) for a in range(n)})
    data = {i: rows.get(k, {}) for i, k in enumerate(keys)}
    rhs = [sp.QQ(w[a].numerator, w[a].denominator) if a == c else sp.QQ(0) for a, c in keys]
    from poissonkit.structure._exact_linear import solve_sparse

    return solve_sparse(list(data.values()), rhs, n, sp.QQ).consistent


def graded_casimir_rows(B: Bivector, pos: Sequence[int], degree: int
                        ) -> list[PolyElement] | None:
    """A basis of the Casimirs of degree ``1..degree`` in the variables ``pos`` (ring
    elements over ``QQ``, ``grlex`` on ``B.coords``), or None if ``B`` is not linear."""
    from poissonkit.structure.casimirs import _nullspace

    P = linear_terms(B)
    if P is None:
        return None
    # integer structure constants (one common scale: the kernel does not change)
    lcm = 1
    for row in P:
        for entry in row:
            for _c, v in entry:
                lcm = lcm * v.denominator // gcd(lcm, v.denominator)
    Pz = [[[(c, int(v * lcm)) for c, v in entry] for entry in row] for row in P]
    n = B.dim
    rows = _constraints(P)
    zw, z2 = _z_weights(rows, n), _z2_weights(rows, n)
    nz = len(zw[0]) if zw else 0
    inner = [k for k in range(nz) if rows and _inner(P, [zw[a][k] for a in range(n)])]
    R = PolyRing(B.coords, sp.QQ, grlex)
    gens = lie_generators(Pz)
    flips = _inner_involutions(P)
    inner_code = _encode(zw, inner, degree)
    outer_code = _encode(zw, [k for k in range(nz) if k not in inner], degree)
    out: list[PolyElement] = []
    for d in range(1, degree + 1):
        classes: dict[tuple, list[tuple[int, ...]]] = defaultdict(list)
        for combo in combinations_with_replacement(pos, d):
            if sum(map(inner_code.__getitem__, combo)) or _xor(map(flips.__getitem__, combo)):
                continue  # an inner grading: no Casimir has a component of this weight
            e = [0] * n
            for j in combo:
                e[j] += 1
            key = (sum(map(outer_code.__getitem__, combo)), _xor(map(z2.__getitem__, combo)))
            classes[key].append(tuple(e))
        for monos in classes.values():
            out.extend(_class_kernel(Pz, monos, R, _nullspace, gens))
    return out


def _encode(zw: list[tuple], ks: Sequence[int], degree: int) -> list[int]:
    """Per coordinate, its weights in the gradings ``ks`` packed into one integer.

    The weights are scaled to integers per grading and written as signed digits in base
    ``B > 2 * degree * max|w|``: the sum of at most ``degree`` codes is then the code of the
    summed weights (no digit overflows), zero exactly when every summed weight is zero, and
    distinct for distinct weights. One integer addition per factor instead of a tuple of
    Fractions (the enumeration of monomials dominated the search).
    """
    if not ks:
        return [0] * len(zw)
    cols = []
    for k in ks:
        scale = 1
        for w in zw:
            scale = scale * w[k].denominator // gcd(scale, w[k].denominator)
        cols.append([int(w[k] * scale) for w in zw])
    base = 2 * degree * max(max(abs(v) for v in col) for col in cols) + 1
    return [sum(col[a] * base ** i for i, col in enumerate(cols)) for a in range(len(zw))]


def _inner_involutions(P: _Linear) -> list[int]:
    """Per coordinate, a bitmask of its signs under the involutions ``exp(pi ad x_h)`` that are
    diagonal in the basis (bit ``k`` set: ``x_a -> -x_a`` under the ``k``-th).

    If ``A = ad x_h`` has ``A^3 = -A`` then ``exp(t A) = 1 + sin t A + (1 - cos t) A^2``, so
    ``exp(pi A) = 1 + 2 A^2`` exactly. Casimirs are invariant under the flow of every ``x_h``
    (the coadjoint action of the connected group), so when ``1 + 2 A^2`` is diagonal with signs
    ``s_a`` only monomials with an even number of factors ``s_a = -1`` occur in a Casimir.
    Rotations by ``pi`` in ``so(p, q)``, ``u(n)``: they cut the ``Z/2``-classes of the basis
    ``m_ij`` (all ``2^n`` sign patterns of the axes) down to the two that hold Casimirs.
    """
    n = len(P)
    out = [0] * n
    k = 0
    for h in range(n):
        A = [[Fraction(0)] * n for _ in range(n)]  # A[c][a]: coefficient of x_c in {x_h, x_a}
        for a in range(n):
            for c, v in P[h][a]:
                A[c][a] += v
        if not any(any(row) for row in A):
            continue
        A2 = _matmul(A, A)
        if _matmul(A2, A) != [[-x for x in row] for row in A]:
            continue
        if any(A2[i][j] for i in range(n) for j in range(n) if i != j):
            continue
        signs = [1 + 2 * A2[a][a] for a in range(n)]
        if set(signs) <= {1, -1} and -1 in signs:
            for a in range(n):
                if signs[a] == -1:
                    out[a] |= 1 << k
            k += 1
    return out


def _matmul(A: list[list[Fraction]], B: list[list[Fraction]]) -> list[list[Fraction]]:
    n = len(A)
    cols = [[B[r][c] for r in range(n)] for c in range(n)]
    return [[sum((x * y for x, y in zip(row, col) if x and y), Fraction(0)) for col in cols]
            for row in A]


def _xor(masks) -> int:
    acc = 0
    for m in masks:
        acc ^= m
    return acc


def lie_generators(P: list[list[list[tuple[int, int]]]] | _Linear, prime: int = 2**31 - 1
                   ) -> list[int]:
    """Coordinates ``x_i`` that generate the Lie algebra (a subset, usually a few).

    ``{x_a, C} = {x_b, C} = 0`` imply ``{{x_a, x_b}, C} = 0`` (Jacobi), so a Casimir need only
    commute with generators of the algebra: far fewer equations than one per coordinate. The
    generated subalgebra is computed modulo a prime; its dimension mod ``p`` is at most the
    rational one, so "all of g mod p" certifies that the chosen set generates over ``QQ``. If
    it does not (an unlucky prime), every coordinate is returned.
    """
    n = len(P)
    if any(v.denominator % prime == 0 for row in P for entry in row for _c, v in entry):
        return list(range(n))
    P = [[[(c, v.numerator * pow(v.denominator, -1, prime) % prime) for c, v in entry]
          for entry in row] for row in P]  # integers or Fractions, reduced mod p
    order = sorted(range(n), key=lambda a: -len({c for row in P[a] for c, _v in row}))
    gens: list[int] = []
    span: dict[int, list[int]] = {}
    for a in order:
        if len(span) == n:
            break
        if _reduce_mod(_unit(a, n), span, prime) is None:
            continue  # already generated
        gens.append(a)
        span = _closure(P, gens, prime)
    return gens if len(span) == n else list(range(n))


def _unit(a: int, n: int) -> list[int]:
    v = [0] * n
    v[a] = 1
    return v


def _reduce_mod(v: list[int], span: dict[int, list[int]], p: int) -> list[int] | None:
    """``v`` reduced by the echelon rows ``span`` (pivot -> row with 1 at the pivot), or None."""
    v = [x % p for x in v]
    for piv, row in span.items():
        f = v[piv]
        if f:
            v = [(x - f * y) % p for x, y in zip(v, row)]
    return v if any(v) else None


def _closure(P, gens: list[int], p: int) -> dict[int, list[int]]:
    """Echelon basis (mod ``p``) of the subalgebra generated by the coordinates ``gens``."""
    n = len(P)
    span: dict[int, list[int]] = {}
    queue = [_unit(a, n) for a in gens]
    while queue:
        v = _reduce_mod(queue.pop(), span, p)
        if v is None:
            continue
        piv = next(k for k, x in enumerate(v) if x)
        inv = pow(v[piv], -1, p)
        v = [x * inv % p for x in v]
        for q, row in span.items():  # keep the rows reduced at the new pivot
            f = row[piv]
            if f:
                span[q] = [(x - f * y) % p for x, y in zip(row, v)]
        span[piv] = v
        for g in gens:  # [x_g, v] = sum_j v_j {x_g, x_j}
            w = [0] * n
            for j, vj in enumerate(v):
                if vj:
                    for c, coef in P[g][j]:
                        w[c] += vj * coef
            queue.append(w)
    return span


def _class_kernel(P: list[list[list[tuple[int, int]]]], monos: list[tuple[int, ...]],
                  R: PolyRing, nullspace, gens: Sequence[int] | None = None
                  ) -> list[PolyElement]:
    """Kernel of ``C -> ({x_i, C})_i`` on the span of ``monos`` (``i`` over ``gens``, default
    every coordinate)."""
    n = len(P)
    rows: dict[tuple, dict[int, int]] = {}
    for col, m in enumerate(monos):
        for j in range(n):
            mj = m[j]
            if not mj:
                continue
            base = list(m)
            base[j] -= 1
            for i in (range(n) if gens is None else gens):
                for c, v in P[i][j]:
                    t = base.copy()
                    t[c] += 1
                    slot = rows.setdefault((i, tuple(t)), {})
                    slot[col] = slot.get(col, 0) + mj * v
    data: dict[int, dict[int, object]] = {}
    for r in rows.values():
        d = {c: sp.QQ(v) for c, v in r.items() if v}
        if d:
            data[len(data)] = d
    if not data:
        return [R({m: sp.QQ(1)}) for m in monos]
    N = nullspace(DomainMatrix(data, (len(data), len(monos)), sp.QQ))
    return [R({monos[c]: v for c, v in r.items() if v}) for r in N.rep.to_sdm().values()]
