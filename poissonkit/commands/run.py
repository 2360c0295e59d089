"""``poissonkit run [SCENE]``: integrate a scene and write summary, trajectory and plots.

Without a scene it runs the registered default scene — the seed 000 orbit of the magnets plugin
(``seed000``, :func:`poissonkit_magnets.seed000.scene_run`): two cylinder magnets (dumbbell model)
on the circular orbit of radius 10 mm, 20 periods with the order-6 splitting method. Output
folder (default ``./poissonkit-output``):

* ``summary.json`` — parameters, ``P_orb``, ``T_orb``, method, steps, wall time (integration;
  the one-time compilation separately), maximum relative energy error, maximum Casimir drift,
  maximum ``|Δj|/|j|``;
* ``trajectory.npz`` — ``t`` (internal), ``t_si``, ``y`` (rows), ``layout``;
* ``angular_momentum_z.png``, ``radius_and_x.png``, ``orbit.png``, ``drifts.png``.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from poissonkit.errors import InputError, MissingDependencyError, SceneError

DEFAULT_OUT = "poissonkit-output"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit run``."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (TOML) or built-in scene name; "
                        "default: the seed 000 orbit")
    parser.add_argument("--method", default=None,
                        help="integrator registry name "
                        "(default: the scene's, splitting6 for seed 000)")
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--step", type=float, default=None,
                   help="fixed step in seconds (SI; default for the seed scene: T_orb/200)")
    g.add_argument("--tol", type=float, default=None, help="tolerance of adaptive methods")
    d = parser.add_mutually_exclusive_group()
    d.add_argument("--periods", type=float, default=None,
                   help="duration in orbital periods (seed scene; default 20)")
    d.add_argument("--duration", type=float, default=None, help="duration in seconds (SI)")
    parser.add_argument("--tilt", type=float, default=0.0,
                        help="seed scene: tilt both axes by this angle [rad] (default 0: the "
                        "exact circular orbit; 0.02 gives a wobbling orbit)")
    parser.add_argument("--spin-ratio", type=float, default=20.0,
                        help="seed scene: alpha|m|/omega_orb of each top (default 20; below ~6 "
                        "the tilted orbit is unstable)")
    parser.add_argument("--out", default=DEFAULT_OUT,
                        help=f"output folder (default ./{DEFAULT_OUT})")
    parser.add_argument("--save-every", type=int, default=1, help="keep every k-th step")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--no-plots", action="store_true", help="do not write PNG figures")


def _positive(name: str, value: float | None) -> None:
    if value is not None and not (math.isfinite(value) and value > 0):
        raise InputError(f"--{name} must be a positive number, got {value!r}")


def build_spec(args: argparse.Namespace):
    """The :class:`~poissonkit.numerics.runspec.RunSpec` the options describe.

    No scene: the registered default scene (:func:`poissonkit.plugin.default_scene`); an
    existing path: a TOML scene file; otherwise a registered scene name. Options a registered
    scene declares are handed to it; the others are applied to the run it returns.
    """
    from dataclasses import replace

    for name in ("step", "tol", "periods", "duration"):
        _positive(name, getattr(args, name, None))
    path = Path(args.scene) if args.scene is not None else None
    consumed: set[str] = set()
    if path is None or (not path.exists() and _is_registered_scene(args.scene)):
        from poissonkit.scene.registered import registered_run

        options = {k: getattr(args, k, None) for k in
                   ("method", "step", "tol", "periods", "duration", "tilt", "spin_ratio")}
        spec, consumed = registered_run(args.scene, options)
    else:
        try:
            from poissonkit.scene import build_run, load_scene
        except ImportError:
            raise MissingDependencyError(
                "scene files need poissonkit.scene.load_scene/build_run, which this build lacks"
            ) from None
        spec = build_run(load_scene(path))
    changes: dict[str, Any] = {}
    if args.method and "method" not in consumed:
        changes["method"] = args.method
    tunit = _time_unit(spec)
    if args.step is not None and "step" not in consumed:
        changes.update(step=args.step / tunit, tol=None)
    if args.tol is not None and "tol" not in consumed:
        changes.update(tol=args.tol, step=None)
    if args.duration is not None and "duration" not in consumed:
        changes["t_end"] = args.duration / tunit
    if args.periods is not None and "periods" not in consumed:
        period = spec.metadata.get("T_orb")
        if not period:
            raise SceneError("--periods needs a scene with an orbital period (T_orb); "
                             "use --duration")
        changes["t_end"] = args.periods * float(period) / tunit
    return replace(spec, **changes) if changes else spec


def _is_registered_scene(name: str) -> bool:
    from poissonkit.plugin import names

    return name in names("scene")


def _time_unit(spec) -> float:
    sc = spec.metadata.get("scales") if spec.metadata else None
    if isinstance(sc, dict) and "time" in sc:
        return float(sc["time"])
    s = getattr(spec.system, "scales", None)
    return float(s.time) if s is not None else 1.0


def _solve(spec, progress: bool, save_every: int):
    try:
        from poissonkit.numerics.solver import solve
    except ImportError:
        raise MissingDependencyError(
            "poissonkit.numerics.solver is not available in this build") from None
    return solve(spec.system, spec.y0, spec.t_end, method=spec.method, step=spec.step,
                 tol=spec.tol, progress=progress, save_every=save_every)


def trajectory_rows(sol) -> tuple[np.ndarray, np.ndarray]:
    """``(t, y)`` of a solution with ``y`` as rows (one state per saved time)."""
    t = np.asarray(sol.t, dtype=float)
    y = np.asarray(sol.y, dtype=float)
    if y.ndim == 2 and y.shape[0] != t.shape[0] and y.shape[1] == t.shape[0]:
        y = y.T
    return t, y


def relative_position(spec, y: np.ndarray) -> np.ndarray | None:
    """Relative position ``r_2 - r_1`` of a two-body run (internal units), or ``None``."""
    system = spec.system
    layout = tuple(getattr(system, "layout", ()))
    if hasattr(system, "unpack") and getattr(system, "n_moving", 0) == 2:
        r = system.unpack(y)["r"]
        return r[:, 1] - r[:, 0]
    if layout[:3] and y.shape[1] == 18:  # the seed's centre-of-mass form
        return y[:, 0:3]
    if hasattr(system, "unpack") and getattr(system, "n_moving", 0) >= 1:
        return system.unpack(y)["r"][:, 0]
    return None


def main(args: argparse.Namespace) -> int:
    """Run, write ``summary.json``, ``trajectory.npz`` and the figures; print a short summary."""
    from dataclasses import replace

    from poissonkit.report import diagnostics, write_summary, write_trajectory

    if args.save_every < 1:
        raise InputError(f"--save-every must be >= 1, got {args.save_every}")
    spec = build_spec(args)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # compile the kernels on a one-step run first, so that the progress bar and the reported
    # wall time show the integration itself (compilation is reported separately)
    tc = time.perf_counter()
    if not args.no_progress:
        print("compiling kernels (first run in a process: numba) ...", file=sys.stderr, flush=True)
    warm = replace(spec, t_end=min(float(spec.t_end), float(spec.step or spec.t_end * 1e-3)))
    _solve(warm, progress=False, save_every=1)
    compile_time = time.perf_counter() - tc
    t0 = time.perf_counter()
    sol = _solve(spec, progress=not args.no_progress, save_every=args.save_every)
    wall = getattr(sol, "wall_time", None) or (time.perf_counter() - t0)
    t, y = trajectory_rows(sol)
    diag = diagnostics(spec.system, t, y)
    tunit = _time_unit(spec)
    sc = getattr(spec.system, "scales", None)
    lunit = float(sc.length) if sc is not None else 1.0
    jscale = float(sc.unit("angular_momentum")) if sc is not None else 1.0
    rel = relative_position(spec, y)
    meta = dict(spec.metadata or {})
    summary: dict[str, Any] = {
        "scene": spec.name,
        "method": getattr(sol, "method", spec.method),
        "step": spec.step,
        "tol": spec.tol,
        "steps": int(getattr(sol, "steps", len(t) - 1)),
        "wall_time_s": float(wall),
        "compile_time_s": float(compile_time),
        "wall_time_note": "integration only; compile_time_s is the one-time kernel compilation "
                          "(plus one step) done before it",
        "t_end": float(spec.t_end),
        "t_end_s": float(spec.t_end) * tunit,
        **diag.maxima(),
        "max_rel_angular_momentum_drift_note": "|Δj|/|j|, j = Σ r×p + Σ m (seed eq. 21)",
    }
    if rel is not None:
        rn = np.linalg.norm(rel, axis=1) * lunit
        summary.update(min_distance_m=float(rn.min()), max_distance_m=float(rn.max()))
    for key in ("P_orb", "T_orb", "R_orb"):
        if key in meta:
            summary[key] = meta[key]
    summary["parameters"] = meta
    write_summary(out / "summary.json", summary)
    extra = {} if rel is None else {"r_rel_si": rel * lunit}
    write_trajectory(out / "trajectory.npz", t, y, layout=tuple(getattr(spec.system, "layout", ())),
                     time_unit=tunit, **extra)
    figures: list[str] = []
    if not args.no_plots and rel is not None:
        from poissonkit.report import plots

        figures = [p.name for p in plots.seed_figures(out, t * tunit, rel * lunit,
                                                      diag.angular_momentum[:, 2] * jscale, diag,
                                                      time_scale=tunit)]
    print(f"{spec.name}: {summary['method']}, {summary['steps']} steps in {wall:.3g} s; "
          f"max |ΔH|/|H| = {summary['max_rel_energy_error']:.2e}, "
          f"max Casimir drift = {summary['max_casimir_drift']:.2e}, "
          f"max |Δj|/|j| = {summary['max_rel_angular_momentum_drift']:.2e} "
          f"(compilation {compile_time:.3g} s)")
    print(f"wrote {out / 'summary.json'}, {out / 'trajectory.npz'}"
          + (f", {', '.join(figures)}" if figures else ""), file=sys.stdout)
    return 0
