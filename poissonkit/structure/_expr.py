"""Shared input conversion of the symbolic layer: sympy values in, strings never ``sympify``-ed.

``sympy.sympify`` of a string runs ``eval`` on it, so any entry point that accepts "an expression"
must route its argument through :func:`as_expr` (strings are refused with a pointer to
:func:`poissonkit.structure.parsing.parse_expression`, which parses with an allow-list).
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

from poissonkit.errors import InputError, ParseError


def reject_string(value: object, what: str) -> None:
    """Raise :class:`ParseError` if ``value`` is a string (``sympify`` would ``eval`` it)."""
    if isinstance(value, (str, bytes)):
        raise ParseError(f"{what} must be a sympy expression, not a string {value!r:.60}; parse "
                         "strings with poissonkit.structure.parse_expression")


def as_expr(value: object, what: str = "expression") -> sp.Expr:
    """A sympy scalar expression from a non-string value.

    Parameters
    ----------
    value
        A sympy expression or a Python number (``int``, ``float``, ``Fraction``, numpy scalar).
    what
        What the value is, for the error message ("Hamiltonian", "constraint", ...).

    Raises
    ------
    ParseError
        If ``value`` is a string (use ``parse_expression``).
    InputError
        If ``value`` is not convertible to a scalar sympy expression.
    """
    reject_string(value, what)
    try:
        out = sp.sympify(value, strict=True)
    except (sp.SympifyError, TypeError, ValueError):
        raise InputError(f"{what} must be a sympy expression, got {type(value).__name__}") from None
    if not isinstance(out, sp.Expr) or getattr(out, "is_Matrix", False):
        raise InputError(f"{what} must be a scalar expression, got {type(out).__name__}")
    return out


def as_sympy(value: object, what: str = "value") -> sp.Basic:
    """Like :func:`as_expr` but accepting any sympy object (relations, matrices, symbols)."""
    reject_string(value, what)
    if isinstance(value, (list, tuple)):
        return type(value)(as_sympy(v, what) for v in value)
    if isinstance(value, dict):
        return {as_sympy(k, what): as_sympy(v, what) for k, v in value.items()}
    try:
        return sp.sympify(value, strict=True)
    except (sp.SympifyError, TypeError, ValueError):
        raise InputError(f"{what} must be a sympy object, got {type(value).__name__}") from None


def as_symbols(coords: Iterable[sp.Symbol | str]) -> tuple[sp.Symbol, ...]:
    """Coordinate symbols from symbols or names (names become real symbols); no repeats."""
    if isinstance(coords, str):
        raise InputError(f"coordinates must be a sequence of names or symbols, got the string "
                         f"{coords!r}")
    try:
        items = list(coords)
    except TypeError:  # None, a number, ...
        raise InputError(f"coordinates must be a sequence of names or symbols, got "
                         f"{coords!r}") from None
    out = []
    for c in items:
        if isinstance(c, str):
            out.append(sp.Symbol(c, real=True))
        elif isinstance(c, sp.Symbol):
            out.append(c)
        else:
            raise InputError(f"coordinates must be sympy Symbols or names, got {c!r}")
    if len(set(out)) != len(out):
        raise InputError(f"repeated coordinate in {tuple(map(str, out))}")
    return tuple(out)


def as_bivector(P):
    """The :class:`Bivector` of ``P`` (a bivector or a :class:`HamiltonianSystem`)."""
    from poissonkit.structure.bivector import Bivector
    from poissonkit.structure.system import HamiltonianSystem

    if isinstance(P, HamiltonianSystem):
        return P.structure
    if not isinstance(P, Bivector):
        raise InputError(f"expected a Bivector, got {type(P).__name__}")
    return P
