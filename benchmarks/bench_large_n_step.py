"""What a step of a large scene costs beyond its force evaluations, `poissonkit run` end to end.

Usage::

    python benchmarks/bench_large_n_step.py [--size 25 20 20] [--steps 10] [--repeat 5]
        [--save-every 1]

The scene is ``examples/dipole_lattice_100k.toml`` (point dipoles on a cubic lattice, 0.1 m
cutoff, cell lists, ``splitting4``) with ``--size NX NY NZ`` lattice sites (default 10⁴;
``50 50 40`` is the shipped 10⁵). In one process it measures

* ``t_f``: one force evaluation as a step makes it (the system's compiled ``kick``: gather,
  forces and torques of every pair, push), best of ``--repeat``, interleaved with one-step
  ``solve`` calls (their ratio is the loop's cost per step) and taken before and after the
  runs below;
* the step loop alone: ``solve`` of ``--steps`` steps, saving every ``--save-every``-th;
* ``poissonkit run`` of the same scene (``cli.main``, ``--no-plot``), split into the scene's
  set-up (reading, assembling and building the system), the compile-and-warm-up step, the run
  (saving to the stream included) and the report (diagnostics, trajectory files, summary),

and prints each as a multiple of ``steps × evaluations per step × t_f``, the time the force
evaluations alone would take, by CPU time of the process (all threads; what a shared machine
distorts least: a best-of kick against a single long run by wall time mixes quiet and busy
minutes) and by wall time. Target (issue 33): run + report ≤ 1.3× the evaluations for the 10⁵-body lattice;
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


def clock() -> tuple[float, float]:
    """(wall, CPU time of the process: all its threads)."""
    return time.perf_counter(), time.process_time()


def since(t0: tuple[float, float]) -> np.ndarray:
    w, c = clock()
    return np.array([w - t0[0], c - t0[1]])


def kick_and_step(spec, repeat: int) -> tuple[np.ndarray, np.ndarray]:
    """Best (wall, CPU) of one kick (one force evaluation as the steps make it) and of a
    one-step ``solve``, interleaved so that both see the same load."""
    from poissonkit.numerics.solver import solve

    system = spec.system
    kernels, data, work = system.kernels, system.data, system.work()
    y = np.array(spec.y0, dtype=float)
    kernels.kick(y.copy(), spec.step, data, work)  # compile
    solve(system, y, spec.step, method=spec.method, step=spec.step)
    kick = np.full(2, np.inf)
    step = np.full(2, np.inf)
    for _ in range(repeat):
        yy = y.copy()
        t0 = clock()
        kernels.kick(yy, spec.step, data, work)
        kick = np.minimum(kick, since(t0))
        t0 = clock()
        solve(system, y, spec.step, method=spec.method, step=spec.step)
        step = np.minimum(step, since(t0))
    return kick, step


class Phases:
    """(wall, CPU) of the phases of ``poissonkit run``, by wrapping its module's functions."""

    def __init__(self) -> None:
        self.times: dict[str, list[np.ndarray]] = {}

    def wrap(self, module: object, name: str, label: str) -> None:
        inner = getattr(module, name)

        def timed(*args, **kwargs):
            t0 = clock()
            try:
                return inner(*args, **kwargs)
            finally:
                self.times.setdefault(label, []).append(since(t0))

        setattr(module, name, timed)


def ratio(t: np.ndarray, need: np.ndarray) -> str:
    return f"{t[1]:8.2f} s CPU = {t[1] / need[1]:5.2f}x   (wall {t[0]:7.2f} s = {t[0] / need[0]:5.2f}x)"


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
        spec = build_run(load_scene(path))
        n = spec.system.n_moving
        evals = Splitting(order=4).evaluations
        t_f, t_step = kick_and_step(spec, args.repeat)
        t0 = clock()
        solve(spec.system, spec.y0, args.steps * spec.step, method=spec.method,
              step=spec.step, save_every=args.save_every)
        t_loop = since(t0)

        phases = Phases()
        phases.wrap(run_command, "build_spec", "set-up")
        phases.wrap(run_command, "_solve", "solve")
        phases.wrap(run_command, "_report", "report")
        t0 = clock()
        code = cli.main(["run", str(path), "--out", str(folder / "out"), "--no-plot",
                         "--no-progress", "--save-every", str(args.save_every)])
        t_cli = since(t0)
        t_f2, t_step2 = kick_and_step(spec, args.repeat)
        t_f, t_step = np.minimum(t_f, t_f2), np.minimum(t_step, t_step2)

    load = Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "?"
    need = args.steps * evals * t_f
    warm, run = phases.times["solve"]
    report = phases.times["report"][0]
    setup = phases.times["set-up"][0]
    print(f"N = {n} point dipoles ({' x '.join(map(str, args.size))} lattice), {spec.method}, "
          f"{args.steps} steps, saving every {args.save_every}; load average {load}")
    print(f"  one force evaluation (kick)   t_f = {1e3 * t_f[1]:.1f} ms CPU, {1e3 * t_f[0]:.1f} ms "
          f"wall; a step needs {evals}")
    print(f"  one step (solve), interleaved with the kicks:  {t_step[1] / (evals * t_f[1]):.2f}x "
          f"the evaluations by CPU time ({t_step[0] / (evals * t_f[0]):.2f}x by wall)")
    print(f"  {args.steps} steps need {need[1]:.2f} s CPU of force evaluations; as multiples of it:")
    print(f"  step loop alone (solve)          {ratio(t_loop, need)}")
    print(f"  poissonkit run (exit {code}), {t_cli[0]:.1f} s wall in all:")
    print(f"    run, saving to the stream      {ratio(run, need)}")
    print(f"    report (diagnostics, files)    {ratio(report, need)}")
    print(f"    run + report                   {ratio(run + report, need)}   (target <= 1.30x)")
    print(f"    once per run: set-up {setup[1]:.1f} s CPU = {setup[1] / t_f[1]:.0f} t_f, "
          f"compilation + warm-up step {warm[1]:.1f} s CPU = {warm[1] / t_f[1]:.0f} t_f")


if __name__ == "__main__":
    sys.exit(main())
