"""One compiled force evaluation of N dipolar tops with a cutoff, N = 1e3 … 1e5 at fixed density.

Usage::

    python benchmarks/bench_nbody.py [--max-n 100000] [--density 1.0] [--cutoff 2.5]

Prints the time of one right-hand-side evaluation (forces + torques + kinematics) per N, the
CPU time per body, and the ratio t(N)/t(N0) of CPU times against N/N0 (linear scaling means the two agree).
The target: N = 1e4 in <= 50 ms on a 2-core machine.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import sympy as sp

from poissonkit.numerics import AllPairs, Body, NBodySystem

R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)
DIPOLE = (C3 - 3 * C1 * C2) / R**3


def system_of(n: int, density: float, cutoff: float, seed: int = 0):
    rng = np.random.default_rng(seed)
    side = (n / density) ** (1 / 3)
    pos = rng.uniform(0, side, size=(n, 3))
    nu = rng.normal(size=(n, 3))
    nu /= np.linalg.norm(nu, axis=1)[:, None]
    bodies = [Body(f"b{k}", 1.0, 1.0) for k in range(n)]
    sys = NBodySystem(bodies, [AllPairs(DIPOLE)], cutoff=cutoff)
    y = sys.pack(pos, rng.normal(size=(n, 3)), nu, rng.normal(size=(n, 3)))
    return sys, y


def time_rhs(sys, y, repeat: int) -> float:
    out = np.empty_like(y)
    work = sys.work()
    k = sys.kernels
    k.rhs(y, sys.data, work, out)  # compile / warm up
    best = cpu = np.inf
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        k.rhs(y, sys.data, work, out)
        best = min(best, time.perf_counter() - t)
        cpu = min(cpu, time.process_time() - c)
    return best, cpu


def count_pairs(sys, y, cutoff: float) -> int:
    """Pairs closer than the cutoff (scipy KD-tree; independent of the cell list)."""
    from scipy.spatial import cKDTree

    r = sys.unpack(y)["r"]
    return len(cKDTree(r).query_pairs(cutoff))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-n", type=int, default=100_000)
    ap.add_argument("--density", type=float, default=1.0)
    ap.add_argument("--cutoff", type=float, default=2.5)
    args = ap.parse_args()
    ns = [n for n in (1_000, 3_000, 10_000, 30_000, 100_000) if n <= args.max_n]
    print(f"density {args.density} per unit volume, cutoff {args.cutoff} "
          f"(~{4 / 3 * np.pi * args.cutoff**3 * args.density:.0f} neighbours per body)")
    print(f"{'N':>8} {'wall [ms]':>10} {'cpu [ms]':>9} {'us/body':>9} {'t/t0':>8} {'N/N0':>8} "
          f"{'pairs<rc':>10}")
    t0 = None
    for n in ns:
        sys, y = system_of(n, args.density, args.cutoff)
        t, cpu = time_rhs(sys, y, repeat=5 if n <= 30_000 else 3)
        t0 = t0 or cpu
        pairs = count_pairs(sys, y, args.cutoff)
        print(f"{n:>8} {1e3 * t:>10.2f} {1e3 * cpu:>9.2f} {1e6 * cpu / n:>9.2f} {cpu / t0:>8.2f} "
              f"{n / ns[0]:>8.1f} {pairs:>10}")


if __name__ == "__main__":
    main()
