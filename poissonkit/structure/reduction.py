"""Reduction of a Poisson structure by a symmetry, through polynomial invariants.

A compact group ``G`` (a torus, ``SO(2)``, ...) acting linearly and by Poisson maps is given by
its infinitesimal generators: linear vector fields, or Hamiltonian functions whose Hamiltonian
vector fields ``P dJ`` generate the action. The invariant polynomials ``R[x]^G`` form a Poisson
subalgebra; choosing generators ``pi_1 .. pi_m`` (a Hilbert basis) gives the *reduced* Poisson
algebra: ``{pi_i, pi_j}`` is invariant, hence a polynomial in the ``pi``, and the relations
(syzygies) among the ``pi`` cut out the orbit space (Cushman & Bates, *Global Aspects of
Classical Integrable Systems*, Birkhäuser 1997, ch. II–IV and appendix on invariant theory;
Arms, Cushman & Gotay 1991).

Everything is exact linear algebra degree by degree (the generators being linear, the invariants
of each degree form a subspace):

* invariants of degree ``d``: the kernel of ``f -> X_a f`` on homogeneous polynomials;
* Hilbert basis to degree ``D``: at each degree, a complement of the products of the
  generators of lower degree (:func:`poissonkit.structure._casimir_basis.reduced_generators`);
* brackets: ``{pi_i, pi_j}`` computed in the coordinates and written back as a polynomial in the
  ``pi`` (solving for the coefficients of the ``pi``-monomials of the right weight);
* relations: the kernel of the ``pi``-monomials in each weight, modulo multiples of lower ones;
* Casimirs: the invariants ``f`` with ``{f, pi_j} = 0`` for every ``j`` (Casimirs of the orbit
  space, computed in the coordinates, so relations are taken into account), as polynomials
  in the ``pi``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import combinations_with_replacement

import sympy as sp
from sympy.polys.orderings import grlex
from sympy.polys.rings import PolyElement, PolyRing

from poissonkit.errors import InputError
from poissonkit.structure._casimir_basis import gen_monomials, reduced_generators, relations
from poissonkit.structure._exact_linear import solve_sparse
from poissonkit.structure._expr import as_bivector, as_expr
from poissonkit.structure.bivector import Bivector

__all__ = ["ReducedPoissonAlgebra", "reduce_by_symmetry"]


@dataclass(frozen=True)
class ReducedPoissonAlgebra:
    """The reduced Poisson algebra: invariants, their brackets, relations and Casimirs.

    Attributes
    ----------
    coords
        The original coordinates.
    symbols
        One symbol per invariant (``pi_1, pi_2, ...`` unless named), the variables of
        :attr:`brackets`, :attr:`relations`, :attr:`casimirs`.
    invariants
        The invariants ``pi_k`` as polynomials in :attr:`coords` (homogeneous).
    degrees
        Their degrees.
    brackets
        ``brackets[i, j] = {pi_i, pi_j}`` as a polynomial in :attr:`symbols` (one representative
        modulo the relations).
    relations
        Generating relations ``R(pi) = 0`` of weight ``<= relation_degree`` (weight of ``pi_k``
        its degree), none implied by lower ones.
    casimirs
        Generators of the invariant Casimirs of degree ``<= degree``, written in the ``pi``.
    degree
        The degree to which invariants and Casimirs were searched.
    """

    coords: tuple[sp.Symbol, ...]
    symbols: tuple[sp.Symbol, ...]
    invariants: tuple[sp.Expr, ...]
    degrees: tuple[int, ...]
    brackets: sp.ImmutableMatrix
    relations: tuple[sp.Expr, ...]
    casimirs: tuple[sp.Expr, ...]
    degree: int
    _ctx: _Context = field(repr=False, compare=False)

    @property
    def bivector(self) -> Bivector:
        """The reduced bracket as a bivector on the ``pi`` (Poisson on the relations' zero set)."""
        return Bivector.from_matrix(sp.Matrix(self.brackets), self.symbols)

    def reduce(self, H) -> sp.Expr:
        """An invariant polynomial ``H`` rewritten as a polynomial in the invariants.

        Parameters
        ----------
        H
            Expression in :attr:`coords`, invariant under the action.

        Returns
        -------
        sympy.Expr
            ``h(pi)`` with ``h(pi(x)) = H(x)`` (one representative modulo the relations).

        Raises
        ------
        InputError
            ``H`` is not a polynomial, not invariant, or not a polynomial in the invariants
            found (raise ``degree``).
        """
        H = as_expr(H, "Hamiltonian")
        cx = self._ctx
        extra = H.free_symbols - set(cx.coords) - set(cx.params)
        if extra:  # parameters of the Hamiltonian join the coefficient field
            cx = _Context(cx.bivector, cx.raw_fields, sorted(extra, key=str))
        f = cx.poly(H)
        if any(cx.act(f, X) for X in cx.fields):
            raise InputError(f"{H} is not invariant under the action")
        gens = [cx.poly(e) for e in self.invariants]
        out = cx.express(f, gens, list(self.degrees), self.symbols)
        if out is None:
            raise InputError(f"{H} is not a polynomial in the {len(self.symbols)} invariants "
                             f"of degree <= {self.degree}; raise degree")
        return out


class _Context:
    """The ring, the bracket and the generating vector fields, in sparse form."""

    def __init__(self, P: Bivector, fields: list[list[sp.Expr]],
                 extra: Sequence[sp.Symbol] = ()) -> None:
        self.bivector, self.raw_fields = P, fields
        self.coords = list(P.coords)
        n = self.n = len(self.coords)
        syms = set().union(*(e.free_symbols for e in P.matrix), *(
            e.free_symbols for X in fields for e in X), extra) - set(self.coords)
        self.params = sorted(syms, key=str)
        self.K = sp.QQ.frac_field(*self.params) if self.params else sp.QQ
        self.R = PolyRing(self.coords, self.K, grlex)
        self.P = [[self.poly(P.matrix[i, j]) for j in range(n)] for i in range(n)]
        self.fields = [[self.poly(e) for e in X] for X in fields]
        self._column_cache: dict[tuple, tuple] = {}
        for X in self.fields:
            # linear fields (rotations, ...) or constant ones (translations) keep the invariants
            # of each degree a kernel inside that degree; affine mixtures do not
            degs = {sum(m) for e in X for m in e.monoms()}
            if degs - {0, 1} or degs == {0, 1}:
                raise InputError("the action must be linear or a translation: each generating "
                                 "vector field needs components all linear or all constant "
                                 "in the coordinates")

    def poly(self, e: sp.Expr) -> PolyElement:
        e = sp.expand(e)
        if e == 0:
            return self.R.zero
        try:
            return self.R.from_expr(e)
        except (ValueError, sp.PolynomialError, sp.CoercionFailed):
            raise InputError(f"{e} is not a polynomial in {tuple(map(str, self.coords))}") \
                from None

    def act(self, f: PolyElement, X: list[PolyElement]) -> PolyElement:
        g = self.R.gens
        return sum((X[i] * f.diff(g[i]) for i in range(self.n) if X[i]), self.R.zero)

    def bracket(self, f: PolyElement, h: PolyElement) -> PolyElement:
        g = self.R.gens
        df = [f.diff(x) for x in g]
        dh = [h.diff(x) for x in g]
        return sum((self.P[i][j] * df[i] * dh[j] for i in range(self.n) for j in range(self.n)
                    if self.P[i][j] and df[i] and dh[j]), self.R.zero)

    def invariants(self, d: int) -> list[PolyElement]:
        """A basis of the invariant homogeneous polynomials of degree ``d``."""
        monos = [self._mono(c) for c in combinations_with_replacement(range(self.n), d)]
        rows: dict[tuple[int, tuple], dict[int, object]] = {}
        for c, m in enumerate(monos):
            f = self.R({m: self.K.one})
            for a, X in enumerate(self.fields):
                for mono, v in self.act(f, X).terms():
                    rows.setdefault((a, mono), {})[c] = v
        sol = solve_sparse(list(rows.values()), [self.K.zero] * len(rows), len(monos), self.K)
        return [self.R({monos[c]: v for c, v in vec.items()}) for vec in sol.directions]

    def _mono(self, combo: Sequence[int]) -> tuple[int, ...]:
        e = [0] * self.n
        for j in combo:
            e[j] += 1
        return tuple(e)

    def _columns(self, gens: list[PolyElement], degs: list[int], top: int
                 ) -> tuple[list[tuple[int, ...]], dict[tuple, int], list[dict[int, object]]]:
        """The monomials in ``gens`` of weight ``<= top`` and their coefficient rows, cached
        per ``top`` for one list of generators (every bracket of a reduction reuses them)."""
        cache = self._column_cache
        key = (id(gens), tuple(degs), top)
        if key in cache and cache[key][0] is gens:
            return cache[key][1]
        exps = [(0,) * len(gens), *gen_monomials(degs, top)]
        index: dict[tuple, int] = {}
        rows: list[dict[int, object]] = []
        for c, e in enumerate(exps):
            p = self.R.one
            for g, k in zip(gens, e):
                if k:
                    p = p * g ** k
            for mono, v in p.terms():
                r = index.setdefault(mono, len(rows))
                if r == len(rows):
                    rows.append({})
                rows[r][c] = v
        cache[key] = (gens, (exps, index, rows))
        return exps, index, rows

    def express(self, f: PolyElement, gens: list[PolyElement], degs: list[int],
                syms: Sequence[sp.Symbol]) -> sp.Expr | None:
        """``f`` as a polynomial in ``gens`` (``None`` if it is not one up to its degree)."""
        if not f:
            return sp.Integer(0)
        top = max(sum(m) for m in f.monoms())
        exps, index, rows = self._columns(gens, degs, top)
        rhs = [self.K.zero] * len(rows)
        for mono, v in f.terms():
            if mono not in index:
                return None
            rhs[index[mono]] = v
        sol = solve_sparse(rows, rhs, len(exps), self.K)
        if not sol.consistent:
            return None
        return sp.expand(sp.Add(*[self.K.to_sympy(v) * _monomial(syms, exps[c])
                                  for c, v in sol.particular.items()]))


def _monomial(syms: Sequence[sp.Symbol], e: Sequence[int]) -> sp.Expr:
    return sp.Mul(*[s ** k for s, k in zip(syms, e)])


def _fields(P: Bivector, generators: Sequence) -> list[list[sp.Expr]]:
    from poissonkit.structure.schouten import Multivector

    out = []
    for g in generators:
        if isinstance(g, Multivector):
            if g.degree != 1:
                raise InputError("a generator given as a multivector must be a vector field")
            out.append([g.components.get((i,), sp.Integer(0)) for i in range(P.dim)])
        elif isinstance(g, (list, tuple, sp.MatrixBase)):
            comps = [as_expr(c, "vector field component") for c in g]
            if len(comps) != P.dim:
                raise InputError(f"a vector field needs {P.dim} components, got {len(comps)}")
            out.append(comps)
        else:  # a Hamiltonian: its vector field P dJ generates the action
            J = as_expr(g, "generating Hamiltonian")
            out.append(list(P.matrix * P.gradient(J)))
    if not out:
        raise InputError("give at least one generator of the action")
    return out


def reduce_by_symmetry(P, generators: Sequence, degree: int, *,
                       invariants: Sequence | None = None,
                       names: Sequence[str | sp.Symbol] | None = None,
                       relation_degree: int | None = None) -> ReducedPoissonAlgebra:
    """Reduce a Poisson structure by a linear symmetry: invariants, brackets, relations, Casimirs.

    Parameters
    ----------
    P
        A bivector with polynomial entries, invariant under the action.
    generators
        Infinitesimal generators of the action: linear vector fields (component lists or
        :class:`~poissonkit.structure.schouten.Multivector`) or Hamiltonian functions ``J``
        (the action is then the flow of ``P dJ``).
    degree
        Invariants (and Casimirs) are searched up to this polynomial degree.
    invariants
        Use these invariants instead of a computed Hilbert basis (e.g. the ones of a paper);
        each is checked to be invariant.
    names
        Names of the invariant symbols (default ``pi_1, pi_2, ...``).
    relation_degree
        Weight bound for the relations (default ``2 * degree``).

    Returns
    -------
    ReducedPoissonAlgebra
        Invariants, their brackets as polynomials in the invariants, the relations, the
        reduced Casimirs, and :meth:`ReducedPoissonAlgebra.reduce` for Hamiltonians.

    Raises
    ------
    InputError
        Non-linear action, non-polynomial bracket, a given invariant that is not invariant, or
        a bracket of invariants that is not a polynomial in them (raise ``degree``).

    Notes
    -----
    Method: :mod:`poissonkit.structure.reduction`. The computed Hilbert basis is complete up
    to ``degree`` only: the invariants of higher degree may need more generators.

    Examples
    --------
    >>> import sympy as sp
    >>> x1, x2, y1, y2 = sp.symbols("x1 x2 y1 y2")
    >>> from poissonkit.structure import Bivector
    >>> P = Bivector.from_matrix(sp.Matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-1, 0, 0, 0],
    ...                                     [0, -1, 0, 0]]), (x1, x2, y1, y2))
    >>> H = (x1**2 + y1**2 + x2**2 + y2**2) / 2   # 1:1 resonance
    >>> red = reduce_by_symmetry(P, [H], 2)
    >>> red.degrees, len(red.relations)
    ((2, 2, 2, 2), 1)
    """
    from poissonkit.structure.casimirs import _normalise

    P = as_bivector(P)
    if isinstance(degree, bool) or not isinstance(degree, int) or degree < 1:
        raise InputError(f"degree must be a positive integer, got {degree!r}")
    cx = _Context(P, _fields(P, generators))
    if invariants is None:
        rows = [f for d in range(1, degree + 1) for f in cx.invariants(d)]
        gens, degs = reduced_generators(rows, _normalise) if rows else ([], [])
    else:
        gens = [cx.poly(as_expr(f, "invariant")) for f in invariants]
        for f, g in zip(invariants, gens):
            if any(cx.act(g, X) for X in cx.fields):
                raise InputError(f"{f} is not invariant under the action")
            if len({sum(m) for m in g.monoms()}) != 1:
                raise InputError(f"the invariant {f} is not homogeneous")
        degs = [sum(g.monoms()[0]) for g in gens]
    syms = tuple(sp.Symbol(s) if isinstance(s, str) else s for s in names) if names else \
        sp.symbols(f"pi_1:{len(gens) + 1}")
    if len(syms) != len(gens):
        raise InputError(f"{len(gens)} invariants but {len(syms)} names")
    m = len(gens)
    B = sp.zeros(m, m)
    for i in range(m):
        for j in range(i + 1, m):
            b = cx.express(cx.bracket(gens[i], gens[j]), gens, degs, syms)
            if b is None:
                raise InputError(f"{{{syms[i]}, {syms[j]}}} is not a polynomial in the "
                                 "invariants found: raise degree or check that P is invariant")
            B[i, j], B[j, i] = b, -b
    rels = relations(gens, degs, relation_degree or 2 * degree) if gens else []
    rel_exprs = tuple(sp.expand(sp.Add(*[cx.K.to_sympy(v) * _monomial(syms, e)
                                         for e, v in r.items()])) for r in rels)
    cas = _casimirs(cx, gens, degs, syms, degree)
    return ReducedPoissonAlgebra(tuple(cx.coords), syms, tuple(g.as_expr() for g in gens),
                                 tuple(degs), sp.ImmutableMatrix(B), rel_exprs, cas, degree, cx)


def _casimirs(cx: _Context, gens: list[PolyElement], degs: list[int],
              syms: Sequence[sp.Symbol], degree: int) -> tuple[sp.Expr, ...]:
    """Invariants ``f`` of degree ``<= degree`` with ``{f, pi_j} = 0``, generators, in the pi."""
    from poissonkit.structure.casimirs import _normalise

    found: list[PolyElement] = []
    # A bracket homogeneous of one degree maps degree pieces to degree pieces, so Casimirs can be
    # sought one degree at a time; otherwise (canonical + Lie–Poisson, as for the two tops'
    # T*R^3 x e(3) x e(3), whose rotation generator r x p + m' + m'' mixes degrees 2 and 1)
    # all degrees together.
    degs_P = {sum(m) for row in cx.P for e in row if e for m in e.monoms()}
    pieces = [[f for d in range(1, degree + 1) for f in cx.invariants(d)]] if len(degs_P) > 1 \
        else [cx.invariants(d) for d in range(1, degree + 1)]
    for basis in pieces:
        if not basis:
            continue
        rows: dict[tuple, dict[int, object]] = {}
        for c, f in enumerate(basis):
            for j, g in enumerate(gens):
                for mono, v in cx.bracket(f, g).terms():
                    rows.setdefault((j, mono), {})[c] = v
        sol = solve_sparse(list(rows.values()), [cx.K.zero] * len(rows), len(basis), cx.K)
        for vec in sol.directions:
            found.append(sum((basis[c].mul_ground(v) for c, v in vec.items()), cx.R.zero))
    if not found:
        return ()
    cas, _ = reduced_generators(found, _normalise)
    out = []
    for c in cas:
        e = cx.express(c, gens, degs, syms)
        out.append(e if e is not None else c.as_expr())
    return tuple(out)
