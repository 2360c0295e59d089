"""Rank of a bivector: generic (exact arithmetic at random points) or at a given point.

Rank = sum of the ranks of the independent blocks (:mod:`poissonkit.structure.decomposition`).
The random points come from the one sampler of the symbolic checks
(:mod:`poissonkit.structure.sampling`). Method notes: ``docs/casimirs.md``.
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.polys.matrices import DomainMatrix

from poissonkit.errors import DimensionError, InputError, UnknownNameError
from poissonkit.structure._expr import as_expr
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.zerotest import _Atomizer, canonical_atom
from poissonkit.structure.sampling import PointStream, Sampler, false_positive_fraction
from poissonkit.structure.decomposition import _bivector, _blocks, _sub

__all__ = ["RankResult", "rank"]


class RankResult(int):
    """The rank (an ``int``) with how it was obtained.

    Attributes
    ----------
    point
        ``{coordinate or parameter: value}`` where the rank was evaluated (the last trial).
    generic
        ``True`` for the generic rank (random points), ``False`` for the rank at a given point.
    error_bound
        Upper bound on the probability that the generic rank is *larger* than reported
        (Schwartz–Zippel over all trials); ``0`` at a given point (``None`` there if
        parameters or undefined-function jets had to be drawn at random); ``None`` when the
        entries are not polynomial/rational (square roots, opaque functions), where no bound
        is proved.
    note
        How undefined functions and parameters were sampled.
    """

    point: dict
    generic: bool
    error_bound: Fraction | None
    note: str

    def __new__(cls, value: int, point: dict, generic: bool, error_bound, note: str):
        obj = super().__new__(cls, value)
        obj.point, obj.generic, obj.error_bound, obj.note = point, generic, error_bound, note
        return obj

    def __repr__(self) -> str:
        kind = "generic" if self.generic else "at point"
        return f"RankResult({int(self)}, {kind}, error_bound={self.error_bound})"


def _function_atoms(M: sp.Matrix) -> set:
    """Undefined functions, their derivatives and ``Subs`` of them in the entries of ``M``."""
    atoms: set = set()
    for e in M:
        atoms |= e.atoms(AppliedUndef, sp.Derivative, sp.Subs)
    return atoms


def _jets(expr_matrix: sp.Matrix, rng: PointStream, values: dict) -> sp.Matrix:
    """Replace undefined-function values/derivatives by random rationals.

    Each distinct quantity gets its own value: atoms are keyed by :func:`canonical_atom`
    (the same value written with expanded / unexpanded arguments is one quantity), and
    ``xreplace`` matches outermost first, so ``Subs(Derivative(g(..)))`` is replaced whole.
    ``values`` (canonical atom -> value) is filled in and reused.
    """
    atoms = _function_atoms(expr_matrix)
    if not atoms:
        return expr_matrix
    rep = {}
    for a in sorted(atoms, key=sp.default_sort_key):
        key = canonical_atom(a)
        if key not in values:
            values[key] = rng.value("jet:" + sp.srepr(key))
        rep[a] = values[key]
    return expr_matrix.xreplace(rep)


def _numeric_rank(M: sp.Matrix) -> int:
    if all(e.is_Rational for e in M):
        return DomainMatrix.from_Matrix(M).convert_to(sp.QQ).rank()
    try:
        return DomainMatrix.from_Matrix(M, extension=True).rank()
    except Exception:  # domain construction failed (e.g. transcendental numbers)
        return sp.Matrix(M).rank(simplify=True)


def _degree_bound(M: sp.Matrix) -> int | None:
    """Max over rows of the total degree after clearing the row's denominators, or None."""
    at = _Atomizer()
    worst = 0
    for i in range(M.rows):
        row = [sp.together(at(e)) for e in M.row(i)]
        if at.relations or at.opaque:
            return None
        dens = [sp.fraction(e)[1] for e in row]
        lcm = sp.lcm(dens) if dens else 1
        for e in row:
            if e == 0:
                continue
            num = sp.cancel(e * lcm)
            syms = sorted(num.free_symbols, key=str)
            if not syms:
                continue
            try:
                worst = max(worst, sp.Poly(num, *syms).total_degree())
            except sp.PolynomialError:
                return None
    return worst


def rank(P, point=None, *, trials: int = 2, seed: int | None = None) -> RankResult:
    """Rank of ``P``: generic (random exact points) or at a given point.

    Parameters
    ----------
    P
        A :class:`Bivector` (or system).
    point
        ``None`` for the generic rank; otherwise the point, as a sequence of coordinate values
        or a mapping ``{coordinate or name: value}`` (it may also give parameter values).
        Parameters and undefined-function jets not given are sampled at random (generic).
    trials
        Number of independent random points for the generic rank (the maximum is reported).
    seed
        Seed of the random points (reproducible results).

    Returns
    -------
    RankResult
        An ``int`` subclass with ``point``, ``generic``, ``error_bound``, ``note``.

    Notes
    -----
    Exact arithmetic throughout (rationals, or algebraic numbers when square roots appear).
    The rank at a random point is never larger than the generic rank; it is smaller only if the
    point is a zero of a non-zero ``r x r`` minor, of total degree at most ``n * delta``
    (``delta`` = largest entry degree after clearing row denominators). Points are drawn from
    ``{k/N : |k| <= N}^n`` with ``N = 10**6`` (the one sampler of the symbolic checks,
    :mod:`poissonkit.structure.sampling`; ``seed=None`` draws a fresh seed, named in
    ``note``), so each trial errs with probability at most ``n delta / (2N + 1)``
    (Schwartz–Zippel), and all trials with at most its power.
    Independent blocks are ranked separately.
    """
    P = _bivector(P)
    if not isinstance(trials, int) or trials < 1:
        raise InputError(f"trials must be a positive int, got {trials!r}")
    rng = PointStream(Sampler(seed))
    given: dict = {}
    if point is not None:
        given = _point_dict(P, point)
    free_params = sorted(set().union(*(e.free_symbols for e in P.matrix)) - set(P.coords), key=str)
    total = 0
    bound: Fraction | None = Fraction(0)
    used: dict = {}
    n_trials = trials if point is None else 1
    for idx in _blocks(P):
        B = _sub(P, idx)
        best, last = -1, {}
        for _ in range(n_trials):
            r, vals = _rank_once(B, given, free_params, rng, generic=point is None)
            if r > best:
                best, last = r, vals
        total += best
        used.update(last)
        if point is None and bound is not None and best < B.dim:
            delta = _degree_bound(B.matrix)
            if delta is None:
                bound = None
            else:
                bound += false_positive_fraction(B.dim * delta, n_trials)
    if point is not None:
        sampled = any(s not in given for s in free_params) or any(
            e.has(AppliedUndef, sp.Derivative, sp.Subs) for e in P.matrix)
        # exact at the point, unless parameters / function jets had to be sampled
        bound = None if sampled else Fraction(0)
    note = ("parameters and undefined-function jets not given were drawn at random "
            f"(rank for generic values; seed {rng.sampler.seed})")
    return RankResult(total, used, point is None, bound, note)


def _point_dict(P: Bivector, point) -> dict:
    if isinstance(point, Mapping):
        out = {}
        free = set().union(*(e.free_symbols for e in P.matrix)) | set(P.coords)
        names = {str(s): s for s in free}
        for k, v in point.items():
            if str(k) not in names:
                raise UnknownNameError("symbol", str(k), names)
            out[names[str(k)]] = _point_value(v, str(k))
        missing = [str(c) for c in P.coords if c not in out]
        if missing:
            raise InputError(f"point does not give coordinates {missing}")
        return out
    vals = list(point)
    if len(vals) != P.dim:
        raise DimensionError(f"point has {len(vals)} values for {P.dim} coordinates")
    return {c: _point_value(v, str(c)) for c, v in zip(P.coords, vals)}


def _point_value(v, name: str) -> sp.Expr:
    """A point coordinate as an exact sympy value (floats made rational; strings refused)."""
    e = as_expr(v, f"point value of {name}")
    return sp.nsimplify(e, rational=True) if isinstance(e, sp.Float) else e


def _rank_once(B: Bivector, given: dict, params: list, rng: PointStream, generic: bool):
    """Rank of ``B`` at one point (given coordinates, random parameters / jets where not given).

    Undefined-function atoms (``g(gamma)``, ``dg/dgamma_x``, ``Subs(..)``) are replaced by
    random rationals *before* the point is substituted: their values at the point are the
    free jet of a generic function, and substituting numbers inside a ``Derivative`` would be
    meaningless (differentiation with respect to a number).
    """
    for _attempt in range(20):
        rng.next_point()
        vals = {}
        for c in B.coords:
            vals[c] = given[c] if c in given else rng.value(c.name)
        for s in params:
            vals[s] = given[s] if s in given else rng.value(s.name)
        jets: dict = {}
        M = _jets(B.matrix, rng, jets)
        M = M.xreplace(vals)
        # floats would make the rank numerical: read them as the rationals they print as
        M = M.applyfunc(lambda e: sp.nsimplify(e, rational=True) if e.has(sp.Float) else e)
        if any(e.has(sp.zoo, sp.nan, sp.oo) for e in M):
            if not generic:
                raise InputError("the bivector is not defined at the given point "
                                 "(division by zero)")
            continue
        vals.update({str(k): v for k, v in jets.items()})
        return _numeric_rank(M), vals
    raise InputError("could not find a random point where the bivector is defined")
