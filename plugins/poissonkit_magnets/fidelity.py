"""Model fidelity: how wrong is each cheap magnet model for a pair of cylinders?

The estimates are worst cases over orientations of the relative force error
``|F_model - F_exact| / |F_exact|`` for two uniformly, axially magnetised cylinders (radius ``a``,
full height ``h = 2 l``), against the exact disk model. They follow the multipole analysis of
docs/magnets.md: a model that reproduces the axial moments ``q_n = mu * t_n`` of the cylinder up to
some order errs first by the next moments,

    err ~ C2 D3 / r^2 + C4 D5 / r^4,

where ``D3``, ``D5`` are (sums over both bodies of) the mismatches of ``t_3`` and of
``t_5 + t_3^2`` (the latter from the products of two octupoles), with the measured constants
``C2 = 20/3`` (coaxial; side-by-side 5, T 5/6) and ``C4 = 14``. The series converges only beyond
the sum ``S`` of the bounding-sphere radii ``sqrt(l^2 + a^2)``; the factor ``1/(1 - (S/r)^2)^2``
reproduces the growth of the error towards ``S`` (fitted on coaxial pairs, where it is worst),
and below ``1.05 S`` no cheap model is trusted (infinite estimate: nearly touching end faces need
the exact model). A safety factor of 2 covers the remaining spread; the test suite checks that
the estimate bounds the true force error on a grid of separations, orientations and aspect
ratios (tests/magnets/test_magnets_fidelity.py), and docs/magnets.md lists measured ratios.

Cost order (per evaluation): dipole < dumbbell = dumbbell_octupole << cylinder.
"""

from __future__ import annotations

import math

from poissonkit.errors import InputError, UnknownNameError

#: Models in increasing cost; the dumbbells cost the same.
MODELS_BY_COST: tuple[str, ...] = ("dipole", "dumbbell_octupole", "dumbbell", "cylinder")

C2 = 20.0 / 3.0
C4 = 14.0
SAFETY = 2.0
#: Below this multiple of the summed bounding radii only the exact model is trusted.
NEAR_LIMIT = 1.05
#: Nominal accuracy of the exact cylinder quadrature with default nodes (docs/magnets.md).
CYLINDER_ERROR = 1e-9


def _check_size(name: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not (v > 0 and math.isfinite(v)):
        raise InputError(f"{name} must be positive and finite, got {value!r}")
    return v


def _moments(model: str, a: float, h: float) -> tuple[float, float, float, float]:
    """``(t3, t5, t3_model, t5_model)``: normalised axial moments q_n/mu of the cylinder and
    of the model body."""
    l = 0.5 * h
    t3 = l * l - 0.75 * a * a
    t5 = l ** 4 - 2.5 * l * l * a * a + 0.625 * a ** 4
    if model == "dipole":
        return t3, t5, 0.0, 0.0
    if model == "dumbbell":
        return t3, t5, l * l, l ** 4
    if model == "dumbbell_octupole":
        if t3 <= 0:
            return t3, t5, math.nan, math.nan
        return t3, t5, t3, t3 * t3
    raise UnknownNameError("magnet model", model, MODELS_BY_COST)


def estimated_error(model: str, r: float, radius: float, length: float,
                    radius2: float | None = None, length2: float | None = None) -> float:
    """Estimated worst-case relative force error of ``model`` for two cylinders.

    Parameters
    ----------
    model
        ``"dipole"``, ``"dumbbell"`` (poles at the end faces, ``l = h/2``),
        ``"dumbbell_octupole"`` or ``"cylinder"``.
    r
        Centre distance (m).
    radius, length
        Radius and full height of cylinder 1 (m); also of cylinder 2 unless ``radius2`` /
        ``length2`` are given.

    Returns
    -------
    float
        Estimated ``|dF|/|F|`` (worst over orientations); ``inf`` where the model is not
        trusted (nearly touching, or ``dumbbell_octupole`` for flat cylinders with
        ``h <= sqrt(3) a``).
    """
    r = _check_size("r", r)
    a1 = _check_size("radius", radius)
    h1 = _check_size("length", length)
    a2 = a1 if radius2 is None else _check_size("radius2", radius2)
    h2 = h1 if length2 is None else _check_size("length2", length2)
    return pair_error(model, r, a1, h1, a2, h2)


def pair_error(model: str, r: float, a1: float, h1: float, a2: float, h2: float) -> float:
    """:func:`estimated_error` without argument checks; a size of 0 is allowed.

    A body of zero radius and length is a point dipole (all its higher moments vanish), so
    the dipole model of two point magnets is exact (0) and that of a point magnet and a
    cylinder errs by the cylinder's moments alone.
    """
    if model == "cylinder":
        return CYLINDER_ERROR
    s = math.hypot(0.5 * h1, a1) + math.hypot(0.5 * h2, a2)
    if r <= NEAR_LIMIT * s:
        _moments(model, a1, h1)  # still reject unknown names
        return math.inf
    d3 = 0.0
    d5 = 0.0
    for a, h in ((a1, h1), (a2, h2)):
        t3, t5, m3, m5 = _moments(model, a, h)
        if math.isnan(m3):
            return math.inf
        d3 += 0.5 * abs(t3 - m3)
        d5 += 0.5 * (abs(t5 - m5) + abs(t3 * t3 - m3 * m3))
    x2 = (s / r) ** 2
    base = C2 * d3 / r ** 2 + C4 * d5 / r ** 4
    return SAFETY * base / (1.0 - x2) ** 2


def cheapest_model(tol: float, r: float, radius: float, length: float,
                   radius2: float | None = None, length2: float | None = None) -> str:
    """The cheapest model whose :func:`estimated_error` is within ``tol``.

    Returns ``"cylinder"`` when no cheap model qualifies (the exact model is always allowed).
    Between the two equally cheap dumbbells the more accurate one is preferred.
    """
    try:
        tol = float(tol)
    except (TypeError, ValueError):
        raise InputError(f"tol must be a number, got {tol!r}") from None
    if not (tol > 0 and math.isfinite(tol)):
        raise InputError(f"tol must be positive and finite, got {tol!r}")
    if estimated_error("dipole", r, radius, length, radius2, length2) <= tol:
        return "dipole"
    best = min(("dumbbell_octupole", "dumbbell"),
               key=lambda m: estimated_error(m, r, radius, length, radius2, length2))
    if estimated_error(best, r, radius, length, radius2, length2) <= tol:
        return best
    return "cylinder"
