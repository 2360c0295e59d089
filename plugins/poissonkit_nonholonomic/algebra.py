"""Exact zero tests for expressions with square roots (the survey's ``g = sqrt(Q(x))``).

Every bracket of the survey's rolling systems contains ``g = sqrt(Q(x))`` with ``Q`` polynomial.
``sympy`` can differentiate such expressions, but deciding that a large sum of them is zero
(``[P, P] = 0``) is slow and unreliable with ``simplify``. Here each distinct square root
``sqrt(Q)`` is replaced by a new symbol ``s`` with the rule ``s**2 = Q`` and the chain rule
``ds/dx = Q_x / (2 s)``. An expression then is a rational function of ``(x, s)``; it vanishes
on the real domain where ``Q > 0`` iff its numerator, reduced modulo ``s**2 - Q`` to
``alpha(x) + beta(x) s``, has ``alpha = beta = 0`` (sufficient always; also necessary when ``Q``
is not a perfect square, which holds for every system here).

Only the random-point path of :mod:`poissonkit_nonholonomic.verify` (large systems such as the
BMF bivector) and the BMF claim (55) use this module; symbolic proofs go through the core
(:mod:`poissonkit.structure.jacobi`, :mod:`poissonkit.structure.checks`), which has no
random-point test for vector-field identities. Here exact rational arithmetic is done at random
rational points (Schwartz–Zippel): a nonzero polynomial numerator of total degree ``D`` vanishes
at a point drawn uniformly from ``S^n`` with probability at most ``D / |S|``;
``|S| = 2 * RANDOM_RANGE + 1`` here.
"""

from __future__ import annotations

import random as _random
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from poissonkit.errors import InputError

#: Random rational points have numerators in [-RANDOM_RANGE, RANDOM_RANGE] over small denominators.
RANDOM_RANGE = 10**6


@dataclass(frozen=True)
class Radicals:
    """Square roots replaced by symbols: ``subs_back[s] = Q`` means ``s = sqrt(Q)``."""

    roots: Mapping[sp.Symbol, sp.Expr] = field(default_factory=dict)

    def derivative(self, f: sp.Expr, x: sp.Symbol) -> sp.Expr:
        """``d f / d x`` with ``d s / d x = Q_x / (2 s)`` for each radical symbol ``s``."""
        out = sp.diff(f, x)
        for s, Q in self.roots.items():
            dQ = sp.diff(Q, x)
            if dQ != 0:
                fs = sp.diff(f, s)
                if fs != 0:
                    out += fs * dQ / (2 * s)
        return out

    def restore(self, f: sp.Expr) -> sp.Expr:
        """Put the square roots back."""
        return f.subs({s: sp.sqrt(Q) for s, Q in self.roots.items()})


def extract_radicals(exprs: Iterable[sp.Expr], prefix: str = "_s") -> tuple[list[sp.Expr], Radicals]:
    """Replace every ``Q**(n/2)`` (``n`` odd) by ``s**n`` with a new symbol ``s`` per base ``Q``.

    Parameters
    ----------
    exprs
        Expressions sharing the radicals (e.g. all entries of a bivector and a Hamiltonian).
    prefix
        Name prefix of the new symbols.

    Returns
    -------
    (list of expressions, Radicals)
    """
    exprs = [sp.sympify(e) for e in exprs]
    bases: dict[sp.Expr, sp.Symbol] = {}

    def base_symbol(Q: sp.Expr) -> sp.Symbol:
        if Q not in bases:
            bases[Q] = sp.Symbol(f"{prefix}{len(bases)}", positive=True)
        return bases[Q]

    def is_half(e) -> bool:
        return e.is_Pow and e.exp.is_Rational and e.exp.q == 2

    def repl(e):
        return base_symbol(e.base) ** e.exp.p

    out = []
    for e in exprs:
        # innermost first: bases never contain radicals in our systems, but be safe
        for _ in range(3):
            new = e.replace(is_half, repl)
            if new == e:
                break
            e = new
        out.append(e)
    return out, Radicals({s: Q for Q, s in bases.items()})


def _reduce_numerator(num: sp.Expr, radicals: Radicals) -> list[sp.Expr]:
    """Coefficients ``[alpha, beta, ...]`` of ``num`` modulo ``s**2 - Q`` for each radical."""
    parts = [sp.expand(num)]
    for s, Q in radicals.roots.items():
        new_parts = []
        for part in parts:
            if not part.has(s):
                new_parts.append(part)
                continue
            poly = sp.Poly(part, s)
            even, odd = sp.Integer(0), sp.Integer(0)
            for (k,), c in poly.terms():
                if k % 2 == 0:
                    even += c * Q ** (k // 2)
                else:
                    odd += c * Q ** (k // 2)
            new_parts.extend([sp.expand(even), sp.expand(odd)])
        parts = new_parts
    return parts


def vanishes(expr: sp.Expr, radicals: Radicals | None = None) -> bool:
    """Whether ``expr`` (in radical symbols) is identically zero given ``s**2 = Q``.

    Exact: numerator of the combined fraction, reduced modulo every ``s**2 - Q``.
    """
    radicals = radicals or Radicals()
    expr = sp.sympify(expr)
    if expr == 0:
        return True
    num, _den = sp.fraction(sp.together(expr))
    return all(p == 0 for p in _reduce_numerator(num, radicals))


def random_rational(rng: _random.Random) -> sp.Rational:
    """A random rational ``p / q`` with ``|p| <= RANDOM_RANGE`` and ``q`` in 1..97."""
    return sp.Rational(rng.randint(-RANDOM_RANGE, RANDOM_RANGE), rng.randint(1, 97))


def sphere_point(rng: _random.Random) -> tuple[sp.Rational, sp.Rational, sp.Rational]:
    """A random rational point on the unit sphere (inverse stereographic projection)."""
    u = sp.Rational(rng.randint(-999, 999), rng.randint(1, 500))
    v = sp.Rational(rng.randint(-999, 999), rng.randint(1, 500))
    n = 1 + u**2 + v**2
    return (2 * u / n, 2 * v / n, (1 - u**2 - v**2) / n)


@dataclass
class PointSampler:
    """Draw exact random points of ``coords`` honouring simple constraints.

    Supported constraints: ``x^2 + y^2 + z^2 - 1`` on three coordinates (rational sphere points)
    and constraints linear in one coordinate (solved for it). ``box`` optionally restricts
    coordinates to small rationals (keeps ``Q > 0`` for the radicals, e.g. ``1 - d (gamma, A gamma)``).
    """

    coords: Sequence[sp.Symbol]
    constraints: Sequence[sp.Expr] = ()
    seed: int = 20140301
    small: bool = False

    def __post_init__(self) -> None:
        self.rng = _random.Random(self.seed)
        self.sphere: list[tuple[sp.Symbol, sp.Symbol, sp.Symbol]] = []
        self.solved: list[tuple[sp.Symbol, sp.Expr]] = []
        for c in self.constraints:
            c = sp.expand(c)
            vars_ = [x for x in self.coords if c.has(x)]
            if len(vars_) == 3 and sp.expand(c - sum(v**2 for v in vars_) + 1) == 0:
                self.sphere.append(tuple(vars_))  # type: ignore[arg-type]
                continue
            for x in vars_:
                if sp.degree(c, x) == 1 and x not in {v for t in self.sphere for v in t}:
                    sol = sp.solve(c, x)
                    if len(sol) == 1:
                        self.solved.append((x, sol[0]))
                        break
            else:
                raise InputError(f"cannot sample points on the constraint {c} = 0")

    def draw(self) -> dict[sp.Symbol, sp.Expr]:
        """One random point as a substitution dict."""
        point: dict[sp.Symbol, sp.Expr] = {}
        for triple in self.sphere:
            point.update(dict(zip(triple, sphere_point(self.rng))))
        fixed = {x for x, _ in self.solved}
        for x in self.coords:
            if x not in point and x not in fixed:
                if self.small:
                    point[x] = sp.Rational(self.rng.randint(-30, 30), 100)
                else:
                    point[x] = random_rational(self.rng)
        for x, sol in self.solved:
            point[x] = sol.subs(point)
        return point
