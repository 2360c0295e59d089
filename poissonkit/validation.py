"""Checks of user-given numbers, shared by every layer: one message per kind of mistake.

Each function returns the value in its canonical Python form or raises
:class:`~poissonkit.errors.InputError` naming what was wrong (``what`` is how the caller names
the input, e.g. ``"body 'a': mass"`` or ``"Scales.length"``). ``bool`` is refused wherever a
number is expected: ``True`` is an ``int`` to Python, never a length to a user.
"""

from __future__ import annotations

import math

import numpy as np

from poissonkit.errors import InputError

__all__ = ["count", "finite_number", "positive_number", "vector3"]


def _real(value: object, what: str, kind: str) -> float:
    """``float(value)`` for a real number (not a bool), else :class:`InputError`."""
    if isinstance(value, (bool, np.bool_)):
        raise InputError(f"{what} must be {kind}, got {value!r}")
    try:
        return float(value)  # type: ignore[arg-type]  # anything float() takes is welcome
    except (TypeError, ValueError, OverflowError):  # OverflowError: an int like 10**400
        raise InputError(f"{what} must be {kind}, got {value!r}") from None


def finite_number(value: object, what: str) -> float:
    """``value`` as a finite float.

    Raises
    ------
    InputError
        If ``value`` is not a real number, or is infinite or NaN.
    """
    v = _real(value, what, "a number")
    if not math.isfinite(v):
        raise InputError(f"{what} must be finite, got {value!r}")
    return v


def positive_number(value: object, what: str) -> float:
    """``value`` as a finite float ``> 0``.

    Raises
    ------
    InputError
        If ``value`` is not a real number, or is not positive and finite.
    """
    v = _real(value, what, "a number")
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{what} must be positive and finite, got {value!r}")
    return v


def count(value: object, what: str, low: int = 0) -> int:
    """``value`` as an ``int >= low`` (numpy integers accepted, floats and bools not).

    Raises
    ------
    InputError
        If ``value`` is not an integer or is below ``low``.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{what} must be an integer, got {value!r}")
    if value < low:
        raise InputError(f"{what} must be at least {low}, got {value!r}")
    return int(value)


def vector3(value: object, what: str) -> np.ndarray:
    """``value`` as a finite float array of shape ``(3,)``.

    Raises
    ------
    InputError
        If ``value`` is not three finite real numbers.
    """
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a 3-vector of numbers, got {value!r}") from None
    # three scalar tests: np.all costs ~15 µs a call, and scenes check 10⁶ vectors
    if v.shape != (3,) or not (math.isfinite(v[0]) and math.isfinite(v[1])
                               and math.isfinite(v[2])):
        raise InputError(f"{what} must be a finite 3-vector, got {value!r}")
    return v
