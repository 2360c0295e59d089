"""Model only what a scene needs: a ~100-magnet cluster, uniform exact models vs the planner.

Both runs integrate the same cluster (seeded random positions and axes, magnets of seed 000:
d = 2.5 mm, h = 20 mm, J = 1.58359e6 A/m, released from rest) with the same integrator and
step. The baseline uses the exact cylinder model for every pair; the planner picks per pair the
cheapest model within the force tolerance (dipole / dumbbell / the same exact cylinder) and
re-plans every few steps. Printed: the plan, wall times, the speed-up, the force error of the
planned system at t = 0 and the observed trajectory error (final positions of the planned run
against the exact run, relative to how far the bodies moved).

    python examples/cluster_planner.py                 # N = 100, 10 steps (a few minutes)
    python examples/cluster_planner.py --n 30 --steps 6   # quicker

The exact model uses 6 x 12 quadrature nodes (``n_radial``, ``n_angular``); at the closest
distance in the cluster its own error against 12 x 24 nodes is printed too.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from poissonkit_nbody import random_cluster

from poissonkit.numerics.solver import solve
from poissonkit.scene.assembly import (
    auto_scales,
    bodies_of,
    edges_of,
    resolve,
    state_of,
    system_of,
)
from poissonkit.scene.planner import Planner, run_planned

MAGNET = {  # seed 000 magnets, SI
    "mass": 7800 * math.pi * 1.25e-3 ** 2 * 0.02,
    "inertia": 7800 * math.pi * 1.25e-3 ** 2 * 0.02 * (3 * 1.25e-3 ** 2 + 0.02 ** 2) / 12,
    "magnetization": 1.58359e6,
    "radius": 1.25e-3,
    "length": 0.02,
}


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100, help="number of magnets")
    ap.add_argument("--cluster-radius", type=float, default=0.3, help="m")
    ap.add_argument("--tol", type=float, default=1e-3, help="relative force tolerance")
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--replan-every", type=int, default=5)
    ap.add_argument("--method", default="splitting2")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--nodes", default="6,12", help="exact model's n_radial,n_angular")
    ap.add_argument("--models", default="dipole,dumbbell,cylinder",
                    help="planner candidates, comma-separated")
    args = ap.parse_args(argv)
    n_radial, n_angular = (int(x) for x in args.nodes.split(","))

    G = random_cluster(args.n, args.cluster_radius, MAGNET, seed=args.seed,
                       min_distance=0.022)  # > 2 bounding radii would forbid T-shapes; 22 mm
    G.graph["params"] = {"n_radial": n_radial, "n_angular": n_angular}
    bodies = bodies_of(G)
    edges = edges_of(G)
    # initial overlap check, as a scene file would do
    from poissonkit.scene.schema import check_overlaps

    check_overlaps([G.nodes[k] for k in G.nodes], "cluster")
    scales = auto_scales(bodies)
    step = 0.02 * scales.time
    duration = args.steps * step
    planner = Planner(tol=args.tol, replan_every=args.replan_every,
                      models=tuple(args.models.split(",")))

    # --- uniform exact baseline
    exact_pairs = [resolve(e, bodies, "cylinder") for e in edges]
    exact = system_of(bodies, exact_pairs, scales=scales)
    y0 = state_of(bodies, exact)
    exact.forces(y0)  # compile outside the timing
    solve(exact, y0, step / scales.time, method=args.method, step=step / scales.time)
    t0 = time.perf_counter()
    F_exact, _, _ = exact.forces(y0)
    t_force_exact = time.perf_counter() - t0
    t0 = time.perf_counter()
    sol = solve(exact, y0, duration / scales.time, method=args.method, step=step / scales.time)
    wall_exact = time.perf_counter() - t0
    r_exact = exact.unpack(sol.y[-1], si=True)["r"]

    # --- planner
    pbodies, ppairs, plan = planner.prepare(bodies, edges)
    planned = system_of(pbodies, ppairs, scales=scales)
    yp = state_of(pbodies, planned)
    planned.forces(yp)
    t0 = time.perf_counter()
    F_plan, _, _ = planned.forces(yp)
    t_force_plan = time.perf_counter() - t0
    run_planned(bodies, edges, planner, step, step, method=args.method, scales=scales)  # warm-up
    run = run_planned(bodies, edges, planner, duration, step, method=args.method, scales=scales)
    r_plan = run.final_state["r"]

    moved = np.linalg.norm(r_exact - np.array([b.r for b in bodies]), axis=1)
    dev = np.linalg.norm(r_plan - r_exact, axis=1)
    force_err = np.linalg.norm(F_plan - F_exact, axis=1) / np.linalg.norm(F_exact, axis=1)
    dmin = min(np.linalg.norm(np.subtract(bodies[e.j].r, bodies[e.i].r)) for e in edges)

    # accuracy of the 6 x 12 "exact" model itself at the closest distance
    from poissonkit.numerics.potentials import compile_potential
    from poissonkit.plugin import potential

    cyl = potential("cylinder")
    base = resolve(edges[0], bodies, "cylinder").params
    coarse = compile_potential(cyl, dict(base))
    fine = compile_potential(cyl, {**base, "n_radial": 12, "n_angular": 24})
    uc, uf = np.array(coarse(dmin, 0.9, 0.8, 0.7)), np.array(fine(dmin, 0.9, 0.8, 0.7))
    quad_err = float(np.max(np.abs(uc - uf)) / np.max(np.abs(uf)))

    out = {
        "n": args.n, "pairs": len(edges), "tol": args.tol, "models": args.models,
        "steps": args.steps,
        "step_s": step, "method": args.method, "closest_distance_m": dmin,
        "initial_plan": plan.counts(), "switches": len(run.switches),
        "max_switch_energy_jump_J": max((abs(s.energy_jump) for s in run.switches), default=0.0),
        "force_eval_exact_s": t_force_exact, "force_eval_planned_s": t_force_plan,
        "wall_exact_s": wall_exact, "wall_planned_s": run.wall_time,
        "speedup": wall_exact / run.wall_time,
        "max_force_error_t0": float(force_err.max()),
        "median_force_error_t0": float(np.median(force_err)),
        "max_trajectory_error_rel": float(np.max(dev) / np.max(moved)),
        "max_displacement_m": float(np.max(moved)),
        "max_position_deviation_m": float(np.max(dev)),
        "exact_model_quadrature_error_at_dmin": quad_err,
        "neglected_energy_bound_J": plan.neglected_energy_bound,
    }
    width = max(len(k) for k in out)
    for k, v in out.items():
        print(f"{k:<{width}}  {v:.4g}" if isinstance(v, float) else f"{k:<{width}}  {v}")
    for s in run.switches[:10]:
        print(f"  t = {s.t:.3e} s  {s.bodies[0]}-{s.bodies[1]}: {s.old} -> {s.new} at "
              f"{1e3 * s.distance:.1f} mm, energy jump {s.energy_jump:.3e} J")
    return out


if __name__ == "__main__":
    main()
