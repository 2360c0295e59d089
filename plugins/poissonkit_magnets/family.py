"""The magnet model family: dipole, dumbbells and exact cylinders of one pair of magnets.

Registered through ``poissonkit_model_families``: the planner and ``pair_interaction("auto")``
choose per pair of magnets the cheapest of these models whose estimated force error
(:mod:`poissonkit_magnets.fidelity`, the one estimator) is within the tolerance.

Body attributes read: ``radius`` and ``length`` (full height) of the cylinder, and its strength
``moment`` (or ``magnetization`` with the size). A body without sizes is a point dipole.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from poissonkit.conventions import MU0
from poissonkit.plugin.contributions import ModelFamily
from poissonkit_magnets.fidelity import MODELS_BY_COST, estimated_error, pair_error

#: Relative cost per evaluation, in the order of MODELS_BY_COST (the dumbbells cost the same).
COSTS: tuple[float, ...] = (0.0, 1.0, 1.0, 2.0)
#: The models a scene plans with unless it lists its own.
DEFAULT_MODELS: tuple[str, ...] = ("dipole", "dumbbell", "cylinder")


def _size(body: Mapping[str, Any]) -> tuple[float, float]:
    """``(radius, full height)`` of a body (0 where unknown)."""
    return float(body.get("radius", 0.0) or 0.0), float(body.get("length", 0.0) or 0.0)


def moment(body: Mapping[str, Any]) -> float:
    """Magnetic moment of a body [A m²]: ``moment``, else magnetisation × cylinder volume."""
    mu = body.get("moment")
    if mu is not None:
        return float(mu)
    m = body.get("magnetization")
    a, h = _size(body)
    if m is None or not (a > 0 and h > 0):
        return 0.0
    return float(m) * math.pi * a * a * h


def applies(body1: Mapping[str, Any], body2: Mapping[str, Any]) -> bool:
    """Both bodies are magnets (a positive moment, given or from the magnetisation)."""
    return moment(body1) > 0 and moment(body2) > 0


def estimate(model: str, r: float, body1: Mapping[str, Any], body2: Mapping[str, Any]) -> float:
    """Worst-case relative force error of ``model`` (:func:`fidelity.estimated_error`).

    Cylinders of known size use the estimate as is (``cylinder``: its quadrature accuracy).
    Without sizes only the dipole model is defined: exact for two point magnets, and erring by
    the moments of the sized one otherwise; the other models are not trusted (``inf``).
    """
    a1, h1 = _size(body1)
    a2, h2 = _size(body2)
    if min(a1, h1, a2, h2) > 0:
        return estimated_error(model, r, a1, h1, a2, h2)
    if model not in MODELS_BY_COST:
        estimated_error(model, 1.0, 1.0, 1.0)  # the unknown name raises, listing the models
    if model != "dipole":
        return math.inf
    if not (a1 or h1 or a2 or h2):
        return 0.0
    return pair_error(model, r, a1, h1, a2, h2)


def energy_bound(r: float, body1: Mapping[str, Any], body2: Mapping[str, Any]) -> float:
    """Bound on |U| of two magnets at distance ``r`` in any orientation [J].

    The dipole energy ``k (c3 − 3 c1 c2)/r³``, ``k = μ0 μ1 μ2/(4π)``, is at most ``2k/r³`` in
    modulus (coaxial), and the exact energy differs from it by at most the dipole model's
    relative error: ``|U| ≤ 2k/r³ (1 + ε_dipole(r))``.
    """
    k = MU0 * moment(body1) * moment(body2) / (4 * math.pi)
    return 2.0 * k / r ** 3 * (1.0 + estimate("dipole", r, body1, body2))


MAGNET_FAMILY = ModelFamily(
    name="magnets",
    doc="Uniformly, axially magnetised cylinders: point dipoles far, dumbbells (poles at the "
        "end faces, or octupole-corrected) mid, exact cylinders near; force-error estimate of "
        "docs/magnets.md (multipole mismatch, safety factor 2).",
    models=MODELS_BY_COST,
    costs=COSTS,
    defaults=DEFAULT_MODELS,
    estimate=estimate,
    applies=applies,
    reads=("radius", "length"),
    energy_bound=energy_bound,
)
