"""``poissonkit run SCENE --engine lammps --ranks N``: the run on LAMMPS, written as any run.

The scene is checked (:func:`poissonkit.engines.lammps.can_express`), run on LAMMPS with
``N`` MPI ranks (:func:`~poissonkit.engines.lammps.run_lammps`), and its trajectory, already
in poissonkit's state layout, goes through the same writer as a poissonkit run (summary,
trajectory dataset in SI, figures), written once; the summary adds ``engine``, ``ranks`` and
``setup_time_s`` (``compile_time_s`` is ``null``: nothing is compiled; ``wall_time_s`` is
LAMMPS's own loop time), and the energy error is poissonkit's energy evaluated on LAMMPS's
states. ``docs/lammps.md``.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from poissonkit.errors import InputError

if TYPE_CHECKING:
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solution import Solution

#: What the run command's ``_report`` is: writes the outputs, returns the exit code.
Report = Callable[[argparse.Namespace, "RunSpec", "Solution", Path, Path, float, float,
                   "float | None"], int]

#: Options of a poissonkit run that a LAMMPS run does not have.
_NOT_WITH_LAMMPS = {"resume": "--resume", "checkpoint_every": "--checkpoint-every",
                    "save_dt": "--save-dt", "tol": "--tol"}


def check_engine_options(args: argparse.Namespace) -> None:
    """:class:`InputError` for ``--ranks`` without ``--engine lammps``, a bad rank count or an
    option LAMMPS runs do not have."""
    ranks = getattr(args, "ranks", None)
    if getattr(args, "engine", "poissonkit") != "lammps":
        if ranks is not None:
            raise InputError("--ranks N runs a scene on N MPI ranks of LAMMPS: pass "
                             "--engine lammps too")
        return
    if ranks is not None and ranks < 1:
        raise InputError(f"--ranks must be >= 1, got {ranks}")
    for key, flag in _NOT_WITH_LAMMPS.items():
        if getattr(args, key, None):
            raise InputError(f"{flag} is not available with --engine lammps")


def run_on_lammps(args: argparse.Namespace, spec: RunSpec, out: Path,
                  energy_tol: float | None, report: Report) -> int:
    """Run ``spec`` on LAMMPS and write its outputs into ``out``; return the exit code."""
    from poissonkit.engines.lammps import can_express, run_lammps
    from poissonkit.numerics.checkpoint import TrajectoryStream

    ok, why = can_express(spec)
    if not ok:
        raise InputError(f"--engine lammps: LAMMPS cannot run scene {spec.name!r}: {why}")
    if spec.step is None:
        raise InputError("--engine lammps needs a fixed step: pass --step SECONDS")
    if spec.events and not getattr(args, "no_contact", False):
        raise InputError("--engine lammps does not stop at contacts of finite-size bodies: "
                         "pass --no-contact to run without that event")
    ranks = getattr(args, "ranks", None) or 1
    sol = run_lammps(spec, float(spec.t_end), float(spec.step), ranks=ranks,
                     save_every=args.save_every or 1)
    parts = out / "trajectory.parts"
    TrajectoryStream(parts).write(sol.t, sol.y)
    # the summary names the engine, the ranks and LAMMPS's setup time (sol.extra); nothing is
    # compiled, so no compile time is passed
    return report(args, spec, sol, out, parts, sol.wall_time, 0.0, energy_tol)
