"""A run that stops on an error keeps what it did: its partial result, and messages in seconds.

When the integration of ``poissonkit run`` raises (a non-finite state — e.g. a body leaving a
tabulated field's region —, a method's own failure, a second Ctrl-C), :func:`partial_solution`
hands the rows the loop still held to the trajectory stream (the numerics attach them to the
error as its :class:`~poissonkit.errors.AbortState`, ``IntegrationError.abort`` or
``InterruptedRun.abort``) and returns a
:class:`~poissonkit.numerics.solution.Solution` ending at the last good saved state, with
``extra["failure"]`` describing the failure (:func:`failure_record`). The run's usual writer
(:func:`poissonkit.report.run_output.write_run_outputs`) then writes ``summary.json``
(``status: "failed"``), the trajectory up to that state and the figures.

The numerics speak in the scene's internal time unit; :func:`in_seconds` rewrites their
``t = …`` and ``Δt = …`` into seconds here, where the unit is known.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.errors import AbortState, IntegrationError, InterruptedRun, NonFiniteStateError
from poissonkit.numerics.fields.regions import FieldRegionError
from poissonkit.report.run_units import layout_of, scene_time_unit

if TYPE_CHECKING:
    from poissonkit.numerics.checkpoint import TrajectoryStream
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.numerics.solution import Solution

# (the lookahead refuses a match that stops inside a number, so "t = 0.331 s" is left alone
# rather than read as "t = 0.33" followed by "1 s")
_TIME = re.compile(r"(?P<name>\bt|Δt) = (?P<value>[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
                   r"(?![\d.eE]| s\b)")


def in_seconds(message: str, time_unit: float) -> str:
    """``message`` with every internal ``t = X`` / ``Δt = X`` given in seconds instead."""
    if time_unit == 1.0:
        return _TIME.sub(lambda m: f"{m['name']} = {m['value']} s", message)
    return _TIME.sub(lambda m: f"{m['name']} = {float(m['value']) * time_unit:.6g} s", message)


def failure_record(spec: RunSpec, exc: BaseException, time_unit: float, last_t: float
                   ) -> dict[str, Any]:
    """What ``summary.json["failure"]`` says of an aborted run: ``kind`` (the error's class),
    ``reason`` (its message, times in seconds), ``time_s`` (where the run failed),
    ``last_saved_time_s``, and where known ``step``, ``body``, ``field`` and ``quantity`` at
    fault; for a scene written in other units (``[units]``) also ``time_scene`` in
    ``time_scene_unit``, also named at the end of ``reason``."""
    abort = abort_state(exc)
    if isinstance(exc, KeyboardInterrupt):
        reason = "interrupted twice (Ctrl-C): aborted"
    else:
        reason = in_seconds(str(exc), time_unit)
    failed_at = last_t
    if isinstance(exc, NonFiniteStateError):
        failed_at = exc.time
    elif abort is not None:
        failed_at = abort.time_reached
    record: dict[str, Any] = {
        "kind": "KeyboardInterrupt" if isinstance(exc, KeyboardInterrupt) else type(exc).__name__,
        "reason": reason,
        "time_s": float(failed_at) * time_unit, "last_saved_time_s": float(last_t) * time_unit}
    factor, label = scene_time_unit(spec)
    if label != "s":  # a scene written in other units ([units]) also gets the time in them
        record["time_scene"], record["time_scene_unit"] = float(failed_at) * factor, label
        record["reason"] += f" (that is {float(failed_at) * factor:.6g} {label})"
    if isinstance(exc, NonFiniteStateError):
        record["step"] = exc.step
    elif abort is not None:
        record["step"] = abort.steps_done
    layout = layout_of(spec.system)
    if abort is not None and abort.body is not None:
        record["body"] = abort.body
    if isinstance(exc, FieldRegionError):
        record["field"] = exc.field
        record["quantity"] = (f"position {exc.position} m at t = {exc.position_time_s:.6g} s, "
                              f"leaving the region of field {exc.field!r}")
    if isinstance(exc, NonFiniteStateError) and abort is not None and abort.bad_components \
            and layout:
        names = [layout[i] for i in abort.bad_components if 0 <= i < len(layout)]
        record.setdefault("quantity",
                          "non-finite state components: " + ", ".join(names[:12]))
        bodies = _bodies_of(spec, names)
        if bodies and "body" not in record:
            record["body"] = bodies[0] if len(bodies) == 1 else bodies
    return record


def abort_state(exc: BaseException) -> AbortState | None:
    """Where the compiled loop stood when ``exc`` ended it, if the numerics said."""
    if isinstance(exc, (IntegrationError, InterruptedRun)):
        return exc.abort
    return None


def _bodies_of(spec: RunSpec, names: list[str]) -> list[str]:
    """Body names found in state component names (``"<body>.<quantity>…"`` layouts)."""
    known = [str(b) for b in (spec.metadata or {}).get("bodies", ()) if isinstance(b, str)]
    found: list[str] = []
    for n in names:
        head = n.split(".")[0] if "." in n else n.rsplit("_", 1)[0]
        body = next((b for b in known if n.startswith(b)), head)
        if body not in found:
            found.append(body)
    return found


def partial_solution(spec: RunSpec, exc: BaseException, stream: TrajectoryStream,
                     method: str, time_unit: float, wall: float) -> Solution:
    """The partial result of a run aborted by ``exc``: the held rows are written to ``stream``
    (the initial state if nothing was saved yet) and the solution ends at the last saved state,
    its ``extra["failure"]`` set (:func:`failure_record`)."""
    from poissonkit.numerics.solution import Solution

    abort = abort_state(exc)
    if abort is not None and len(abort.held_rows[0]):
        t_held, y_held = (np.asarray(a, dtype=float) for a in abort.held_rows)
        good = np.all(np.isfinite(y_held), axis=1) & np.isfinite(t_held)
        stream.write(t_held[good], y_held[good])
    y0 = np.asarray(spec.y0, dtype=float)
    if stream.rows == 0:  # nothing saved yet: the initial state is the last good one
        stream.write(np.array([0.0]), y0.reshape(1, -1))
    from poissonkit.numerics.parts import iter_parts, verify_parts

    infos = verify_parts(stream.folder)  # one part in memory at a time: the first, the last
    t_first, y_first = next(iter_parts(infos[:1]))
    t_last, y_last = next(iter_parts(infos[-1:]))
    last_t = float(t_last[-1])
    failure = failure_record(spec, exc, time_unit, last_t)
    steps = failure.get("step", 0)
    return Solution(t=np.array([t_first[0], last_t]), y=np.vstack([y_first[0], y_last[-1]]),
                    method=method, steps=int(steps), wall_time=wall, system=None,
                    message=failure["reason"],
                    extra={"streamed_rows": stream.rows, "stream": str(stream.folder),
                           "failure": failure, "interrupted": False})
