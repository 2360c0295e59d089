"""The searched space of :func:`~poissonkit.structure.hamiltonize.hamiltonize`: the
:class:`~poissonkit.structure.hamiltonize_problem.Ansatz` built from its keyword arguments and
checked against the problem, and the unknown coefficients (columns) of its linear system.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.hamiltonize_problem import Ansatz, HamiltonizationProblem

__all__ = ["ansatz_columns", "checked_ansatz"]

_POSITION_STEMS = ("gamma", "q", "nu")


def _default_split(coords: Sequence[sp.Symbol]) -> tuple[tuple, tuple]:
    pos = tuple(c for c in coords if str(c).split(".")[-1].split("_")[0] in _POSITION_STEMS)
    if not pos:
        return tuple(coords), ()
    return pos, tuple(c for c in coords if c not in pos)


def _monomials(n: int, idx: Sequence[int], degree: int) -> list[tuple[int, ...]]:
    out = []
    for d in range(degree + 1):
        for combo in itertools.combinations_with_replacement(idx, d):
            e = [0] * n
            for j in combo:
                e[j] += 1
            out.append(tuple(e))
    return out


def _build_ansatz(coords, positions, momenta, degree, momentum_terms, s, zero) -> Ansatz:
    """The :class:`Ansatz` from :func:`~poissonkit.structure.hamiltonize.hamiltonize`'s keyword
    arguments."""
    pos, mom = _default_split(coords)
    if positions is not None:
        pos = tuple(_coord(coords, c) for c in positions)
    if momenta is not None:
        mom = tuple(_coord(coords, c) for c in momenta)
    elif positions is not None:
        mom = tuple(c for c in coords if c not in pos)
    return Ansatz(pos, mom, 1 if degree is None else degree,
                  momentum_terms if mom else "none", s, _zero_pairs(zero, coords, pos, mom))


def ansatz_columns(ansatz: Ansatz, coords, mu_degree: int | None,
                   copies: int = 1) -> list[tuple]:
    """The unknowns: ``("P", i, j, monomial, k)`` (``Q_k^{ij} += u * monomial``, ``i < j``; one
    copy ``Q_k`` per integral of a Hamiltonian span, else ``k = 0``) and, for a multiplier
    ansatz, ``("mu", None, None, monomial, 0)``."""
    n = len(coords)
    pidx = [coords.index(c) for c in ansatz.positions]
    midx = [coords.index(c) for c in ansatz.momenta]
    mono_list = []
    for b in _monomials(n, pidx, ansatz.degree):
        if ansatz.momentum_terms in ("affine", "none") or not midx:
            mono_list.append(b)
        if ansatz.momentum_terms != "none":
            for m in midx:
                e = list(b)
                e[m] += 1
                mono_list.append(tuple(e))
    columns: list[tuple] = []
    for k in range(copies):
        for i in range(n):
            for j in range(i + 1, n):
                if (i, j) not in ansatz.zero:
                    columns.extend(("P", i, j, mono, k) for mono in mono_list)
    if mu_degree is not None:
        columns.extend(("mu", None, None, mono, 0) for mono in _monomials(n, range(n), mu_degree))
    return columns


def _coord(coords, c) -> sp.Symbol:
    for x in coords:
        if x == c or str(x) == str(c):
            return x
    from poissonkit.errors import UnknownNameError

    raise UnknownNameError("coordinate", str(c), [str(x) for x in coords])


def _zero_pairs(zero, coords, pos, mom) -> frozenset:
    if isinstance(zero, str):
        zero = (zero,)
    pairs = set()
    for item in zero:
        if item in ("positions", "momenta"):
            group = [coords.index(c) for c in (pos if item == "positions" else mom)]
            pairs |= {(a, b) for a, b in itertools.combinations(sorted(group), 2)}
        else:
            pairs.add(tuple(item))
    return frozenset(pairs)


def checked_ansatz(problem: HamiltonizationProblem, ansatz: Ansatz | None, multiplier,
                   prefactor, degree: int | None, positions: Sequence | None,
                   momenta: Sequence | None, momentum_terms: str, s: sp.Expr,
                   zero: Sequence) -> Ansatz:
    """The given ``ansatz`` (or one built from the keyword arguments of
    :func:`~poissonkit.structure.hamiltonize.hamiltonize`), checked against ``problem``.

    Raises
    ------
    InputError
        Conflicting arguments, an ansatz coordinate outside the problem, or nothing to search.
    """
    coords = problem.coords
    span = problem.hamiltonian_span
    if isinstance(multiplier, tuple) and span:
        raise InputError("a polynomial multiplier ansatz and a Hamiltonian searched among "
                         "integrals cannot be combined; fix one of them")
    if ansatz is None:
        ansatz = _build_ansatz(coords, positions, momenta, degree, momentum_terms, s, zero)
    elif degree is not None or prefactor is not None:
        raise InputError("give either an Ansatz or degree/prefactor, not both")
    for c in ansatz.positions + ansatz.momenta:
        if c not in coords:
            raise InputError(f"Ansatz coordinate {c} is not a coordinate of the system")
    if problem.hamiltonian is None and not span and not problem.casimir_forms():
        raise InputError("nothing to search for: no Hamiltonian and no Casimirs given")
    return ansatz
