"""Fixed cost of one ``solve`` call, and ``splitting2`` per step against REBOUND's leapfrog.

Usage::

    python benchmarks/bench_solve_overhead.py [--calls 2000] [--repeat 7] [--quick]

System: the outer Solar System of ``bench_vs_rebound.py`` (Sun + 4 giants, G = 1,
``AllPairs("gravity")``), step 0.05 yr. One process, kernels compiled before timing.

1. **Overhead per call**: ``solve(..., method="splitting2")`` over 10 steps, ``--calls`` times;
   best and median wall time of a call, and the fixed overhead = best call − 10 × the cost of
   one step (from a 20 000-step run). Twice: with the same initial state every call, and with a
   new one every call (a sweep: nothing about the state can be remembered). Then where the
   time goes: cProfile over the same calls, cumulative time of each stage, scaled to the
   unprofiled call (the profiler slows Python-heavy stages more than numpy and compiled code:
   the shares are indicative).
2. **Per step against REBOUND**: wall time of the whole ``solve`` call (overhead included,
   energy saved every n/200 steps) against ``rebound.Simulation.integrate`` with
   ``leapfrog`` (same step, ``exact_finish_time=0``) over 20 000 and 200 000 steps; the plain
   numba leapfrog of ``bench_vs_rebound.py`` for scale. Rounds interleave the codes (a burst of
   load hits all alike); the best of ``--repeat`` rounds counts. Targets: ≤ 1.3× (20 000) and
   ≤ 1.1× (200 000).
"""

from __future__ import annotations

import argparse
import cProfile
import itertools
import math
import pstats
import time

import numpy as np

from bench_vs_rebound import YEAR, outer_solar_system, plain_leapfrog, poissonkit_system
from poissonkit.numerics import solve

#: (label, file suffix, function name) of the stages reported, outermost first
STAGES = (
    ("solve, argument checks", "numerics/solver.py", "solve"),
    ("integrator look-up (registry, options, object)", "numerics/solver.py",
     "_integrator_and_capabilities"),
    ("capability checks", "numerics/solver.py", "refuse_beyond"),
    ("state checks (overlap, axes)", "nbody/system.py", "check_overlap"),
    ("splitting set-up (step, kernels, buffers, digest)", "integrators/splitting.py",
     "integrate"),
    ("driver (chunks, save buffer, result)", "integrators/driver.py", "drive"),
    ("compiled loop (10 steps)", "integrators/splitting.py", "run"),
)


def _cum(stats: pstats.Stats, suffix: str, name: str, caller: str | None = None) -> float:
    """Cumulative seconds of function ``name`` in a file ending in ``suffix`` (only the calls
    from functions named ``caller`` if given)."""
    total = 0.0
    table = stats.stats  # type: ignore[attr-defined]  # pstats keeps it undeclared
    for (file, _, func), (_, _, _, ct, callers) in table.items():
        if func != name or not file.endswith(suffix):
            continue
        if caller is None:
            total += ct
        else:
            total += sum(v[3] for (_, _, f), v in callers.items() if f == caller)
    return total


def breakdown(call, calls: int, per_call: float) -> list[tuple[str, float]]:
    """(stage, seconds per call) of ``call()``, from cProfile, scaled to ``per_call``."""
    prof = cProfile.Profile()
    prof.enable()
    for _ in range(calls):
        call()
    prof.disable()
    st = pstats.Stats(prof)
    c = {label: _cum(st, suffix, name) for label, suffix, name in STAGES}
    lookup, caps = c[STAGES[1][0]], c[STAGES[2][0]]
    # the overlap check of solve itself; the integrator's check_state is part of its set-up
    state = _cum(st, "nbody/system.py", "check_overlap", caller="solve")
    setup, drive, loop = c[STAGES[4][0]], c[STAGES[5][0]], c[STAGES[6][0]]
    total = c[STAGES[0][0]]
    parts = [
        (STAGES[0][0], total - lookup - caps - state - setup),
        (STAGES[1][0], lookup), (STAGES[2][0], caps), (STAGES[3][0], state),
        (STAGES[4][0], setup - drive), (STAGES[5][0], drive - loop), (STAGES[6][0], loop),
    ]
    scale = per_call * calls / total
    return [(label, v * scale / calls) for label, v in parts]


def best_call(call, calls: int) -> tuple[float, float]:
    """(best, median) seconds of ``calls`` calls of ``call()``."""
    ts = np.empty(calls)
    for k in range(calls):
        t = time.perf_counter()
        call()
        ts[k] = time.perf_counter() - t
    return float(ts.min()), float(np.median(ts))


def rebound_leapfrog(m, x, v, h: float, n: int) -> float:
    """Seconds of REBOUND's leapfrog over ``n`` steps (set-up not timed)."""
    import rebound

    sim = rebound.Simulation()
    sim.G = 1.0
    for k in range(len(m)):
        sim.add(m=m[k], x=x[k, 0], y=x[k, 1], z=x[k, 2], vx=v[k, 0], vy=v[k, 1], vz=v[k, 2])
    sim.integrator = "leapfrog"
    sim.dt = h
    t = time.perf_counter()
    sim.integrate(n * h, exact_finish_time=0)
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--quick", action="store_true", help="300 calls, 3 rounds")
    args = ap.parse_args()
    if args.quick:
        args.calls, args.repeat = 300, 3
    m, x, v = outer_solar_system()
    system, y0 = poissonkit_system(m, x, v)
    h = 0.05 * YEAR
    few = 10

    # warm up: compile, first look-ups
    solve(system, y0, few * h, method="splitting2", step=h)
    plain_leapfrog(x.copy(), v.copy(), m, h, 10)

    def long_run(n: int) -> float:
        t = time.perf_counter()
        solve(system, y0, n * h, method="splitting2", step=h, save_every=max(1, n // 200))
        return time.perf_counter() - t

    per_step = min(long_run(20000) for _ in range(args.repeat)) / 20000
    rng = np.random.default_rng(1)
    states = [y0 * (1 + 1e-9 * rng.standard_normal(y0.size)) for _ in range(args.calls)]
    it = itertools.cycle(states)

    def same() -> object:
        return solve(system, y0, few * h, method="splitting2", step=h)

    def fresh() -> object:
        return solve(system, next(it), few * h, method="splitting2", step=h)

    print(f"solve overhead: outer Solar System (5 bodies), splitting2, {few} steps, "
          f"{args.calls} calls; one step costs {per_step * 1e6:.3f} us")
    for label, call in (("same initial state", same), ("new initial state each call", fresh)):
        best, med = best_call(call, args.calls)
        print(f"  {label:28s} call best {best * 1e3:.3f} ms  median {med * 1e3:.3f} ms  "
              f"fixed overhead {(best - few * per_step) * 1e3:.3f} ms  (target < 0.5 ms)")
    best, _ = best_call(fresh, args.calls)
    print("  breakdown (new initial state each call; cProfile, scaled to the best call):")
    for label, sec in breakdown(fresh, args.calls, best):
        print(f"    {label:52s} {sec * 1e6:7.1f} us  {100 * sec / best:5.1f} %")

    print(f"\nsplitting2 against REBOUND leapfrog, step 0.05 yr, whole solve call, best of "
          f"{args.repeat} interleaved rounds (ratios in one process)")
    for n in (20000, 200000):
        rb = pk = pl = math.inf
        for _ in range(args.repeat):
            rb = min(rb, rebound_leapfrog(m, x, v, h, n))
            pk = min(pk, long_run(n))
            xx, vv = x.copy(), v.copy()
            t = time.perf_counter()
            plain_leapfrog(xx, vv, m, h, n)
            pl = min(pl, time.perf_counter() - t)
        target = 1.3 if n == 20000 else 1.1
        print(f"  {n:7d} steps: REBOUND {rb / n * 1e9:6.1f} ns/step  poissonkit "
              f"{pk / n * 1e9:6.1f} ns/step  plain numba {pl / n * 1e9:6.1f} ns/step   "
              f"ratio splitting2 / REBOUND {pk / rb:.2f} (target <= {target})   "
              f"plain / REBOUND {pl / rb:.2f}")


if __name__ == "__main__":
    main()
