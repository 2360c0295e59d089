"""Shared helpers of the non-holonomic systems: exact parameters, vectors, the eps-matrix.

Conventions: :mod:`poissonkit.conventions` (``xdot = N P dH``); the survey's body-frame systems
read ``X = -g^{-1} P_g dH``, i.e. they are declared with ``multiplier = -1/g``.
"""

from __future__ import annotations

from fractions import Fraction
from numbers import Real
from collections.abc import Sequence
from typing import Union

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.blocks import eps_matrix
from poissonkit.structure.checks import CheckResult

#: A physical parameter: an exact or float number, or a sympy expression (a symbol keeps it
#: symbolic).
Scalar = Union[int, float, Fraction, sp.Expr]
#: A vector parameter: three scalars.
Triple = Union[Sequence[Scalar], sp.Matrix]

__all__ = ["block", "cross", "dot", "eps_matrix", "exact", "gamma_M", "positive", "vec"]


def exact(value: Scalar, name: str = "parameter") -> sp.Expr:
    """An exact sympy number (or keep a sympy expression / symbol as it is).

    Floats are read through their shortest decimal representation, so ``0.3 -> 3/10``.

    Raises
    ------
    InputError
        If the value is neither a real number nor a sympy expression, or is not finite.
    """
    if isinstance(value, sp.Basic):
        return value
    if isinstance(value, bool):
        raise InputError(f"{name} must be a number, got {value!r}")
    if isinstance(value, int):
        return sp.Integer(value)
    if isinstance(value, Fraction):
        return sp.Rational(value.numerator, value.denominator)
    if isinstance(value, Real):
        f = float(value)
        if f != f or f in (float("inf"), float("-inf")):
            raise InputError(f"{name} must be finite, got {value!r}")
        return sp.Rational(repr(f))
    raise InputError(f"{name} must be a number or a sympy expression, got {value!r}")


def positive(value: Scalar, name: str) -> sp.Expr:
    """:func:`exact`, and reject numbers that are not > 0 (symbols pass)."""
    v = exact(value, name)
    if v.is_number and not v > 0:
        raise InputError(f"{name} must be > 0, got {value!r}")
    return v


def vec(name: str) -> tuple[sp.Symbol, sp.Symbol, sp.Symbol]:
    """Three real symbols ``name_x, name_y, name_z``."""
    return sp.symbols(f"{name}_x {name}_y {name}_z", real=True)


def gamma_M(second: str = "M") -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
    """The survey's coordinates: ``gamma`` and the momentum-like vector (``M``, ``K``, ...)."""
    return vec("gamma"), vec(second)


def dot(a, b) -> sp.Expr:
    """``(a, b)``."""
    return sum(x * y for x, y in zip(a, b))


def cross(a, b) -> list[sp.Expr]:
    """``a x b``."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def block(top_left, top_right, bottom_left, bottom_right) -> sp.Matrix:
    """The 6x6 matrix ``[[TL, TR], [BL, BR]]`` of 3x3 blocks."""
    m = sp.zeros(6, 6)
    m[0:3, 0:3] = sp.Matrix(top_left)
    m[0:3, 3:6] = sp.Matrix(top_right)
    m[3:6, 0:3] = sp.Matrix(bottom_left)
    m[3:6, 3:6] = sp.Matrix(bottom_right)
    return m


def three(values: Triple, name: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Three exact components of a parameter vector."""
    try:
        items = list(values)
    except TypeError:
        raise InputError(f"{name} must be a 3-vector, got {values!r}") from None
    if len(items) != 3:
        raise InputError(f"{name} must have 3 components, got {len(items)}")
    return tuple(exact(v, f"{name}[{i}]") for i, v in enumerate(items))  # type: ignore[return-value]


def euler_bivector(field, coords, momenta, hamiltonian) -> sp.Matrix:
    """The rank-2 bivector ``P = X ^ Z / Z(H)`` with ``Z = sum_p p d/dp`` (Euler field in momenta).

    If ``X(H) = 0`` then ``P dH = (X Z(H) - Z X(H)) / Z(H) = X`` exactly. ``P`` is Poisson iff
    ``[Z, X]`` lies in ``span(X, Z)``; this holds when the momentum components of ``X`` are
    homogeneous quadratic and the others linear in the momenta (``[Z, X] = X``, inertial motion),
    and generally fails with a potential.
    """
    n = len(coords)
    Z = [c if c in momenta else sp.Integer(0) for c in coords]
    ZH = sum(z * sp.diff(hamiltonian, c) for z, c in zip(Z, coords))
    P = sp.zeros(n, n)
    for i in range(n):
        for j in range(i + 1, n):
            P[i, j] = (field[i] * Z[j] - Z[i] * field[j]) / ZH
            P[j, i] = -P[i, j]
    return P


def claim_outcome(res: CheckResult, method: str) -> tuple[bool, str, str]:
    """``(holds, detail, method)`` of a claim checked by a core check (a ``CheckResult``).

    A failure's detail names the first failing component, its value and, for the random-point
    method, the exact counterexample point.
    """
    if res.holds:
        return True, "", method
    label, value = res.failures[0]
    point = res.point or {}
    at = ", ".join(f"{k} = {v}" for k, v in point.items())
    return False, (f"component {label} = {str(value)[:120]}" + (f" at {at}" if at else ""))[:400], \
        method

