"""Planned runs: integrate a scene while its planner re-checks each pair's model.

:func:`run_planned` integrates in chunks of ``replan_every`` steps; between chunks the
:class:`~poissonkit.scene.planner.choice.Planner` re-plans at the new positions, and every model
switch (a change of Hamiltonian) is recorded with its energy jump.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.scene.assembly import EdgeSpec, PairSpec
from poissonkit.scene.bodies import BodyModel
from poissonkit.scene.planner.choice import Planner
from poissonkit.scene.planner.plans import Plan, PlannerError, Switch

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
        """Largest relative energy error with the switches' jumps taken out:
        ``max |E(t) − Σ jumps up to t − E(0)| / |E(0)|``
        (:func:`poissonkit.numerics.diagnostics.energy_error_of`)."""
        from poissonkit.numerics.diagnostics import energy_error_of

        jumps = np.zeros_like(self.energy)
        for tj, dj in self.total_jumps:
            jumps[self.t >= tj - 1e-15 * max(1.0, abs(tj))] += dj
        return energy_error_of(self.energy - jumps).max_relative

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
            "max_rel_energy_error_excluding_switches": self.energy_drift(),
            "steps": self.steps,
            "wall_time_s": self.wall_time,
        }


def _pair_energy(spec: PairSpec, pos: np.ndarray, axes: np.ndarray) -> float:
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


def run_planned(bodies: Sequence[BodyModel], edges: Sequence[EdgeSpec], planner: Planner,
                duration: float, step: float, method: str = "splitting4", scales: Any = "auto",
                on_replan: Callable[[float, Plan, list[tuple[int, int, str, str]]], None]
                | None = None) -> PlannedRun:
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
        Internal units (``"auto"``: :func:`poissonkit.scene.assembly.auto_scales` of the bodies
        and their initially planned pairs), kept
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
        scales = auto_scales(bodies, pairs)
    T = scales.time if scales is not None else 1.0
    E_unit = scales.energy if scales is not None else 1.0
    system = system_of(bodies, _ordered(pairs, planner), cutoff=None, scales=scales)
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
            system = system_of(bodies, _ordered(new_pairs, planner), cutoff=None, scales=scales)
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


def _ordered(pairs: list[PairSpec], planner: Planner) -> list[PairSpec]:
    """Pairs sorted by model cost (other potentials last), then name and bodies, so equal
    model sets give identical compiled dispatchers."""
    return sorted(pairs, key=lambda p: (planner.cost(p.potential), p.potential, p.i, p.j))
