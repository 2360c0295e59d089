"""``poissonkit sweep``: run the seed 000 orbit over a grid of parameters and classify each run.

Each grid point is integrated with :func:`poissonkit_magnets.seed000.orbit_fate` and classified as
``bounded``, ``collision`` (the magnets' axis segments come closer than their diameter) or
``escape`` (distance above ``--escape`` orbit radii). Results go to ``sweep.csv`` in ``--out``
and to a table on stdout. Example — the seed's "stable with certain relations between the
parameters", spin against tilt::

    poissonkit sweep --grid spin_ratio=0,2,5,10,20 --grid tilt=0.02,0.1
"""

from __future__ import annotations

import argparse
import csv
import itertools
import math
from pathlib import Path

from poissonkit.errors import InputError, UnknownNameError

#: Parameters of the seed scene a sweep may vary (keywords of ``seed000.orbit_fate``).
PARAMETERS = ("spin_ratio", "tilt", "radius_factor", "momentum_factor")
DEFAULTS = {"spin_ratio": 20.0, "tilt": 0.02, "radius_factor": 1.0, "momentum_factor": 1.0}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``poissonkit sweep``."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="only the built-in seed 000 scene is supported (leave empty)")
    parser.add_argument("--grid", action="append", default=[], metavar="NAME=V1,V2,...",
                        help=f"values of one parameter ({', '.join(PARAMETERS)}); repeatable")
    parser.add_argument("--periods", type=float, default=20.0, help="orbital periods per run")
    parser.add_argument("--escape", type=float, default=3.0, help="escape distance in R_orb")
    parser.add_argument("--out", default="poissonkit-sweep", help="output folder")


def parse_grid(items: list[str]) -> dict[str, list[float]]:
    """``["spin_ratio=0,20", ...]`` -> ``{"spin_ratio": [0.0, 20.0], ...}`` (typed errors)."""
    grid: dict[str, list[float]] = {}
    for item in items:
        name, sep, values = item.partition("=")
        name = name.strip()
        if not sep:
            raise InputError(f"--grid expects NAME=V1,V2,..., got {item!r}")
        if name not in PARAMETERS:
            raise UnknownNameError("sweep parameter", name, PARAMETERS)
        try:
            vals = [float(v) for v in values.split(",") if v.strip()]
        except ValueError:
            raise InputError(f"--grid {name}: values must be numbers, got {values!r}") from None
        if not vals or not all(math.isfinite(v) for v in vals):
            raise InputError(f"--grid {name}: give at least one finite value")
        grid[name] = vals
    return grid


def main(args: argparse.Namespace) -> int:
    """Run every grid point; write ``sweep.csv``; print the table."""
    from poissonkit_magnets import seed000

    if args.scene is not None:
        raise InputError("poissonkit sweep supports only the built-in seed 000 scene for now")
    if not (math.isfinite(args.periods) and args.periods > 0):
        raise InputError(f"--periods must be > 0, got {args.periods!r}")
    grid = parse_grid(args.grid) or {"spin_ratio": [0.0, 2.0, 20.0]}
    names = list(grid)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    print(" ".join(f"{n:>15s}" for n in names) + "      fate   r_min   r_max  periods  |dH|/H")
    for values in itertools.product(*(grid[n] for n in names)):
        kw = dict(DEFAULTS)
        kw.update(zip(names, values))
        fate = seed000.orbit_fate(periods=args.periods, escape_distance=args.escape, **kw)
        row = {**kw, "fate": fate.kind, "r_min": fate.r_min, "r_max": fate.r_max,
               "periods": fate.t_end, "max_energy_error": fate.max_energy_error}
        rows.append(row)
        print(" ".join(f"{v:15.4g}" for v in values)
              + f" {fate.kind:>9s} {fate.r_min:7.3f} {fate.r_max:7.3f} {fate.t_end:8.3f} "
              f"{fate.max_energy_error:7.1e}", flush=True)
    with (out / "sweep.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out / 'sweep.csv'}")
    return 0
