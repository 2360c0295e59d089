"""The one random-point sampler and zero test of the randomized symbolic checks.

Every randomized check of :mod:`poissonkit.structure` (the Jacobi identity at random points,
:func:`~poissonkit.structure.jacobi.check_jacobi` with ``method="random"``; the field checks at
random rational points, :class:`~poissonkit.structure.randompoints.RandomPoints`; the generic
rank, :func:`~poissonkit.structure.casimirs.rank`) draws its values here.

The sampler
-----------
A value is an integer ``p`` uniform in ``[-SAMPLE_RANGE, SAMPLE_RANGE]`` (in ``[1,
SAMPLE_RANGE]`` or ``[-SAMPLE_RANGE, -1]`` for a symbol that must be positive or negative),
used as ``p`` or as the rational ``p / SAMPLE_RANGE``. Draws are reproducible and independent
of the order in which symbols are met: the value of a key (a symbol's name) at point ``index``
comes from a generator seeded by ``(seed, index, key)``. A ``seed`` of ``None`` is a fresh seed
from the operating system, kept in :attr:`Sampler.seed` so that a run can be reproduced.

The false-positive probability
------------------------------
If a rational function ``E`` is not identically zero and its cleared numerator has total degree
``<= D`` in the sampled variables, then ``E`` vanishes at one sampled point with probability at
most ``D * m``, where ``m`` is the largest probability of a single value of one variable
(Schwartz–Zippel, in its form for independent variables with bounded point masses):
``m = 1/(2 SAMPLE_RANGE + 1)`` for signed draws, ``1/SAMPLE_RANGE`` when some draws are
sign-restricted. ``t`` independent points all pass with probability at most ``(D m)**t``
(:func:`false_positive_bound`). With ``SAMPLE_RANGE = 10**6`` a Jacobiator of degree 100
passes three points with probability below ``1.3e-13``.

The zero test
-------------
At a point, values are exact: rationals, or exact sums of products of square roots
(:class:`~poissonkit.structure.surds.Surd`, or sympy numbers). :func:`is_zero_at_point`
decides zero exactly (no floating point), so a non-zero value is a genuine counterexample.
"""

from __future__ import annotations

import random
from fractions import Fraction
from typing import Protocol

import sympy as sp

__all__ = ["SAMPLE_RANGE", "PointStream", "Sampler", "false_positive_bound",
           "false_positive_fraction", "is_zero_at_point"]

#: Half-width of the sample set: integers ``p`` with ``|p| <= SAMPLE_RANGE``.
SAMPLE_RANGE: int = 10**6


class ExactValue(Protocol):
    """A value at a point that knows whether it is zero (``bool(v)`` is ``v != 0``, exactly)."""

    def __bool__(self) -> bool: ...


class Sampler:
    """Seeded, reproducible random values of named variables at numbered points.

    Parameters
    ----------
    seed
        Seed (``None``: a fresh one from the operating system, stored in :attr:`seed`).

    Examples
    --------
    >>> s = Sampler(1)
    >>> s.integer("x", 0) == Sampler(1).integer("x", 0)
    True
    >>> abs(s.rational("x", 0)) <= 1
    True
    """

    def __init__(self, seed: int | None = None) -> None:
        self.seed: int = seed if seed is not None else random.SystemRandom().randrange(2**32)

    def __repr__(self) -> str:
        return f"Sampler(seed={self.seed})"

    def integer(self, key: str, index: int, sign: int = 0) -> int:
        """The integer of ``key`` at point ``index``: uniform in ``[-SAMPLE_RANGE,
        SAMPLE_RANGE]`` (``sign > 0``: in ``[1, SAMPLE_RANGE]``; ``sign < 0``: its negative)."""
        rng = random.Random(f"{self.seed}/{index}/{key}")
        if sign > 0:
            return rng.randint(1, SAMPLE_RANGE)
        if sign < 0:
            return -rng.randint(1, SAMPLE_RANGE)
        return rng.randint(-SAMPLE_RANGE, SAMPLE_RANGE)

    def rational(self, key: str, index: int, sign: int = 0) -> sp.Rational:
        """``integer(key, index, sign) / SAMPLE_RANGE`` as an exact sympy rational."""
        return sp.Rational(self.integer(key, index, sign), SAMPLE_RANGE)


class PointStream:
    """Successive random points of one :class:`Sampler`: call :meth:`next_point`, then read
    values by key (point ``k`` of the stream is point ``k`` of the sampler).

    Parameters
    ----------
    sampler
        The sampler (its seed makes the stream reproducible).
    """

    def __init__(self, sampler: Sampler) -> None:
        self.sampler, self.index = sampler, -1

    def next_point(self) -> None:
        """Move to the next point."""
        self.index += 1

    def value(self, key: str) -> sp.Rational:
        """The rational ``p / SAMPLE_RANGE`` of ``key`` at the current point."""
        return self.sampler.rational(key, self.index)


def false_positive_fraction(degree: int, trials: int, *, signed: bool = True) -> Fraction:
    """Exact Schwartz–Zippel bound ``min(1, degree * m)**trials`` (see the module docstring;
    ``m = 1/(2 SAMPLE_RANGE + 1)`` for signed draws, ``1/SAMPLE_RANGE`` otherwise)."""
    mass = Fraction(1, 2 * SAMPLE_RANGE + 1) if signed else Fraction(1, SAMPLE_RANGE)
    return min(Fraction(1), degree * mass) ** trials


def false_positive_bound(degree: int, trials: int, *, signed: bool = True) -> float:
    """:func:`false_positive_fraction` in floating point (probability that a non-zero
    expression of cleared degree ``<= degree`` vanishes at ``trials`` independent points)."""
    per_point = degree / (2 * SAMPLE_RANGE + 1) if signed else degree * (1.0 / SAMPLE_RANGE)
    return min(1.0, per_point) ** trials


def is_zero_at_point(value: sp.Expr | ExactValue | int) -> bool:
    """Exact zero test of a value at a point.

    A sympy number (rationals and square roots of rationals) is zero iff its expansion is
    ``0``: sympy writes products of square roots of rationals over square-free integers, which
    are linearly independent over ``Q``. Any other exact value (a rational, a
    :class:`~poissonkit.structure.surds.Surd`) is zero iff it is falsy.
    """
    if isinstance(value, sp.Basic):
        return sp.expand(value) == 0
    return not value
