"""Closed-form magnet models: point dipoles and dumbbells (seed 000 eq. (16)).

Each model has a sympy expression ``U(r, c1, c2, c3)`` and a compiled kernel returning
``(U, U_r, U_c1, U_c2, U_c3)`` (SI). Formulas: docs/magnets.md.
"""

from __future__ import annotations

import math
from functools import cache
from typing import TYPE_CHECKING

from numba import njit

from poissonkit.numerics.kernels import inverse_powers4

if TYPE_CHECKING:
    import sympy as sp


@cache
def _symbols() -> tuple[sp.Symbol, sp.Symbol, sp.Symbol, sp.Symbol]:
    # sympy loads on the first expression asked for: a run from compiled kernels never needs it
    import sympy as sp

    return sp.symbols("r c1 c2 c3", real=True)


def __getattr__(name: str) -> sp.Symbol:
    """The coordinates ``R, C1, C2, C3`` of the expressions, made on first use."""
    if name in ("R", "C1", "C2", "C3"):
        return _symbols()[("R", "C1", "C2", "C3").index(name)]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def dipole_strength(moment1: float, moment2: float, mu0: float) -> float:
    """``mu0 m1 m2``, rounded as :func:`dipole_core` rounds it (the folded argument of
    :func:`dipole_core_k`)."""
    return mu0 * moment1 * moment2


def dumbbell_strength(moment1: float, moment2: float, l1: float, l2: float, mu0: float
                      ) -> float:
    """``mu0 (m1/2l1)(m2/2l2)/(4 pi)``, rounded as :func:`dumbbell_core` rounds it (the folded
    argument of :func:`dumbbell_core_k`)."""
    return mu0 * (moment1 / (2.0 * l1)) * (moment2 / (2.0 * l2)) / (4.0 * math.pi)


@njit(cache=True)
def dipole_core(r: float, c1: float, c2: float, c3: float, moment1: float, moment2: float,
                mu0: float) -> tuple[float, float, float, float, float]:
    """Two point dipoles: ``U = mu0 m1 m2 (c3 - 3 c1 c2) / (4 pi r^3)`` and its partials."""
    return dipole_core_k(r, c1, c2, c3, mu0 * moment1 * moment2)


@njit(cache=True)
def dipole_core_k(r: float, c1: float, c2: float, c3: float, strength: float
                  ) -> tuple[float, float, float, float, float]:
    """:func:`dipole_core` with ``strength = mu0 m1 m2`` computed once per pair of magnets
    (what a compiled-in constant gave for free: run-time parameters keep the per-pair cost)."""
    k = strength / (4.0 * math.pi * r ** 3)
    u = k * (c3 - 3.0 * c1 * c2)
    return u, -3.0 * u / r, -3.0 * k * c2, -3.0 * k * c1, k


@njit(cache=True)
def dumbbell_core(r: float, c1: float, c2: float, c3: float, moment1: float, moment2: float,
                  l1: float, l2: float, mu0: float) -> tuple[float, float, float, float, float]:
    """Two dumbbells, charges ``+-mu/(2l)`` at ``+-l nu`` (seed 000 eq. (16)) and partials."""
    kap = mu0 * (moment1 / (2.0 * l1)) * (moment2 / (2.0 * l2)) / (4.0 * math.pi)
    return dumbbell_core_k(r, c1, c2, c3, kap, l1, l2)


@njit(cache=True)
def dumbbell_core_k(r: float, c1: float, c2: float, c3: float, kap: float, l1: float,
                    l2: float) -> tuple[float, float, float, float, float]:
    """:func:`dumbbell_core` with ``kap`` (:func:`dumbbell_strength`) computed once per pair of
    magnets instead of three divisions per call.

    The four pole pairs ``(s1, s2) = (+, +), (+, −), (−, +), (−, −)`` side by side: their
    distances go through one 4-lane square root and division
    (:func:`~poissonkit.numerics.kernels.inverse_powers4`). Every operation is the one of the
    pair-by-pair loop ``rr² = r² + l1² + l2² + 2r(s2 l2 c2 − s1 l1 c1) − 2 s1 s2 l1 l2 c3``,
    ``U += s1 s2/rr``, ... with the signs folded (multiplying by ±1 is exact), summed in the
    same order, so the results are bit for bit those of the loop.
    """
    base = r * r + l1 * l1 + l2 * l2
    a = l2 * c2
    b = l1 * c1
    tr = 2.0 * r
    q = 2.0 * l1 * l2 * c3
    x0 = base + tr * (a - b) - q
    x1 = base + tr * (-a - b) + q
    x2 = base + tr * (a + b) + q
    x3 = base + tr * (-a + b) - q
    q0, q1, q2, q3, i0, i1, i2, i3 = inverse_powers4(x0, x1, x2, x3)
    u = 0.0 + q0 - q1 - q2 + q3
    ur = 0.0 - (r + a - b) * i0 + (r - a - b) * i1 + (r + a + b) * i2 - (r - a + b) * i3
    rl1 = r * l1
    rl2 = r * l2
    ll = l1 * l2
    u1 = 0.0 + rl1 * i0 - rl1 * i1 + rl1 * i2 - rl1 * i3
    u2 = 0.0 - rl2 * i0 - rl2 * i1 + rl2 * i2 + rl2 * i3
    u3 = 0.0 + ll * i0 + ll * i1 + ll * i2 + ll * i3
    return kap * u, kap * ur, kap * u1, kap * u2, kap * u3


def dipole_expr(moment1: float, moment2: float, mu0: float) -> sp.Expr:
    """Sympy ``U`` of two point dipoles."""
    import sympy as sp

    R, C1, C2, C3 = _symbols()
    k = sp.Float(mu0) * sp.Float(moment1) * sp.Float(moment2) / (4 * sp.pi)
    return k * (C3 - 3 * C1 * C2) / R ** 3


def dumbbell_expr(moment1: float, moment2: float, l1: float, l2: float, mu0: float) -> sp.Expr:
    """Sympy ``U`` of two dumbbells (seed 000 eq. (16))."""
    import sympy as sp

    R, C1, C2, C3 = _symbols()
    k1 = sp.Float(moment1) / (2 * sp.Float(l1))
    k2 = sp.Float(moment2) / (2 * sp.Float(l2))
    a, b = sp.Float(l1), sp.Float(l2)
    total = sp.Integer(0)
    for s1 in (1, -1):
        for s2 in (1, -1):
            rr2 = R ** 2 + a ** 2 + b ** 2 + 2 * R * (s2 * b * C2 - s1 * a * C1) - 2 * s1 * s2 * a * b * C3
            total += s1 * s2 / sp.sqrt(rr2)
    return sp.Float(mu0) * k1 * k2 / (4 * sp.pi) * total


def effective_half_length(radius: float, length: float) -> float:
    """Octupole-matched dumbbell half-length ``sqrt(l^2 - 3 a^2 / 4)``, ``l = length/2``.

    Raises
    ------
    ValueError
        If the cylinder is so flat (``length < sqrt(3) radius``) that no dumbbell matches its
        octupole moment (the moment is then negative).
    """
    l = 0.5 * length
    q = l * l - 0.75 * radius * radius
    if not q > 0:
        raise ValueError(
            f"octupole-corrected dumbbell needs length > sqrt(3)*radius (got length={length}, "
            f"radius={radius}); use 'dumbbell' or 'cylinder' for flat magnets")
    return math.sqrt(q)
