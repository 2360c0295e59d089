"""The exact symbolic zero test of the structure checks.

:func:`is_zero_expression` decides whether an expression is identically zero (or zero on the
constraint set) without ``simplify`` in loops: rational functions by their numerator in a sparse
rational-function field; otherwise expansion, then square roots ``sqrt(u)`` replaced by symbols
``G`` with ``G**2 = u`` and the residual reduced over a common denominator, then reduction
modulo a Groebner basis of the constraints. Undefined functions ``g(gamma)`` and their
derivatives are independent atoms, so a zero holds for *every* ``g``. ``sympy.simplify`` is the
fallback only for what the algebraic test cannot decide (transcendental functions).

:func:`vanishes` is the zero test of the field checks (:mod:`poissonkit.structure.checks`):
every non-polynomial sub-expression (roots, undefined functions) becomes a symbol with its
polynomial relation, and the numerator is reduced modulo a Groebner basis of those relations and
the constraints. ``True`` is a proof in both.

Their counterpart at a random point is :func:`poissonkit.structure.sampling.is_zero_at_point`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp
from sympy.core.function import AppliedUndef

from poissonkit.errors import InputError
from poissonkit.structure._expr import as_expr

__all__ = ["canonical_atom", "is_zero_expression", "vanishes"]


def _is_half_power(e: sp.Basic) -> bool:
    return (isinstance(e, sp.Pow) and e.exp.is_Rational and e.exp.q == 2
            and bool(e.base.free_symbols))



def _function_atoms(e: sp.Expr) -> set[sp.Expr]:
    return {a for a in sp.preorder_traversal(e)
            if isinstance(a, (AppliedUndef, sp.Derivative, sp.Subs))}


def _dummify_functions(exprs: Sequence[sp.Expr]) -> tuple[list[sp.Expr], dict]:
    """Replace undefined-function atoms by dummies (for polynomial reduction)."""
    atoms: set[sp.Expr] = set()
    for e in exprs:
        atoms |= _function_atoms(e)
    # xreplace matches whole sub-trees top-down; atoms equal up to expansion of their
    # arguments (the same jet value written twice) share one dummy
    by_key: dict[sp.Expr, sp.Dummy] = {}
    rule = {}
    for a in sorted(atoms, key=sp.default_sort_key):
        key = canonical_atom(a)
        if key not in by_key:
            by_key[key] = sp.Dummy(f"F{len(by_key)}")
        rule[a] = by_key[key]
    return [e.xreplace(rule) for e in exprs], rule


def _rational_numerator(e: sp.Expr) -> sp.Expr | None:
    """Expanded numerator of ``e`` over a common denominator, or ``None`` if not rational.

    ``e`` must be a rational function of its symbols and undefined-function atoms (these are
    treated as independent variables, see :func:`_dummify_functions`); square roots and
    transcendental functions give ``None``. Uses sympy's sparse rational-function field, which
    cancels as it goes: much faster than ``expand`` / ``simplify`` on sums of fractions.
    """
    (d,), rule = _dummify_functions([e])
    syms = sorted(d.free_symbols, key=str)
    if not syms:
        return None
    try:
        F, *_ = sp.polys.fields.field(syms, sp.QQ)
        num = F.from_expr(d).numer.as_expr()
    except (sp.PolynomialError, sp.CoercionFailed, ValueError, TypeError):
        return None  # radicals, transcendental functions, non-rational constants
    back = {v: k for k, v in rule.items()}
    return num.xreplace(back) if back else num


class _ZeroTester:
    """Exact zero test with square-root relations and optional constraints."""

    def __init__(self, radicals: Mapping[sp.Symbol, sp.Expr], coords: Sequence[sp.Symbol],
                 constraints: Sequence[sp.Expr] = ()) -> None:
        self.radicals = dict(radicals)
        self.coords = tuple(coords)
        self.gb = None
        if constraints:
            cons = [sp.numer(sp.together(sp.sympify(c))) for c in constraints]
            cons, _ = _dummify_functions(cons)
            for c in cons:
                if not c.is_polynomial(*self.coords):
                    raise InputError(f"constraint {c} is not polynomial in the coordinates")
            self.gb = sp.groebner(cons, *self.coords, order="grevlex")

    def _reduce_constraints(self, e: sp.Expr) -> sp.Expr:
        if self.gb is None or e == 0:
            return e
        (e,), _ = _dummify_functions([e])
        return sp.expand(self.gb.reduce(sp.expand(e))[1])

    def residual(self, e: sp.Expr) -> sp.Expr:
        """``0`` if ``e`` vanishes (on the constraint surface), else a non-zero residual."""
        ex = sp.expand(e)
        if ex == 0:
            return ex
        if not self.radicals and self.gb is None:
            # a sum of fractions with different denominators only cancels over a common one
            num = _rational_numerator(e)
            if num is None:
                num = sp.expand(sp.numer(sp.together(ex)))
            return sp.Integer(0) if num == 0 else ex
        num = _rational_numerator(e)
        if num is None:
            num = sp.expand(sp.numer(sp.together(ex)))
        parts = [num]
        for G, u in self.radicals.items():
            new = []
            for part in parts:
                if not part.has(G):
                    new.append(part)
                    continue
                even = sp.Integer(0)
                odd = sp.Integer(0)
                for term, coeff in sp.collect(part, G, evaluate=False).items():
                    _, k = term.as_coeff_exponent(G)
                    if not k.is_Integer or k < 0:
                        raise InputError("unexpected power of a square-root symbol")
                    k = int(k)
                    rest = term / G**k
                    piece = coeff * rest * u ** (k // 2)
                    if k % 2:
                        odd += piece
                    else:
                        even += piece
                new.extend([sp.expand(even), sp.expand(odd)])
            parts = new
        nonzero = [p for p in (self._reduce_constraints(sp.expand(p)) for p in parts) if p != 0]
        if not nonzero:
            return sp.Integer(0)
        return ex

    def is_zero(self, e: sp.Expr) -> bool:
        return self.residual(e) == 0


def is_zero_expression(e: sp.Expr, constraints: Sequence[sp.Expr] = (),
                       coords: Sequence[sp.Symbol] = ()) -> bool:
    """Exact zero test: expansion, then square-root rationalisation, then constraints.

    Rational functions (of symbols and undefined-function atoms, no constraints) take a fast
    exact path: the numerator over a common denominator, computed in sympy's sparse
    rational-function field, must be zero.

    Square roots ``sqrt(u)`` are replaced by symbols ``G`` with ``G**2 = u``; a residual that does
    not expand to zero is put over a common denominator and reduced (see module docstring).
    Falls back to ``sympy.simplify`` for what the algebraic test cannot decide
    (transcendental functions).
    """
    e = as_expr(e)
    constraints = tuple(as_expr(c, "constraint") for c in constraints)
    if e == 0:
        return True
    if not constraints and not _has_fractional_power(e):
        # rational fast path: exact, and no expansion of the unreduced sum
        num = _rational_numerator(e)
        if num is not None:
            return num == 0
    if sp.expand(e) == 0:
        return True
    bases: dict[sp.Expr, sp.Symbol] = {}
    rule = {}
    for p in sp.preorder_traversal(e):
        if _is_half_power(p):
            base = sp.expand(p.base)
            G = bases.setdefault(base, sp.Dummy(f"G{len(bases)}"))
            rule[p] = G ** p.exp.p
    radicals = {G: u for u, G in bases.items()}
    if constraints and not coords:
        # the variables of the constraints are the surface's coordinates
        coords = sorted(set().union(*(sp.sympify(c).free_symbols for c in constraints)), key=str)
    tester = _ZeroTester(radicals, coords, constraints)
    if tester.is_zero(e.xreplace(rule)):
        return True
    return not constraints and sp.simplify(e) == 0


def _has_fractional_power(e: sp.Expr) -> bool:
    return any(isinstance(a, sp.Pow) and not a.exp.is_Integer for a in sp.preorder_traversal(e))


def _has_transcendental(e: sp.Expr) -> bool:
    return any(isinstance(a, sp.Function) and not isinstance(a, AppliedUndef)
               for a in sp.preorder_traversal(e))


# ---------------------------------------------------------------------------------- atoms
@dataclass
class _Atomizer:
    """Replace non-polynomial sub-expressions by symbols (the atoms of
    :mod:`poissonkit.structure.checks`' module docstring)."""

    table: dict = field(default_factory=dict)        # key -> Dummy
    back: dict = field(default_factory=dict)         # Dummy -> original expression
    relations: list = field(default_factory=list)    # polynomials t**q - b
    opaque: bool = False                             # saw sin/exp/... (not generic functions)
    memo: dict = field(default_factory=dict)         # sub-expression -> atomized form

    def _new(self, key, original) -> sp.Symbol:
        if key not in self.table:
            t = sp.Dummy(f"t{len(self.table)}")
            self.table[key] = t
            self.back[t] = original
        return self.table[key]

    def __call__(self, e):
        e = sp.sympify(e)
        if e.is_Atom:
            return e
        hit = self.memo.get(e)
        if hit is None:
            hit = self.memo[e] = self._atomize(e)
        return hit

    def _atomize(self, e):
        if isinstance(e, sp.Pow):
            base, ex = e.args
            if ex.is_Integer:
                return self(base) ** ex
            if ex.is_Rational:
                # b = nb/db: b**(1/q) = (nb db**(q-1))**(1/q) / db, so that the relation
                # t**q = nb db**(q-1) is polynomial
                nb, db = sp.fraction(sp.together(self(base)))
                q = int(ex.q)
                B = sp.expand(nb * db ** (q - 1))
                key = ("root", B, q)
                fresh = key not in self.table
                t = self._new(key, sp.Pow(base, sp.Rational(1, q)) * self.restore(db))
                if fresh:
                    self.relations.append(t ** q - B)
                return (t / db) ** int(ex.p)
            self.opaque = True
            return self._new(("opaque", e), e)
        if isinstance(e, sp.Subs):
            # Subs(Derivative(g(.., u, ..), u), u, x) with a symbol x is just dg/dx: canonical
            done = e.doit()
            if not isinstance(done, sp.Subs) and done != e:
                return self(done)
        if isinstance(e, (AppliedUndef, sp.Derivative, sp.Subs)):
            # the same jet value may arrive in different literal forms (arguments expanded or
            # not): key it by a canonical form so that it becomes one atom, not two
            return self._new(("function", canonical_atom(e)), e)
        if isinstance(e, sp.Function) or not (e.is_Add or e.is_Mul):
            self.opaque = True
            return self._new(("opaque", e), e)
        return e.func(*[self(a) for a in e.args])

    def restore(self, e):
        """Substitute the original sub-expressions back."""
        return sp.sympify(e).xreplace(self.back)


def canonical_atom(e: sp.Expr) -> sp.Expr:
    """Canonical form of an undefined-function atom (``g(..)``, a derivative, a ``Subs``).

    The arguments (and substitution points) are expanded, so that ``U((a + b)/r)`` and
    ``U(a/r + b/r)`` - the same value of ``U`` - are recognised as one quantity.
    """
    try:
        return sp.expand(e)
    except Exception:  # noqa: BLE001 - expansion failed: the literal form is still a valid key
        return e


def _numerators(exprs: list) -> list:
    """Expanded numerators of rational expressions (sparse field arithmetic, else together)."""
    syms = sorted(set().union(*(e.free_symbols for e in exprs)), key=str)
    if syms:
        try:
            F, *_ = sp.polys.fields.field(syms, sp.QQ)
            return [F.from_expr(e).numer.as_expr() if e != 0 else sp.Integer(0) for e in exprs]
        except (sp.PolynomialError, sp.CoercionFailed, ValueError, TypeError):
            pass  # non-rational constants (pi, I, ...): fall back to sympy's together
    return [sp.expand(sp.fraction(sp.together(e))[0]) for e in exprs]


def _polys(exprs: Iterable, constraints: Sequence, atomizer: _Atomizer):
    nums = _numerators([atomizer(e) for e in exprs])
    cons = _numerators([atomizer(c) for c in constraints]) if constraints else []
    return nums, cons


def _reduce(nums: list, ideal: list) -> list:
    """Normal forms of ``nums`` modulo the ideal generated by ``ideal`` (0 = member)."""
    ideal = [g for g in ideal if g != 0]
    if not ideal:
        return nums
    gens = sorted(set().union(*(n.free_symbols for n in nums + ideal)), key=str)
    if not gens:
        return nums
    G = sp.groebner(ideal, *gens, order="grevlex")
    if list(G.exprs) == [1]:
        raise InputError("constraints are inconsistent (their ideal contains 1)")
    return [G.reduce(n)[1] if n != 0 else n for n in nums]


def _vanishing(exprs: Sequence, constraints: Sequence = ()) -> list:
    """Residuals (0 for each expression that vanishes identically / modulo constraints)."""
    atomizer = _Atomizer()
    nums, cons = _polys(exprs, constraints, atomizer)
    if all(n == 0 for n in nums):
        return [sp.Integer(0)] * len(nums)
    red = _reduce(nums, atomizer.relations + cons)
    out = []
    for e, r in zip(exprs, red):
        if r != 0 and atomizer.opaque and not cons:
            # atoms such as sin/cos were treated as independent: let sympy try identities
            if sp.simplify(e) == 0:
                r = sp.Integer(0)
        out.append(atomizer.restore(r) if r != 0 else sp.Integer(0))
    return out


def vanishes(expr, constraints: Sequence = ()) -> bool:
    """Whether ``expr`` vanishes identically (or modulo the ideal of ``constraints``).

    Parameters
    ----------
    expr
        A sympy expression (may contain parameters, undefined functions, square roots).
    constraints
        Expressions that vanish on the surface of interest, e.g. ``gx**2 + gy**2 + gz**2 - 1``.

    Returns
    -------
    bool
        ``True`` is a proof; see the module docstring for what ``False`` means.
    """
    return _vanishing([as_expr(expr)], _as_exprs(constraints))[0] == 0


# Shared conversions (strings are refused: sympify would eval them).
_expr = as_expr


def _as_exprs(items) -> list:
    if items is None:
        return []
    if isinstance(items, (sp.Basic, str)):
        items = [items]
    return [_expr(c, "constraint") for c in items]
