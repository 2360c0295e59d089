"""Bi-Hamiltonian structures: compatibility, the recursion operator, Lenard–Magri chains.

Two Poisson bivectors ``P1``, ``P2`` are *compatible* when every ``P2 - lam P1`` is Poisson,
i.e. ``[P1, P2] = 0`` (Schouten bracket, :mod:`poissonkit.structure.schouten`). A Casimir of the
pencil, polynomial in ``lam``,

    ``C(lam) = C_0 + lam C_1 + ... + lam^m C_m``,   ``(P2 - lam P1) dC(lam) = 0``,

gives, order by order in ``lam``, the Lenard–Magri chain

    ``P2 dC_0 = 0``,  ``P2 dC_k = P1 dC_{k-1}`` (``k = 1..m``),  ``P1 dC_m = 0``,

whose members are pairwise in involution for both brackets (Magri 1978; e.g. Bolsinov &
Borisov, *Math. Notes* 72 (2002), or Olver, *Applications of Lie Groups to Differential
Equations*, §7.3). Where ``P1`` is invertible, ``N = P2 P1^{-1}`` is the recursion operator
(a Nijenhuis (1,1)-tensor whose eigenvalues are integrals in involution).

Matrices follow :mod:`poissonkit.conventions`: ``P[i, j] = {x_i, x_j}`` and ``P dH`` is the
Hamiltonian vector field, so ``P`` maps covectors to vectors and ``N = P2 P1^{-1}`` maps
vectors to vectors.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure._expr import as_bivector, as_expr
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.checks import CheckResult
from poissonkit.structure.zerotest import vanishes

__all__ = [
    "ConstantCasimirError", "DegenerateBivectorError", "LenardMagriChain", "compatible",
    "involution_both",
    "lenard_magri_chain",
    "lenard_magri_chains", "nijenhuis_torsion", "pencil", "pencil_casimirs",
    "recursion_operator",
]


class DegenerateBivectorError(InputError):
    """``P1`` is not invertible where an inverse is needed (give a leaf block instead)."""


class ConstantCasimirError(InputError):
    """A pencil Casimir that does not depend on the coordinates: its chain has no integrals."""


def _pair(P1, P2) -> tuple[Bivector, Bivector]:
    P1, P2 = as_bivector(P1), as_bivector(P2)
    if P1.coords != P2.coords:
        raise InputError("the two bivectors live on different coordinates: "
                         f"{tuple(map(str, P1.coords))} vs {tuple(map(str, P2.coords))}")
    return P1, P2


def _lam_symbol(lam: sp.Symbol | str | None, P: Bivector) -> sp.Symbol:
    """The pencil parameter; refused if it names a coordinate or a parameter of the brackets."""
    s = sp.Symbol(lam) if isinstance(lam, str) else (lam if lam is not None else sp.Symbol("lam"))
    if not isinstance(s, sp.Symbol):
        raise InputError(f"the pencil parameter must be a symbol, got {lam!r}")
    taken = {str(c) for c in P.coords} | {str(x) for e in P.matrix for x in e.free_symbols}
    if str(s) in taken:
        raise InputError(f"the pencil parameter {s} is already a coordinate or parameter")
    return s


def pencil(P1, P2, lam: sp.Symbol | str | None = None) -> Bivector:
    """The pencil ``P2 - lam P1`` as one bivector with the parameter ``lam``.

    Parameters
    ----------
    P1, P2
        Bivectors on the same coordinates.
    lam
        The pencil parameter (symbol or name; default ``lam``).

    Returns
    -------
    Bivector
        ``P2 - lam P1``.

    Examples
    --------
    >>> from poissonkit.structure import so3
    >>> pencil(so3(), so3()).matrix[0, 1]
    -lam*m_z + m_z
    """
    P1, P2 = _pair(P1, P2)
    return P2 - P1 * _lam_symbol(lam, P1)


def compatible(P1, P2, *, check_poisson: bool = True) -> CheckResult:
    """Whether ``P1`` and ``P2`` form a Poisson pencil (exact).

    Parameters
    ----------
    P1, P2
        Bivectors on the same coordinates.
    check_poisson
        Also prove that ``P1`` and ``P2`` are Poisson (then ``holds`` means every
        ``P2 - lam P1`` is Poisson); with ``False`` only ``[P1, P2] = 0`` is checked.

    Returns
    -------
    CheckResult
        Truthy iff compatible; ``failures`` name the non-zero components of ``[P1, P2]``
        (``"[P1,P2]^{ijk}"``, 0-based) and of the Jacobiators.

    Notes
    -----
    Wraps :func:`poissonkit.structure.schouten.schouten_bracket` and
    :func:`poissonkit.structure.jacobi.check_jacobi` (radical-aware zero test).

    Examples
    --------
    >>> from poissonkit.structure import so3
    >>> bool(compatible(so3(), so3()))
    True
    """
    from poissonkit.structure.jacobi import check_jacobi, is_zero_expression
    from poissonkit.structure.schouten import schouten_bracket

    P1, P2 = _pair(P1, P2)
    fails: list[tuple[str, sp.Expr]] = []
    if check_poisson:
        for name, P in (("P1", P1), ("P2", P2)):
            res = check_jacobi(P, method="exact")
            fails += [(f"Jac_{name}^{key}", v) for key, v in dict(res.failures).items()]
            if not res.is_poisson and not res.failures:
                fails.append((f"Jac_{name}", sp.nan))
    S = schouten_bracket(P1, P2)
    fails += [(f"[P1,P2]^{key}", v) for key, v in S.components.items()
              if not is_zero_expression(v)]
    what = "compatibility [P1, P2] = 0" + (" of two Poisson bivectors" if check_poisson else "")
    return CheckResult(not fails, tuple(fails), what, "Schouten bracket, exact")


def _leaf_indices(P: Bivector, leaf: Sequence[int | str | sp.Symbol]) -> list[int]:
    pos = {str(c): i for i, c in enumerate(P.coords)}
    out = []
    for x in leaf:
        if isinstance(x, int) and not isinstance(x, bool):
            if not 0 <= x < P.dim:
                raise InputError(f"leaf index {x} out of range 0..{P.dim - 1}")
            out.append(x)
        elif str(x) in pos:
            out.append(pos[str(x)])
        else:
            raise InputError(f"{x!r} is not a coordinate of the bivector")
    if len(set(out)) != len(out):
        raise InputError("leaf block repeats a coordinate")
    return out


def recursion_operator(P1, P2, *, leaf: Sequence[int | str | sp.Symbol] | None = None
                       ) -> sp.Matrix:
    """The recursion operator ``N = P2 P1^{-1}`` (a (1,1)-tensor, ``N[i, j] = N^i_j``).

    Parameters
    ----------
    P1, P2
        Bivectors on the same coordinates; ``P1`` must be invertible, or ``leaf`` given.
    leaf
        For a degenerate ``P1``: the coordinates (names or 0-based indices) of a principal block
        ``B = P1[leaf, leaf]`` with ``rank B = rank P1`` (so ``B`` is invertible and the other
        coordinates are transverse to the symplectic leaves). Then ``P1^{-1}`` is replaced by the
        generalised inverse ``G`` equal to ``B^{-1}`` on the block and ``0`` elsewhere; it
        satisfies ``P1 G P1 = P1`` (checked), so ``N = P2 G`` is defined on the vectors
        tangent to the leaves of ``P1`` but only modulo ``P2(ker P1)``: it depends on the block
        unless the Casimirs of ``P1`` are Casimirs of ``P2`` too.

    Returns
    -------
    sympy.Matrix
        ``N`` with simplified entries; ``N P1 = P2`` when ``P1`` is invertible.

    Raises
    ------
    DegenerateBivectorError
        ``P1`` is singular and no ``leaf`` was given, or the leaf block is singular or too
        small.

    Examples
    --------
    >>> from poissonkit.structure import canonical
    >>> recursion_operator(canonical(1), canonical(1) * 2)
    Matrix([
    [2, 0],
    [0, 2]])
    """
    P1, P2 = _pair(P1, P2)
    M1 = sp.Matrix(P1.matrix)
    if leaf is None:
        det = sp.factor(M1.det())
        if det == 0:
            raise DegenerateBivectorError(
                f"P1 is degenerate (rank {M1.rank()} < {P1.dim}); give a leaf block "
                "recursion_operator(..., leaf=[...]) to use a generalised inverse")
        G = M1.inv()
    else:
        idx = _leaf_indices(P1, leaf)
        B = M1.extract(idx, idx)
        if sp.factor(B.det()) == 0:
            raise DegenerateBivectorError(f"the leaf block {[str(P1.coords[i]) for i in idx]} "
                                          "of P1 is singular")
        G = sp.zeros(P1.dim, P1.dim)
        Binv = B.inv()
        for a, i in enumerate(idx):
            for b, j in enumerate(idx):
                G[i, j] = Binv[a, b]
        if not all(vanishes(e) for e in (M1 * G * M1 - M1)):
            raise DegenerateBivectorError(
                "the leaf block has smaller rank than P1: it is not transverse to the "
                "Casimir directions, so P1 G P1 != P1")
    return (sp.Matrix(P2.matrix) * G).applyfunc(sp.cancel)


def nijenhuis_torsion(N: sp.MatrixBase, coords: Sequence[sp.Symbol]) -> dict[tuple[int, int, int],
                                                                           sp.Expr]:
    """Non-zero components of the Nijenhuis torsion of a (1,1)-tensor ``N``.

    ``T^i_{jk} = N^l_j d_l N^i_k - N^l_k d_l N^i_j - N^i_l (d_j N^l_k - d_k N^l_j)`` for
    ``j < k`` (``N[i, j] = N^i_j``, ``d_l = d/dx_l``). The recursion operator of a compatible
    pair with invertible ``P1`` has zero torsion.

    Parameters
    ----------
    N
        Square matrix ``N^i_j``.
    coords
        The coordinates ``x_1 .. x_n``.

    Returns
    -------
    dict
        ``{(i, j, k): T^i_{jk}}`` for the components that do not vanish (empty: ``N`` is
        Nijenhuis).
    """
    N = sp.Matrix(N)
    n = len(coords)
    if N.shape != (n, n):
        raise InputError(f"N has shape {N.shape}, expected ({n}, {n})")
    d = [[[sp.diff(N[i, j], x) for x in coords] for j in range(n)] for i in range(n)]
    out = {}
    for i in range(n):
        for j, k in combinations(range(n), 2):
            t = sum(N[l, j] * d[i][k][l] - N[l, k] * d[i][j][l]
                    - N[i, l] * (d[l][k][j] - d[l][j][k]) for l in range(n))
            if not vanishes(t):
                out[(i, j, k)] = sp.simplify(t)
    return out


@dataclass(frozen=True)
class LenardMagriChain:
    """A Lenard–Magri chain: the ``lam``-coefficients of a Casimir of ``P2 - lam P1``.

    Attributes
    ----------
    P1, P2
        The two brackets.
    lam
        The pencil parameter.
    casimir
        The pencil Casimir ``C(lam)``, a polynomial in ``lam``.
    coefficients
        ``(C_0, .., C_m)`` with ``C(lam) = sum lam^k C_k`` (constants included):
        ``P2 dC_0 = 0``, ``P2 dC_k = P1 dC_{k-1}``, ``P1 dC_m = 0``.
    """

    P1: Bivector
    P2: Bivector
    lam: sp.Symbol
    casimir: sp.Expr
    coefficients: tuple[sp.Expr, ...]

    @property
    def integrals(self) -> tuple[sp.Expr, ...]:
        """The non-constant coefficients, in increasing power of ``lam``."""
        cs = set(self.P1.coords)
        return tuple(c for c in self.coefficients if c.free_symbols & cs)

    def check(self) -> CheckResult:
        """Prove the chain relations ``P2 dC_0 = 0``, ``P2 dC_k = P1 dC_{k-1}``, ``P1 dC_m = 0``.

        Returns
        -------
        CheckResult
            ``failures`` name the relation and coordinate whose residual is non-zero.
        """
        P1, P2 = self.P1, self.P2
        g = [P1.gradient(c) for c in self.coefficients]
        rel = [("P2 dC_0", P2.matrix * g[0])]
        rel += [(f"P2 dC_{k} - P1 dC_{k - 1}", P2.matrix * g[k] - P1.matrix * g[k - 1])
                for k in range(1, len(g))]
        rel.append((f"P1 dC_{len(g) - 1}", P1.matrix * g[-1]))
        fails = tuple((f"{name}[{x}]", sp.simplify(v)) for name, vec in rel
                      for x, v in zip(P1.coords, vec) if not vanishes(v))
        return CheckResult(not fails, fails, "Lenard-Magri chain relations", "exact")

    def in_involution(self) -> CheckResult:
        """Whether the chain's integrals are pairwise in involution for ``P1`` and for ``P2``.

        Returns
        -------
        CheckResult
            Exact; ``failures`` are labelled ``"P1: {F_k, F_l}"`` / ``"P2: {F_k, F_l}"``.
        """
        return involution_both(self.P1, self.P2, self.integrals)


def involution_both(P1, P2, functions: Sequence) -> CheckResult:
    """Whether the functions are pairwise in involution for both brackets (exact).

    Parameters
    ----------
    P1, P2
        Bivectors on the same coordinates.
    functions
        Expressions in their coordinates.

    Returns
    -------
    CheckResult
        ``failures`` are labelled ``"P1: {F_k, F_l}"`` and ``"P2: {F_k, F_l}"`` (1-based).
    """
    from poissonkit.structure.checks import in_involution

    P1, P2 = _pair(P1, P2)
    fs = [as_expr(f, "function") for f in functions]
    fails: list[tuple[str, sp.Expr]] = []
    for name, P in (("P1", P1), ("P2", P2)):
        if len(fs) > 1:
            res = in_involution(P, fs)
            fails += [(f"{name}: {lab}", v) for lab, v in res.failures]
    return CheckResult(not fails, tuple(fails), f"involution of {len(fs)} functions for P1 and P2",
                       "exact")


def _coefficients(C: sp.Expr, lam: sp.Symbol) -> tuple[sp.Expr, ...]:
    try:
        poly = sp.Poly(sp.expand(C), lam)
    except sp.PolynomialError:
        raise InputError(f"the pencil Casimir is not a polynomial in {lam}") from None
    coeffs = poly.all_coeffs()[::-1]  # increasing powers
    return tuple(sp.expand(c) for c in coeffs)


def lenard_magri_chain(P1, P2, casimir, lam: sp.Symbol | str | None = None) -> LenardMagriChain:
    """The Lenard–Magri chain of a given Casimir ``C(lam)`` of the pencil ``P2 - lam P1``.

    Parameters
    ----------
    P1, P2
        Bivectors on the same coordinates (compatible: :func:`compatible`).
    casimir
        ``C(lam)``, polynomial in ``lam`` (rational in the coordinates), e.g. ``det(L - lam)``
        for a Lax matrix ``L``.
    lam
        The symbol of the pencil parameter used in ``casimir`` (default ``lam``).

    Returns
    -------
    LenardMagriChain
        Its ``coefficients`` are the ``lam``-coefficients of ``C``; the chain relations are
        proved before returning.

    Raises
    ------
    ConstantCasimirError
        ``casimir`` does not depend on the coordinates (a constant gives no integrals).
    InputError
        ``casimir`` is not a polynomial in ``lam`` or not a Casimir of the pencil.

    Examples
    --------
    >>> import sympy as sp
    >>> from poissonkit.structure import Bivector, so3
    >>> m = so3().coords
    >>> a = (1, 2, 3)
    >>> C2 = sum(ai * mi**2 for ai, mi in zip(a, m)) / 2
    >>> P2 = Bivector(m, sp.ImmutableMatrix(3, 3, lambda i, j: sum(
    ...     sp.LeviCivita(i, j, k) * sp.diff(C2, m[k]) for k in range(3))))
    >>> lam = sp.Symbol("lam")
    >>> ch = lenard_magri_chain(so3(), P2, C2 - lam * sum(x**2 for x in m) / 2, lam)
    >>> len(ch.integrals), bool(ch.in_involution())
    (2, True)
    """
    P1, P2 = _pair(P1, P2)
    lam = _lam_symbol(lam, P1)
    C = as_expr(casimir, "pencil Casimir")
    if not sp.expand(C).free_symbols & set(P1.coords):
        raise ConstantCasimirError(
            f"the pencil Casimir {C} does not depend on the coordinates "
            f"{tuple(map(str, P1.coords))}: its Lenard-Magri chain has no integrals")
    chain = LenardMagriChain(P1, P2, lam, C, _coefficients(C, lam))
    res = chain.check()
    if not res:
        raise InputError(f"not a Casimir of P2 - {lam} P1: {res.failures[0][0]} = "
                         f"{res.failures[0][1]}")
    return chain


def pencil_casimirs(P1, P2, degree: int, lam: sp.Symbol | str | None = None,
                    params: Sequence = ()) -> tuple[sp.Expr, ...]:
    """Polynomial Casimirs of the pencil ``P2 - lam P1``, cleared to polynomials in ``lam``.

    Parameters
    ----------
    P1, P2
        Bivectors on the same coordinates.
    degree
        Maximal total degree in the coordinates (as :func:`~poissonkit.structure.find_casimirs`).
    lam
        The pencil parameter (default ``lam``).
    params
        Other parameters of the brackets.

    Returns
    -------
    tuple of sympy.Expr
        Generators over ``Q(params, lam)`` found by
        :func:`~poissonkit.structure.find_casimirs`, each multiplied by the common denominator
        of its coefficients and divided by their gcd, both taken over the coefficients of the
        monomials in the coordinates (polynomials in ``lam`` and ``params``). Only factors free
        of the coordinates are removed: a factor ``f(lam)`` can go because a Casimir for every
        ``lam`` stays one after division (by continuity at the roots of ``f``), whereas a factor
        depending on the coordinates cannot (``z (y + lam x)`` is a Casimir of
        ``star d(z (y + lam x))``, ``y + lam x`` is not). Constant terms are dropped, as by
        ``find_casimirs``.

    Examples
    --------
    >>> from poissonkit.structure import so3
    >>> pencil_casimirs(so3(), so3() * 2, 2)
    (m_x**2 + m_y**2 + m_z**2,)
    """
    from poissonkit.structure.casimirs import find_casimirs

    P1, P2 = _pair(P1, P2)
    lam = _lam_symbol(lam, P1)
    found = find_casimirs(pencil(P1, P2, lam), degree, params=[*params, lam])
    return tuple(_clear_content(C, P1.coords) for C in found)


def _clear_content(C: sp.Expr, coords: Sequence[sp.Symbol]) -> sp.Expr:
    """``C`` times its coordinate-free denominator, divided by its coordinate-free content."""
    num, den = sp.fraction(sp.together(C))
    if den.free_symbols & set(coords):  # not a polynomial in the coordinates: leave it alone
        return sp.expand(C)
    poly = sp.Poly(sp.expand(num), *coords)
    content = sp.gcd_list(poly.coeffs())
    if content == 0:
        return sp.expand(num)
    return sp.expand(sum(sp.cancel(c / content) * sp.Mul(*[x ** e for x, e in zip(coords, m)])
                         for m, c in poly.terms()))


def lenard_magri_chains(P1, P2, degree: int, lam: sp.Symbol | str | None = None,
                        params: Sequence = ()) -> tuple[LenardMagriChain, ...]:
    """The Lenard–Magri chains of every polynomial pencil Casimir up to ``degree``.

    Parameters
    ----------
    P1, P2, degree, lam, params
        As in :func:`pencil_casimirs`.

    Returns
    -------
    tuple of LenardMagriChain
        One chain per generator of :func:`pencil_casimirs` (relations proved).

    Raises
    ------
    ConstantCasimirError
        A generator does not depend on the coordinates (cannot happen for the generators of
        :func:`pencil_casimirs`, which drops constants, but refused rather than returned).

    Examples
    --------
    >>> from poissonkit.structure import so3
    >>> import sympy as sp
    >>> m = so3().coords
    >>> P2 = so3().subs(m[2], 2 * m[2])  # a second compatible Lie-Poisson bracket
    >>> [len(ch.integrals) for ch in lenard_magri_chains(so3(), P2, 2)]
    [2]
    """
    P1, P2 = _pair(P1, P2)
    lam = _lam_symbol(lam, P1)
    return tuple(lenard_magri_chain(P1, P2, C, lam)
                 for C in pencil_casimirs(P1, P2, degree, lam, params))
