"""``poissonkit sweep``: run a scene over a grid or random sample of parameters on Dask.

Any scene: a registered scene by name (default: the registered default scene, the magnets
plugin's ``seed000`` orbit with named parameters ``spin_ratio``, ``tilt``, ``radius_factor``,
``momentum_factor``, ``orbit_radius``) or a TOML scene file whose numbers are addressed by
path (``bodies.right.r.0``, ``run.step``, ``bodies.top1.spin``). Results go to
``OUT/sweep.zarr`` (an xarray Dataset, written as batches finish) and, for a two-parameter sweep,
a stability map ``OUT/stability_map.png``. At the end: a per-point table (a summary beyond
50 points), the counts per fate and, on stderr, the failures by kind. Exit codes:
:data:`EXIT_OK`, :data:`EXIT_SOME_FAILED` (some runs or outcomes failed),
:data:`EXIT_ALL_FAILED` (every run failed; also bad input), 2 usage, 130 interrupted. Guide:
``docs/sweeps.md``. Example::

    poissonkit sweep seed000 --param spin_ratio=0:20:11 --param tilt=0:0.2:5 --workers 2

    poissonkit sweep seed000 --param spin_ratio=0:20:11 --param tilt=0:0.2:5 --resume
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from poissonkit.errors import InputError

if TYPE_CHECKING:
    import xarray as xr


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit sweep``."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="registered scene name (default: the default scene, seed000) or a "
                             "scene file (.toml)")
    parser.add_argument("--param", action="append", default=[], metavar="PATH=SPEC",
                        help="swept parameter: PATH=start:stop:count (grid), PATH=v1,v2,... "
                             "(list) or PATH=low:high (with --random); repeatable")
    parser.add_argument("--grid", action="append", default=[], metavar="NAME=V1,V2,...",
                        help="same as --param NAME=V1,V2,... (kept for older scripts)")
    parser.add_argument("--random", type=int, default=None, metavar="N",
                        help="N random points (uniform in the low:high ranges)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random points")
    parser.add_argument("--outcomes", default=None, metavar="A,B,...",
                        help="outcomes to record, built-in or a plugin's (default: the built-in "
                             "ones but megno); see docs/sweeps.md")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                       help="run on an existing Dask cluster")
    where.add_argument("--workers", type=int, default=None,
                       help="worker processes of a local cluster (default: CPUs, at most 4)")
    parser.add_argument("--batch-size", type=int, default=None, help="runs per task")
    parser.add_argument("--out", default="poissonkit-sweep", help="output folder")
    parser.add_argument("--resume", action="store_true",
                        help="finish an interrupted sweep in --out (only missing points run)")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing sweep")
    parser.add_argument("--periods", type=float, default=None,
                        help="duration of each run, in the unit its scene defines: orbital "
                             "periods for seed000 (default 20), seconds for a scene without an "
                             "orbit such as levitron (default 3)")
    parser.add_argument("--escape", type=float, default=None,
                        help="escape distance (seed000: orbit radii, default 3; scene file: "
                             "times the initial size, default 10)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--no-plot", action="store_true", help="no stability map")


def main(args: argparse.Namespace) -> int:
    """Run the sweep, write the store and the map, print a short summary."""
    from poissonkit.sweeps import sweep
    from poissonkit.sweeps.execute import default_store

    if args.periods is not None and not (math.isfinite(args.periods) and args.periods > 0):
        raise InputError(f"--periods must be > 0, got {args.periods!r}")
    params = list(args.param) + list(args.grid)
    if not params:
        raise InputError("give at least one --param PATH=start:stop:count (e.g. "
                         "--param spin_ratio=0:20:5)")
    if args.scene is None:
        from poissonkit.plugin.registry import default_scene

        args.scene = default_scene().name
    from poissonkit.scene.registered import resolve_scene

    # a file, a registered scene or a shipped scene file, by name (as `poissonkit run`)
    scene = resolve_scene(args.scene)
    options: dict[str, Any] = {}  # keywords of sweep(): escape radius, periods
    if args.escape is not None:
        options["escape"] = args.escape
    if args.periods is not None:
        if not isinstance(scene, str):
            raise InputError("--periods applies to a registered scene (e.g. seed000), not to "
                             "a scene file: sweep run.duration instead")
        options["periods"] = args.periods
    out = Path(args.out)
    store = default_store(out)
    import warnings

    from poissonkit.sweeps import StoreRepairWarning

    try:
        with warnings.catch_warnings(record=True) as repairs:
            warnings.simplefilter("always", StoreRepairWarning)
            ds = sweep(scene, params, outcomes=args.outcomes, store=store,
                       scheduler=args.scheduler, workers=args.workers, samples=args.random,
                       seed=args.seed, resume=args.resume, overwrite=args.overwrite,
                       batch_size=args.batch_size, progress=not args.no_progress, **options)
        for w in repairs:  # a clean line for a repaired store; other warnings as Python shows them
            if issubclass(w.category, StoreRepairWarning):
                import sys

                print(f"poissonkit sweep: warning: {w.message}", file=sys.stderr)
            else:
                warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    except KeyboardInterrupt:
        import sys

        print(f"\npoissonkit sweep: interrupted; finished points are in {store}; run the same "
              "command with --resume to compute the rest", file=sys.stderr)
        return 130
    from poissonkit.sweeps.targets import FATES

    _print_results(ds, FATES, store)
    if not args.no_plot and len(ds["fate"].dims) == 2:
        from poissonkit.sweeps.plot import stability_map

        png = stability_map(ds, out / "stability_map.png",
                            chaos="megno" if "megno" in ds else None,
                            title=f"{ds.attrs.get('scene')}: stability map")
        print(f"wrote {png}")
    return _exit_code(ds)


def _print_results(ds: xr.Dataset, fates: tuple[str, ...], store: Path) -> None:
    """The per-point table (a summary for a large sweep), the counts per fate and failures."""
    from poissonkit.sweeps.failures import outcome_failure_count, point_table

    print(point_table(ds, fates))
    failed_run = ds["failed"].values
    partial = outcome_failure_count(ds)
    counts = {name: int(((ds["fate"] == k) & ~ds["failed"]).sum())
              for k, name in enumerate(fates)}
    dims = ", ".join(f"{d}: {n}" for d, n in ds.sizes.items())
    parts = [f"{v} {k}" for k, v in counts.items()]
    if "left_regime" in ds:  # "bounded" is not silent about a run its method could not hold
        bounded = fates.index("bounded")
        outside = int(((ds["fate"] == bounded) & (ds["left_regime"] == 1) & ~ds["failed"]).sum())
        if outside:
            parts[bounded] += f" ({outside} outside the integrator's regime: left_regime = 1)"
    print(f"sweep of {ds.attrs.get('scene')} ({dims}): "
          + ", ".join(parts) + f", {int(failed_run.sum())} failed"
          + (f", {partial} with a failed outcome" if partial else ""))
    print(f"wrote {store}")


#: Exit codes of ``poissonkit sweep`` (2: usage, as for every command; docs/sweeps.md).
EXIT_OK = 0
EXIT_ALL_FAILED = 1  #: every point's run failed (nothing computed); also bad input
EXIT_SOME_FAILED = 5  #: some points' runs or outcomes failed (the rest computed)


def _exit_code(ds: xr.Dataset) -> int:
    """:data:`EXIT_ALL_FAILED` when every point's run failed, :data:`EXIT_SOME_FAILED` when any
    run or outcome failed, with the failures by kind on stderr (kind, count, first example with
    its parameter values); else :data:`EXIT_OK`."""
    import sys

    import numpy as np

    from poissonkit.sweeps.failures import failure_table, outcome_failure_count

    table = failure_table(ds)
    if not table:
        return EXIT_OK
    failed = np.asarray(ds["failed"].values, dtype=bool).reshape(-1)
    if failed.all():
        errors = [str(e) for e in np.asarray(ds["error"].values, dtype=object).reshape(-1) if e]
        first = errors[0] if errors else "no message"
        print(f"poissonkit sweep: every point failed ({failed.size} of {failed.size}); first "
              f"error: {first}", file=sys.stderr)
        print(table, file=sys.stderr)
        return EXIT_ALL_FAILED
    print(f"poissonkit sweep: {int(failed.sum())} of {failed.size} runs failed, "
          f"{outcome_failure_count(ds)} more "
          f"points have a failed outcome (exit {EXIT_SOME_FAILED}); failures by kind:",
          file=sys.stderr)
    print(table, file=sys.stderr)
    return EXIT_SOME_FAILED
