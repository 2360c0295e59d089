"""Polynomial Poisson cohomology in low degrees, and the modular class.

The Lichnerowicz complex of a Poisson bivector ``P`` on ``R^n`` (or ``C^n``) has the polynomial
``k``-vector fields as ``k``-cochains and ``d_P = [P, .]`` as differential (``d_P f = P df``,
``d_P X = -L_X P``). Its cohomology ``H^k`` is: ``H^0`` the Casimirs, ``H^1`` the Poisson
vector fields modulo the Hamiltonian ones (infinitesimal symmetries), ``H^2`` the infinitesimal
deformations modulo the trivial ones (Lichnerowicz 1977; Laurent-Gengoux, Pichereau &
Vanhaecke, *Poisson Structures*, ch. 4).

If the entries of ``P`` are homogeneous of one degree ``p``, ``d_P`` maps ``k``-vectors with
coefficients homogeneous of degree ``d`` to ``(k+1)``-vectors of degree ``d + p - 1``, so
the complex splits by degree and

    ``H^k_d = ker(d_P: C^k_d -> C^{k+1}_{d+p-1}) / d_P(C^{k-1}_{d-p+1})``

is finite-dimensional: exact linear algebra (sympy ``DomainMatrix`` over ``QQ`` or
``QQ(parameters)``) on the coefficients. ``p = 1`` (Lie–Poisson) keeps the degree, ``p = 2``
(quadratic brackets, Jacobian structures of cubics) raises it by one.

The differential is applied to a ``k``-vector ``X`` in coordinates through the
Chevalley–Eilenberg formula on coordinate functions,

    ``(d X)^{j_0..j_k} = sum_a (-1)^a {x_{j_a}, X^{..^a..}}
    + sum_{a<b} (-1)^{a+b} sum_l d_l P^{j_a j_b} X^{l, ..^a..^b..}``,

which is ``[P, X]`` up to an overall sign per degree (irrelevant for kernels and images); the
tests compare with :func:`~poissonkit.structure.schouten.lichnerowicz` independently.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import combinations, combinations_with_replacement

import sympy as sp
from sympy.polys.matrices import DomainMatrix
from sympy.polys.rings import PolyElement, PolyRing

from poissonkit.errors import InputError
from poissonkit.structure._expr import as_bivector
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.schouten import Multivector

__all__ = ["ModularClass", "NotHomogeneousError", "PoissonCohomology", "modular_class",
           "poisson_cohomology"]

Key = tuple[int, ...]
Mono = tuple[int, ...]


class NotHomogeneousError(InputError):
    """The bracket's entries are not homogeneous polynomials of one degree."""


def _monomials(n: int, d: int) -> list[Mono]:
    out = []
    for combo in combinations_with_replacement(range(n), d):
        e = [0] * n
        for j in combo:
            e[j] += 1
        out.append(tuple(e))
    return out


def _sorted_key(idx: Sequence[int]) -> tuple[int, Key] | None:
    """Sign of the permutation sorting ``idx`` and the sorted key (None if an index repeats)."""
    if len(set(idx)) != len(idx):
        return None
    sign, lst = 1, list(idx)
    for i in range(len(lst)):  # insertion sort counting transpositions
        j = i
        while j > 0 and lst[j - 1] > lst[j]:
            lst[j - 1], lst[j] = lst[j], lst[j - 1]
            sign = -sign
            j -= 1
    return sign, tuple(lst)


class _Complex:
    """The graded Lichnerowicz complex of a homogeneous polynomial bivector, in a sparse ring."""

    def __init__(self, P: Bivector, params: Sequence[sp.Symbol]) -> None:
        self.coords = list(P.coords)
        n = self.n = len(self.coords)
        extra = set().union(*(e.free_symbols for e in P.matrix)) - set(self.coords)
        self.params = sorted(set(params) | extra, key=str)
        K = sp.QQ.frac_field(*self.params) if self.params else sp.QQ
        self.K = K
        self.R = R = PolyRing(self.coords, K)
        try:
            self.P = [[R.from_expr(sp.expand(P.matrix[i, j])) if P.matrix[i, j] != 0 else R.zero
                       for j in range(n)] for i in range(n)]
        except (ValueError, sp.PolynomialError, sp.CoercionFailed) as exc:
            raise InputError(f"the bracket is not polynomial in the coordinates: {exc}") from None
        degs = {sum(m) for row in self.P for e in row for m in e.monoms()}
        if len(degs) > 1:
            raise NotHomogeneousError(
                f"the entries of P mix the degrees {sorted(degs)}: the complex does not split "
                "by polynomial degree (give a homogeneous bracket)")
        self.p = degs.pop() if degs else 1
        self.dP = [[[e.diff(R.gens[l]) if e else R.zero for l in range(n)] for e in row]
                   for row in self.P]

    def basis(self, k: int, d: int) -> list[tuple[Key, Mono]]:
        if d < 0 or not 0 <= k <= self.n:
            return []
        monos = _monomials(self.n, d)
        return [(key, m) for key in combinations(range(self.n), k) for m in monos]

    def apply(self, X: dict[Key, PolyElement], k: int) -> dict[Key, PolyElement]:
        """``d X`` for a ``k``-vector ``{key: coefficient}`` (formula in the module notes)."""
        R, n, P, dP = self.R, self.n, self.P, self.dP
        gens = R.gens
        out: dict[Key, PolyElement] = {}
        touched = set().union(*X) if X else set()
        for J in combinations(range(n), k + 1):
            if k and len(touched & set(J)) < k - 1:
                continue
            acc = R.zero
            for a, ja in enumerate(J):
                f = X.get(J[:a] + J[a + 1:])
                if f:
                    t = sum((P[ja][l] * f.diff(gens[l]) for l in range(n) if P[ja][l]), R.zero)
                    acc = acc + t if a % 2 == 0 else acc - t
            for a, b in combinations(range(k + 1), 2):
                rest = J[:a] + J[a + 1:b] + J[b + 1:]
                g = dP[J[a]][J[b]]
                for l in range(n):
                    if not g[l]:
                        continue
                    sk = _sorted_key((l, *rest))
                    if sk is None or sk[1] not in X:
                        continue
                    t = g[l] * X[sk[1]] * sk[0]
                    acc = acc + t if (a + b) % 2 == 0 else acc - t
            if acc:
                out[J] = acc
        return out

    def matrix(self, k: int, d: int) -> tuple[DomainMatrix, list[tuple[Key, Mono]]]:
        """``d_P: C^k_d -> C^{k+1}_{d+p-1}`` in the monomial bases, and the source basis."""
        src = self.basis(k, d)
        tgt = {b: i for i, b in enumerate(self.basis(k + 1, d + self.p - 1))}
        cols: dict[int, dict[int, object]] = {}
        for c, (key, m) in enumerate(src):
            image = self.apply({key: self.R({m: self.K.one})}, k)
            for J, poly in image.items():
                for mono, coeff in poly.terms():
                    cols.setdefault(tgt[(J, mono)], {})[c] = coeff
        shape = (len(tgt), len(src))
        return DomainMatrix(cols, shape, self.K), src

    def element(self, vec: dict[int, object], basis: list[tuple[Key, Mono]], k: int):
        comps: dict[Key, PolyElement] = {}
        for c, v in vec.items():
            key, m = basis[c]
            comps[key] = comps.get(key, self.R.zero) + self.R({m: v})
        if k == 0:
            return comps.get((), self.R.zero).as_expr()
        return Multivector(k, tuple(self.coords), {key: p.as_expr() for key, p in comps.items()})


@dataclass(frozen=True)
class PoissonCohomology:
    """``H^k`` of the polynomial Lichnerowicz complex, degree by degree.

    Attributes
    ----------
    k
        The cohomological degree.
    p
        The polynomial degree of the bracket's entries (``d_P`` shifts degrees by ``p - 1``).
    dimensions
        ``{d: dim H^k_d}`` for the polynomial degrees ``d = 0 .. max_degree`` of the
        coefficients of the ``k``-vectors.
    cocycles, coboundaries
        ``{d: dim}`` of the kernel of ``d_P`` on ``C^k_d`` and of the image in it.
    bases
        ``{d: representatives}``: polynomials (``k = 0``) or
        :class:`~poissonkit.structure.schouten.Multivector` fields, cocycles whose classes form
        a basis of ``H^k_d`` (empty tuples when ``bases=False`` was asked).
    """

    k: int
    p: int
    dimensions: dict[int, int]
    cocycles: dict[int, int]
    coboundaries: dict[int, int]
    bases: dict[int, tuple] = field(default_factory=dict)

    def __repr__(self) -> str:
        return f"PoissonCohomology(k={self.k}, dimensions={self.dimensions})"


def _rows(M: DomainMatrix) -> list[dict[int, object]]:
    return [dict(r) for r in M.to_sdm().values()]


def _complement(image: DomainMatrix | None, kernel: DomainMatrix, K) -> list[dict[int, object]]:
    """Kernel rows whose classes modulo the image rows form a basis of the quotient."""
    ncols = kernel.shape[1]
    chosen: list[dict[int, object]] = []
    base = _rows(image) if image is not None and image.shape[0] else []
    rank = DomainMatrix({i: r for i, r in enumerate(base)}, (len(base), ncols), K).rank() \
        if base else 0
    for r in _rows(kernel):
        rows = base + chosen + [r]
        if DomainMatrix({i: x for i, x in enumerate(rows)}, (len(rows), ncols), K).rank() > rank:
            chosen.append(r)
            rank += 1
    return chosen


def poisson_cohomology(P, k: int, max_degree: int, *, params: Sequence = (),
                       bases: bool = True) -> PoissonCohomology:
    """Dimensions (and bases) of the polynomial Poisson cohomology ``H^k`` per degree.

    Parameters
    ----------
    P
        A Poisson bivector whose entries are homogeneous polynomials of one degree ``p``
        (linear: Lie–Poisson; quadratic; constant). Not checked to be Poisson: use
        :func:`~poissonkit.structure.check_jacobi` first.
    k
        Cohomological degree, ``0 <= k <= n`` (``H^0`` Casimirs, ``H^1`` Poisson modulo
        Hamiltonian vector fields, ``H^2`` deformations modulo trivial ones).
    max_degree
        The polynomial degrees ``0 .. max_degree`` of the coefficients are computed.
    params
        Parameters of ``P`` (found automatically too); dimensions are generic in them.
    bases
        Also return representatives of a basis of each ``H^k_d``.

    Returns
    -------
    PoissonCohomology
        ``dimensions[d] = dim ker - dim im`` in degree ``d``, with the two parts and bases.

    Raises
    ------
    NotHomogeneousError
        The entries of ``P`` are not homogeneous of one degree.
    InputError
        ``k`` or ``max_degree`` out of range, or ``P`` not polynomial.

    Notes
    -----
    Method: module docstring of :mod:`poissonkit.structure.cohomology`. Cost grows as
    ``C(n, k) * C(n + d - 1, d)`` unknowns per degree.

    Examples
    --------
    >>> from poissonkit.structure import so3
    >>> poisson_cohomology(so3(), 0, 4).dimensions  # the Casimirs: powers of |m|^2
    {0: 1, 1: 0, 2: 1, 3: 0, 4: 1}
    >>> poisson_cohomology(so3(), 2, 3, bases=False).dimensions  # semisimple: H^2 = 0
    {0: 0, 1: 0, 2: 0, 3: 0}
    """
    P = as_bivector(P)
    if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k <= P.dim:
        raise InputError(f"k must be an integer in 0..{P.dim}, got {k!r}")
    if isinstance(max_degree, bool) or not isinstance(max_degree, int) or max_degree < 0:
        raise InputError(f"max_degree must be a non-negative integer, got {max_degree!r}")
    cx = _Complex(P, [sp.Symbol(s) if isinstance(s, str) else s for s in params])
    dims, zs, bs, reps = {}, {}, {}, {}
    for d in range(max_degree + 1):
        D, src = cx.matrix(k, d)
        ker = D.nullspace() if D.shape[0] else DomainMatrix.eye(len(src), cx.K)
        if D.shape[0] and ker.shape[0] == 0:
            ker = DomainMatrix.zeros((0, len(src)), cx.K)
        e = d - cx.p + 1
        im = None
        if k >= 1 and e >= 0:
            Dm, _ = cx.matrix(k - 1, e)
            im = Dm.transpose()
        nz = ker.shape[0] if src else 0
        nb = im.rank() if im is not None and im.shape[0] and im.shape[1] else 0
        zs[d], bs[d], dims[d] = nz, nb, nz - nb
        if bases and src:
            reps[d] = tuple(cx.element(r, src, k) for r in _complement(im, ker, cx.K))
        else:
            reps[d] = ()
    return PoissonCohomology(k, cx.p, dims, zs, bs, reps)


@dataclass(frozen=True)
class ModularClass:
    """The modular vector field of ``P`` for the volume ``dx_1 .. dx_n`` and its class in H^1.

    Attributes
    ----------
    field
        ``Y^i = sum_j d_j P^{ji}`` (``Y(f) = div X_f``).
    unimodular
        ``True`` iff ``Y = P df`` for a polynomial ``f`` (then :attr:`hamiltonian` is one).
    hamiltonian
        Such an ``f`` (``0`` when ``Y = 0``), or ``None``.
    exact
        Whether ``unimodular = False`` is proved (homogeneous ``P``: a Hamiltonian of ``Y``
        would be a constant) or only means "no ``f`` of degree ``<= searched_degree``".
    searched_degree
        The degree bound used for ``f``.
    """

    field: tuple[sp.Expr, ...]
    unimodular: bool
    hamiltonian: sp.Expr | None
    exact: bool
    searched_degree: int


def modular_class(P, *, max_degree: int | None = None) -> ModularClass:
    """Modular vector field of a polynomial bivector and whether its class vanishes.

    Parameters
    ----------
    P
        A Poisson bivector with polynomial entries.
    max_degree
        Degree bound for a Hamiltonian ``f`` of the modular field (default: one more than
        the field's degree).

    Returns
    -------
    ModularClass
        The field ``Y``, ``unimodular`` and, when it holds, ``f`` with ``Y = P df``.

    Notes
    -----
    Weinstein, *J. Geom. Phys.* 23 (1997): ``Y`` is a Poisson vector field whose class in
    ``H^1`` does not depend on the volume form; for a Lie–Poisson bracket ``Y`` is the
    trace form ``x -> tr ad_x`` (``Y = 0`` iff the Lie algebra is unimodular). For
    homogeneous ``P`` of degree ``p`` a Hamiltonian of ``Y`` (degree ``p - 1``) would have
    degree 0, so ``unimodular`` is ``Y = 0`` exactly.

    Examples
    --------
    >>> import sympy as sp
    >>> from poissonkit.structure import Bivector, so3
    >>> modular_class(so3()).unimodular
    True
    >>> x, y = sp.symbols("x y")
    >>> modular_class(Bivector.from_matrix(sp.Matrix([[0, x], [-x, 0]]), (x, y))).field
    (0, 1)
    """
    P = as_bivector(P)
    n, X = P.dim, P.coords
    Y = tuple(sp.expand(sum(sp.diff(P.matrix[j, i], X[j]) for j in range(n))) for i in range(n))
    if all(v == 0 for v in Y):
        return ModularClass(Y, True, sp.Integer(0), True, 0)
    degs = [sp.Poly(v, *X).total_degree() for v in Y if v != 0]
    entries = [e for e in P.matrix if e != 0]
    homogeneous = len({m for e in entries for m in map(sum, sp.Poly(e, *X).monoms())}) == 1
    top = max_degree if max_degree is not None else max(degs) + 1
    monos = [m for d in range(1, top + 1) for m in _monomials(n, d)]
    cs = sp.symbols(f"c0:{len(monos)}")
    f = sum(c * sp.Mul(*[x ** e for x, e in zip(X, m)]) for c, m in zip(cs, monos))
    eqs = [sp.expand(v - sum(P.matrix[i, j] * sp.diff(f, X[j]) for j in range(n)))
           for i, v in enumerate(Y)]
    lin = [c for e in eqs for c in sp.Poly(e, *X).coeffs()]
    sol = sp.solve(lin, cs, dict=True) if monos else []
    if sol:
        g = sp.expand(f.subs(sol[0]).subs({c: 0 for c in cs}))
        return ModularClass(Y, True, g, True, top)
    return ModularClass(Y, False, None, homogeneous, top)
