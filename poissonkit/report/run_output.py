"""Everything ``poissonkit run`` writes once the integration is over, in commit order.

Diagnostics from the streamed parts, the trajectory files (:mod:`poissonkit.report.run_files`),
``summary.json`` (:mod:`poissonkit.report.run_summary`) as the commit record, then the parts
are removed and the figures drawn. The command (:mod:`poissonkit.commands.run`) prints what
:func:`write_run_outputs` returns and chooses the exit code.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from poissonkit.contracts import HasEnergy
from poissonkit.report.run_summary import (distance_figures, run_problems, run_provenance,
                                           summary_document)
from poissonkit.report.run_units import relative_position, scales_of, time_unit

if TYPE_CHECKING:
    from poissonkit.numerics.events import EventRecord
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solution import Solution


@dataclass
class RunOutputs:
    """What a finished run wrote.

    Attributes
    ----------
    summary
        The ``summary.json`` document.
    files
        Names of the files written in the output folder (``summary.json`` first).
    figures
        Names of the figures drawn.
    problems
        The warnings (also in ``summary["warnings"]``).
    interrupted, touching
        Stopped on request; the contact / collision events that stopped it.
    energy_error, energy_tol
        ``max |ΔH|/|H(0)|`` and the tolerance it is held to.
    failure
        What stopped a failed run (``summary["failure"]``, :mod:`poissonkit.report.run_abort`),
        ``None`` for a run that did not fail.
    """

    summary: dict[str, Any]
    files: list[str]
    figures: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    interrupted: bool = False
    touching: list[EventRecord] = field(default_factory=list)
    energy_error: float = 0.0
    energy_tol: float = 0.0
    failure: dict[str, Any] | None = None


@dataclass(frozen=True)
class OutputLimits:
    """Row counts that choose the files: above ``max_npz_rows`` saved rows the trajectory stays
    in parts; above ``dataset_max_rows`` the dataset is a Zarr store; ``plot_rows`` rows at most
    are kept for the figures."""

    plot_rows: int
    max_npz_rows: int
    dataset_max_rows: int


def write_run_outputs(args: argparse.Namespace, spec: RunSpec, sol: Solution, out: Path,
                      parts: Path, *, wall: float, compile_time: float, energy_tol: float,
                      limits: OutputLimits) -> RunOutputs:
    """Diagnostics, files, summary and figures of a finished (or stopped) run in ``out``,
    from the parts streamed into ``parts`` (``args``: the command's options, for provenance
    and ``--no-plots``)."""
    from poissonkit.files.killpoints import kill_point
    from poissonkit.report import invariant_report, streamed_diagnostics, write_summary
    from poissonkit.report.resume import finish_parts
    from poissonkit.report.run_files import write_trajectory_files

    nrows = int(sol.extra.get("streamed_rows", len(sol.t)))
    system = cast(HasEnergy, spec.system)  # every system a scene builds has an energy
    diag, t, y = streamed_diagnostics(system, parts, plot_rows=limits.plot_rows)
    tunit = time_unit(spec)
    sc = scales_of(spec.system)
    lunit = float(sc.length) if sc is not None else 1.0
    jscale = float(sc.unit("angular_momentum")) if sc is not None else 1.0
    rel = relative_position(spec, y)
    meta = dict(spec.metadata or {})
    interrupted = bool(sol.extra.get("interrupted"))
    touching = [e for e in sol.events if e.kind in ("contact", "collision")]
    summary = summary_document(spec, sol, wall=wall, compile_time=compile_time, time_unit=tunit,
                               energy_tol=energy_tol, invariants=invariant_report(system, diag),
                               scales=sc, interrupted=interrupted, touching=touching)
    if rel is not None:
        summary.update(distance_figures(rel, lunit, len(t), nrows, limits.plot_rows))
    for key in ("P_orb", "T_orb", "R_orb"):
        if key in meta:
            summary[key] = meta[key]
    summary["parameters"] = meta
    summary.update(run_provenance(args, spec, sc))
    summary["saved_rows"] = nrows
    from poissonkit.scene.registered import scene_outcome

    outcome = scene_outcome(spec, t, y, sol.events)  # a registered scene's fate, if it has one
    if outcome is not None:
        summary["outcome"] = outcome
    if nrows <= limits.max_npz_rows:
        files, named = write_trajectory_files(
            out, spec, sol, parts, y, t, scales=sc, time_unit=tunit,
            dataset_max_rows=limits.dataset_max_rows, view=not args.no_plots)
        summary.update(named)
    else:
        summary["trajectory"] = ("trajectory.parts/ (read with "
                                 "poissonkit.numerics.checkpoint.read_trajectory)")
        files = ["summary.json", "trajectory.parts/"]
    energy_error = float(summary["max_rel_energy_error"])
    failure = sol.extra.get("failure")
    problems = run_problems(energy_error, summary["message"], energy_tol, interrupted, touching,
                            tunit, failure)
    summary["warnings"] = problems
    write_summary(out / "summary.json", summary)  # the commit record (report/resume.py)
    kill_point("summary-written")
    # parts go only after the summary; a stopped, checkpointed run keeps them for --resume
    finish_parts(out, keep=(interrupted and (out / "checkpoints").is_dir())
                 or nrows > limits.max_npz_rows)
    figures: list[str] = []
    if not args.no_plots:
        from poissonkit.numerics.events import Contact
        from poissonkit.report.figures import RunData, write_figures

        shapes = {s.name: (s.radius, s.half_length) for e in spec.events
                  if isinstance(e, Contact) for s in e.shapes}
        run = RunData(spec.system, t, y, diag, time_unit=tunit, name=spec.name, metadata=meta,
                      shapes=shapes, relative=None if rel is None else rel * lunit,
                      jz=diag.angular_momentum[:, 2] * jscale)
        figures = [p.name for p in write_figures(out, run)]
    return RunOutputs(summary=summary, files=files, figures=figures, problems=problems,
                      interrupted=interrupted, touching=touching, energy_error=energy_error,
                      energy_tol=energy_tol, failure=failure)
