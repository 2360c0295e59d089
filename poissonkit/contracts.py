"""The contracts between poissonkit's layers, as :class:`typing.Protocol` classes.

Each concept that one layer hands to another (a numerics system, its compiled kernels, an
integrator, a sweep scene, a model family) is declared here once. Code that dispatches on a
contract uses ``isinstance`` with a ``runtime_checkable`` protocol, never ``hasattr`` probes;
what an integrator *can* do (checkpoint, stream, events, ...) is declared on its registry entry
(:class:`poissonkit.plugin.contributions.IntegratorEntry`), not discovered.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, runtime_checkable

# --------------------------------------------------------------------------- numerics systems

# --------------------------------------------------------------------------- integrators

# --------------------------------------------------------------------------- model families


@runtime_checkable
class ErrorEstimator(Protocol):
    """A model family's error estimate (:attr:`poissonkit.plugin.ModelFamily.estimate`).

    ``estimator(model, r, body1, body2)``: estimated worst-case relative force error of the
    registered potential ``model`` for two bodies, given as attribute mappings (``radius``,
    ``length``, ``moment``, ... as the family declares in ``reads``), at centre distance
    ``r`` [m]; ``inf`` where the model is not trusted. Non-increasing in ``r``.
    """

    def __call__(self, model: str, r: float, body1: Mapping[str, Any],
                 body2: Mapping[str, Any]) -> float: ...


# --------------------------------------------------------------------------- sweep scenes
