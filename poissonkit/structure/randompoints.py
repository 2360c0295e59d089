"""Randomized checks in exact arithmetic: expressions evaluated at seeded random rational points.

This is the ``method="random"`` of the field checks in :mod:`poissonkit.structure.checks`
(:func:`~poissonkit.structure.checks.is_first_integral`, ``in_involution``,
``is_conformally_hamiltonian``, ``is_invariant_measure``, ``check_vanishing``), the analogue of
``check_jacobi(method="random")`` for vector-field identities. It is meant for systems whose
symbolic proof is slow (the rolling balls with ``g = sqrt(Q)``: seconds to minutes per claim).

How a point is evaluated
------------------------
Every sampled symbol (coordinates and parameters) gets a random rational
``scale * p / SAMPLE_RANGE`` with ``p`` a uniform integer in ``[-SAMPLE_RANGE, SAMPLE_RANGE]``
from the one sampler of the symbolic checks (:class:`~poissonkit.structure.sampling.Sampler`)
(symbols declared ``positive`` or ``negative`` get that sign, ``integer`` ones the integer
``p``), drawn from a generator seeded by ``(seed, point index, symbol name)``: a run is
reproducible and does not depend on the order in which symbols are met. The scale is 1 (the
unit box, where the survey's radicands such as ``1 - d (gamma, A gamma)`` are mostly positive);
points found outside the domain are replaced by points at scales ``1/8, 8, 1/64, ...``. Sympy expressions are then evaluated bottom-up (sub-expressions
memoised per point) in exact arithmetic:

* rationals for ``+``, ``*`` and integer powers;
* ``b**(p/2)`` with ``b`` rational at the point: ``sqrt(b)`` is written over a *coprime base*
  of the point's radicands, i.e. ``sqrt(b) = c * prod_j sqrt(b_j)`` with ``b_j`` pairwise
  coprime non-square integers (refined when a new radicand shares a factor with a generator).
  Products of square roots of distinct subsets of such ``b_j`` are linearly independent over
  ``Q`` (Besicovitch), so a value is a vector of rational coefficients and **is zero iff every
  coefficient is zero**: the zero test at a point is exact, with no numerics;
* a point where a denominator vanishes or a radicand is ``<= 0`` (outside the real domain of the
  expressions) is skipped and a further point is drawn.

Derivatives (``dH``, ``dF``, ``d_i P_ij``, ``d_i (rho N)``) are never formed symbolically: the
checks take them at the point by exact forward-mode differentiation of the expression tree
(``ev.d(e, x)`` in :meth:`RandomPoints.test`), which for the Routh sphere's large entries is
~100x cheaper than ``sympy.diff``.

Consequently a ``False`` result is always a genuine counterexample: the reported point (exact
rationals) satisfies the constraints and the reported value there is a non-zero real number.

Constraint surfaces
-------------------
With ``constraints``, points are drawn on the surface through a rational parametrisation:
either given (``parametrization={coord: expression in new symbols}``, checked against the
constraints) or recognised: the unit sphere ``x**2 + y**2 + z**2 - 1`` in three coordinates
(inverse stereographic projection ``(2u, 2v, 1 - u**2 - v**2)/(1 + u**2 + v**2)``, which covers
every rational point but the pole) and constraints linear in one coordinate (solved for it).

The false-positive bound
------------------------
If the tested expression ``E`` is not zero on the domain (or the surface), its value is
``num/den`` with ``num`` a polynomial of total degree ``D`` in the sampled variables (after
clearing denominators and, for ``k`` distinct square roots, taking the norm, which multiplies
the degree by at most ``2**k``). Each sampled variable is independent with point masses at most
``eps = 1/SAMPLE_RANGE``, so by the Schwartz–Zippel lemma (in its form for independent variables
with bounded point masses) ``E`` vanishes at a point with probability ``<= D * eps``, and passes
``t`` independent points with probability ``<= (D * eps)**t``. With a parametrisation of degree
``delta`` the degree is ``D * delta``. This is the ``false_positive_bound`` of the result.

Caveats (honestly): the norm argument needs radicands that are not perfect squares (as
functions): ``sqrt((x - 1/2)**2) - (x - 1/2)`` vanishes on ``x > 1/2`` and passes at points
drawn there, so a piecewise identity can pass with a probability the bound does not cover
(the unit box is sampled first). ``D`` is an upper bound computed structurally from the expression trees
(degrees add under ``*``, common denominators are formed per distinct factor), which is
rigorous for rational expressions but *heuristic* for square roots (a radical ``sqrt(b)`` counts
as half the degree of ``b``; the norm argument is sound, the bookkeeping of repeated radicals in
denominators is not proved tight). Points outside the domain are rejected, so the points are
drawn conditionally on the domain: the bound grows by the inverse of the acceptance rate
(reported in the note). Undefined functions (``g(gamma)``) and transcendental functions are
not supported here (``RandomPointError``): use the exact method.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure._expr import as_expr, as_symbols
from poissonkit.structure._point_eval import RandomPointError, _Evaluator, _PointContext
from poissonkit.structure.degreebound import _as_degree, _Degree
from poissonkit.structure.surds import _MPQ, _to_sympy, _Undefined
from poissonkit.structure.surfaces import (_check_acyclic, _param_degree, _recognise,
                                           sphere_parametrization)
from poissonkit.structure.sampling import (SAMPLE_RANGE, Sampler, false_positive_bound,
                                           is_zero_at_point)

__all__ = [
    "SAMPLE_RANGE", "RandomPointError", "RandomPoints",
    "sphere_parametrization",
]

#: Points tried per requested point before giving up (denominators / radicands vanishing).
MAX_ATTEMPTS_FACTOR: int = 20


class RandomPoints:
    """A reproducible set of random rational points, optionally on a constraint surface.

    Pass one instance as ``points=`` to several checks of :mod:`poissonkit.structure.checks`
    (``method="random"``) to share the points, the derivatives and the memoised values of
    common sub-expressions (``P``, ``dH``, ...) between them.

    Parameters
    ----------
    coords
        The coordinates (what derivatives are taken with respect to); a
        :class:`~poissonkit.structure.Bivector` or a system gives its own.
    constraints
        Expressions vanishing on the surface of interest, e.g. ``gx**2 + gy**2 + gz**2 - 1``.
    parametrization
        ``{coord: rational expression in new symbols}`` parametrising the surface; recognised
        automatically for unit spheres and constraints linear in one coordinate.
    trials
        Points per check (points where an expression is undefined are replaced by new ones).
    seed
        Seed (``None``: a fresh random seed, stored in :attr:`seed` for reproduction).

    Raises
    ------
    InputError
        Bad ``trials``, constraints that cannot be parametrised, or a parametrisation that does
        not satisfy the constraints.

    Examples
    --------
    >>> import sympy as sp
    >>> x, y = sp.symbols("x y", real=True)
    >>> pts = RandomPoints((x, y), seed=1)
    >>> pts.value(x**2 - y**2 - (x - y) * (x + y), 0)
    0
    """

    def __init__(self, coords, constraints: Sequence = (),
                 parametrization: Mapping | None = None, trials: int = 3,
                 seed: int | None = None) -> None:
        from poissonkit.structure.bivector import Bivector
        from poissonkit.structure.system import HamiltonianSystem

        if isinstance(coords, (Bivector, HamiltonianSystem)):
            coords = coords.coords
        self.coords: tuple[sp.Symbol, ...] = as_symbols(coords)
        if isinstance(trials, bool) or not isinstance(trials, int) or trials < 1:
            raise InputError(f"trials must be a positive int, got {trials!r}")
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int)):
            raise InputError(f"seed must be an int or None, got {seed!r}")
        self.trials = trials
        self._sampler = Sampler(seed)
        self.seed: int = self._sampler.seed
        if isinstance(constraints, (sp.Basic, str)):
            constraints = [constraints]
        self.constraints: tuple[sp.Expr, ...] = tuple(as_expr(c, "constraint")
                                                      for c in constraints)
        if parametrization is None:
            param = _recognise(self.constraints, self.coords) if self.constraints else {}
        else:
            if not isinstance(parametrization, Mapping):
                raise InputError("parametrization must be a mapping {coordinate: expression}")
            by_name = {str(c): c for c in self.coords}
            param = {}
            for k, v in parametrization.items():
                key = k if isinstance(k, sp.Symbol) else by_name.get(str(k))
                if key is None:
                    raise InputError(f"parametrization of unknown coordinate {k!r}")
                param[key] = as_expr(v, f"parametrization of {k}")
            for c in self.constraints:
                if sp.simplify(sp.together(c.xreplace(param))) != 0:
                    raise InputError(f"parametrization does not satisfy the constraint {c} = 0")
        _check_acyclic(param)
        self.parametrization: dict[sp.Symbol, sp.Expr] = param
        self.param_degree = _param_degree(param) if param else 1
        self._contexts: list[_PointContext] = []
        self._deriv: dict[tuple[sp.Expr, sp.Symbol], sp.Expr] = {}
        self._degrees: dict[sp.Expr, _Degree] = {}
        #: square-root symbols of :meth:`derivative`: ``{s: Q}`` with ``s = sqrt(Q)``
        self.radical_bases: dict[sp.Symbol, sp.Expr] = {}
        self._radical_of: dict[sp.Expr, sp.Symbol] = {}
        self._radical_form: dict[sp.Expr, sp.Expr] = {}

    def __repr__(self) -> str:
        surface = f", on {len(self.constraints)} constraint(s)" if self.constraints else ""
        return f"RandomPoints({len(self.coords)} coords, trials={self.trials}, seed={self.seed}{surface})"

    # -- sampling
    def draw(self, s: sp.Symbol, index: int):
        """The random value of symbol ``s`` at point ``index`` (deterministic given the seed).

        ``scale * p / SAMPLE_RANGE`` with ``p`` uniform in ``[-SAMPLE_RANGE, SAMPLE_RANGE]``
        (``[1, SAMPLE_RANGE]`` for a positive symbol, negated for a negative one; integer
        symbols: ``p`` itself). The scale is 1 for the first ``trials`` points, then runs
        through ``1/8, 8, 1/64, 64, ...`` for further points (domains of square roots such as
        ``1 - d (gamma, A gamma) > 0`` are bounded; others may exclude the unit box).
        """
        # the sign respects the symbol's assumptions: sympy may have simplified with them
        # (sqrt(I**2) = I for a positive I), so a point violating them could be a false witness
        sign = 1 if s.is_nonnegative else -1 if s.is_nonpositive else 0
        num = self._sampler.integer(s.name, index, sign)
        if s.is_integer:
            return _MPQ(num)
        level = index // self.trials
        power = 3 * ((level + 1) // 2)
        scale = _MPQ(1, 2**power) if level % 2 else _MPQ(2**power)
        return _MPQ(num, SAMPLE_RANGE) * scale

    def context(self, index: int) -> _PointContext:
        while len(self._contexts) <= index:
            self._contexts.append(_PointContext(self, len(self._contexts)))
        return self._contexts[index]

    def value(self, expr, index: int = 0) -> sp.Expr:
        """Exact value of ``expr`` at point ``index`` as a sympy number (for inspection).

        Raises
        ------
        RandomPointError
            If ``expr`` is not defined at that point or cannot be evaluated exactly.
        """
        try:
            return _to_sympy(self.context(index).value(as_expr(expr)))
        except _Undefined:
            raise RandomPointError(f"expression not defined (real) at point {index}") from None

    def point(self, index: int) -> dict[sp.Symbol, sp.Rational]:
        """The sampled symbols of point ``index`` so far (coordinates, parameters)."""
        return self.context(index).point()

    # -- calculus
    def derivative(self, expr: sp.Expr, x: sp.Symbol) -> sp.Expr:
        """``d expr / d x``, cached (shared between checks using this instance).

        Square roots ``sqrt(Q)`` are replaced by positive symbols ``s`` (evaluated as
        ``sqrt(Q)`` at a point) and differentiated by the chain rule ``ds/dx = Q_x / (2 s)``:
        much cheaper than sympy's derivative of the radicals, and the result is what
        :meth:`value` evaluates.
        """
        key = (expr, x)
        d = self._deriv.get(key)
        if d is None:
            r = self.radical_form(expr)
            d = sp.diff(r, x)
            for s in r.free_symbols:
                base = self.radical_bases.get(s)
                if base is None:
                    continue
                db = self.derivative(base, x)
                if db != 0:
                    d += sp.diff(r, s) * db / (2 * s)
            self._deriv[key] = d
        return d

    def radical_form(self, expr: sp.Expr) -> sp.Expr:
        """``expr`` with every ``Q**(p/2)`` replaced by ``s**p``, ``s`` a square-root symbol."""
        hit = self._radical_form.get(expr)
        if hit is None:
            hit = expr.replace(
                lambda t: t.is_Pow and t.exp.is_Rational and t.exp.q == 2
                and bool(t.base.free_symbols),
                lambda t: self._radical_symbol(t.base) ** int(t.exp.p))
            self._radical_form[expr] = hit
        return hit

    def _radical_symbol(self, base: sp.Expr) -> sp.Symbol:
        s = self._radical_of.get(base)
        if s is None:
            s = sp.Dummy(f"sqrt{len(self._radical_of)}", positive=True)
            self._radical_of[base] = s
            self.radical_bases[s] = base
        return s

    def degree(self, e: sp.Expr) -> _Degree:
        """Structural degree bounds of ``e`` (see the module docstring)."""
        memo = self._degrees
        hit = memo.get(e)
        if hit is not None:
            return hit
        if e.is_Rational or e.is_Float:
            out = _Degree(0)
        elif e.is_Symbol:
            base = self.radical_bases.get(e)
            out = _Degree(1) if base is None else self._half(base)
        elif e.is_Add:
            out = _Degree(0)
            for a in e.args:
                out = out + self.degree(a)
        elif e.is_Mul:
            out = _Degree(0)
            for a in e.args:
                out = out * self.degree(a)
        elif e.is_Pow and e.exp.is_Integer:
            b = self.degree(e.base)
            k = int(e.exp)
            out = b**k if k >= 0 else b.inverse(e.base) ** (-k)
        elif e.is_Pow and e.exp.is_Rational and e.exp.q == 2:
            b = self.degree(e.base)
            half = self._half(e.base)
            p = int(e.exp.p)
            rest = b ** ((p - 1) // 2) if p > 0 else b.inverse(e.base) ** ((1 - p) // 2)
            out = half * rest
        elif isinstance(e, sp.Abs):
            out = self.degree(e.args[0])   # |f| = f or -f: the same polynomial up to sign
        else:
            out = _Degree(1)  # not evaluable anyway; the evaluator raises
        memo[e] = out
        return out

    def derivative_degree(self, e: sp.Expr) -> _Degree:
        """Degree record of any partial derivative of ``e``: for ``A / prod f_k**m_k``, the
        derivative is ``(...)/prod f_k**(m_k + 1)`` with numerator degree
        ``<= deg A + sum deg f_k``; a square root ``sqrt(Q)`` adds ``Q`` to the denominator."""
        rec = self.degree(e)
        den = {k: (d, m + 1) for k, (d, m) in rec.den.items()}
        num = rec.num + sum(d for d, _ in rec.den.values())
        for r in rec.radicals:
            dr = self.degree(r)
            den[("sqrt", r)] = (dr.num, 1)
            num += dr.num
        return _Degree(num, den, rec.radicals)

    def _half(self, base: sp.Expr) -> _Degree:
        """Degree record of ``sqrt(base)``: ``sqrt(A/B) = sqrt(A B)/B``, ``sqrt(A B)`` counted
        as half the degree of ``A B`` (the norm over it doubles the final degree)."""
        b = self.degree(base)
        return _Degree((b.num + b.den_degree() + 1) // 2, dict(b.den),
                       b.radicals | {sp.expand(base)})

    # -- the test
    def test(self, components: Sequence[tuple[str, Callable[[Callable], Any]]], what: str = ""
             ) -> tuple[tuple[tuple[str, sp.Expr], ...], dict | None, float, str]:
        """Evaluate ``build(ev)`` for every ``(label, build)`` at ``trials`` valid points.

        ``ev(e)`` is the exact value of a sympy expression at the point and ``ev.d(e, x)`` its
        exact partial derivative (forward mode); ``build`` combines values with ``+``, ``-``
        and ``*`` (so the same ``build`` also computes the degree bound, with ``ev`` returning
        degree records).

        Returns
        -------
        (failures, point, false_positive_bound, note)
            ``failures``: ``(label, exact non-zero value)`` at the first failing point (then
            ``point`` is that point and the bound 0); else empty.
        """
        D = 1
        # the degree bound of a partial derivative is the same whatever the variable
        degrees = _Evaluator(self.degree, lambda e, _x: self.derivative_degree(e))
        for _, build in components:
            D = max(D, _as_degree(build(degrees)).bound())
        D *= self.param_degree
        done = 0
        index = 0
        skipped = 0
        limit = MAX_ATTEMPTS_FACTOR * self.trials + 20
        while done < self.trials:
            if index >= limit:
                raise RandomPointError(
                    f"{what or 'random check'}: found only {done} of {self.trials} points where "
                    f"the expressions are defined and real in {index} attempts")
            ctx = self.context(index)
            index += 1
            try:
                vals = [(label, ctx.value_of(build)) for label, build in components]
            except _Undefined:
                skipped += 1
                continue
            fails = tuple((label, _to_sympy(v)) for label, v in vals if not is_zero_at_point(v))
            if fails:
                return fails, ctx.point(), 0.0, self._note(index, skipped, D)
            done += 1
        # sign-restricted draws have point masses up to 1/SAMPLE_RANGE: the unsigned bound
        bound = false_positive_bound(D, self.trials, signed=False)
        return (), None, bound, self._note(index, skipped, D)

    def _note(self, used: int, skipped: int, D: int) -> str:
        where = " on the constraint surface (rational parametrisation)" if self.constraints else ""
        out = (f"exact arithmetic at {used - skipped} random rational point(s){where}, seed "
               f"{self.seed}, grid 1/{SAMPLE_RANGE}, degree bound D = {D}")
        if skipped:
            out += f"; {skipped} point(s) outside the domain skipped (bound is conditional)"
        return out
