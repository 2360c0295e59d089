"""Cost of one kick, right-hand side and energy of a system of tops (issue 33, first bullet).

A kick of two tops used to cost three times its pair formula: the general kernels read their
arrays out of the named kernel data, and numba counted references to each (an atomic increment
and decrement per read) without being able to prune them across the call of a potential too
large to inline. The kernels of a sum of force terms that allocate nothing are now compiled
without reference counts (:mod:`poissonkit.numerics.nbody.assemble`), and so is the pair term
those loops call per pair; this benchmark times them against the same kernels with the counts
(``assemble(..., counted=True)`` around the pair term compiled as before: the code as it was),
in the same process, interleaved, and checks that both give the same numbers bit for bit.

Cases (internal units):

* ``seed``: seed 000 as an :class:`~poissonkit.numerics.nbody.NBodySystem`, two tops with the
  dumbbell potential (``poissonkit_magnets.seed000.nbody_system``);
* ``dipole-N`` / ``dumbbell-N``: ``N`` = 2, 3, 10 tops on a ring, one ``AllPairs`` of the
  registry's ``dipole`` / ``dumbbell`` potential, no cutoff (the encounter benchmarks' sizes);
* ``cluster-N``: ``N`` = 10³ (``--cluster``) dipolar spheres with a hard core and a cutoff on a
  jittered cubic lattice (cell lists): the large-N path, which keeps its reference counts
  (its cell list allocates), so both columns are the same compiled kernels and the ratio
  must be 1.

Every figure is the best of ``--repeat`` runs of a compiled loop of ``--calls`` calls, in thread
CPU time (``time.thread_time``), divided by the number of calls: ns per call as a compiled time
loop sees it. Run::

    python benchmarks/bench_tops_kick.py                  # all cases
    python benchmarks/bench_tops_kick.py --quick          # fewer calls and repeats
    python benchmarks/bench_tops_kick.py --cluster 4096   # a larger cluster (16³)

A last table splits a step of ``solve(..., "splitting8_bce")`` into its drifts and kicks
(:func:`bench_breakdown`): what the time loop adds per stage beyond the two calls.
"""

from __future__ import annotations

import argparse
import copy
import time
from collections.abc import Callable

import numpy as np

from poissonkit.numerics import AllPairs, Body, NBodySystem
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import Kernels
from poissonkit.numerics.nbody.assemble import assemble
from poissonkit.numerics.nbody.loops import _build_kernels, _no_cell_loop, force_loops
from poissonkit.numerics.nbody.pairkernels import _dispatcher
from poissonkit.numerics.nbody.pairterms import pair_terms
from poissonkit.numerics.nbody.state import GENERAL

#: the three kernels timed, as ``name -> loop(kernels) -> f(y, data, work, out, n)``
_loops: dict[str, Callable[[Kernels], Callable[..., float]]] = {}


def _loop(kind: str) -> Callable[[Callable[[Kernels], Callable[..., float]]],
                                 Callable[[Kernels], Callable[..., float]]]:
    def register(make: Callable[[Kernels], Callable[..., float]]
                 ) -> Callable[[Kernels], Callable[..., float]]:
        _loops[kind] = make
        return make
    return register


@_loop("kick")
def _kick_loop(k: Kernels) -> Callable[..., float]:
    kick = k.kick

    @jit
    def run(y, data, work, out, n):
        for _ in range(n):
            kick(y, 1e-12, data, work)
        return y[0]
    return run


@_loop("rhs")
def _rhs_loop(k: Kernels) -> Callable[..., float]:
    rhs = k.rhs

    @jit
    def run(y, data, work, out, n):
        for _ in range(n):
            rhs(y, data, work, out)
        return out[0]
    return run


@_loop("energy")
def _energy_loop(k: Kernels) -> Callable[..., float]:
    energy = k.energy

    @jit
    def run(y, data, work, out, n):
        e = 0.0
        for _ in range(n):
            e += energy(y, data, work)
        return e
    return run


def ring(n: int, potential: str) -> tuple[NBodySystem, np.ndarray]:
    """``n`` magnets (1 cm, 0.1 A m², 10 g) on a ring of 5 cm radius, tilted axes, SI."""
    from poissonkit.plugin import potential as lookup

    pot = lookup(potential)
    params = {"moment1": 0.1, "moment2": 0.1}
    if potential == "dumbbell":
        params |= {"half_length1": 0.005, "half_length2": 0.005}
    bodies = [Body(f"m{k}", mass=0.01, alpha=1e3) for k in range(n)]
    s = NBodySystem(bodies, [AllPairs(pot, params)])
    th = 2 * np.pi * np.arange(n) / n
    pos = 0.05 * np.stack([np.cos(th), np.sin(th), 0.1 * np.sin(3 * th)], axis=1)
    axes = np.stack([np.cos(th + 1.0), np.sin(th + 1.0), 0.3 * np.ones(n)], axis=1)
    rng = np.random.default_rng(3)
    return s, s.pack(pos, 1e-3 * rng.standard_normal((n, 3)), axes,
                     1e-6 * rng.standard_normal((n, 3)), normalize=True)


def seed() -> tuple[NBodySystem, np.ndarray]:
    """Seed 000 as two tops (the circular orbit, axes tilted by 0.05 rad)."""
    from poissonkit_magnets.seed000.two_body import nbody_system

    s = nbody_system()
    tilt = np.array([0.0, np.sin(0.05), np.cos(0.05)])
    y = s.pack(np.array([[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0]]), np.array([[0, -1.0, 0], [0, 1.0, 0]]),
               np.stack([tilt, tilt]), np.array([[0, 0, 20.0], [0, 0, 20.0]]), normalize=True)
    return s, y


def cluster(n: int) -> tuple[NBodySystem, np.ndarray]:
    """About ``n`` dipolar spheres, ``(c3 − 3 c1 c2)/(20 r³) + 1/r⁹``, cutoff 2, on a jittered
    cubic lattice of spacing 1.1 (cell lists; the dipole benchmark of the parallel loops)."""
    import sympy as sp

    side = max(2, round(n ** (1 / 3)))
    r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
    pot = (c3 - 3 * c1 * c2) / (20 * r**3) + 1 / r**9
    m = side ** 3
    s = NBodySystem([Body(f"d{k}", 1.0, 1.0) for k in range(m)], [AllPairs(pot)],
                    cutoff=2.0, parallel=False)
    rng = np.random.default_rng(5)
    g = np.stack(np.meshgrid(*[np.arange(side)] * 3, indexing="ij"), -1).reshape(-1, 3)
    pos = 1.1 * g + 0.05 * rng.standard_normal((m, 3))
    axes = rng.standard_normal((m, 3))
    return s, s.pack(pos, 0.1 * rng.standard_normal((m, 3)), axes,
                     0.1 * rng.standard_normal((m, 3)), normalize=True)


def baseline(s: NBodySystem) -> Kernels:
    """The system's kernels as they were: compiled with numba's reference counts, and the pair
    term that the loops without cutoff call per pair too (now compiled without them)."""
    ka, kr = _dispatcher(s._kerns, s._rkerns)
    if s.cutoff is not None:  # the cell-list path: the same kernels as s.kernels
        return _build_kernels(ka, kr, parallel=False, verlet=s.skin is not None, counted=True)
    pt = pair_terms(ka, kr)
    counted_pair = jit(pt.term.py_func)  # as pair_terms compiled it before
    return assemble(GENERAL, (force_loops(counted_pair, pt.radial, pt.all_radial,
                                          _no_cell_loop),), counted=True)


def time_call(run: Callable[..., float], args: tuple, calls: int, repeat: int) -> float:
    """Best thread CPU time per call [ns] of ``run(*args, calls)``."""
    run(*args, 2)
    best = np.inf
    for _ in range(repeat):
        t = time.thread_time()
        run(*args, calls)
        best = min(best, time.thread_time() - t)
    return best / calls * 1e9


def same_numbers(s: NBodySystem, y: np.ndarray, old: Kernels, new: Kernels) -> bool:
    """Kick, rhs and energy of both kernel sets agree to the bit at ``y``."""
    out = []
    for k in (old, new):
        yk = y.copy()
        k.kick(yk, 1e-3, s.data, s.work())
        r = np.empty_like(y)
        k.rhs(y, s.data, s.work(), r)
        out.append((yk, r, np.array([k.energy(y, s.data, s.work())])))
    return all(a.tobytes() == b.tobytes() for a, b in zip(*out))


def bench(name: str, s: NBodySystem, y: np.ndarray, calls: int, repeat: int) -> None:
    old, new = baseline(s), s.kernels
    cells = [f"{name:13s} {len(s.bodies):5d}"]
    for kind, make in _loops.items():
        runs = {"old": make(old), "new": make(new)}
        best = {"old": np.inf, "new": np.inf}
        for _ in range(3):  # interleaved, so that a load change hits both
            for key, run in runs.items():
                args = (y.copy(), s.data, s.work(), np.empty_like(y))
                best[key] = min(best[key], time_call(run, args, calls, repeat))
        cells.append(f"{best['old']:9.1f} {best['new']:9.1f} {best['new'] / best['old']:6.2f}")
    same = same_numbers(s, y, old, new)
    print(" | ".join(cells) + f" | {'yes' if same else 'NO'}", flush=True)


def bench_steps(name: str, s: NBodySystem, y: np.ndarray, steps: int, repeat: int) -> None:
    """``solve`` with ``splitting8_bce`` (the encounters' method): CPU time per force
    evaluation (``Solution.nfev``), drift and loop included, old kernels against new (two
    copies of the system)."""
    from poissonkit.numerics import solve

    old = copy.copy(s)
    old._kernels = baseline(s)  # the same system with the kernels as they were
    best = {"old": np.inf, "new": np.inf}
    finals = {}
    kw = dict(method="splitting8_bce", step=1e-3, save_every=steps)
    for _ in range(repeat):
        for key, system in (("old", old), ("new", s)):
            solve(system, y, 1e-4 * steps, **kw)  # compiled and warm
            t = time.thread_time()
            sol = solve(system, y, 1e-3 * steps, **kw)
            best[key] = min(best[key], time.thread_time() - t)
            finals[key] = np.asarray(sol.y)[-1]
            evals = sol.nfev
    same = finals["old"].tobytes() == finals["new"].tobytes()
    print(f"{name:13s} {len(s.bodies):5d} | {best['old'] / evals * 1e9:9.1f} "
          f"{best['new'] / evals * 1e9:9.1f} {best['new'] / best['old']:6.2f} | "
          f"{'yes' if same else 'NO'}", flush=True)


def _stage_loops(k: Kernels) -> dict[str, Callable[..., float]]:
    """Compiled loops of ``n`` drifts, kicks and stages (a drift then a kick) of ``k``."""
    drift, kick = k.drift, k.kick

    @jit
    def drifts(y, data, work, n):
        for _ in range(n):
            drift(y, 1e-12, data)
        return y[0]

    @jit
    def kicks(y, data, work, n):
        for _ in range(n):
            kick(y, 1e-12, data, work)
        return y[0]

    @jit
    def stages(y, data, work, n):
        for _ in range(n):
            drift(y, 1e-12, data)
            kick(y, 1e-12, data, work)
        return y[0]
    return {"drift": drifts, "kick": kicks, "stage": stages}


def bench_breakdown(name: str, s: NBodySystem, y: np.ndarray, calls: int, steps: int,
                    repeat: int) -> None:
    """Where a step of ``splitting8_bce`` goes (19 stages of a drift and a kick): ns per drift,
    per kick and per stage in a bare compiled loop, then per force evaluation of ``solve``;
    the last column (solve less the bare stage) is what the time loop adds per stage."""
    from poissonkit.numerics import solve

    best = {}
    for key, run in _stage_loops(s.kernels).items():
        best[key] = time_call(run, (y.copy(), s.data, s.work()), calls, repeat)
    kw = {"method": "splitting8_bce", "step": 1e-3, "save_every": steps}
    t_solve = np.inf
    for _ in range(repeat):
        solve(s, y, 1e-3 * max(steps // 10, 1), **kw)  # compiled and warm
        t = time.thread_time()
        sol = solve(s, y, 1e-3 * steps, **kw)
        t_solve = min(t_solve, time.thread_time() - t)
    per_eval = t_solve / sol.nfev * 1e9
    print(f"{name:13s} {len(s.bodies):5d} | {best['drift']:9.1f} {best['kick']:9.1f} "
          f"{best['stage']:9.1f} | {per_eval:9.1f} {per_eval - best['stage']:9.1f}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer calls and repeats")
    ap.add_argument("--cluster", type=int, default=1000, help="bodies of the large-N case")
    ap.add_argument("--repeat", type=int, default=7)
    a = ap.parse_args()
    calls, repeat = (20_000, 3) if a.quick else (200_000, a.repeat)
    print("ns per call, best of the runs (thread CPU time); old = with reference counts")
    print(f"{'case':13s} {'N':>5s} | {'kick old':>9s} {'new':>9s} {'ratio':>6s} | "
          f"{'rhs old':>9s} {'new':>9s} {'ratio':>6s} | {'energy old':>9s} {'new':>9s} "
          f"{'ratio':>6s} | same bits")
    bench("seed", *seed(), calls, repeat)
    for pot in ("dipole", "dumbbell"):
        for n in (2, 3, 10):
            bench(f"{pot}-{n}", *ring(n, pot), max(calls // (n * n // 4 + 1), 1000), repeat)
    print("\nsolve, splitting8_bce: ns per kick (drift, loop and solve's set-up included)")
    print(f"{'case':13s} {'N':>5s} | {'old':>9s} {'new':>9s} {'ratio':>6s} | same bits")
    bench_steps("seed", *seed(), 2000 if a.quick else 20000, repeat)
    bench_steps("dipole-3", *ring(3, "dipole"), 2000 if a.quick else 20000, repeat)
    print("\nwhere a step goes (new kernels): ns per drift, kick, stage; solve per evaluation")
    print(f"{'case':13s} {'N':>5s} | {'drift':>9s} {'kick':>9s} {'stage':>9s} | "
          f"{'solve':>9s} {'loop':>9s}")
    for name, (s, y) in (("seed", seed()), ("dipole-3", ring(3, "dipole")),
                         ("dumbbell-3", ring(3, "dumbbell")), ("dipole-10", ring(10, "dipole"))):
        n = len(s.bodies)
        bench_breakdown(name, s, y, max(calls // (n * n // 4 + 1), 1000),
                        max((200 if a.quick else 2000) * 10 // (n * n // 4 + 1), 20), repeat)
    s, y = cluster(a.cluster)
    bench_breakdown(f"cluster-{len(s.bodies)}", s, y, 3, 3, min(repeat, 3))
    bench(f"cluster-{len(s.bodies)}", s, y, max(calls // len(s.bodies) // 20, 3), repeat)


if __name__ == "__main__":
    main()
