"""The Hamiltonian as an unknown combination of given integrals, and the integrals' Casimir
combinations of a found bracket.

Searching ``X = N P dH`` with ``H = sum_k c_k I_k`` and unknown constants ``c`` is bilinear in
``(c, P)``. :func:`poissonkit.structure.hamiltonize.hamiltonize` linearises it: ``W_k = c_k Q``
are independent unknowns and ``sum_k W_k dI_k = X/(N s)`` is linear. Every ``(c, Q)`` gives a
solution ``W``, so an inconsistency certificate of the linear system proves that *no*
combination works. On the affine family ``W(t)`` this module restores ``W_k = c_k Q`` chart by
chart: ``c`` is projective (its scale goes into ``Q``), and the charts ``c_{k0} = 1``,
``c_k = 0`` for ``k < k0`` cover every non-zero ``c``. In chart ``k0``, ``Q = W_{k0}`` and the
conditions are polynomial in ``(t, c_{k0+1}, ...)``:

* ``W_k = 0`` for ``k < k0`` and ``W_k = c_k W_{k0}`` for ``k > k0`` (coefficient-wise),
* ``[s W_{k0}, s W_{k0}] = 0`` (Jacobi of ``P = s Q``).

Each chart's equations are solved exactly (reduced Groebner basis, then ``solve``). If every
chart has the unit ideal, no combination of the integrals is a Hamiltonian of a bracket of the
ansatz: a proof, stated in the certificate.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import sympy as sp

from poissonkit.structure.bivector import Bivector
from poissonkit.structure.hamiltonize_result import Certificate

__all__ = ["casimir_combinations", "impose_span"]

#: Name stem of the unknown coefficients of the Hamiltonian (``c2, c3, ...``).
COEFFICIENT_STEM = "c"


def _coefficients(Q: sp.Matrix, coords: Sequence[sp.Symbol]) -> dict[tuple, sp.Expr]:
    """``{(i, j, monomial): coefficient}`` of the upper triangle of a polynomial matrix."""
    out: dict[tuple, sp.Expr] = {}
    n = len(coords)
    for i in range(n):
        for j in range(i + 1, n):
            e = sp.expand(Q[i, j])
            if e != 0:
                for mono, cf in sp.Poly(e, *coords).as_dict().items():
                    out[(i, j, mono)] = cf
    return out


def _coefficient_symbols(m: int, taken: set[str]) -> tuple[sp.Symbol, ...]:
    stem = COEFFICIENT_STEM
    while any(f"{stem}{k}" in taken for k in range(1, m + 1)):
        stem += "_"
    return sp.symbols(f"{stem}1:{m + 1}", real=True)


def _solve_chart(eqs: list[sp.Expr], unknowns: list[sp.Symbol]):
    """``(basis, solutions)``; ``basis == (1,)`` proves there is none."""
    eqs = [e for e in (sp.expand(q) for q in eqs) if e != 0]
    if not eqs:
        return (), [{}]
    if any(not (e.free_symbols & set(unknowns)) for e in eqs):
        return (sp.Integer(1),), []   # a non-zero equation free of unknowns
    basis = tuple(sp.groebner(eqs, *unknowns, order="grevlex").exprs)
    if basis == (1,):
        return basis, []
    return basis, sp.solve(list(basis), unknowns, dict=True)


def impose_span(Qs: Sequence[sp.Matrix], prefactor: sp.Expr, coords: Sequence[sp.Symbol],
                tau: Sequence[sp.Symbol], span: Mapping[str, sp.Expr], multiplier: sp.Expr,
                jacobi: Callable[[sp.Matrix], list[sp.Expr]]) -> tuple[str, dict]:
    """Restore ``W_k = c_k Q`` and impose Jacobi, chart by chart (see the module docstring).

    Parameters
    ----------
    Qs
        The copies ``W_k`` (affine in ``tau``), one per integral of ``span``.
    prefactor
        ``s`` in ``P = s Q``.
    coords, tau
        Coordinates and the free parameters of the linear family.
    span
        ``{name: I_k}``.
    multiplier
        ``N`` (fixed).
    jacobi
        Equations in ``tau`` equivalent to ``[sQ, sQ] = 0`` for a matrix ``Q``.

    Returns
    -------
    (status, fields)
        ``"found"``, ``"no_jacobi_solution"`` (with a certificate) or ``"jacobi_unsolved"``,
        and the :class:`~poissonkit.structure.hamiltonize_result.HamiltonizeResult` fields.
    """
    names, ints = list(span), list(span.values())
    m = len(ints)
    taken = {str(x) for x in coords} | {str(t) for t in tau}
    for e in list(ints) + [multiplier, prefactor]:
        taken |= {str(x) for x in sp.sympify(e).free_symbols}
    cs = _coefficient_symbols(m, taken)
    coeffs = [_coefficients(Q, coords) for Q in Qs]
    sols, mults, hams, bases, count = [], [], [], [], 0
    unsolved = False
    for k0 in range(m):
        eqs: list[sp.Expr] = []
        for k in range(k0):
            eqs += list(coeffs[k].values())
        for k in range(k0 + 1, m):
            keys = set(coeffs[k]) | set(coeffs[k0])
            eqs += [coeffs[k].get(key, 0) - cs[k] * coeffs[k0].get(key, 0) for key in keys]
        eqs += jacobi(Qs[k0])
        count += len(eqs)
        unknowns = list(tau) + list(cs[k0 + 1:])
        basis, found = _solve_chart(eqs, unknowns)
        bases.append(basis)
        if not found and basis != (1,):
            unsolved = True
        H0 = ints[k0] + sum((cs[k] * ints[k] for k in range(k0 + 1, m)), sp.Integer(0))
        for sd in found:
            Q = Qs[k0].subs(sd).applyfunc(sp.factor)  # one fraction per entry, readable
            if Q.is_zero_matrix:
                continue
            sols.append(Bivector(tuple(coords), sp.ImmutableMatrix(Q * prefactor)))
            mults.append(multiplier)
            hams.append(sp.expand(H0.subs(sd)))
    params = tuple(tau) + tuple(cs[1:])
    fields = dict(count=count, parameters=params,
                  jacobi_equations=tuple(e for b in bases for e in b if b != (1,)))
    if sols:
        return "found", dict(fields, solutions=tuple(sols), multipliers=tuple(mults),
                             hamiltonians=tuple(hams))
    if unsolved:
        return "jacobi_unsolved", fields
    return "no_jacobi_solution", dict(fields, certificate=Certificate(
        "jacobi", equations=(sp.Integer(1),), text=(
            f"In each of the {m} charts of H = sum c_k I_k over ({', '.join(names)}) (c_k0 = 1, "
            "earlier c_k = 0) the conditions W_k = c_k Q and Jacobi generate the unit ideal "
            "(reduced Groebner basis [1]): no combination of the integrals is the Hamiltonian "
            "of a bracket of the ansatz.")))


def casimir_combinations(P: Bivector, functions: Mapping[str, sp.Expr]
                         ) -> tuple[dict[str, sp.Expr], ...]:
    """A basis of the constant-coefficient combinations of ``functions`` that are Casimirs of
    ``P`` (exact: ``P d(sum d_k F_k) = 0`` split over coordinate monomials, solved for ``d``).

    Parameters
    ----------
    P
        The bivector.
    functions
        ``{name: F_k}``.

    Returns
    -------
    tuple of dict
        One ``{name: d_k}`` per basis vector of the solution space (zero coefficients left
        out; empty if no non-trivial combination is a Casimir). Coefficients may contain the
        parameters of ``P`` (the answer is then generic in them).
    """
    names, fs = list(functions), list(functions.values())
    if not fs:
        return ()
    d = sp.symbols(f"d1:{len(fs) + 1}")
    coords = P.coords
    comb = sum((dk * F for dk, F in zip(d, fs)), sp.Integer(0))
    v = P.matrix * sp.Matrix([sp.diff(comb, x) for x in coords])
    eqs = []
    for e in v:
        num = sp.expand(sp.numer(sp.together(sp.expand(e))))
        if num != 0:
            eqs += list(sp.Poly(num, *coords).as_dict().values())
    if not eqs:
        basis = [sp.Matrix([1 if i == k else 0 for i in range(len(fs))]) for k in range(len(fs))]
    else:
        A, _ = sp.linear_eq_to_matrix(eqs, d)
        basis = A.nullspace()
    out = []
    for vec in basis:
        den = sp.lcm([sp.fraction(sp.together(x))[1] for x in vec])
        out.append({n: sp.factor(sp.cancel(x * den)) for n, x in zip(names, vec)
                    if sp.cancel(x) != 0})
    return tuple(out)
