"""Exact numbers at a point: rationals and sums of products of square roots.

A value of the randomized checks at a random rational point lies in ``Q(sqrt(b_1), ...)``
with the ``b_j`` pairwise coprime non-square integers (a *coprime base*, refined when a new
radicand shares a factor with a generator). Products of square roots of distinct subsets of
such ``b_j`` are linearly independent over ``Q`` (Besicovitch), so a :class:`Surd` is zero iff
every coefficient is zero: the zero test at a point is exact, with no numerics.
"""

from __future__ import annotations

from collections.abc import Sequence
from math import gcd, isqrt
from typing import Any

import sympy as sp
from sympy.polys.domains import QQ

__all__ = ["Surd"]

_MPQ = QQ.dtype
_ZERO = _MPQ(0)
_ONE = _MPQ(1)
_HALF = _MPQ(1, 2)


class _Undefined(Exception):
    """The expression is not defined (real) at this point: skip the point."""


class _Rebase(Exception):
    """A new radicand shares a factor with a generator: refine the base, re-evaluate."""

    def __init__(self, n: int) -> None:
        super().__init__(n)
        self.n = n


# ---------------------------------------------------------------------- multi-quadratic numbers
class _Base:
    """Pairwise coprime, non-square integers ``b_j`` (generators ``sqrt(b_j)``) of one point."""

    def __init__(self, gens: Sequence[int] = ()) -> None:
        self.gens: list[int] = list(gens)
        self._prod: dict[int, int] = {0: 1}

    def product(self, mask: int) -> int:
        """``prod_{j in mask} b_j``."""
        p = self._prod.get(mask)
        if p is None:
            p = 1
            for j, b in enumerate(self.gens):
                if mask >> j & 1:
                    p *= b
            self._prod[mask] = p
        return p

    def express(self, n: int) -> tuple[int, int]:
        """``(c, mask)`` with ``n = c**2 * prod_{j in mask} b_j``; may append a generator."""
        c, mask, rem = 1, 0, n
        for j, b in enumerate(self.gens):
            k = 0
            while rem % b == 0:
                rem //= b
                k += 1
            if k:
                c *= b ** (k // 2)
                if k % 2:
                    mask |= 1 << j
            if gcd(rem, b) > 1:
                raise _Rebase(n)
        r = isqrt(rem)
        if r * r == rem:
            return c * r, mask
        # rem is coprime to every generator and not a square: a new independent generator
        self.gens.append(rem)
        return c, mask | 1 << (len(self.gens) - 1)

    def refined(self, n: int) -> _Base:
        """A coprime base of the generators and ``n`` (squares dropped)."""
        items = [x for x in [*self.gens, n] if x > 1]
        changed = True
        while changed:
            changed = False
            items = sorted(set(items))
            for a_i in range(len(items)):
                for b_i in range(a_i + 1, len(items)):
                    a, b = items[a_i], items[b_i]
                    g = gcd(a, b)
                    if g > 1:
                        rest = [x for t, x in enumerate(items) if t not in (a_i, b_i)]
                        items = [x for x in (*rest, a // g, b // g, g) if x > 1]
                        changed = True
                        break
                if changed:
                    break
        return _Base([x for x in items if isqrt(x) ** 2 != x])


class Surd:
    """An element ``sum_mask c_mask prod_{j in mask} sqrt(b_j)`` of ``Q(sqrt(b_1), ...)``.

    The coefficients are exact rationals and the generators form a coprime base, so the element
    is zero iff it has no term. Instances are produced by the evaluator; arithmetic with
    rationals and with surds of the same point is supported.
    """

    __slots__ = ("base", "terms")

    def __init__(self, base: _Base, terms: dict[int, Any]) -> None:
        self.base = base
        self.terms = terms

    @staticmethod
    def make(base: _Base, terms: dict[int, Any]):
        terms = {m: c for m, c in terms.items() if c}
        if not terms:
            return _MPQ(0)
        if len(terms) == 1 and 0 in terms:
            return terms[0]
        return Surd(base, terms)

    def _terms(self, other) -> dict[int, Any]:
        return other.terms if isinstance(other, Surd) else {0: other}

    def __add__(self, other):
        out = dict(self.terms)
        for m, c in self._terms(other).items():
            out[m] = out.get(m, 0) + c
        return Surd.make(self.base, out)

    __radd__ = __add__

    def __neg__(self):
        return Surd(self.base, {m: -c for m, c in self.terms.items()})

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, Surd):
            if not other:
                return _MPQ(0)
            return Surd(self.base, {m: c * other for m, c in self.terms.items()})
        out: dict[int, Any] = {}
        prod = self.base.product
        for m1, c1 in self.terms.items():
            for m2, c2 in other.terms.items():
                m = m1 ^ m2
                out[m] = out.get(m, 0) + c1 * c2 * prod(m1 & m2)
        return Surd.make(self.base, out)

    __rmul__ = __mul__

    def __pow__(self, k: int):
        result: Any = _MPQ(1)
        base: Any = self
        while k:
            if k & 1:
                result = base * result
            k >>= 1
            if k:
                base = base * base
        return result

    def inverse(self):
        """``1/self`` by successive conjugation (``(a + b t)(a - b t) = a**2 - b**2 t**2``)."""
        top = max(m.bit_length() for m in self.terms) - 1
        bit = 1 << top
        a = Surd.make(self.base, {m: c for m, c in self.terms.items() if not m & bit})
        b = Surd.make(self.base, {m ^ bit: c for m, c in self.terms.items() if m & bit})
        conj = a - b * Surd(self.base, {bit: _MPQ(1)})
        norm = a * a - b * b * self.base.gens[top]
        return conj * _inverse(norm)

    def __bool__(self) -> bool:
        return bool(self.terms)

    def to_sympy(self) -> sp.Expr:
        return sp.Add(*[sp.Rational(c.numerator, c.denominator) * sp.sqrt(self.base.product(m))
                        for m, c in self.terms.items()])


def _inverse(x):
    if isinstance(x, Surd):
        return x.inverse()
    if not x:
        raise _Undefined
    return 1 / x


def _to_sympy(x) -> sp.Expr:
    if isinstance(x, Surd):
        return x.to_sympy()
    return sp.Rational(x.numerator, x.denominator)
