"""Model only what a scene needs: per-pair choice of the cheapest adequate magnet model.

Given a force tolerance ``tol``, each pair of cylindrical magnets gets the cheapest model whose
estimated error is within ``tol`` — far: ``dipole``, mid: ``dumbbell`` (or
``dumbbell_octupole``), near: the exact ``cylinder`` — and the choice is re-checked as the
distances change (:func:`run_planned` re-plans every ``replan_every`` steps).

Error estimates
---------------
The estimate of a model for a pair at centre distance ``r`` is, when the magnets plugin is
installed, :func:`poissonkit_magnets.fidelity.estimated_error` (worst case over orientations of
the relative force error, safety factor 2). Otherwise the built-in estimate
:func:`builtin_estimate` is used:

    err = [C3 (D3_i + D3_j)/2 / r² + C5 (D5_i + D5_j)/2 / r⁴] / (1 − (ρ/r)²)²,

with ``D3``, ``D5`` the mismatches of the normalised axial moments ``q3/μ = l² − 3a²/4`` and
``q5/μ = l⁴ − 5/2 l²a² + 5/8 a⁴`` of each cylinder (radius ``a``, half-height ``l``) between the
model and the cylinder, ``ρ`` the sum of the bounding radii ``sqrt(l² + a²)``, ``C3 = 10``,
``C5 = 30`` and no cheap model trusted for ``r ≤ ρ``. Both are checked against the exact disk
model in ``tests/scene/test_scene_planner.py`` (force *and* torque errors, relative to the
larger of the exact value and the dipole scale, over coaxial, side-by-side, T and random
configurations and several aspect ratios).

Switching and hysteresis
------------------------
A pair keeps its model while the model's estimate stays within ``tol``. It moves to a cheaper
model only when that one is within ``(1 − hysteresis) tol``, and to a more accurate one (the
cheapest within ``(1 − hysteresis) tol``) as soon as its current estimate exceeds ``tol``. So a
pair oscillating about a threshold does not switch back and forth. Each switch changes the
Hamiltonian: :func:`run_planned` records the energy jump ``U_new − U_old`` of the pair at the
switch (and the jump of the total energy, their sum).

What else the plan does
-----------------------
* **Point masses.** A top none of whose kept pairs depends on its axis (e.g. only gravity, or a
  non-magnetic body) becomes a point mass: its axis and angular momentum leave the state (its
  free rotation is decoupled; its rotational energy ``α|m|²/2`` is constant and reported).
* **Fixed bodies** carry no degrees of freedom (``NBodySystem`` gets them as fixed bodies);
  pairs of two fixed bodies are dropped (constant energy, no force on anything that moves).
* **Cutoff.** Magnet pairs farther apart than ``cutoff`` are dropped. The neglected energy of
  a dropped pair is bounded by ``|U| ≤ 2 k / r³ (1 + ε_dip(r))``, ``k = μ0 μ_i μ_j / (4π)``: the
  dipole energy ``k (c3 − 3 c1 c2)/r³`` is at most ``2k/r³`` in modulus (coaxial), and the exact
  energy differs from the dipole one by at most the dipole model's relative error ``ε_dip``
  (the same estimate as above). Central (orientation-free) pairs beyond the cutoff are dropped
  with their exact ``|U(r)|``; other pairs are never dropped. The plan reports the sum of the
  bounds, re-evaluated at every re-plan. Dropped pairs come back when they are within the cutoff
  again (a pair is dropped only beyond ``1.05 cutoff`` once kept).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from poissonkit.conventions import MU0
from poissonkit.errors import InputError, UnknownNameError

#: The models the planner knows, cheapest first; the dumbbells cost the same.
KNOWN_MODELS: tuple[str, ...] = ("dipole", "dumbbell_octupole", "dumbbell", "cylinder")
#: Cost class of each model (only the order matters for the choice).
COST_RANK: dict[str, int] = {"dipole": 0, "dumbbell": 1, "dumbbell_octupole": 1, "cylinder": 2}
C3 = 10.0
C5 = 30.0
#: Once kept, a pair is dropped only beyond this multiple of the cutoff.
CUTOFF_HYSTERESIS = 1.05


class PlannerError(InputError):
    """The planner was configured or used wrongly (unknown model, bad tolerance, ...)."""


# ---------------------------------------------------------------------------- estimates

def _axial(a: float, l: float) -> tuple[float, float]:
    """Normalised axial moments q3/μ, q5/μ of a uniformly magnetised cylinder."""
    return l * l - 0.75 * a * a, l ** 4 - 2.5 * l * l * a * a + 0.625 * a ** 4


def _model_moments(model: str, a: float, l: float) -> tuple[float, float]:
    t3, _ = _axial(a, l)
    if model == "dipole":
        return 0.0, 0.0
    if model == "dumbbell":
        return l * l, l ** 4
    if model == "dumbbell_octupole":
        return (t3, t3 * t3) if t3 > 0 else (math.nan, math.nan)
    if model == "cylinder":
        return _axial(a, l)
    raise UnknownNameError("planner model", model, KNOWN_MODELS)


def builtin_estimate(model: str, r: float, a1: float, l1: float, a2: float, l2: float) -> float:
    """Built-in worst-case relative force/torque error of ``model`` (module docstring)."""
    if model == "cylinder":
        return 0.0
    rho = math.hypot(a1, l1) + math.hypot(a2, l2)
    d3 = d5 = 0.0
    for a, l in ((a1, l1), (a2, l2)):
        m3, m5 = _model_moments(model, a, l)
        if math.isnan(m3):
            return math.inf
        t3, t5 = _axial(a, l)
        d3 += 0.5 * abs(t3 - m3)
        d5 += 0.5 * abs(t5 - m5)
    if d3 == 0.0 and d5 == 0.0:
        return 0.0  # point magnets: the model is exact
    if r <= rho:
        return math.inf
    return (C3 * d3 / r ** 2 + C5 * d5 / r ** 4) / (1.0 - (rho / r) ** 2) ** 2


def _fidelity():
    try:
        from poissonkit_magnets import fidelity
    except ImportError:
        return None
    return fidelity if hasattr(fidelity, "estimated_error") else None


def estimated_error(model: str, r: float, body1: Mapping[str, float], body2: Mapping[str, float],
                    source: str = "auto") -> float:
    """Estimated relative error of ``model`` for two magnets at centre distance ``r`` [m].

    Parameters
    ----------
    model
        ``"dipole"``, ``"dumbbell"``, ``"dumbbell_octupole"`` or ``"cylinder"``.
    body1, body2
        Magnet parameters (``radius``, ``half_length``; a magnet without them is a point
        dipole, for which the dipole model is exact).
    source
        ``"auto"`` (the magnets plugin's fidelity module if installed, else the built-in),
        ``"magnets"`` or ``"builtin"``.
    """
    if model not in KNOWN_MODELS:
        raise UnknownNameError("planner model", model, KNOWN_MODELS)
    a1, l1 = body1.get("radius", 0.0), body1.get("half_length", 0.0)
    a2, l2 = body2.get("radius", 0.0), body2.get("half_length", 0.0)
    sized = min(a1, l1, a2, l2) > 0
    if not sized:
        if model == "dipole" and not (a1 or l1 or a2 or l2):
            return 0.0
        if model == "dipole":
            return builtin_estimate(model, r, a1, l1, a2, l2)
        return math.inf  # the other models need the magnet's size
    fid = _fidelity() if source in ("auto", "magnets") else None
    if source == "magnets" and fid is None:
        raise PlannerError("the magnets plugin's fidelity module is not available")
    if fid is not None:
        if model == "cylinder":
            return float(fid.CYLINDER_ERROR) if hasattr(fid, "CYLINDER_ERROR") else 0.0
        return float(fid.estimated_error(model, r, a1, 2 * l1, a2, 2 * l2))
    return builtin_estimate(model, r, a1, l1, a2, l2)


# ---------------------------------------------------------------------------- plan objects

@dataclass(frozen=True)
class PairPlan:
    """The model of one planned magnet pair at the time of planning."""

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


# ---------------------------------------------------------------------------- planner

def _is_magnet(body: Any) -> bool:
    return body.magnet.get("moment", 0.0) > 0


@dataclass(frozen=True)
class Planner:
    """Chooses per pair the cheapest magnet model within a force tolerance.

    Parameters
    ----------
    tol
        Relative force (and torque) tolerance of each pair's model.
    models
        Candidate potentials (subset of ``dipole``, ``dumbbell``, ``dumbbell_octupole``,
        ``cylinder``); a pair for which none is within ``tol`` gets the most accurate one.
    hysteresis
        In [0, 1): a cheaper model must be within ``(1 − hysteresis) tol`` to be switched to.
    cutoff
        Magnet pairs farther apart are dropped [m] (``None``: never).
    replan_every
        Steps between re-plans in :func:`run_planned`.
    estimate
        ``"auto"``, ``"magnets"`` or ``"builtin"`` (see :func:`estimated_error`).
    """

    tol: float
    models: tuple[str, ...] = ("dipole", "dumbbell", "cylinder")
    hysteresis: float = 0.5
    cutoff: float | None = None
    replan_every: int = 100
    estimate: str = "auto"

    def __post_init__(self) -> None:
        if not (isinstance(self.tol, (int, float)) and math.isfinite(self.tol) and self.tol > 0):
            raise PlannerError(f"planner tol must be a positive number, got {self.tol!r}")
        models = tuple(self.models)
        if not models:
            raise PlannerError("planner needs at least one model")
        for m in models:
            if m not in KNOWN_MODELS:
                raise UnknownNameError("planner model", m, KNOWN_MODELS)
        object.__setattr__(self, "models", tuple(sorted(models, key=lambda m: COST_RANK[m])))
        if not 0 <= self.hysteresis < 1:
            raise PlannerError(f"hysteresis must be in [0, 1), got {self.hysteresis!r}")
        if self.cutoff is not None and not self.cutoff > 0:
            raise PlannerError(f"cutoff must be > 0, got {self.cutoff!r}")
        if int(self.replan_every) < 1:
            raise PlannerError(f"replan_every must be >= 1, got {self.replan_every!r}")
        if self.estimate not in ("auto", "magnets", "builtin"):
            raise PlannerError(f"estimate must be 'auto', 'magnets' or 'builtin', got "
                               f"{self.estimate!r}")
        # caches (not part of the value): thresholds per (model, geometry, limit) and resolved
        # pair parameters, so re-planning thousands of pairs costs O(1) per pair
        object.__setattr__(self, "_thresholds", {})
        object.__setattr__(self, "_specs", {})

    def threshold(self, model: str, limit: float, body1: Mapping[str, float],
                  body2: Mapping[str, float]) -> float:
        """Smallest distance [m] beyond which ``model``'s estimate stays within ``limit``.

        The estimates decrease with distance, so ``estimated_error(model, r) <= limit`` iff
        ``r >= threshold`` (found by bisection once per model, geometry and limit, then cached).
        """
        geom = (body1.get("radius", 0.0), body1.get("half_length", 0.0),
                body2.get("radius", 0.0), body2.get("half_length", 0.0))
        key = (model, limit, geom)
        hit = self._thresholds.get(key)  # type: ignore[attr-defined]
        if hit is not None:
            return hit
        size = max(math.hypot(geom[0], geom[1]) + math.hypot(geom[2], geom[3]), 1e-12)

        def ok(r: float) -> bool:
            return estimated_error(model, r, body1, body2, self.estimate) <= limit

        lo, hi = size * 1e-3, size * 1e7
        if ok(lo):
            out = 0.0
        elif not ok(hi):
            out = math.inf
        else:
            for _ in range(60):
                mid = math.sqrt(lo * hi)
                lo, hi = (lo, mid) if ok(mid) else (mid, hi)
            out = hi
        self._thresholds[key] = out  # type: ignore[attr-defined]
        return out

    @classmethod
    def from_spec(cls, spec: Any) -> Planner:
        """From a scene's :class:`~poissonkit.scene.schema.PlannerSpec`."""
        return cls(tol=spec.tol, models=tuple(spec.models), hysteresis=spec.hysteresis,
                   cutoff=spec.cutoff, replan_every=spec.replan_every)

    # -- one pair
    def errors(self, r: float, body1: Mapping[str, float], body2: Mapping[str, float]
               ) -> dict[str, float]:
        """Estimated error of every candidate model for a pair at distance ``r``."""
        return {m: estimated_error(m, r, body1, body2, self.estimate) for m in self.models}

    def choose(self, r: float, body1: Mapping[str, float], body2: Mapping[str, float],
               current: str | None = None) -> tuple[str, float]:
        """``(model, estimated error)`` for a pair at distance ``r`` (see the hysteresis rule).

        Among models of equal cost the one valid from the shorter distance (the more accurate
        one) is preferred.
        """
        relaxed = self.tol * (1.0 - self.hysteresis)

        def first_within(limit: float) -> str | None:
            ranked = sorted(self.models, key=lambda m: (COST_RANK[m],
                                                        self.threshold(m, limit, body1, body2)))
            return next((m for m in ranked if r >= self.threshold(m, limit, body1, body2)), None)

        if current is None or current not in self.models:
            pick = first_within(self.tol)
        elif r >= self.threshold(current, self.tol, body1, body2):
            cheaper = first_within(relaxed)
            pick = cheaper if cheaper is not None and COST_RANK[cheaper] < COST_RANK[current] \
                else current
        else:
            pick = first_within(relaxed) or first_within(self.tol)
        if pick is None:  # nothing is good enough: the most accurate candidate
            errs = self.errors(r, body1, body2)
            pick = min(self.models, key=lambda m: (errs[m], COST_RANK[m]))
        return pick, estimated_error(pick, r, body1, body2, self.estimate)

    # -- a whole scene
    def prepare(self, bodies: Sequence[Any], edges: Sequence[Any]) -> tuple[list, list, Plan]:
        """Plan a scene at its initial positions.

        Parameters
        ----------
        bodies
            :class:`poissonkit.scene.bodies.BodyModel` objects.
        edges
            :class:`poissonkit.scene.assembly.EdgeSpec` objects; an edge is *planned* when both bodies
            are magnets (``moment`` given) and its potential is unset or one of ``models``.

        Returns
        -------
        (bodies, pairs, plan)
            Bodies with orientation-free tops turned into point masses, the resolved
            :class:`poissonkit.scene.assembly.PairSpec` list for ``NBodySystem``, and the :class:`Plan`.
        """
        positions = np.array([b.r for b in bodies], float)
        plan, pairs, new_bodies = self._plan(list(bodies), list(edges), positions, None)
        return new_bodies, pairs, plan

    def replan(self, plan: Plan, bodies: Sequence[Any], edges: Sequence[Any],
               positions: np.ndarray) -> tuple[Plan, list, list[tuple[int, int, str, str]]]:
        """Re-check every planned pair at new ``positions`` (N×3, SI).

        Returns the new plan, the resolved pairs and the changes ``(i, j, old, new)`` where
        ``old``/``new`` may be ``"dropped"``.
        """
        plan2, pairs, _ = self._plan(list(bodies), list(edges), np.asarray(positions, float),
                                     plan)
        old = {(p.i, p.j): p.model for p in plan.pairs}
        old.update({(d.i, d.j): "dropped" for d in plan.dropped if d.reason == "cutoff"})
        new = {(p.i, p.j): p.model for p in plan2.pairs}
        new.update({(d.i, d.j): "dropped" for d in plan2.dropped if d.reason == "cutoff"})
        changes = [(i, j, old.get((i, j), "dropped"), m) for (i, j), m in new.items()
                   if old.get((i, j)) != m]
        return plan2, pairs, sorted(changes)

    def _plan(self, bodies: list, edges: list, positions: np.ndarray, previous: Plan | None):
        from poissonkit.plugin import potential as lookup
        from poissonkit.scene.assembly import resolve

        names = tuple(b.name for b in bodies)
        prev_model = {} if previous is None else {(p.i, p.j): p.model for p in previous.pairs}
        prev_err = {} if previous is None else {(p.i, p.j): p.estimated_error
                                                for p in previous.pairs}
        prev_dropped = set() if previous is None else {
            (d.i, d.j) for d in previous.dropped if d.reason == "cutoff"}
        chosen: list[PairPlan] = []
        dropped: list[DroppedPair] = []
        kept: list[tuple[Any, str | None]] = []  # (edge, model or None for unplanned)
        unplanned = 0
        for e in edges:
            bi, bj = bodies[e.i], bodies[e.j]
            r = float(np.linalg.norm(positions[e.j] - positions[e.i]))
            if bi.fixed and bj.fixed:
                dropped.append(DroppedPair(e.i, e.j, r, "fixed"))
                continue
            planned = (_is_magnet(bi) and _is_magnet(bj)
                       and (e.potential is None or e.potential in self.models))
            if not planned and e.potential is None:
                continue  # no potential and not two magnets: the pair does not interact
            if self.cutoff is not None:
                limit = self.cutoff if ((e.i, e.j) in prev_dropped or previous is None) \
                    else CUTOFF_HYSTERESIS * self.cutoff
                if r > limit:
                    bound = self._dropped_bound(e, bodies, r, planned, lookup)
                    if bound is not None:
                        dropped.append(DroppedPair(e.i, e.j, r, "cutoff", bound))
                        continue
            if not planned:
                if e.potential is None:
                    continue  # no potential and not two magnets: the pair does not interact
                unplanned += 1
                kept.append((e, None))
                continue
            cur = prev_model.get((e.i, e.j))
            if cur is not None and self._keeps(cur, r, bi.magnet, bj.magnet):
                # fast path: still inside the band where the current model stays
                model, err = cur, prev_err[(e.i, e.j)]
            else:
                model, err = self.choose(r, bi.magnet, bj.magnet, cur)
            chosen.append(PairPlan(e.i, e.j, model, r, err))
            kept.append((e, model))
        # tops none of whose kept pairs depends on their axis become point masses
        needs_axis = [False] * len(bodies)
        for e, model in kept:
            orient = "both" if model is not None else lookup(e.potential).orientation
            if orient in ("both", "first"):
                needs_axis[e.i] = True
            if orient in ("both", "second"):
                needs_axis[e.j] = True
        new_bodies = list(bodies)
        point, e_rot = [], 0.0
        for k, b in enumerate(bodies):
            if b.is_top and not needs_axis[k]:
                point.append(b.name)
                e_rot += 0.5 * b.alpha * float(np.dot(b.m, b.m))
                new_bodies[k] = replace(b, alpha=None, nu=None, m=None)
        pairs = [self._resolved(e, new_bodies, model, resolve) for e, model in kept]
        plan = Plan(self.tol, names, tuple(chosen), tuple(dropped), tuple(point), e_rot,
                    unplanned)
        return plan, pairs, new_bodies

    def _keeps(self, current: str, r: float, body1: Mapping[str, float],
               body2: Mapping[str, float]) -> bool:
        """True if :meth:`choose` would keep ``current`` at distance ``r`` (cached thresholds):
        its estimate is within ``tol`` and no cheaper model is within the relaxed tolerance."""
        key = ("band", current, body1.get("radius", 0.0), body1.get("half_length", 0.0),
               body2.get("radius", 0.0), body2.get("half_length", 0.0))
        band = self._thresholds.get(key)  # type: ignore[attr-defined]
        if band is None:
            if current not in self.models:
                band = (math.inf, math.inf)
            else:
                relaxed = self.tol * (1.0 - self.hysteresis)
                band = (self.threshold(current, self.tol, body1, body2),
                        min((self.threshold(m, relaxed, body1, body2) for m in self.models
                             if COST_RANK[m] < COST_RANK[current]), default=math.inf))
            self._thresholds[key] = band  # type: ignore[attr-defined]
        return band[0] <= r < band[1]

    def _resolved(self, e: Any, bodies: list, model: str | None, resolve: Any) -> Any:
        """``resolve(e, bodies, model)``, cached per (edge, bodies of the pair, model)."""
        bi, bj = bodies[e.i], bodies[e.j]
        key = (id(e), id(bi), id(bj), model)
        hit = self._specs.get(key)  # type: ignore[attr-defined]
        if hit is None:
            hit = (e, bi, bj, resolve(e, bodies, model))  # keep the objects alive with the ids
            self._specs[key] = hit  # type: ignore[attr-defined]
        return hit[3]

    def _dropped_bound(self, e, bodies, r, planned, lookup) -> float | None:
        """Energy bound of a pair beyond the cutoff, or ``None`` if it must be kept."""
        bi, bj = bodies[e.i], bodies[e.j]
        if planned:
            k = MU0 * bi.magnet["moment"] * bj.magnet["moment"] / (4 * math.pi)
            eps = estimated_error("dipole", r, bi.magnet, bj.magnet, self.estimate)
            return 2.0 * k / r ** 3 * (1.0 + eps)
        if e.potential is None:
            return None
        entry = lookup(e.potential)
        if entry.orientation != "none":
            return None
        from poissonkit.numerics.potentials import compile_potential
        from poissonkit.scene.assembly import resolve

        spec = resolve(e, bodies)
        f = compile_potential(entry, dict(spec.params))
        return abs(float(f(r, 0.0, 0.0, 0.0)[0]))


# ---------------------------------------------------------------------------- planned runs

@dataclass(frozen=True)
class PlannedRun:
    """Result of :func:`run_planned` (SI units).

    Attributes
    ----------
    t
        Times of the saved states [s] (start, then every re-plan, then the end).
    positions
        Positions of *all* bodies at those times, shape ``(len(t), N, 3)`` [m].
    energy
        Total energy of the system in force at each saved time [J]; after a switch the next
        value is of the new Hamiltonian.
    switches
        Every model change, with the pair's energy jump.
    total_jumps
        ``(t, H_new(y) − H_old(y))`` of the whole system at each re-plan that changed something
        [J]; equals the sum of the pairs' jumps at that time.
    plans
        The plan in force after each re-plan (the first is the initial plan).
    steps, wall_time
        Integrator steps and wall-clock seconds of the whole run (including re-planning).
    """

    t: np.ndarray
    positions: np.ndarray
    energy: np.ndarray
    switches: tuple[Switch, ...]
    total_jumps: tuple[tuple[float, float], ...]
    plans: tuple[Plan, ...]
    steps: int
    wall_time: float
    names: tuple[str, ...] = ()
    final_state: Mapping[str, np.ndarray] = field(default_factory=dict)

    def energy_drift(self) -> float:
        """Largest |E(t) − E(0) − Σ jumps up to t| relative to |E(0)| (switches excluded)."""
        jumps = np.zeros_like(self.energy)
        for tj, dj in self.total_jumps:
            jumps[self.t >= tj - 1e-15 * max(1.0, abs(tj))] += dj
        ref = self.energy[0]
        return float(np.max(np.abs(self.energy - ref - jumps)) / max(abs(ref), 1e-300))

    def usage(self) -> dict[str, dict[str, Any]]:
        """Per pair that ever switched: its sequence of ``(t_start [s], model)`` segments."""
        first = {(p.i, p.j): p.model for p in self.plans[0].pairs}
        out: dict[str, dict[str, Any]] = {}
        for s in self.switches:
            key = f"{s.bodies[0]}-{s.bodies[1]}"
            entry = out.setdefault(key, {"segments": [(0.0, first.get((s.i, s.j), "dropped"))]})
            entry["segments"].append((s.t, s.new))
        return out

    def report(self) -> dict[str, Any]:
        """A JSON-ready summary of models, switches, energy jumps and cost."""
        return {
            "initial_plan": self.plans[0].report() | {"pairs": len(self.plans[0].pairs)},
            "final_models": self.plans[-1].counts(),
            "switches": [{"t_s": s.t, "bodies": list(s.bodies), "from": s.old, "to": s.new,
                          "distance_m": s.distance, "energy_jump_J": s.energy_jump}
                         for s in self.switches],
            "total_energy_jumps_J": [list(x) for x in self.total_jumps],
            "max_neglected_energy_bound_J": max(p.neglected_energy_bound for p in self.plans),
            "energy_drift_excluding_switches": self.energy_drift(),
            "steps": self.steps,
            "wall_time_s": self.wall_time,
        }


def _pair_energy(spec: Any, pos: np.ndarray, axes: np.ndarray) -> float:
    """U of one resolved pair at SI positions/axes (kernel of the registry potential)."""
    from poissonkit.numerics.potentials import compile_potential
    from poissonkit.plugin import potential as lookup

    d = pos[spec.j] - pos[spec.i]
    r = float(np.linalg.norm(d))
    e = d / r
    c1, c2 = float(e @ axes[spec.i]), float(e @ axes[spec.j])
    c3 = float(axes[spec.i] @ axes[spec.j])
    f = compile_potential(lookup(spec.potential), dict(spec.params))
    return float(f(r, c1, c2, c3)[0])


def run_planned(bodies: Sequence[Any], edges: Sequence[Any], planner: Planner, duration: float,
                step: float, method: str = "splitting4", scales: Any = "auto",
                on_replan: Any = None) -> PlannedRun:
    """Integrate with per-pair models re-planned every ``planner.replan_every`` steps.

    Parameters
    ----------
    bodies, edges
        :class:`poissonkit.scene.bodies.BodyModel` list and :class:`poissonkit.scene.assembly.EdgeSpec` list
        (e.g. ``bodies_of(G)``, ``edges_of(G)``).
    planner
        The planner (tolerance, models, hysteresis, cutoff, re-plan cadence).
    duration, step
        Duration and fixed step [s].
    method
        Integrator registry name (a fixed-step method).
    scales
        Internal units (``"auto"``: :func:`poissonkit.scene.assembly.auto_scales` of the bodies), kept
        for the whole run so the state carries over unchanged between re-plans.
    on_replan
        Optional callback ``on_replan(t, plan, changes)``.

    Returns
    -------
    PlannedRun
    """
    from poissonkit.numerics import solver
    from poissonkit.scene.assembly import auto_scales, state_of, system_of

    if not (duration > 0 and step > 0 and step <= duration):
        raise PlannerError(f"need 0 < step <= duration, got step={step!r}, duration={duration!r}")
    start = time.perf_counter()
    bodies = list(bodies)
    edges = list(edges)
    bodies, pairs, plan = planner.prepare(bodies, edges)
    if isinstance(scales, str) and scales == "auto":
        scales = auto_scales(bodies)
    T = scales.time if scales is not None else 1.0
    E_unit = scales.energy if scales is not None else 1.0
    system = system_of(bodies, _ordered(pairs), cutoff=None, scales=scales)
    y = state_of(bodies, system)
    fixed_pos = np.array([b.r for b in bodies], float)
    moving = [k for k, b in enumerate(bodies) if not b.fixed]
    tops = [k for k in moving if bodies[k].is_top]
    fixed_axes = np.array([b.nu if b.is_top else (0.0, 0.0, 0.0) for b in bodies], float)

    def full(yv: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict]:
        st = system.unpack(yv, si=True)
        pos = fixed_pos.copy()
        pos[moving] = st["r"]
        ax = fixed_axes.copy()
        ax[tops] = st["nu"] / np.linalg.norm(st["nu"], axis=1)[:, None] if tops else ax[tops]
        return pos, ax, st

    n_total = round(duration / step)
    if abs(n_total * step - duration) > 1e-9 * duration:
        n_total = math.ceil(duration / step)
    h = step / T
    t_saved = [0.0]
    pos0, _, _ = full(y)
    positions = [pos0]
    energies = [system.energy(y) * E_unit]
    switches: list[Switch] = []
    jumps: list[tuple[float, float]] = []
    plans = [plan]
    done = 0
    t = 0.0
    while done < n_total:
        n = min(planner.replan_every, n_total - done)
        sol = solver.solve(system, y, t + n * h, method=method, step=h, t0=t, save_every=n)
        y = np.asarray(sol.y[-1], float)
        t = float(sol.t[-1])
        done += n
        pos, ax, _ = full(y)
        t_si = t * T
        positions.append(pos)
        t_saved.append(t_si)
        energies.append(system.energy(y) * E_unit)
        if done >= n_total:
            break
        new_plan, new_pairs, changes = planner.replan(plan, bodies, edges, pos)
        if changes:
            old_specs = {(p.i, p.j): p for p in pairs}
            new_specs = {(p.i, p.j): p for p in new_pairs}
            for i, j, old, new in changes:
                u_old = _pair_energy(old_specs[(i, j)], pos, ax) if (i, j) in old_specs else 0.0
                u_new = _pair_energy(new_specs[(i, j)], pos, ax) if (i, j) in new_specs else 0.0
                switches.append(Switch(t_si, i, j, (bodies[i].name, bodies[j].name), old, new,
                                       float(np.linalg.norm(pos[j] - pos[i])), u_new - u_old))
            e_old = system.energy(y) * E_unit
            system = system_of(bodies, _ordered(new_pairs), cutoff=None, scales=scales)
            e_new = system.energy(y) * E_unit
            jumps.append((t_si, e_new - e_old))
            energies[-1] = e_new  # the saved energy continues with the new Hamiltonian
            pairs = new_pairs
            if on_replan is not None:
                on_replan(t_si, new_plan, changes)
        plan = new_plan
        plans.append(plan)
    _, _, st = full(y)
    return PlannedRun(np.array(t_saved), np.array(positions), np.array(energies),
                      tuple(switches), tuple(jumps), tuple(plans), n_total,
                      time.perf_counter() - start, tuple(b.name for b in bodies), st)


def _ordered(pairs: list) -> list:
    """Pairs sorted by model so equal model sets give identical compiled dispatchers."""
    return sorted(pairs, key=lambda p: (COST_RANK.get(p.potential, 3), p.potential, p.i, p.j))
