"""A dipolar-sphere lattice on LAMMPS with 1 and 2 MPI ranks: wall time, CPU time, loop time.

Usage::

    python benchmarks/bench_lammps_ranks.py [--side 20] [--steps 300] [--ranks 1 2]
        [--repeat 2]

The scene is ``side³`` dipolar spheres (NdFeB balls as in ``examples/dipole_lattice_100k.toml``:
moment 0.155 A m², all axes along +z) on a cubic lattice of spacing 3 cm, every pair within the
0.1 m cutoff interacting through the ``dipole`` potential (73 pairs per body in LAMMPS's half
list), run for ``--steps`` steps of 0.1 ms by ``poissonkit.engines.run_lammps`` — what
``poissonkit run SCENE --engine lammps --ranks N`` does — with each rank count in turn,
interleaved ``--repeat`` times. For each run it prints:

* ``loop``: LAMMPS's own "Loop time" (the steps, their dumps included), the figure LAMMPS's
  published benchmarks compare (https://www.lammps.org/bench.html);
* ``wall``: the whole call (starting ``mpirun`` and the ranks, reading the data, the steps,
  reading the dump back);
* ``cpu``: the CPU time of the worker processes (user + system, all ranks together): on a
  machine with free cores, 2 ranks should spend about the CPU time of 1 rank;

then the best loop time per rank count, the speed-up of the best 2-rank loop over the best
1-rank loop, and the largest relative difference of the final states of 1 and 2 ranks
(round-off of the summation order). The load average is printed first: with fewer free cores
than ranks, the speed-up says nothing about LAMMPS (docs/lammps.md, "Scaling").
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SCENE = """
name = "dipolar_sphere_lattice"
[assembly]
name = "lattice"
params = {{ nx = {n}, ny = {n}, nz = {n}, spacing = 0.03, mass = 7.658e-4, alpha = 3.872e7, \
moment = 0.15546875, potential = "dipole", interactions = "complete" }}
[interactions]
potential = "dipole"
cutoff = 0.1
[run]
step = 1e-4
duration = {duration}
"""


def _children_cpu() -> float:
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark; print one line per run and the summary."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--side", type=int, default=20, help="bodies per lattice edge (N = side³)")
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args(argv)
    from poissonkit.engines import run_lammps
    from poissonkit.engines.lammps import loop_time
    from poissonkit.scene import load_scene
    from poissonkit.scene.build import build_scene

    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; N = "
          f"{args.side ** 3}, {args.steps} steps")
    best: dict[int, float] = {}
    final: dict[int, np.ndarray] = {}
    with tempfile.TemporaryDirectory(prefix="bench-lammps-") as tmp:
        path = Path(tmp) / "lattice.toml"
        path.write_text(SCENE.format(n=args.side, duration=args.steps * 1e-4), encoding="utf-8")
        built = build_scene(load_scene(path))
        for rep in range(args.repeat):
            for ranks in args.ranks:
                out = Path(tmp) / f"r{ranks}-{rep}"
                c0, t0 = _children_cpu(), time.perf_counter()
                sol = run_lammps(built, built.t_end, built.step, ranks=ranks, out=out,
                                 save_every=args.steps)
                wall, cpu = time.perf_counter() - t0, _children_cpu() - c0
                loop = loop_time(out / "log.lammps") or float("nan")
                best[ranks] = min(best.get(ranks, np.inf), loop)
                final[ranks] = sol.y[-1]
                print(f"ranks {ranks}: loop {loop:8.3f} s   wall {wall:8.3f} s   "
                      f"cpu {cpu:8.3f} s")
    print("best loop time: " + ", ".join(f"{r} rank(s) {t:.3f} s" for r, t in best.items()))
    if 1 in best and 2 in best:
        print(f"speed-up 1 -> 2 ranks (loop time): {best[1] / best[2]:.2f}x")
        diff = np.abs(final[2] - final[1]).max() / np.abs(final[1]).max()
        print(f"final states of 1 and 2 ranks differ by {diff:.1e} (relative)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
