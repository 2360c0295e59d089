"""The model-fidelity planner: one import path for its three parts.

* :mod:`poissonkit.scene.planner.choice` — :class:`Planner`, the per-pair choice of the cheapest
  model of a registered model family within a force tolerance (hysteresis, cutoff, point masses).
* :mod:`poissonkit.scene.planner.plans` — what a plan holds: :class:`Plan`, :class:`PairPlan`,
  :class:`DroppedPair`, :class:`Switch`, and :class:`PlannerError`.
* :mod:`poissonkit.scene.planner.run` — :func:`run_planned`, the integration loop that re-plans
  every ``replan_every`` steps, and its result :class:`PlannedRun`.
"""

from poissonkit.scene.planner.choice import (CUTOFF_HYSTERESIS, Planner, body_attributes,
                                             estimated_error, family_of)
from poissonkit.scene.planner.run import PlannedRun, run_planned
from poissonkit.scene.planner.plans import DroppedPair, PairPlan, Plan, PlannerError, Switch

__all__ = [
    "CUTOFF_HYSTERESIS", "DroppedPair", "PairPlan", "Plan", "PlannedRun", "Planner",
    "PlannerError", "Switch", "body_attributes", "estimated_error", "family_of", "run_planned",
]
