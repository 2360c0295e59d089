"""Cost of what ``poissonkit run`` adds to a plain ``solve``: the scene's default contact event
(located events keep the two previous states and the smallest distance per step) and the
stop-request chunking (SIGINT). Ratio against a plain run of the same scene, same process.

Usage: ``python benchmarks/bench_run_controls.py``
"""

from __future__ import annotations

import time
from pathlib import Path

from poissonkit.numerics import solve
from poissonkit.scene import build_run, load_scene

ROOT = Path(__file__).resolve().parents[1]


def best_of(n: int, fn) -> float:
    best = float("inf")
    for _ in range(n):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def main() -> None:
    for name in ("two_magnets", "magnet_chain"):
        spec = build_run(load_scene(ROOT / "poissonkit" / "scene" / "shipped" / f"{name}.toml"))
        h = spec.step / 200  # long enough that per-run overheads do not dominate

        def plain():
            solve(spec.system, spec.y0, spec.t_end, spec.method, step=h, save_every=100)

        def controlled():
            solve(spec.system, spec.y0, spec.t_end, spec.method, step=h, save_every=100,
                  events=spec.events, stop=lambda: False)

        controlled()  # compile both variants first
        plain()
        a, b = best_of(3, plain), best_of(3, controlled)
        steps = round(spec.t_end / h)
        print(f"{name}: {steps} steps, plain {a:.3f} s, contact event + stop chunks {b:.3f} s, "
              f"ratio {b / a:.3f}")


if __name__ == "__main__":
    main()
