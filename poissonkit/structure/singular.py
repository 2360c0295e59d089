"""Singular set of a bivector: where its rank drops below the generic rank.

The union over the independent blocks (:mod:`poissonkit.structure.decomposition`) of each
block's own singular set, cut out by its Pfaffians. Method notes: ``docs/casimirs.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import combinations

import sympy as sp

from poissonkit.errors import PoissonkitError
from poissonkit.structure.zerotest import _Atomizer
from poissonkit.structure.decomposition import _bivector, _blocks, _sub
from poissonkit.structure.rank import rank

__all__ = ["SingularSet", "SingularSetTooExpensive", "singular_set"]


class SingularSetTooExpensive(PoissonkitError):
    """The singular set needs more Pfaffians than the caller allowed (``max_minors``)."""


@dataclass(frozen=True)
class SingularSet:
    """Where the rank of ``P`` drops below its generic value.

    Attributes
    ----------
    rank
        The generic rank.
    components
        One tuple of equations per block whose rank can drop: the set is the **union** over
        components of the common zeros of that component's equations.
    undefined
        Expressions whose zeros make ``P`` undefined (denominators), reported separately.
    note
        Method remarks (non-polynomial atoms, parameters).
    """

    rank: int
    components: tuple[tuple[sp.Expr, ...], ...]
    undefined: tuple[sp.Expr, ...] = ()
    note: str = ""

    @property
    def equations(self) -> tuple[sp.Expr, ...]:
        """One list of equations for the whole set: products across components (union)."""
        if not self.components:
            return (sp.Integer(1),)
        eqs: list[sp.Expr] = [sp.Integer(1)]
        for comp in self.components:
            eqs = [sp.factor(a * b) for a in eqs for b in comp]
        return tuple(eqs)

    @property
    def empty(self) -> bool:
        """Whether the rank never drops (where ``P`` is defined)."""
        return not self.components


def _pfaffian(A: sp.Matrix) -> sp.Expr:
    n = A.rows
    if n == 0:
        return sp.Integer(1)
    if n % 2:
        return sp.Integer(0)
    total = sp.Integer(0)
    for j in range(1, n):
        a = A[0, j]
        if a == 0:
            continue
        keep = [k for k in range(1, n) if k != j]
        total += (-1) ** (j + 1) * a * _pfaffian(A.extract(keep, keep))
    return sp.expand(total)


def _squarefree(p: sp.Expr, gens) -> sp.Expr | None:
    """Product of the distinct non-constant irreducible factors (None if p is a non-zero const)."""
    if not gens:
        return None if p != 0 else sp.Integer(0)
    _c, facs = sp.factor_list(p, *gens)
    facs = [f for f, _m in facs if f.free_symbols & set(gens)]
    if not facs:
        return None
    return sp.expand(sp.Mul(*facs))


def _simplify_ideal(polys: list, gens: list) -> list | None:
    """Generators with the same zero set, square-free and Groebner-reduced; None = empty set."""
    current = polys
    for _ in range(4):
        sq = []
        for p in current:
            s = _squarefree(p, gens)
            if s is None:
                return None  # a non-zero constant: no common zeros
            if s != 0:
                sq.append(s)
        sq = list(dict.fromkeys(sq))
        if not sq:
            return []
        G = list(sp.groebner(sq, *gens, order="grevlex").exprs)
        if G == [1]:
            return None
        if set(G) == set(current):
            break
        current = G
    return current


def singular_set(P, *, max_minors: int = 2000) -> SingularSet:
    """Where ``rank P`` is smaller than its generic rank ``r``.

    The rank of an antisymmetric matrix drops below ``r`` exactly where all principal
    ``r x r`` Pfaffians vanish. Per block, their numerators are computed, every non-polynomial
    sub-expression (``sqrt``, undefined functions, ...) is replaced by an independent symbol,
    and the generators are made square-free and Groebner-reduced repeatedly. Each step keeps
    the ideal's zero set in the enlarged space, and substituting the true values of the
    replaced sub-expressions keeps equality of zero sets pointwise, so the returned equations
    describe the singular set *exactly* (if not always in the simplest form). Parameters are
    kept symbolic: the equations hold jointly in coordinates and parameters.

    Parameters
    ----------
    P
        The bivector.
    max_minors
        Refuse (:class:`SingularSetTooExpensive`) if a block needs more Pfaffians than this.

    Returns
    -------
    SingularSet
        For e(3): one component ``(nu_x, nu_y, nu_z)``, i.e. ``nu = 0``.
    """
    P = _bivector(P)
    comps: list[tuple[sp.Expr, ...]] = []
    undefined: list[sp.Expr] = []
    total_rank = 0
    notes = set()
    for idx in _blocks(P):
        B = _sub(P, idx)
        r = int(rank(B, seed=0, trials=3))
        total_rank += r
        if r == 0:
            continue  # rank 0 cannot drop
        subsets = math.comb(B.dim, r)
        if subsets > max_minors:
            raise SingularSetTooExpensive(
                f"block {[str(c) for c in B.coords]} needs {subsets} Pfaffians of order {r} "
                f"(max_minors={max_minors})")
        at = _Atomizer()
        for e in B.matrix:
            if e != 0:
                den = sp.fraction(sp.together(at(e)))[1]
                if den.free_symbols:
                    undefined.append(at.restore(den))
        nums = []
        for sub in combinations(range(B.dim), r):
            pf = _pfaffian(B.matrix.extract(list(sub), list(sub)))
            if pf == 0:
                continue
            num, _den = sp.fraction(sp.together(at(pf)))
            nums.append(sp.expand(num))
        if at.back:
            notes.add("non-polynomial sub-expressions were treated as independent symbols "
                      "and substituted back")
        gens = sorted(set().union(*(p.free_symbols for p in nums)) if nums else set(), key=str)
        ideal = _simplify_ideal(nums, gens) if gens else (None if nums else [])
        if ideal is None:
            continue
        comps.append(tuple(sp.factor(at.restore(p)) for p in ideal))
    und = []
    for d in undefined:
        try:
            facs = sp.factor_list(d)[1]
        except sp.PolynomialError:
            facs = [(d, 1)]
        for f, _m in facs:
            f = sp.factor(f)
            if f.free_symbols and f not in und:
                und.append(f)
    return SingularSet(total_rank, tuple(comps), tuple(und), "; ".join(sorted(notes)))
