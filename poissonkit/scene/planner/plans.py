"""What a plan holds: the model of each planned pair, the dropped pairs, and model switches.

Produced by :class:`poissonkit.scene.planner.choice.Planner` and
:func:`poissonkit.scene.planner.run.run_planned`; each has a JSON-ready ``report()``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from poissonkit.errors import InputError


class PlannerError(InputError):
    """The planner was configured or used wrongly (unknown model, bad tolerance, ...)."""


@dataclass(frozen=True)
class PairPlan:
    """The model of one planned pair at the time of planning."""

    i: int
    j: int
    model: str
    distance: float
    estimated_error: float


@dataclass(frozen=True)
class DroppedPair:
    """A pair left out of the system: ``reason`` is ``"cutoff"`` or ``"fixed"``."""

    i: int
    j: int
    distance: float
    reason: str
    energy_bound: float = 0.0


@dataclass(frozen=True)
class Plan:
    """Which model each pair uses, what was dropped, and which tops became point masses."""

    tol: float
    names: tuple[str, ...]
    pairs: tuple[PairPlan, ...]
    dropped: tuple[DroppedPair, ...]
    point_masses: tuple[str, ...] = ()
    constant_rotational_energy: float = 0.0
    unplanned: int = 0

    @property
    def neglected_energy_bound(self) -> float:
        """Sum of the bounds on the energy of the pairs dropped by the cutoff [J]."""
        return math.fsum(d.energy_bound for d in self.dropped if d.reason == "cutoff")

    def counts(self) -> dict[str, int]:
        """How many planned pairs use each model (dropped pairs under ``"dropped"``)."""
        out: dict[str, int] = {}
        for p in self.pairs:
            out[p.model] = out.get(p.model, 0) + 1
        out["dropped"] = sum(1 for d in self.dropped if d.reason == "cutoff")
        return out

    def model_of(self, i: int, j: int) -> str | None:
        """Model of pair (i, j) (``None`` if it is not planned or dropped)."""
        for p in self.pairs:
            if (p.i, p.j) == (min(i, j), max(i, j)):
                return p.model
        return None

    def report(self) -> dict[str, Any]:
        """A JSON-ready summary: counts, point masses, dropped pairs and the energy bound."""
        return {
            "tol": self.tol,
            "models": self.counts(),
            "pairs": [{"bodies": [self.names[p.i], self.names[p.j]], "model": p.model,
                       "distance_m": p.distance, "estimated_error": p.estimated_error}
                      for p in self.pairs],
            "unplanned_pairs": self.unplanned,
            "point_masses": list(self.point_masses),
            "constant_rotational_energy_J": self.constant_rotational_energy,
            "dropped_fixed_pairs": sum(1 for d in self.dropped if d.reason == "fixed"),
            "dropped_cutoff_pairs": sum(1 for d in self.dropped if d.reason == "cutoff"),
            "neglected_energy_bound_J": self.neglected_energy_bound,
        }


@dataclass(frozen=True)
class Switch:
    """A pair changed model at time ``t`` [s]; ``energy_jump`` = U_new − U_old of the pair [J]."""

    t: float
    i: int
    j: int
    bodies: tuple[str, str]
    old: str
    new: str
    distance: float
    energy_jump: float
