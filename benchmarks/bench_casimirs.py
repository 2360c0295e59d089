"""Casimir finding and rank on seed 000's 18-dim structure: block-wise vs monolithic.

Run: ``python benchmarks/bench_casimirs.py``. Prints wall times and the ratio of the monolithic
baseline (the whole 18x18 system solved at once, in the same process) to poissonkit's
block-wise path.
"""

from __future__ import annotations

import time

from poissonkit.structure import canonical, direct_sum, e3
from poissonkit.structure.casimirs import _block_casimirs, find_casimirs, rank


def _best(fn, repeat: int = 3) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    P = direct_sum(("orbit", canonical(3, "r", "p")), ("top1", e3()), ("top2", e3()))
    fast = _best(lambda: find_casimirs(P, 2))
    slow = _best(lambda: _block_casimirs(P, list(P.coords), 2), repeat=1)
    print(f"find_casimirs(18-dim, degree 2): {fast:.3f} s; monolithic baseline {slow:.3f} s; "
          f"ratio {slow / fast:.1f}x")
    r = _best(lambda: rank(P, seed=0))
    print(f"rank(18-dim) generic (2 trials): {r:.3f} s")
    P3 = find_casimirs(e3(), 3)
    t3 = _best(lambda: find_casimirs(e3(), 3))
    print(f"find_casimirs(e3, degree 3): {t3:.3f} s -> {len(P3)} generators")


if __name__ == "__main__":
    main()
