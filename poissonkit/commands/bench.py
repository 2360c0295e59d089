"""``poissonkit bench [SCENE]``: speed against error of every integrator on a scene.

Computes a high-accuracy reference itself (``splitting8`` with a tiny step, checked by
``dop853`` at ``tol = 1e-13``; their agreement is printed and written), sweeps each method over
step sizes (fixed-step methods) or tolerances (adaptive ones), and writes to ``--out``
(default ``./poissonkit-bench``):

* ``workprecision.csv`` — one row per solve (method, setting, steps, wall time, final-state
  error, max relative energy error);
* ``workprecision.png`` — both errors against wall time, log–log;
* ``workprecision.md`` — the reference check and the table of time-to-error 1e-6 / 1e-9.

Without a scene it uses the registered default scene (the seed 000 orbit), perturbed (axes
tilted by ``--tilt`` rad, default 0.05) so that every degree of freedom moves, for ``--periods``
orbital periods (default 20).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import cast

from poissonkit.contracts import HasEnergy
from poissonkit.errors import InputError, MissingDependencyError
from poissonkit.files import atomic
from poissonkit.numerics.runspec import RunSpec

DEFAULT_METHODS = ("splitting2", "splitting4", "splitting6", "splitting8", "midpoint", "rk45",
                   "dop853", "lsoda")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit bench``."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file or built-in name (default: the seed 000 orbit)")
    parser.add_argument("--methods", default=",".join(DEFAULT_METHODS),
                        help="comma-separated integrator names (default: %(default)s)")
    parser.add_argument("--periods", type=float, default=20.0,
                        help="seed scene: duration in orbital periods (default 20)")
    parser.add_argument("--tilt", type=float, default=0.05,
                        help="seed scene: initial tilt of both axes [rad] (default 0.05)")
    parser.add_argument("--out", default="poissonkit-bench", help="output folder")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the files of an earlier run in --out (default: refuse)")
    parser.add_argument("--quick", action="store_true",
                        help="fewer settings per method (a smoke run)")
    parser.add_argument("--budget", type=float, default=10.0,
                        help="stop refining a method after a solve slower than this [s]")
    parser.add_argument("--repeats", type=int, default=1, help="best of N timings per point")


def _spec(args: argparse.Namespace) -> RunSpec:
    path = Path(args.scene) if args.scene is not None else None
    if path is None or not path.exists():
        from poissonkit.plugin import names

        if path is None or args.scene in names("scene"):
            from poissonkit.scene.registered import registered_run

            if not (math.isfinite(args.periods) and args.periods > 0):
                raise InputError(f"--periods must be > 0, got {args.periods!r}")
            return registered_run(args.scene, {"periods": args.periods, "tilt": args.tilt})[0]
    try:
        from poissonkit.scene import build_run, load_scene
    except ImportError:
        raise MissingDependencyError(
            "scene files need poissonkit.scene (load_scene/build_run)") from None
    return build_run(load_scene(path))


def main(args: argparse.Namespace) -> int:
    """Reference, sweep, CSV/PNG/markdown; prints the time-to-error table."""
    from poissonkit.numerics import workprecision as wp
    from poissonkit.plugin import names

    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    known = set(names("integrator"))
    unknown = [m for m in methods if m not in known]
    if unknown:
        from poissonkit.errors import UnknownNameError

        raise UnknownNameError("integrator", unknown[0], known)
    spec = _spec(args)
    out = atomic.prepare_output_dir(args.out, overwrite=args.overwrite)
    t_end = float(spec.t_end)
    print(f"bench {spec.name}: t_end = {t_end:.6g} (internal), computing reference ...", flush=True)
    system = cast(HasEnergy, spec.system)  # every system a scene builds has an energy
    ref = wp.reference(system, spec.y0, t_end)
    print(f"reference {ref.primary[0]} ({ref.primary[1]} {ref.primary[2]:.3g}) vs "
          f"{ref.secondary[0]} ({ref.secondary[1]} {ref.secondary[2]:.3g}): "
          f"agreement {ref.agreement:.2e}  [{ref.wall_time:.2f} s]", flush=True)
    if args.quick:
        settings = wp.plan(methods, t_end, n_steps=3, step_range=(0.2, 0.02),
                           tols=(1e-5, 1e-8, 1e-11))
    else:
        settings = wp.plan(methods, t_end)

    def show(p: wp.WorkPoint) -> None:
        print(f"  {p.method:12s} {p.kind}={p.setting:<10.3g} steps={p.steps:<8d} "
              f"wall={p.wall_time:9.4f} s  err={p.final_error:9.2e}  "
              f"max |ΔH|/|H|={p.max_rel_energy_error:9.2e}"
              + (f"  [{p.note}]" if p.note else ""),
              flush=True)

    pts = wp.sweep(system, spec.y0, t_end, ref, settings, repeats=args.repeats,
                   time_budget=args.budget, on_point=show)
    wp.write_csv(out / "workprecision.csv", pts)
    wp.plot(out / "workprecision.png", pts,
            title=f"{spec.name}: work-precision (reference agreement {ref.agreement:.1e})")
    tab = wp.table(pts, (1e-6, 1e-9))
    atomic.write_text(out / "workprecision.md",
        f"# Work-precision: {spec.name}\n\n"
        f"Reference: {ref.primary} checked by {ref.secondary}; agreement "
        f"{ref.agreement:.2e} (block-relative final-state error).\n\n{tab}\n")
    print(tab)
    print(f"wrote {out / 'workprecision.csv'}, {out / 'workprecision.png'}, "
          f"{out / 'workprecision.md'}")
    return 0
