"""What a step of a large scene costs beyond its force evaluations, `poissonkit run` end to end.

Usage::

    python benchmarks/bench_large_n_step.py [--size 25 20 20] [--steps 10] [--repeat 5]
        [--save-every 1]

The scene is ``examples/dipole_lattice_100k.toml`` (point dipoles on a cubic lattice, 0.1 m
cutoff, cell lists, ``splitting4``) with ``--size NX NY NZ`` lattice sites (default 10⁴;
``50 50 40`` is the shipped 10⁵). In one process it measures

* ``t_f``: one force evaluation as a step makes it (the system's compiled ``kick``: gather,
  forces and torques of every pair, push), best of ``--repeat``, taken before and after the
  runs below so that both see the same load;
* the step loop alone: ``solve`` of ``--steps`` steps, saving every ``--save-every``-th;
* ``poissonkit run`` of the same scene (``cli.main``, ``--no-plot``), split into the scene's
  set-up (reading, assembling and building the system), the compile-and-warm-up step, the run
  (saving to the stream included) and the report (diagnostics, trajectory files, summary),

and prints each as a multiple of ``steps × evaluations per step × t_f``, the time the force
evaluations alone would take. Ratios in one process hold on a loaded machine much better than
seconds do. Target (issue 33): run + report ≤ 1.3× the evaluations for the 10⁵-body lattice;
set-up and compilation are paid once per run and reported apart.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "examples" / "dipole_lattice_100k.toml"


def scene_file(folder: Path, size: tuple[int, int, int], steps: int) -> Path:
    """The lattice scene with ``size`` sites per axis and a run of ``steps`` steps."""
    text = SCENE.read_text(encoding="utf-8")
    nx, ny, nz = size
    text, n = re.subn(r"nx = \d+, ny = \d+, nz = \d+", f"nx = {nx}, ny = {ny}, nz = {nz}", text)
    assert n == 1, "the lattice line of the example scene changed"
    text = re.sub(r"duration = [0-9.e+-]+", f"duration = {steps}e-4", text)
    path = folder / f"lattice_{nx}x{ny}x{nz}.toml"
    path.write_text(text, encoding="utf-8")
    return path


def kick_time(spec, repeat: int) -> float:
    """Best time of one kick (one force evaluation as the steps make it)."""
    system = spec.system
    kernels, data, work = system.kernels, system.data, system.work()
    y = np.array(spec.y0, dtype=float)
    best = np.inf
    for _ in range(repeat + 1):  # the first call may compile
        yy = y.copy()
        tic = time.perf_counter()
        kernels.kick(yy, spec.step, data, work)
        best = min(best, time.perf_counter() - tic)
    return best


class Phases:
    """Wall time of the phases of ``poissonkit run``, by wrapping its module's functions."""

    def __init__(self) -> None:
        self.times: dict[str, list[float]] = {}

    def wrap(self, module: object, name: str, label: str) -> None:
        inner = getattr(module, name)

        def timed(*args, **kwargs):
            tic = time.perf_counter()
            try:
                return inner(*args, **kwargs)
            finally:
                self.times.setdefault(label, []).append(time.perf_counter() - tic)

        setattr(module, name, timed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, nargs=3, default=(25, 20, 20), metavar="N")
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--save-every", type=int, default=1)
    args = parser.parse_args()

    from poissonkit import cli
    from poissonkit.commands import run as run_command
    from poissonkit.numerics.integrators.splitting import Splitting
    from poissonkit.numerics.solver import solve
    from poissonkit.scene import build_run, load_scene

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = scene_file(folder, tuple(args.size), args.steps)
        tic = time.perf_counter()
        spec = build_run(load_scene(path))
        t_build = time.perf_counter() - tic
        n = spec.system.n_moving
        evals = Splitting(order=4).evaluations
        t_f = kick_time(spec, args.repeat)
        solve(spec.system, spec.y0, spec.step, method=spec.method, step=spec.step)  # compile
        tic = time.perf_counter()
        solve(spec.system, spec.y0, args.steps * spec.step, method=spec.method,
              step=spec.step, save_every=args.save_every)
        t_loop = time.perf_counter() - tic

        phases = Phases()
        phases.wrap(run_command, "build_spec", "set-up")
        phases.wrap(run_command, "_solve", "solve")
        phases.wrap(run_command, "_report", "report")
        tic = time.perf_counter()
        code = cli.main(["run", str(path), "--out", str(folder / "out"), "--no-plot",
                         "--no-progress", "--save-every", str(args.save_every)])
        t_cli = time.perf_counter() - tic
        t_f = min(t_f, kick_time(spec, args.repeat))

    load = Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "?"
    need = args.steps * evals * t_f
    warm, run = phases.times["solve"]
    report = phases.times["report"][0]
    setup = phases.times["set-up"][0]
    print(f"N = {n} point dipoles ({' x '.join(map(str, args.size))} lattice), {spec.method}, "
          f"{args.steps} steps, saving every {args.save_every}; load average {load}")
    print(f"  one force evaluation (kick)        t_f = {1e3 * t_f:9.1f} ms; a step needs "
          f"{evals}: {args.steps} steps need {need:.2f} s")
    print(f"  step loop alone (solve)            {t_loop:8.2f} s = {t_loop / need:5.2f}x the "
          "evaluations")
    print(f"  poissonkit run (exit {code})          {t_cli:8.2f} s in all:")
    print(f"    run, saving to the stream        {run:8.2f} s = {run / need:5.2f}x")
    print(f"    report (diagnostics, files)      {report:8.2f} s = {report / need:5.2f}x")
    print(f"    run + report                     {run + report:8.2f} s = "
          f"{(run + report) / need:5.2f}x   (target <= 1.30x)")
    print(f"    once per run: set-up {setup:.2f} s = {setup / t_f:.0f} t_f (build_run alone "
          f"{t_build:.2f} s), compilation + warm-up step {warm:.2f} s = {warm / t_f:.0f} t_f")


if __name__ == "__main__":
    sys.exit(main())
