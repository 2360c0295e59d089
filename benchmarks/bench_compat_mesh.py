"""Mesh evaluation: poissonkit.compat.NumPoissonGeometry vs numericalpoissongeometry (same process).

Times the Hamiltonian vector field (``num_hamiltonian_vf``) and the Poisson bracket
(``num_poisson_bracket``) on ``--points`` random points (default 10^5). The baseline,
NumericalPoissonGeometry 1.1.2, evaluates point by point in a Python loop; running it on 10^5
points takes minutes, so it is timed on ``n1 = --baseline-points`` (default 2000) and
``n2 = 10 n1`` points (best of two runs each) and extrapolated linearly from those two sizes:
``t(N) = t(n2) + (N - n2) (t(n2) - t(n1)) / (n2 - n1)`` — its fixed set-up cost (sympy
differentiation and simplification) is counted once, not multiplied. Ours runs on the full mesh
and is timed twice: *cold* (a fresh instance each time: parsing, symbolic derivation, lambdify,
evaluation; best of two) and *warm* (compiled function cached by a first call, evaluation only;
best of ``--repeat``). Both sides first run once on the small mesh to check that they agree, so
sympy's internal caches are equally warm for both.

Run::

    python benchmarks/bench_compat_mesh.py            # 10^5 points, baseline on 2000 and 20000
    python benchmarks/bench_compat_mesh.py --points 100000 --baseline-points 1000

Needs ``pip install numericalpoissongeometry`` (bench/test extra).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

CASES = [
    # (name, dim, bivector, H, G)
    ("so(3), rational H (NPG docs)", 3,
     {(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"},
     "1/(x1 - x2) + 1/(x1 - x3) + 1/(x2 - x3)", "x1*x2 + x3**2"),
    ("e(3), heavy top", 6,
     {(1, 5): "x3", (1, 6): "-x2", (2, 4): "-x3", (2, 6): "x1", (3, 4): "x2", (3, 5): "-x1",
      (4, 5): "x6", (4, 6): "-x5", (5, 6): "x4"},
     "x4**2/2 + x5**2/3 + x6**2/4 + x3", "x1*x4 + x2*x5 + x3*x6 + x4**2"),
    ("quadratic on R^4, exp/sin", 4,
     {(1, 2): "x1*x2", (1, 3): "-x1*x3", (2, 3): "x2*x3", (3, 4): "1", (1, 4): "x4**2"},
     "exp(x1)*sin(x2) + x3*x4", "x1**2 + cos(x4)"),
]


def _time(fn, repeat: int = 1) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--baseline-points", type=int, default=2_000)
    ap.add_argument("--repeat", type=int, default=3, help="best of N for the warm timing")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    try:
        from numpoisson.numpoisson import NumPoissonGeometry as Baseline
    except ImportError:
        print("numericalpoissongeometry is not installed: pip install numericalpoissongeometry")
        return 2
    from poissonkit.compat import NumPoissonGeometry

    rng = np.random.default_rng(args.seed)
    n1 = args.baseline_points
    n2 = 10 * n1
    print(f"mesh: {args.points} points (ours); baseline timed on {n1} and {n2} points and "
          f"extrapolated linearly to {args.points}")
    header = (f"{'case':30s} {'method':20s} {'base t(n1)':>10s} {'base t(n2)':>10s} "
              f"{'base est.':>9s} {'ours cold':>9s} {'ours warm':>9s} {'ratio cold':>10s} "
              f"{'ratio warm':>10s}")
    print(header)
    print("-" * len(header))
    worst = float("inf")
    for name, dim, biv, H, G in CASES:
        mesh = rng.uniform(0.5, 1.5, (args.points, dim)) + 2.0 * np.arange(dim)  # no poles
        small, medium = mesh[:n1], mesh[:n2]
        base = Baseline(dim)
        methods = {
            "num_hamiltonian_vf": (lambda obj, m: obj.num_hamiltonian_vf(biv, H, m)),
            "num_poisson_bracket": (lambda obj, m: obj.num_poisson_bracket(biv, H, G, m)),
        }
        for method, call in methods.items():
            # correctness first: same numbers on the baseline's mesh
            ref = call(base, small)
            got = call(NumPoissonGeometry(dim), small)
            if not np.allclose(ref, got, rtol=1e-9, atol=1e-12):
                print(f"MISMATCH in {name} {method}")
                return 1
            t1 = _time(lambda: call(Baseline(dim), small), 2)
            t2 = _time(lambda: call(Baseline(dim), medium), 2)
            marginal = max(t2 - t1, 0.0) / (n2 - n1)
            t_base_full = t2 + (args.points - n2) * marginal
            t_cold = _time(lambda: call(NumPoissonGeometry(dim), mesh), 2)
            warm = NumPoissonGeometry(dim)
            call(warm, mesh[:10])
            t_warm = _time(lambda: call(warm, mesh), args.repeat)
            r_cold, r_warm = t_base_full / t_cold, t_base_full / t_warm
            worst = min(worst, r_cold)
            print(f"{name:30s} {method:20s} {t1:9.2f}s {t2:9.2f}s {t_base_full:8.1f}s "
                  f"{t_cold:8.3f}s {t_warm:8.4f}s {r_cold:9.0f}x {r_warm:9.0f}x")
        sys.stdout.flush()
    print(f"smallest cold ratio (including symbolic derivation and compilation): {worst:.0f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
