"""Exact evaluation at one random point: values and forward-mode derivatives of sympy trees.

:class:`_PointContext` holds the sampled values of one point of
:class:`~poissonkit.structure.randompoints.RandomPoints` and evaluates expressions there in
exact arithmetic (rationals and square roots over a common radical base, see
:mod:`poissonkit.structure.surds`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.surds import (_HALF, _MPQ, _ONE, _ZERO, Surd, _Base, _inverse, _Rebase,
                                        _Undefined)

if TYPE_CHECKING:
    from poissonkit.structure.randompoints import RandomPoints

__all__ = ["RandomPointError"]


class RandomPointError(InputError):
    """An expression cannot be evaluated exactly at random points (undefined or transcendental
    functions, nested or higher roots, floats that are not finite), or no point of the domain
    was found."""


def _unsupported(e: sp.Expr) -> str:
    from sympy.core.function import AppliedUndef

    if isinstance(e, (AppliedUndef, sp.Derivative, sp.Subs)):
        return (f"undefined function {e} cannot be evaluated at random points; use "
                "method='exact' (which proves the claim for every function)")
    return (f"{type(e).__name__} ({str(e)[:60]}) cannot be evaluated exactly at random points; "
            "use method='exact'")


class _PointContext:
    """One random point: sampled values, radical base and memoised sub-expression values."""

    def __init__(self, owner: RandomPoints, index: int) -> None:
        self.owner = owner
        self.index = index
        self.values: dict[sp.Symbol, Any] = {}
        self.base = _Base()
        self.memo: dict[sp.Expr, Any] = {}
        self.dmemo: dict[sp.Symbol, dict[sp.Expr, Any]] = {}
        #: what builds receive: ``ev(e)`` is the value, ``ev.d(e, x)`` the partial derivative
        self.ev = _Evaluator(self._ev, self.d)

    def _reset(self, n: int) -> None:
        self.base = self.base.refined(n)
        self.memo.clear()
        self.dmemo.clear()

    def symbol(self, s: sp.Symbol):
        v = self.values.get(s)
        if v is None:
            base = self.owner.radical_bases.get(s)
            if base is not None:   # a square-root symbol of RandomPoints.derivative
                return self._sqrt(self._ev(base))
            param = self.owner.parametrization.get(s)
            v = self.owner.draw(s, self.index) if param is None else self.value(param)
            self.values[s] = v
        return v

    def value(self, e: sp.Expr):
        """Exact value of ``e`` here (raises ``_Undefined`` outside the domain)."""
        while True:
            try:
                return self._ev(e)
            except _Rebase as r:
                self._reset(r.n)

    def _ev(self, e):
        memo = self.memo
        v = memo.get(e)
        if v is not None:
            return v
        if e.is_Rational:
            v = _MPQ(int(e.p), int(e.q))
        elif e.is_Symbol:
            v = self.symbol(e)
        elif e.is_Add:
            it = iter(e.args)
            v = self._ev(next(it))
            for a in it:
                v = v + self._ev(a)
        elif e.is_Mul:
            # no short cut at a zero factor: every factor must be defined at the point
            v = _MPQ(1)
            for a in e.args:
                v = self._ev(a) * v
        elif e.is_Pow:
            v = self._pow(e)
        elif isinstance(e, sp.Abs):
            v = self._ev(e.args[0])
            if isinstance(v, Surd):
                raise RandomPointError(f"Abs of an irrational value is not supported: {e}")
            v = abs(v)
        elif e.is_Float:
            if not e.is_finite:
                raise RandomPointError(f"non-finite number {e} in the expression")
            r = sp.Rational(e)   # the float's exact binary value
            v = _MPQ(int(r.p), int(r.q))
        else:
            raise RandomPointError(_unsupported(e))
        memo[e] = v
        return v

    def _pow(self, e):
        b, x = e.args
        if x.is_Integer:
            bv = self._ev(b)
            k = int(x)
            if k >= 0:
                return bv**k
            return _inverse(bv) ** (-k)
        if x.is_Rational and x.q == 2:
            bv = self._ev(b)
            return self._sqrt(bv) * bv ** ((int(x.p) - 1) // 2)
        raise RandomPointError(f"only integer powers and square roots can be evaluated "
                               f"exactly, got {e}")

    def d(self, e, x: sp.Symbol):
        """Exact ``d e / d x`` at this point by forward-mode differentiation of the tree
        (coordinates independent; no symbolic derivative is formed)."""
        memo = self.dmemo.get(x)
        if memo is None:
            memo = self.dmemo[x] = {}
        v = memo.get(e)
        if v is not None:
            return v
        if e.is_Symbol:
            base = self.owner.radical_bases.get(e)
            if base is None:
                v = _ONE if e == x else _ZERO
            else:   # s = sqrt(Q): ds = dQ / (2 s)
                dq = self.d(base, x)
                v = dq * _inverse(self._ev(e)) * _HALF if dq else _ZERO
        elif e.is_Rational or e.is_Float:
            v = _ZERO
        elif e.is_Add:
            v = _ZERO
            for a in e.args:
                v = self.d(a, x) + v
        elif e.is_Mul:
            args = e.args
            v = _ZERO
            for i, a in enumerate(args):
                da = self.d(a, x)
                if da:
                    for j, b in enumerate(args):
                        if j != i:
                            da = self._ev(b) * da
                    v = da + v
            self._ev(e)   # definedness of the product itself
        elif e.is_Pow:
            b, k = e.args
            db = self.d(b, x)
            val = self._ev(e)
            if not db:
                v = _ZERO
            elif k.is_Integer and k > 0:
                v = self._ev(b) ** (int(k) - 1) * db * int(k)
            else:   # k e / b * db, for negative integers and half-integers
                v = val * _inverse(self._ev(b)) * db * _MPQ(int(k.p), int(k.q))
        elif isinstance(e, sp.Abs):
            a = self._ev(e.args[0])
            if not a:
                raise _Undefined   # |x| is not differentiable at 0
            v = self.d(e.args[0], x) if a > 0 else -self.d(e.args[0], x)
        else:
            raise RandomPointError(_unsupported(e))
        memo[e] = v
        return v

    def _sqrt(self, bv):
        if isinstance(bv, Surd):
            raise RandomPointError("nested square roots are not supported")
        if bv <= 0:
            raise _Undefined   # outside the real domain (or on its boundary)
        n, d = int(bv.numerator), int(bv.denominator)
        c, mask = self.base.express(n * d)
        return Surd.make(self.base, {mask: _MPQ(c, d)})   # sqrt(n/d) = sqrt(n d)/d

    def value_of(self, build: Callable[[Callable], Any]):
        """``build(ev)`` at this point, re-run from scratch when the radical base is refined."""
        while True:
            try:
                return build(self.ev)
            except _Rebase as r:
                self._reset(r.n)

    def point(self) -> dict[sp.Symbol, sp.Rational]:
        return {s: sp.Rational(int(v.numerator), int(v.denominator))
                for s, v in sorted(self.values.items(), key=lambda kv: str(kv[0]))}


class _Evaluator:
    """What a check's ``build`` receives: ``ev(e)`` for a sympy expression, ``ev.d(e, x)`` for
    its partial derivative in ``x``; exact values at a point (:class:`_PointContext`) or degree
    records for the bound (:meth:`RandomPoints.test`), so that one ``build`` serves both."""

    __slots__ = ("_value", "d")

    def __init__(self, value: Callable[[Any], Any], d: Callable[[Any, sp.Symbol], Any]) -> None:
        self._value = value
        self.d = d

    def __call__(self, e):
        return self._value(e)
