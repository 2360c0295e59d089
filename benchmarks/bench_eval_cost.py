"""Where the cost of one force evaluation of two tops goes (issue 33, "Tops on the lean path").

Times, in the same process, the compiled pieces of one evaluation of the seed's two-body system
(:func:`poissonkit_magnets.seed000.two_body.two_body_system`: two dumbbells): the pair kernel
alone (scaled to internal units, as the kick calls it), ``forces``, the kick, the drift,
``sin`` + ``cos`` and ``1/sqrt`` as dependency chains (their latency), and a full run of
``splitting8_bce`` per force evaluation (drift included: the figure that matters). Each piece is
a compiled loop of ``--calls`` calls, timed by the thread's CPU time, best of ``--repeat``, also
given as a ratio to an empty compiled loop measured alongside::

    PYTHONPATH=$PWD:$PWD/plugins python benchmarks/bench_eval_cost.py
    PYTHONPATH=$PWD:$PWD/plugins python benchmarks/bench_eval_cost.py --against f063eb9
    PYTHONPATH=$PWD:$PWD/plugins python benchmarks/bench_eval_cost.py --against f063eb9 \
        --step-only --rounds 25 --repeat 3

``--against REV`` also builds the same system with the files of git revision ``REV``
(``twobody.py``, ``kernels.py``, the scaled wrapper and the dumbbell core, loaded as separate
modules; the kernel cache is off for the process) and measures old then new ``--rounds`` times:
the median of the per-round ratios old/new is the load-robust figure to quote on a shared
machine.
"""

from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import time
import types
from pathlib import Path

import numba
import numpy as np

from poissonkit.numerics.solver import solve
from poissonkit_magnets import seed000


@numba.njit
def _empty(n, y):
    s = 0.0
    for i in range(n):
        s += y[i & 7]
    return s


@numba.njit
def _loop_kernel(kern, n, r0):
    s = 0.0
    for i in range(n):
        r = r0 * (1.0 + 1e-9 * (i & 7))
        u, ur, u1, u2, u3 = kern(r, 0.3, -0.2, 0.9)
        s += u + ur + u1 + u2 + u3
    return s


@numba.njit
def _loop_kick(kick, n, y, data, work):
    for i in range(n):
        kick(y, 1e-12 if i & 1 else -1e-12, data, work)
    return y[3]


@numba.njit
def _loop_drift(drift, n, y, data):
    for i in range(n):
        drift(y, 1e-6 if i & 1 else -1e-6, data)
    return y[0]


@numba.njit
def _loop_forces(forces, n, y, data, work):
    s = 0.0
    for i in range(n):
        y[0] += 1e-15 if i & 1 else -1e-15
        s += forces(y, data, work)
    return s


@numba.njit(error_model="numpy")
def _loop_sincos(n, th):
    # each argument depends on the last result: latency, as in a drift's rotation
    s = 0.0
    for i in range(n):
        t = th + 1e-20 * s
        s += math.sin(t) + math.cos(t)
    return s


@numba.njit(error_model="numpy")
def _loop_sqrt_div(n, x):
    s = 0.0
    for i in range(n):
        t = x + 1e-20 * s
        s += 1.0 / math.sqrt(t)
    return s


def _best(call, repeat: int) -> float:
    call()  # compile / warm
    best = math.inf
    for _ in range(repeat):
        c = time.thread_time()
        call()
        best = min(best, time.thread_time() - c)
    return best


ROOT = Path(__file__).resolve().parents[1]
#: module name -> file, of the pieces an evaluation of two tops runs through
PIECES = {"kernels": "poissonkit/numerics/kernels.py",
          "potentials": "poissonkit/numerics/potentials.py",
          "analytic": "plugins/poissonkit_magnets/analytic.py",
          "twobody": "poissonkit/numerics/twobody.py"}


def _load_old(rev: str) -> dict[str, types.ModuleType]:
    """The :data:`PIECES` of git revision ``rev`` as fresh modules; ``twobody`` and
    ``potentials`` import the old ``kernels``."""
    mods: dict[str, types.ModuleType] = {}
    for name, path in PIECES.items():
        src = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{path}"], check=True,
                             capture_output=True, text=True).stdout
        src = src.replace("cache=True", "cache=False")  # no file to cache against
        if name in ("twobody", "potentials"):
            src = src.replace("from poissonkit.numerics.kernels import",
                              "from _old_kernels import")
        mod = types.ModuleType(f"_old_{name}")
        mod.__file__ = f"<{rev}:{path}>"
        sys.modules[mod.__name__] = mod
        exec(compile(src, mod.__file__, "exec"), mod.__dict__)  # noqa: S102 - our own git tree
        if name == "twobody":
            # the current data classes: a numba cache pickles argument types by module name,
            # and a type of this unimportable module would spoil the on-disk indexes
            from poissonkit.numerics import twobody

            mod.TwoBodyData, mod.TwoBodyWork = twobody.TwoBodyData, twobody.TwoBodyWork
        mods[name] = mod
    return mods


def old_system(rev: str):
    """The seed encounter's two-body system with the kernels of revision ``rev`` (the kernel
    cache is switched off for this process: old and new closures share names)."""
    import os

    from poissonkit.numerics.jit import CACHE_ENV

    os.environ[CACHE_ENV] = "off"
    from poissonkit_magnets.models import _dumbbell_fold
    from poissonkit.numerics.jit import jit

    mods = _load_old(rev)
    spec = seed000.default_run(periods=10, tilt=0.01, momentum_factor=0.8)
    system = spec.system
    t = seed000.parameter_table()
    fold = _dumbbell_fold(float(t.mu), float(t.mu), float(t.l), float(t.l), float(t.mu0))
    core = mods["analytic"].dumbbell_core_k

    @jit(error_model="python")
    def si(r, c1, c2, c3):
        return core(r, c1, c2, c3, *fold)

    scales = system.scales
    kern = mods["potentials"].scaled_kernel(si, scales.length, scales.energy)
    old = mods["twobody"].TwoBodySystem.__new__(mods["twobody"].TwoBodySystem)
    old.__dict__.update(system.__dict__)
    old._kern = kern
    old._kernels = mods["twobody"]._build(kern)
    return spec, old


def measure(calls: int, repeat: int, run_step: float = 0.05, system=None,
            step_only: bool = False) -> dict[str, float]:
    """ns per call of each piece (thread CPU time, best of ``repeat``) and ``"empty"``; with
    ``step_only`` the full splitting step alone."""
    spec = seed000.default_run(periods=10, tilt=0.01, momentum_factor=0.8)
    system = system or spec.system
    t_end = float(spec.t_end)

    def run():
        return solve(system, spec.y0, t_end, method="splitting8_bce", step=run_step,
                     save_every=10**9)

    if step_only:
        return {"splitting8_bce per evaluation": _best(run, repeat) / run().nfev * 1e9}
    k = system.kernels
    y = np.array(spec.y0, dtype=float)
    data, work = system.data, system.work()
    r0 = float(np.linalg.norm(y[:3]))
    ns = {}
    ns["empty"] = _best(lambda: _empty(calls, y), repeat) / calls * 1e9
    ns["potential (scaled)"] = _best(lambda: _loop_kernel(system._kern, calls, r0),
                                     repeat) / calls * 1e9
    ns["forces (partials)"] = _best(lambda: _loop_forces(k.forces, calls, y.copy(), data, work),
                                    repeat) / calls * 1e9
    ns["kick"] = _best(lambda: _loop_kick(k.kick, calls, y.copy(), data, work),
                       repeat) / calls * 1e9
    ns["drift"] = _best(lambda: _loop_drift(k.drift, calls, y.copy(), data), repeat) / calls * 1e9
    ns["sin + cos (latency)"] = _best(lambda: _loop_sincos(calls, 0.3), repeat) / calls * 1e9
    ns["1/sqrt (latency)"] = _best(lambda: _loop_sqrt_div(calls, 0.3), repeat) / calls * 1e9
    nfev = run().nfev
    ns["splitting8_bce per evaluation"] = _best(run, max(3, repeat // 3)) / nfev * 1e9
    return ns


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=100_000, help="calls per compiled loop")
    ap.add_argument("--repeat", type=int, default=9, help="best of this many loops")
    ap.add_argument("--against", metavar="REV", default=None,
                    help="also time the kernels of git revision REV; print old/new ratios")
    ap.add_argument("--step-only", action="store_true",
                    help="time the full splitting step only (more rounds per minute)")
    ap.add_argument("--rounds", type=int, default=7,
                    help="with --against: measure old then new this many times")
    args = ap.parse_args()
    if args.against is None:
        ns = measure(args.calls, args.repeat, step_only=args.step_only)
        base = ns["empty"]
        print(f"{'piece':32s} {'ns/call':>9s} {'/ empty loop':>13s}")
        for name, v in ns.items():
            print(f"{name:32s} {v:9.1f} {v / base:13.1f}")
        return
    _, old = old_system(args.against)
    rounds: list[tuple[dict[str, float], dict[str, float]]] = []
    for _ in range(args.rounds):  # old and new back to back: each round sees one load
        rounds.append((measure(args.calls, args.repeat, system=old, step_only=args.step_only),
                       measure(args.calls, args.repeat, step_only=args.step_only)))
    print(f"{'piece':32s} {args.against + ' ns':>12s} {'now ns':>9s} {'old/now':>8s} "
          f"{'range':>12s}   (best of each; ratio: median over {args.rounds} rounds)")
    for name in rounds[0][1]:
        ratios = sorted(o[name] / n[name] for o, n in rounds)
        was = min(o[name] for o, _ in rounds)
        now = min(n[name] for _, n in rounds)
        print(f"{name:32s} {was:12.1f} {now:9.1f} {statistics.median(ratios):8.2f} "
              f"{ratios[0]:5.2f}-{ratios[-1]:.2f}")

if __name__ == "__main__":
    main()
