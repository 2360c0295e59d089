"""Jacobi identity checks: exact (sparse, radical-aware) and randomized (exact arithmetic).

``Jac^{ijk} = sum_m (P^{im} d_m P^{jk} + P^{jm} d_m P^{ki} + P^{km} d_m P^{ij})``
``= {x_i, {x_j, x_k}} + cyclic`` and ``[P, P] = 2 Jac`` (:mod:`poissonkit.conventions`).

How the exact check stays fast
------------------------------
* **Sparsity.** Only triples ``(i, j, k)`` with a term ``P^{im} d_m P^{jk} != 0`` are formed:
  for every non-constant entry ``P^{jk}`` and every coordinate ``x_m`` it depends on, ``i`` runs
  over the non-zero entries of column ``m``. A direct sum's Jacobiator is therefore block-local
  without being told, and constant (canonical) blocks cost nothing.
* **Cached derivatives.** ``d_m P^{jk}`` is computed once per entry and coordinate.
* **Sparse polynomial arithmetic first.** When every entry is a polynomial in the coordinates,
  square-root symbols ``G``, ``1/G`` and the parameters (or rational in the parameters only),
  ``Jac`` is computed in a sympy sparse polynomial ring and reduced there (see
  :func:`_ring_nonzero`); only triples that do not vanish there are re-examined with expressions.
  This covers Lie–Poisson, canonical and the Chaplygin ball with symbolic ``d, a_i``.
* **No simplify in loops.** Zero is tested by expansion. Square roots ``sqrt(u)`` are replaced
  by a symbol ``G`` with ``d_m G = d_m u / (2 G)``; a residual that does not cancel by expansion
  is brought over a common denominator and reduced with ``G**2 -> u``; the result is zero iff
  the coefficients of ``1`` and ``G`` both expand to zero (exact unless ``u`` is a perfect
  square of a rational function, in which case a non-zero residual is confirmed with
  ``sympy.simplify``). Undefined functions ``g(gamma)`` and their derivatives are independent
  atoms, so a zero result holds for *every* ``g``.
* **Constraints.** ``constraints=((gamma, gamma) - 1,)`` checks Jacobi at the points of the
  surface: every residual coefficient is reduced modulo a Groebner basis of the constraints
  (in the coordinates; parameters are coefficients) and must reduce to zero.

Randomized check
----------------
``method="random"`` evaluates ``Jac`` at random integer points in exact arithmetic (rationals and
exact square roots). Parameters are sampled too, and every undefined-function atom
(``g(gamma)``, ``dg/dgamma_1``, ``d^2 g/dgamma_1 dgamma_2``, ...) gets an independent random
value: these are the jet values of a random polynomial of sufficient degree, so the check covers
arbitrary ``g``. The values come from the one sampler of the symbolic checks
(:mod:`poissonkit.structure.sampling`: integers in ``S = [-SAMPLE_RANGE, SAMPLE_RANGE]``,
seeded and reproducible; a ``None`` seed is drawn fresh and reported in the note). By
Schwartz–Zippel, a non-zero Jacobiator whose cleared numerator has degree ``<= D`` vanishes at a
uniform point of ``S^N`` with probability ``<= D/|S|``; the result states ``(D/|S|)**trials``
with a conservative ``D`` (see :func:`_degree_bound`).
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping, Sequence

import sympy as sp

from poissonkit.errors import InputError, NotPoissonError
from poissonkit.structure._expr import as_expr
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.jacobi_result import JacobiResult, Key
from poissonkit.structure.sampling import (SAMPLE_RANGE, Sampler, false_positive_bound,
                                           is_zero_at_point)
from poissonkit.structure.zerotest import (_function_atoms, canonical_atom, _has_transcendental,
                                           _is_half_power, _ZeroTester, is_zero_expression)

_METHODS = ("auto", "exact", "random")
#: Without square roots, the polynomial-ring path is used above this total operation count.
RING_MIN_OPS: int = 300
#: Above this total operation count of the entries, ``method="auto"`` picks the random check.
AUTO_EXACT_OPS: int = 2500


# ---------------------------------------------------------------------- radicals and atoms
class _Atomised:
    """Entries of P with square roots replaced by symbols, and a derivation that knows them."""

    def __init__(self, P: Bivector) -> None:
        self.coords = P.coords
        self.pos = {c: i for i, c in enumerate(P.coords)}
        self.radicals: dict[sp.Symbol, sp.Expr] = {}  # G -> u with G**2 = u
        bases: dict[sp.Expr, sp.Symbol] = {}
        entries: dict[tuple[int, int], sp.Expr] = {}
        n = P.dim
        for i in range(n):
            for j in range(i + 1, n):
                e = P.matrix[i, j]
                if e == 0:
                    continue
                pows = [p for p in sp.preorder_traversal(e) if _is_half_power(p)]
                rule = {}
                for p in pows:
                    if any(_is_half_power(q) for q in sp.preorder_traversal(p.base)):
                        continue  # nested radicals: leave to expansion / simplify
                    base = sp.expand(p.base)
                    if base not in bases:
                        G = sp.Dummy(f"G{len(bases)}")
                        bases[base] = G
                        self.radicals[G] = base
                    rule[p] = bases[base] ** p.exp.p
                entries[(i, j)] = e.xreplace(rule) if rule else e
        self.entries = entries
        # d_m u for each radical base, cached
        self._du: dict[tuple[sp.Symbol, int], sp.Expr] = {}
        self._deriv: dict[tuple[tuple[int, int], int], sp.Expr] = {}
        self.deps: dict[tuple[int, int], set[int]] = {}
        for key, e in entries.items():
            dep = {self.pos[s] for s in e.free_symbols if s in self.pos}
            for G in e.free_symbols & set(self.radicals):
                dep |= {self.pos[s] for s in self.radicals[G].free_symbols if s in self.pos}
            self.deps[key] = dep

    def entry(self, i: int, j: int) -> sp.Expr:
        if i < j:
            return self.entries.get((i, j), sp.Integer(0))
        if i > j:
            e = self.entries.get((j, i))
            return -e if e is not None else sp.Integer(0)
        return sp.Integer(0)

    def derivative(self, key: tuple[int, int], m: int) -> sp.Expr:
        """``d_m P^{key}`` (upper-triangle key), chain rule through the radical symbols."""
        ck = (key, m)
        if ck not in self._deriv:
            e = self.entries.get(key, sp.Integer(0))
            x = self.coords[m]
            d = sp.diff(e, x)
            for G in e.free_symbols & set(self.radicals):
                du = self._du.get((G, m))
                if du is None:
                    du = self._du[(G, m)] = sp.diff(self.radicals[G], x)
                if du != 0:
                    d += sp.diff(e, G) * du / (2 * G)
            self._deriv[ck] = d
        return self._deriv[ck]

    def signed_derivative(self, j: int, k: int, m: int) -> sp.Expr:
        if j < k:
            return self.derivative((j, k), m)
        return -self.derivative((k, j), m)

    def column(self, m: int) -> list[int]:
        """Indices ``i`` with ``P^{im} != 0``."""
        return [i for i in range(len(self.coords)) if self.entry(i, m) != 0]

    def candidates(self) -> list[Key]:
        """Triples ``i < j < k`` whose Jacobiator can be non-zero."""
        cols: dict[int, list[int]] = {}
        out: set[Key] = set()
        for (j, k), dep in self.deps.items():
            for m in dep:
                if m not in cols:
                    cols[m] = self.column(m)
                for i in cols[m]:
                    if i != j and i != k:
                        out.add(tuple(sorted((i, j, k))))  # type: ignore[arg-type]
        return sorted(out)

    def jac(self, i: int, j: int, k: int) -> sp.Expr:
        """``Jac^{ijk}`` as an unexpanded sum (radical symbols in place)."""
        total = sp.Integer(0)
        terms = []
        for a, b, c in ((i, j, k), (j, k, i), (k, i, j)):
            key = (b, c) if b < c else (c, b)
            for m in self.deps.get(key, ()):
                pam = self.entry(a, m)
                if pam != 0:
                    terms.append(pam * self.signed_derivative(b, c, m))
        if terms:
            total = sp.Add(*terms)
        return total

    def restore(self, e: sp.Expr) -> sp.Expr:
        """Put the square roots back (for reports)."""
        return e.xreplace({G: sp.sqrt(u) for G, u in self.radicals.items()})


def jacobiator_terms(P: Bivector) -> dict[Key, sp.Expr]:
    """Unexpanded ``Jac^{ijk}`` for every candidate triple (square roots restored)."""
    at = _Atomised(P)
    out = {}
    for key in at.candidates():
        e = at.jac(*key)
        if e != 0:
            out[key] = at.restore(e)
    return out


# ---------------------------------------------------------------------- polynomial-ring path
def _ring_nonzero(at: _Atomised, keys: Sequence[Key]) -> list[Key] | None:
    """Fast exact path in a sparse polynomial ring; ``None`` if the entries do not fit.

    Fits when every entry (square roots replaced by ``G``) is a polynomial in the coordinates,
    ``G`` and ``1/G`` with coefficients rational in the parameters (e(3), canonical, Lie–Poisson,
    the Chaplygin ball with symbolic ``d, a_i`` or ``I_i``). ``Jac`` is computed with the ring's
    sparse arithmetic (``d_m G = d_m u / (2 G)``, ``d_m G^{-1} = -d_m u G^{-3} / 2``), multiplied
    by a power of ``G`` to clear ``1/G`` and reduced with ``G^2 = u``; the coefficients of every
    parity pattern of the ``G``'s must vanish. Returns the triples that did *not* reduce to zero
    (to be confirmed by the expression path, which also covers perfect-square ``u``).
    """
    from sympy.polys.domains import QQ
    from sympy.polys.rings import ring

    entries = at.entries
    if any(_function_atoms(e) for e in entries.values()):
        return None
    Gs = sorted(at.radicals, key=str)
    Ginv = {G: sp.Dummy(f"{G.name}inv") for G in Gs}
    coords = list(at.coords)
    params = sorted(set().union(*(e.free_symbols for e in entries.values()),
                                *(u.free_symbols for u in at.radicals.values()))
                    - set(coords) - set(Gs), key=str)
    Gset = set(Gs)
    n = len(coords)

    def to_ring(R, e: sp.Expr):
        e = e.replace(lambda t: t.is_Pow and t.base in Gset and t.exp.is_negative,
                      lambda t: Ginv[t.base] ** (-t.exp))
        return R.from_expr(e)

    built = None
    # parameters as extra generators over QQ (fast); failing that (parameters in denominators,
    # e.g. 1/(I1 + d)), as coefficients in the fraction field QQ(params) (exact, slower)
    for extra, domain in ((params, QQ), ([], QQ.frac_field(*params) if params else QQ)):
        try:
            R, *gens = ring(coords + Gs + [Ginv[G] for G in Gs] + list(extra), domain)
            ent = {key: to_ring(R, e) for key, e in entries.items()}
            U = {G: R.from_expr(u) for G, u in at.radicals.items()}
            built = (R, gens, ent, U)
            break
        except Exception:  # noqa: BLE001 - sympy cannot put it in this ring: try the next
            continue
    if built is None:
        return None
    R, gens, ent, U = built
    gG = {G: gens[n + k] for k, G in enumerate(Gs)}
    gGi = {G: gens[n + len(Gs) + k] for k, G in enumerate(Gs)}
    dU = {(G, m): U[G].diff(gens[m]) for G in Gs for m in range(n)}
    deriv: dict = {}

    def D(key, m):
        if (key, m) not in deriv:
            p = ent.get(key, R.zero)
            out = p.diff(gens[m])
            for G in Gs:
                du = dU[(G, m)]
                if du:
                    out += (p.diff(gG[G]) * gGi[G] - p.diff(gGi[G]) * gGi[G] ** 3) * du * QQ(1, 2)
            deriv[(key, m)] = out
        return deriv[(key, m)]

    def entry(i, j):
        if i < j:
            return ent.get((i, j), R.zero)
        return -ent.get((j, i), R.zero) if i > j else R.zero

    upow: dict = {}

    def u_power(G, k):
        if (G, k) not in upow:
            upow[(G, k)] = U[G] ** k
        return upow[(G, k)]

    bad: list[Key] = []
    ng = len(Gs)
    for i, j, k in keys:
        jac = R.zero
        for a, b, c in ((i, j, k), (j, k, i), (k, i, j)):
            key = (b, c) if b < c else (c, b)
            sign = 1 if b < c else -1
            for m in at.deps.get(key, ()):
                pam = entry(a, m)
                if pam:
                    jac += sign * pam * D(key, m)
        if not jac:
            continue
        if not Gs:
            bad.append((i, j, k))
            continue
        # clear 1/G, reduce G^2 = u, group by parity of the G exponents
        terms = list(jac.terms())
        N = [max(0, max(mon[n + ng + t] - mon[n + t] for mon, _ in terms)) for t in range(ng)]
        groups: dict = {}
        for mon, coeff in terms:
            base = R({tuple(mon[:n]) + (0,) * (2 * ng) + tuple(mon[n + 2 * ng:]): coeff})
            parity = []
            for t, G in enumerate(Gs):
                e = mon[n + t] - mon[n + ng + t] + N[t]
                if e // 2:
                    base *= u_power(G, e // 2)
                parity.append(e % 2)
            pk = tuple(parity)
            groups[pk] = groups.get(pk, R.zero) + base
        if any(groups.values()):
            bad.append((i, j, k))
    return bad


# ---------------------------------------------------------------------- exact check
def _check_exact(P: Bivector, constraints: Sequence[sp.Expr]) -> dict[Key, sp.Expr]:
    at = _Atomised(P)
    tester = _ZeroTester(at.radicals, P.coords, constraints)
    failures: dict[Key, sp.Expr] = {}
    keys = at.candidates()
    # the ring pays off with square roots or big entries; small Lie–Poisson blocks expand faster
    big = at.radicals or sum(sp.count_ops(e) for e in at.entries.values()) > RING_MIN_OPS
    if not constraints and big:
        suspicious = _ring_nonzero(at, keys)
        if suspicious is not None:
            keys = suspicious  # the rest vanish exactly; confirm these with expressions
    for key in keys:
        e = at.jac(*key)
        if e == 0:
            continue
        res = tester.residual(e)
        if res == 0:
            continue
        restored = at.restore(res)
        # transcendental identities (sin^2 + cos^2 = 1, ...) are beyond the algebraic test
        if _has_transcendental(restored) and not constraints and sp.simplify(restored) == 0:
            continue
        failures[key] = restored
    return failures


# ---------------------------------------------------------------------- randomized check
def _total_degree(e: sp.Expr, gens: Sequence[sp.Symbol]) -> int:
    num, den = sp.fraction(sp.together(e))
    deg = 0
    for part in (num, den):
        try:
            deg += sp.Poly(part, *gens).total_degree() if gens else 0
        except sp.PolynomialError:
            deg += 4  # non-polynomial atoms (functions): count them as low-degree variables
    return deg


def _degree_bound(at: _Atomised, gens: Sequence[sp.Symbol]) -> int:
    """Conservative degree ``D`` of the cleared numerator of any ``Jac^{ijk}``.

    With ``delta`` the largest ``deg num + deg den`` of an entry (square-root symbols counted
    as variables, undefined functions as degree-4 atoms), each of the at most ``3 n`` terms
    ``P^{im} d_m P^{jk}`` has cleared degree ``<= 3 delta``; over a common denominator of at
    most ``3 n`` factors the numerator degree is ``<= 9 n delta``; the square-root relations
    at most double it and add the degree of ``u``.
    """
    n = len(at.coords)
    delta = max((_total_degree(e, gens) for e in at.entries.values()), default=1)
    udeg = max((_total_degree(u, gens) for u in at.radicals.values()), default=0)
    return max(1, 2 * 9 * n * max(delta, 1) + udeg)


def _check_random(P: Bivector, trials: int, seed: int | None,
                  parametrization: Mapping[sp.Symbol, sp.Expr] | None
                  ) -> tuple[dict[Key, sp.Expr], float, int]:
    """Jacobiator values at random integer points (:class:`~poissonkit.structure.sampling.
    Sampler`); ``(failures, false-positive bound, seed)``."""

    at = _Atomised(P)
    keys = at.candidates()
    # Everything that is not a coordinate is sampled: parameters and function jets.
    jac_exprs = {key: at.jac(*key) for key in keys}
    free: set[sp.Expr] = set()
    fatoms: set[sp.Expr] = set()
    for e in jac_exprs.values():
        fatoms |= _function_atoms(e)
        free |= e.free_symbols
    radical_syms = set(at.radicals)
    params = sorted(free - set(P.coords) - radical_syms, key=str)
    sampler = Sampler(seed)
    gens = list(P.coords) + params + sorted(radical_syms, key=str)
    D = _degree_bound(at, gens)
    failures: dict[Key, sp.Expr] = {}
    par_syms: list[sp.Symbol] = []
    if parametrization is not None:
        par_syms = sorted(set().union(*(sp.sympify(v).free_symbols
                                        for v in parametrization.values())) - set(params), key=str)
    # one random value per distinct jet quantity (atoms equal up to argument expansion)
    jet_keys = {a: canonical_atom(a) for a in fatoms}
    jet_names = {k: "jet:" + sp.srepr(k) for k in set(jet_keys.values())}

    def draw(symbols: Iterable[sp.Symbol], index: int) -> dict[sp.Expr, sp.Integer]:
        return {x: sp.Integer(sampler.integer(x.name, index)) for x in symbols}

    done = 0
    attempts = 0
    while done < trials:
        index = attempts
        attempts += 1
        if attempts > 20 * trials + 20:
            raise InputError("random Jacobi check: could not find points where P is defined")
        values = draw(params, index)
        if parametrization is not None:
            pv = draw(par_syms, index)
            for c in P.coords:
                values[c] = (sp.sympify(parametrization[c]).xreplace(pv) if c in parametrization
                             else sp.Integer(sampler.integer(c.name, index)))
        else:
            values.update(draw(P.coords, index))
        jets = {a: sp.Integer(sampler.integer(jet_names[k], index)) for a, k in jet_keys.items()}
        rule = {**jets, **values}
        # radical symbols take the exact square root of their base at the point
        for G, u in at.radicals.items():
            uval = sp.expand(u.xreplace(rule))
            if uval == 0:
                break
            rule[G] = sp.sqrt(uval)
        else:
            try:
                vals = {key: e.xreplace(rule) for key, e in jac_exprs.items()}
            except ZeroDivisionError:
                continue
            if any(v.has(sp.zoo, sp.nan, sp.oo) for v in vals.values()):
                continue
            for key, v in vals.items():
                if not is_zero_at_point(v):
                    failures[key] = sp.expand(v)
            done += 1
            if failures:
                break
    bound = 0.0 if failures else false_positive_bound(D, trials)
    return failures, bound, sampler.seed


# ---------------------------------------------------------------------- public API
def _auto_method(P: Bivector) -> str:
    ops = sum(sp.count_ops(e) for e in P.matrix if e != 0)
    return "exact" if ops <= AUTO_EXACT_OPS else "random"


def check_jacobi(P: Bivector, method: str = "auto", constraints: Sequence = (),
                 trials: int = 3, seed: int | None = None,
                 parametrization: Mapping | None = None) -> JacobiResult:
    """Check the Jacobi identity ``[P, P] = 0``.

    Parameters
    ----------
    P
        The bivector (or a HamiltonianSystem, whose structure is checked).
    method
        ``"exact"`` (symbolic, sparse, radical-aware), ``"random"`` (exact arithmetic at random
        integer points, jets of undefined functions randomised) or ``"auto"`` (exact unless the
        entries are large).
    constraints
        Expressions vanishing on a surface (e.g. ``gamma_x**2 + gamma_y**2 + gamma_z**2 - 1``):
        check Jacobi only at its points. Exact: Groebner reduction. Random: needs
        ``parametrization``.
    trials
        Random points (random method).
    seed
        Seed of the random points (reproducible runs).
    parametrization
        ``{coord: expression in new symbols}`` parametrising the constraint surface rationally
        (e.g. the stereographic sphere); used by the random method with constraints.

    Returns
    -------
    JacobiResult

    Raises
    ------
    InputError
        Unknown method, bad trials, constraints that are not polynomial, or a parametrisation
        that does not satisfy the constraints.

    Examples
    --------
    >>> from poissonkit.structure import e3
    >>> check_jacobi(e3()).is_poisson
    True
    """
    from poissonkit.structure.system import HamiltonianSystem

    if isinstance(P, HamiltonianSystem):
        P = P.structure
    if not isinstance(P, Bivector):
        raise InputError(f"check_jacobi needs a Bivector, got {type(P).__name__}")
    if method not in _METHODS:
        raise InputError(f"unknown Jacobi method {method!r}; available: {', '.join(_METHODS)}")
    if not isinstance(trials, int) or trials < 1:
        raise InputError(f"trials must be a positive int, got {trials!r}")
    constraints = tuple(as_expr(c, "constraint") for c in constraints)
    t0 = time.perf_counter()
    note = ""
    chosen = method
    if method == "auto":
        chosen = _auto_method(P)
        if chosen == "random" and constraints and parametrization is None:
            chosen = "exact"
        note = f"auto chose {chosen}"
    if chosen == "random" and constraints:
        if parametrization is None:
            raise InputError("random Jacobi check on a constraint surface needs a "
                             "parametrization of the surface")
        parametrization = {P.symbol(str(k)) if not isinstance(k, sp.Symbol) else k:
                           as_expr(v, f"parametrization of {k}")
                           for k, v in parametrization.items()}
        for c in constraints:
            if sp.simplify(sp.together(c.xreplace(parametrization))) != 0:
                raise InputError(f"parametrization does not satisfy the constraint {c} = 0")
    if chosen == "exact":
        failures = _check_exact(P, constraints)
        bound = 0.0
        if constraints:
            note = (note + "; " if note else "") + "reduced modulo a Groebner basis of the constraints"
        result_trials = 0
    else:
        failures, bound, used_seed = _check_random(P, trials, seed,
                                                   parametrization if constraints else None)
        result_trials = trials
        note = (note + "; " if note else "") + (
            f"{trials} random integer points in [-{SAMPLE_RANGE}, {SAMPLE_RANGE}] "
            f"(seed {used_seed}), exact arithmetic")
    return JacobiResult(is_poisson=not failures, method=chosen, failures=failures,
                        false_positive_bound=bound, seconds=time.perf_counter() - t0,
                        coords=P.coords, trials=result_trials, note=note)


def require_poisson(P: Bivector, **kwargs) -> JacobiResult:
    """Like :func:`check_jacobi`, but raise :class:`~poissonkit.errors.NotPoissonError` on failure."""
    res = check_jacobi(P, **kwargs)
    if not res.is_poisson:
        first = next(iter(res.named_failures().items()))
        raise NotPoissonError(f"not Poisson: {first[0]} = {first[1]}"
                              f" ({len(res.failures)} non-zero component(s))")
    return res


__all__ = ["JacobiResult", "check_jacobi", "is_zero_expression", "jacobiator_terms",
           "require_poisson"]
