"""The ``summary.json`` document of ``poissonkit run``: what ran, what it cost, its invariant
drifts, its units and provenance, and the warnings a run earns.

The figures come from :mod:`poissonkit.report.summary` (diagnostics as defined once in
:mod:`poissonkit.numerics.diagnostics`) and :mod:`poissonkit.report.provenance`; this module
arranges them into the document the CLI writes and reads back (``--from-summary``).
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.numerics.units import Scales
from poissonkit.report.run_abort import in_seconds

if TYPE_CHECKING:
    from poissonkit.numerics.events import EventRecord
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solution import Solution
    from poissonkit.report.provenance import JSONValue


def run_status(sol: Solution, interrupted: bool, touching: list[EventRecord]) -> str:
    """``"failed"``, ``"interrupted"``, ``"contact"``, ``"escape"`` or ``"done"``."""
    return ("failed" if sol.extra.get("failure") else "interrupted" if interrupted else "contact" if touching
            else "escape" if any(e.kind == "escape" for e in sol.events) else "done")


def summary_document(spec: RunSpec, sol: Solution, *, wall: float, compile_time: float,
                     time_unit: float, energy_tol: float, invariants: Mapping[str, object],
                     scales: Scales | None, interrupted: bool, touching: list[EventRecord]
                     ) -> dict[str, Any]:
    """The run's figures: scene, method, cost, times (internal and SI), status, events, the
    energy tolerance and the invariant report, with the energy in joules when the run has
    internal units."""
    tunit = time_unit
    summary: dict[str, Any] = {  # the JSON document; values read back below are floats
        "scene": spec.name,
        "method": sol.method,
        "step": spec.step,
        "tol": spec.tol,
        "steps": int(sol.steps),
        "wall_time_s": float(wall),
        "compile_time_s": float(compile_time),
        "wall_time_note": "integration only; compile_time_s is the one-time kernel compilation "
                          "(plus one step) done before it",
        "t_end": float(spec.t_end),
        "t_end_s": float(spec.t_end) * tunit,
        "t_reached": float(sol.t[-1]),
        "t_reached_s": float(sol.t[-1]) * tunit,
        "status": run_status(sol, interrupted, touching),
        "message": in_seconds(sol.message, tunit),
        "events": [dict(e.__dict__, time_s=e.time * tunit, time_error_s=e.time_error * tunit)
                   for e in sol.events],
        "energy_tol": energy_tol,
        **invariants,
    }
    if scales is not None:
        summary.update(energy_reference_J=summary["energy_reference"] * float(scales.energy),
                       max_abs_energy_error_J=summary["max_abs_energy_error"]
                       * float(scales.energy))
    engine = sol.extra.get("engine")
    if engine is not None:  # run by another engine (docs/lammps.md): nothing was compiled
        summary.update(engine=engine, ranks=sol.extra.get("ranks"), compile_time_s=None,
                       setup_time_s=float(sol.extra.get("setup_time_s", 0.0)),
                       wall_time_note=f"{engine}'s own loop time of the steps; setup_time_s is "
                                      "the rest (starting its ranks, reading the data and the "
                                      "trajectory); no kernel is compiled")
    summary["units_note"] = ("absolute figures and references are in internal units (the "
                             "scene's scales: parameters.scales); *_J in joules")
    if sol.extra.get("failure"):
        summary["failure"] = dict(sol.extra["failure"])
    if sol.extra.get("field_regrowths"):  # a tabulated field's region grew (or could not)
        summary["field_regrowths"] = list(sol.extra["field_regrowths"])
    summary["written_utc"] = datetime.now(UTC).isoformat(timespec="seconds")
    if "resumed_from" in sol.extra:
        summary["resumed_from"] = Path(sol.extra["resumed_from"]).name
    return summary


def distance_figures(rel: np.ndarray, length: float, shown: int, nrows: int, plot_rows: int
                     ) -> dict[str, object]:
    """Smallest and largest two-body distance [m] over the ``shown`` rows of ``nrows`` saved
    (all of them up to ``plot_rows``)."""
    rn = np.linalg.norm(rel, axis=1) * length
    return {"min_distance_m": float(rn.min()), "max_distance_m": float(rn.max()),
            "distance_note": "over the saved states (every --save-every steps)"
            if nrows <= plot_rows else f"over {shown} of {nrows} saved states"}


def run_provenance(args: argparse.Namespace, spec: RunSpec, scales: Scales | None
                   ) -> dict[str, JSONValue]:
    """Versions, command line, options, scene copy and units (``summary.json``)."""
    from poissonkit.report.provenance import provenance
    from poissonkit.scene.registered import resolve_scene

    target = resolve_scene(args.scene) if args.scene is not None else None
    found = provenance(args, target, scales)
    source = found["scene_source"]
    if isinstance(source, dict) and source.get("kind") == "registered":
        # a registered scene is code: its name and the parameters it resolved to
        source.update(resolved_name=spec.name, parameters=dict(spec.metadata or {}))
    if getattr(args, "from_summary", None) is not None:
        found["rerun_of"] = str(Path(args.from_summary).resolve())
    return found


def run_problems(energy_error: float, message: str, tol: float, interrupted: bool,
                 touching: list[EventRecord], time_unit: float,
                 failure: Mapping[str, object] | None = None) -> list[str]:
    """The warnings of a run: failed, stopped early, bodies touched, energy error above
    tolerance (``message``: the run's status message, times in seconds)."""
    out = []
    if failure:
        out.append(f"run failed at t = {failure['time_s']:.9g} s: {failure['reason']}; the "
                   f"trajectory up to t = {failure['last_saved_time_s']:.9g} s (the last good "
                   "saved state), the summary and the figures are written")
    if interrupted:
        out.append(f"run interrupted: {message}; partial results written "
                   "(resume with --resume if --checkpoint-every was given)")
    for e in touching:
        where = (f"at t = {e.time * time_unit:.9g} s (located to {e.time_error * time_unit:.2g} "
                 f"s, step {e.step}); the run stopped there")
        field_name = e.detail.get("field")
        if field_name is not None:  # a field's source is a solid (docs/fields.md)
            body = (e.detail.get("bodies") or ["?"])[0]
            out.append(f"body {body!r} touched the source of field {field_name!r} {where} — "
                       "the body would enter the magnet beyond this time")
            continue
        names, dist = e.detail.get("bodies") or [], e.detail.get("distance_m")
        who = f"bodies {' and '.join(map(repr, names))}" if names else "bodies"
        at = f" at a centre distance of {dist:.6g} m" if e.kind == "collision" and dist else ""
        out.append(f"{who} touched ({e.kind}){at} {where} — the scene's bodies interpenetrate "
                   "beyond this time")
    if energy_error > tol:
        out.append(f"energy error max |ΔH|/|H(0)| = {energy_error:.3g} "
                   f"exceeds the scene's tolerance {tol:g}")
    return out
