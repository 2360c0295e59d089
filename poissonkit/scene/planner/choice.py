"""Model only what a scene needs: per pair, the cheapest adequate model of its model family.

A model family (:class:`poissonkit.plugin.ModelFamily`, registered by a plugin through the
hook ``poissonkit_model_families``) names pair potentials that model the same pair at several
fidelities, cheapest first, with an error estimate and the test of which pairs it models. The
magnets plugin registers dipole / dumbbells / exact cylinders; any plugin can add its own.

Given a force tolerance ``tol``, each pair that a family applies to gets the cheapest of the
family's candidate models whose estimated error is within ``tol``, and the choice is re-checked
as the distances change (:func:`poissonkit.scene.planner.run.run_planned` re-plans every
``replan_every`` steps). The estimates are the families' own (for magnets,
:mod:`poissonkit_magnets.fidelity`; checked against exact models in
``tests/scene/test_scene_planner.py`` and ``tests/magnets/test_magnets_fidelity.py``).

Switching and hysteresis
------------------------
A pair keeps its model while the model's estimate stays within ``tol``. It moves to a cheaper
model only when that one is within ``(1 − hysteresis) tol``, and to a more accurate one (the
cheapest within ``(1 − hysteresis) tol``) as soon as its current estimate exceeds ``tol``. So a
pair oscillating about a threshold does not switch back and forth. Each switch changes the
Hamiltonian: ``run_planned`` records the energy jump ``U_new − U_old`` of the pair at the
switch (and the jump of the total energy, their sum).

What else the plan does
-----------------------
* **Point masses.** A top none of whose kept pairs depends on its axis (e.g. only gravity, or a
  non-magnetic body) becomes a point mass: its axis and angular momentum leave the state (its
  free rotation is decoupled; its rotational energy ``α|m|²/2`` is constant and reported).
* **Fixed bodies** carry no degrees of freedom (``NBodySystem`` gets them as fixed bodies);
  pairs of two fixed bodies are dropped (constant energy, no force on anything that moves).
* **Cutoff.** Planned pairs farther apart than ``cutoff`` are dropped when their family gives
  an energy bound (magnets: ``|U| ≤ 2 k / r³ (1 + ε_dip(r))``, ``k = μ0 μ_i μ_j / (4π)``, see
  :func:`poissonkit_magnets.family.energy_bound`). Central (orientation-free) pairs beyond the
  cutoff are dropped with their exact ``|U(r)|``; other pairs are never dropped. The plan
  reports the sum of the bounds, re-evaluated at every re-plan. Dropped pairs come back when
  they are within the cutoff again (a pair is dropped only beyond ``1.05 cutoff`` once kept).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.contracts import Integrator, System
from poissonkit.errors import InputError, UnknownNameError
from poissonkit.plugin.contributions import ModelFamily
from poissonkit.scene.assembly import EdgeSpec, PairSpec, resolve
from poissonkit.scene.bodies import BodyModel
from poissonkit.scene.planner.plans import DroppedPair, PairPlan, Plan, PlannerError

if TYPE_CHECKING:
    from poissonkit.scene.schema import PlannerSpec

#: Once kept, a pair is dropped only beyond this multiple of the cutoff.
CUTOFF_HYSTERESIS = 1.05


def _families() -> list[ModelFamily]:
    from poissonkit.plugin import model_families

    return model_families()


def family_of(model: str, families: Sequence[ModelFamily] | None = None) -> ModelFamily:
    """The registered model family that contains the potential ``model``.

    Raises
    ------
    UnknownNameError
        ``model`` is in no registered family (the message lists the models that are).
    """
    families = _families() if families is None else families
    for family in families:
        if model in family.models:
            return family
    raise UnknownNameError("planner model", model, [m for f in families for m in f.models])


def estimated_error(model: str, r: float, body1: Mapping[str, Any],
                    body2: Mapping[str, Any]) -> float:
    """Estimated relative force error of ``model`` for a pair at centre distance ``r`` [m].

    Parameters
    ----------
    model
        A model of a registered family (magnets: ``"dipole"``, ``"dumbbell"``,
        ``"dumbbell_octupole"``, ``"cylinder"``).
    body1, body2
        The bodies' attributes (magnets: ``radius``, ``length``; a magnet without them is a
        point dipole, for which the dipole model is exact).

    Returns
    -------
    float
        The family's estimate; ``inf`` where the model is not trusted.
    """
    return float(family_of(model).estimate(model, r, body1, body2))


#: Distances [m] beyond which (and below whose inverse) no threshold is searched: a model not
#: within the tolerance at 1e30 m is never good enough, one good at 1e-30 m is always.
BRACKET_LIMIT = 1e30


def body_attributes(body: BodyModel) -> Mapping[str, Any]:
    """The attributes of a body that model families read: its magnet data (size, moment) and
    every attribute the registered potentials declare (:attr:`BodyModel.extra`)."""
    return {**body.extra, **body.magnet} if body.extra else body.magnet


@dataclass(frozen=True)
class Planner:
    """Chooses per pair the cheapest model of its family within a force tolerance.

    Parameters
    ----------
    tol
        Relative force (and torque) tolerance of each pair's model.
    models
        Candidate potentials, each a model of a registered family (e.g. ``dipole``,
        ``dumbbell``, ``dumbbell_octupole``, ``cylinder`` of the magnets family); ``None``: the
        default models of every registered family. A pair for which none is within ``tol``
        gets the most accurate one.
    hysteresis
        In [0, 1): a cheaper model must be within ``(1 − hysteresis) tol`` to be switched to.
    cutoff
        Planned pairs farther apart are dropped [m] (``None``: never).
    replan_every
        Steps between re-plans in :func:`poissonkit.scene.planner.run.run_planned`.
    """

    tol: float
    models: tuple[str, ...] | None = None
    hysteresis: float = 0.5
    cutoff: float | None = None
    replan_every: int = 100

    def __post_init__(self) -> None:
        if not (isinstance(self.tol, (int, float)) and math.isfinite(self.tol) and self.tol > 0):
            raise PlannerError(f"planner tol must be a positive number, got {self.tol!r}")
        families = _families()
        if self.models is None:
            models = tuple(m for f in families for m in (f.defaults or f.models))
        else:
            models = tuple(self.models)
            if not models:
                raise PlannerError("planner needs at least one model")
        family = {m: family_of(m, families) for m in models}
        models = tuple(sorted(models, key=lambda m: family[m].cost(m)))
        object.__setattr__(self, "models", models)
        if not 0 <= self.hysteresis < 1:
            raise PlannerError(f"hysteresis must be in [0, 1), got {self.hysteresis!r}")
        if self.cutoff is not None and not self.cutoff > 0:
            raise PlannerError(f"cutoff must be > 0, got {self.cutoff!r}")
        if int(self.replan_every) < 1:
            raise PlannerError(f"replan_every must be >= 1, got {self.replan_every!r}")
        # the candidates of each family, cheapest first (families in registration order)
        groups = [(f, tuple(m for m in models if family[m] is f)) for f in families]
        object.__setattr__(self, "_groups", tuple((f, ms) for f, ms in groups if ms))
        object.__setattr__(self, "_family", family)
        object.__setattr__(self, "_cost", {m: f.cost(m) for f in reversed(families)
                                           for m in f.models})
        # caches (not part of the value): thresholds per (model, attributes read, limit) and
        # resolved pair parameters, so re-planning thousands of pairs costs O(1) per pair
        object.__setattr__(self, "_thresholds", {})
        object.__setattr__(self, "_specs", {})

    @classmethod
    def from_spec(cls, spec: PlannerSpec) -> Planner:
        """From a scene's :class:`~poissonkit.scene.schema.PlannerSpec`."""
        models = None if spec.models is None else tuple(spec.models)
        return cls(tol=spec.tol, models=models, hysteresis=spec.hysteresis,
                   cutoff=spec.cutoff, replan_every=spec.replan_every)

    # -- families
    def cost(self, model: str) -> float:
        """Relative cost of a model in its family (``inf`` for a potential of no family)."""
        return self._cost.get(model, math.inf)  # type: ignore[attr-defined]

    def family_for(self, body1: Mapping[str, Any], body2: Mapping[str, Any],
                   potential: str | None = None) -> tuple[ModelFamily, tuple[str, ...]] | None:
        """``(family, candidate models)`` planning this pair, or ``None``.

        The first family with candidates that applies to the pair and, if the pair names its
        ``potential``, has it among its candidates.
        """
        for family, models in self._groups:  # type: ignore[attr-defined]
            if (potential is None or potential in models) and family.applies(body1, body2):
                return family, models
        return None

    def _candidates(self, body1: Mapping[str, Any], body2: Mapping[str, Any]
                    ) -> tuple[ModelFamily, tuple[str, ...]]:
        found = self.family_for(body1, body2)
        if found is None:
            names = [f.name for f, _ in self._groups]  # type: ignore[attr-defined]
            raise PlannerError(f"no model family among the planner's ({', '.join(names)}) "
                               "applies to this pair")
        return found

    def _estimate(self, model: str, r: float, body1: Mapping[str, Any],
                  body2: Mapping[str, Any]) -> float:
        return float(self._family[model].estimate(model, r, body1, body2))  # type: ignore

    def threshold(self, model: str, limit: float, body1: Mapping[str, Any],
                  body2: Mapping[str, Any]) -> float:
        """Smallest distance [m] beyond which ``model``'s estimate stays within ``limit``.

        The estimates decrease with distance, so ``estimate(model, r) <= limit`` iff
        ``r >= threshold`` (found by bisection once per model, attributes read and limit, then
        cached).
        """
        family = self._family[model]  # type: ignore[attr-defined]
        geom = _read(family, body1, body2)
        key = (model, limit, geom)
        hit = self._thresholds.get(key)  # type: ignore[attr-defined]
        if hit is not None:
            return hit
        size = max(math.hypot(body1.get("radius", 0.0), body1.get("half_length", 0.0))
                   + math.hypot(body2.get("radius", 0.0), body2.get("half_length", 0.0)), 1e-12)

        def ok(r: float) -> bool:
            return self._estimate(model, r, body1, body2) <= limit

        lo, hi = size * 1e-3, size * 1e7
        # the bracket comes from the magnet size where there is one; for bodies whose size the
        # planner cannot know (any other family) it widens by factors of 1e3 until it holds
        while not ok(hi) and hi < BRACKET_LIMIT:
            lo, hi = hi, hi * 1e3
        while ok(lo) and lo > 1.0 / BRACKET_LIMIT:
            lo, hi = lo * 1e-3, lo
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

    # -- one pair
    def errors(self, r: float, body1: Mapping[str, Any], body2: Mapping[str, Any]
               ) -> dict[str, float]:
        """Estimated error of every candidate model of the pair's family at distance ``r``."""
        _, models = self._candidates(body1, body2)
        return {m: self._estimate(m, r, body1, body2) for m in models}

    def choose(self, r: float, body1: Mapping[str, Any], body2: Mapping[str, Any],
               current: str | None = None) -> tuple[str, float]:
        """``(model, estimated error)`` for a pair at distance ``r`` (see the hysteresis rule).

        Among models of equal cost the one valid from the shorter distance (the more accurate
        one) is preferred.
        """
        _, models = self._candidates(body1, body2)
        relaxed = self.tol * (1.0 - self.hysteresis)

        def first_within(limit: float) -> str | None:
            ranked = sorted(models, key=lambda m: (self.cost(m),
                                                   self.threshold(m, limit, body1, body2)))
            return next((m for m in ranked if r >= self.threshold(m, limit, body1, body2)), None)

        if current is None or current not in models:
            pick = first_within(self.tol)
        elif r >= self.threshold(current, self.tol, body1, body2):
            cheaper = first_within(relaxed)
            pick = cheaper if cheaper is not None and self.cost(cheaper) < self.cost(current) \
                else current
        else:
            pick = first_within(relaxed) or first_within(self.tol)
        if pick is None:  # nothing is good enough: the most accurate candidate
            errs = {m: self._estimate(m, r, body1, body2) for m in models}
            pick = min(models, key=lambda m: (errs[m], self.cost(m)))
        return pick, self._estimate(pick, r, body1, body2)

    # -- a whole scene
    def prepare(self, bodies: Sequence[BodyModel], edges: Sequence[EdgeSpec]
                ) -> tuple[list[BodyModel], list[PairSpec], Plan]:
        """Plan a scene at its initial positions.

        Parameters
        ----------
        bodies
            :class:`poissonkit.scene.bodies.BodyModel` objects.
        edges
            :class:`poissonkit.scene.assembly.EdgeSpec` objects; an edge is *planned* when a
            family of the planner applies to its bodies (magnets: both have a ``moment``) unless
            the edge names its own potential that is not one of that family's candidates. Edges
            not planned use their potential (their own or the default); without one they do not
            interact.

        Returns
        -------
        (bodies, pairs, plan)
            Bodies with orientation-free tops turned into point masses, the resolved
            :class:`poissonkit.scene.assembly.PairSpec` list for ``NBodySystem``, and the
            :class:`~poissonkit.scene.planner.plans.Plan`.
        """
        positions = np.array([b.r for b in bodies], float)
        plan, pairs, new_bodies = self._plan(list(bodies), list(edges), positions, None)
        return new_bodies, pairs, plan

    def replan(self, plan: Plan, bodies: Sequence[BodyModel], edges: Sequence[EdgeSpec],
               positions: np.ndarray) -> tuple[Plan, list[PairSpec], list[tuple[int, int, str, str]]]:
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

    def _plan(self, bodies: list[BodyModel], edges: list[EdgeSpec], positions: np.ndarray,
              previous: Plan | None) -> tuple[Plan, list[PairSpec], list[BodyModel]]:
        from poissonkit.plugin import potential as lookup

        names = tuple(b.name for b in bodies)
        prev_model = {} if previous is None else {(p.i, p.j): p.model for p in previous.pairs}
        prev_err = {} if previous is None else {(p.i, p.j): p.estimated_error
                                                for p in previous.pairs}
        prev_dropped = set() if previous is None else {
            (d.i, d.j) for d in previous.dropped if d.reason == "cutoff"}
        chosen: list[PairPlan] = []
        dropped: list[DroppedPair] = []
        kept: list[tuple[EdgeSpec, str | None]] = []  # (edge, model or None for unplanned)
        unplanned = 0
        for e in edges:
            bi, bj = bodies[e.i], bodies[e.j]
            r = float(np.linalg.norm(positions[e.j] - positions[e.i]))
            if bi.fixed and bj.fixed:
                dropped.append(DroppedPair(e.i, e.j, r, "fixed"))
                continue
            ai, aj = body_attributes(bi), body_attributes(bj)
            # a default potential does not keep a family from planning the pair; an edge's own
            # potential does unless it is one of the family's candidates
            found = self.family_for(ai, aj, e.potential if e.own_potential else None)
            if found is None and e.potential is None:
                continue  # no potential and no family models the pair: it does not interact
            if self.cutoff is not None:
                limit = self.cutoff if ((e.i, e.j) in prev_dropped or previous is None) \
                    else CUTOFF_HYSTERESIS * self.cutoff
                if r > limit:
                    bound = self._dropped_bound(e, bodies, r, found)
                    if bound is not None:
                        dropped.append(DroppedPair(e.i, e.j, r, "cutoff", bound))
                        continue
            if found is None:
                unplanned += 1
                kept.append((e, None))
                continue
            cur = prev_model.get((e.i, e.j))
            if cur is not None and self._keeps(cur, r, ai, aj):
                # fast path: still inside the band where the current model stays
                model, err = cur, prev_err[(e.i, e.j)]
            else:
                model, err = self.choose(r, ai, aj, cur)
            chosen.append(PairPlan(e.i, e.j, model, r, err))
            kept.append((e, model))
        # tops none of whose kept pairs depends on their axis become point masses
        needs_axis = [False] * len(bodies)
        for e, model in kept:
            orient = lookup(model if model is not None else e.potential).orientation
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
        pairs = [self._resolved(e, new_bodies, model) for e, model in kept]
        plan = Plan(self.tol, names, tuple(chosen), tuple(dropped), tuple(point), e_rot,
                    unplanned)
        return plan, pairs, new_bodies

    def _keeps(self, current: str, r: float, body1: Mapping[str, Any],
               body2: Mapping[str, Any]) -> bool:
        """True if :meth:`choose` would keep ``current`` at distance ``r`` (cached thresholds):
        its estimate is within ``tol`` and no cheaper model is within the relaxed tolerance."""
        family = self._family.get(current)  # type: ignore[attr-defined]
        if family is None:
            return False
        key = ("band", current, _read(family, body1, body2))
        band = self._thresholds.get(key)  # type: ignore[attr-defined]
        if band is None:
            _, models = self._candidates(body1, body2)
            relaxed = self.tol * (1.0 - self.hysteresis)
            band = (self.threshold(current, self.tol, body1, body2),
                    min((self.threshold(m, relaxed, body1, body2) for m in models
                         if self.cost(m) < self.cost(current)), default=math.inf))
            self._thresholds[key] = band  # type: ignore[attr-defined]
        return band[0] <= r < band[1]

    def _resolved(self, e: EdgeSpec, bodies: list[BodyModel], model: str | None) -> PairSpec:
        """``resolve(e, bodies, model)``, cached per (edge, bodies of the pair, model)."""
        bi, bj = bodies[e.i], bodies[e.j]
        key = (id(e), id(bi), id(bj), model)
        hit = self._specs.get(key)  # type: ignore[attr-defined]
        if hit is None:
            hit = (e, bi, bj, resolve(e, bodies, model))  # keep the objects alive with the ids
            self._specs[key] = hit  # type: ignore[attr-defined]
        return hit[3]

    def _dropped_bound(self, e: EdgeSpec, bodies: list[BodyModel], r: float,
                       found: tuple[ModelFamily, tuple[str, ...]] | None) -> float | None:
        """Energy bound of a pair beyond the cutoff, or ``None`` if it must be kept."""
        from poissonkit.plugin import potential as lookup

        bi, bj = bodies[e.i], bodies[e.j]
        if found is not None:
            family = found[0]
            if family.energy_bound is None:
                return None
            return float(family.energy_bound(r, body_attributes(bi), body_attributes(bj)))
        if e.potential is None:
            return None
        entry = lookup(e.potential)
        if entry.orientation != "none":
            return None
        from poissonkit.numerics.potentials import compile_potential

        spec = resolve(e, bodies)
        f = compile_potential(entry, dict(spec.params))
        return abs(float(f(r, 0.0, 0.0, 0.0)[0]))


def _read(family: ModelFamily, body1: Mapping[str, Any], body2: Mapping[str, Any]) -> tuple:
    """The attributes ``family`` reads of both bodies: the key of its cached thresholds."""
    return (family.name, tuple(body1.get(k) for k in family.reads),
            tuple(body2.get(k) for k in family.reads))


#: Below this final-state error a close approach of tops is integrated by the time-transformed
#: splitting of ``TimeTransformedSplitting.for_close_approach``; at it ``splitting8_bce`` needs
#: fewer evaluations on the mildest approach measured (docs/performance.md, "Force evaluations
#: per accuracy").
CLOSE_APPROACH_ERROR = 1e-7


def close_approach_integrator(system: System, y0: np.ndarray, error: float) -> Integrator | str:
    """The integrator for an orbit of tops with close approaches, for a final-state ``error``.

    For orbits whose pericentre lies well inside the start distance (the seed encounter: 0.43;
    on a near-circular orbit the fixed step needs 1.2× fewer evaluations at 1e-10).

    ``splitting8_bce`` (fixed step) down to :data:`CLOSE_APPROACH_ERROR`; below it, and when the
    start is in an attractive well (``V(y₀) < 0``), the order-10 time-transformed splitting with
    a tracked kinetic energy (1.3–1.55× fewer force evaluations at 1e-8 on eccentric approaches,
    1.3× at 1e-10 on the seed encounter, at 1.04× the cost per evaluation). That one is an
    object (its shift depends on ``y0``): the registry's ``logh10`` with the options
    ``track_kinetic=True, shift=3|V(y₀)|``, named ``"logh10"`` in results and summaries.
    """
    from poissonkit.numerics.integrators.time_transformed import TimeTransformedSplitting

    if error >= CLOSE_APPROACH_ERROR:
        return "splitting8_bce"
    try:
        return TimeTransformedSplitting.for_close_approach(system, y0)
    except InputError:  # a repulsive start or no forces kernel: no well to adapt to
        return "splitting8_bce"
