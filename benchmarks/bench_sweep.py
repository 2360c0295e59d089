"""Sweep throughput: runs per second of a seed-orbit sweep on 1 and 2 local Dask workers,
against the same runs in a plain Python loop in this process.

The sweep: spin ratio x tilt grid of the seed orbit (default 20 x 20 = 400 points), 20 orbital
periods per run, default outcomes (no MEGNO), batches chosen by the sweep. Measured in one
process, in this order:

1. the plain loop: :meth:`SeedScene.run` + the outcome reduction per point, after one warm-up
   run (the baseline: no Dask, no store), in this process;
2. for 1 and 2 workers: start a ``LocalCluster`` (timed separately, includes each worker's
   one-off build of the system and its kernels through a warm-up sweep of one point per worker),
   run the same plain loop inside one worker process (the baseline under the same scheduling
   as the sweep), then time the full sweep with a Zarr store.

Printed: runs/s of each, speed-up on 2 workers over 1, and the overhead of the sweep against the
loop at equal work per core (``t_sweep * workers / t_loop - 1``). On a machine that other jobs
share, the loop and the sweeps see different load; run it twice.

    python benchmarks/bench_sweep.py              # 20 x 20
    python benchmarks/bench_sweep.py --n 10       # 10 x 10, quicker
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
import time
from pathlib import Path

from poissonkit.sweeps import grid, sweep
from poissonkit.sweeps.execute import make_client
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, reduce_run
from poissonkit.sweeps.params import Design
from poissonkit_magnets.seed000_sweep import SeedScene


def plain_loop(scene: SeedScene, design: Design) -> float:
    """Wall time of every point in a plain loop in the calling process (system built and
    warmed up first, not timed)."""
    prep = scene.prepare()
    reduce_run(scene.run(prep, {"spin_ratio": 20.0, "tilt": 0.02}), DEFAULT_OUTCOMES)
    t0 = time.perf_counter()
    for _k, values in design.points():
        reduce_run(scene.run(prep, values), DEFAULT_OUTCOMES)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20, help="grid points per axis")
    ap.add_argument("--periods", type=float, default=20.0)
    ap.add_argument("--workers", default="1,2")
    args = ap.parse_args()
    axes = [grid("spin_ratio", 0.0, 30.0, args.n), grid("tilt", 0.0, 0.1, args.n)]
    design = Design(axes=tuple(axes))
    scene = SeedScene(periods=args.periods)
    print(f"{design.size} runs of {args.periods:g} periods; load average {os.getloadavg()}")
    t_loop = plain_loop(scene, design)
    print(f"plain loop, this process:   {t_loop:7.2f} s  {design.size / t_loop:7.1f} runs/s")

    tmp = Path(tempfile.mkdtemp(prefix="bench-sweep-"))
    rates = {}
    try:
        for w in (int(x) for x in args.workers.split(",")):
            t0 = time.perf_counter()
            client, close = make_client(workers=w)
            try:
                # one-off: every worker builds the seed system and compiles its kernels
                sweep(scene, {"tilt": [0.01 * k for k in range(w)]}, client=client,
                      progress=False, batch_size=1)
                t_start = time.perf_counter() - t0
                # baseline under the same conditions: the plain loop inside one worker process
                t_in_worker = client.submit(plain_loop, scene, design, pure=False).result()
                t0 = time.perf_counter()
                sweep(scene, list(axes), client=client, store=tmp / f"w{w}.zarr",
                      progress=False)
                t = time.perf_counter() - t0
            finally:
                close()
            rates[w] = design.size / t
            print(f"sweep, {w} worker(s):       {t:7.2f} s  {rates[w]:7.1f} runs/s   "
                  f"cluster start + warm-up {t_start:.1f} s; plain loop in a worker "
                  f"{t_in_worker:.2f} s; overhead at equal work per core "
                  f"{100 * (t * w / t_in_worker - 1):+.0f} % (vs this process's loop "
                  f"{100 * (t * w / t_loop - 1):+.0f} %)")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if 1 in rates and 2 in rates:
        print(f"speed-up 2 workers / 1 worker: {rates[2] / rates[1]:.2f}x")
    print(f"load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
