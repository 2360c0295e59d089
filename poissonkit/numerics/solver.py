"""``solve``: one entry point for every integrator in the registry."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from poissonkit.errors import DimensionError, InputError, IntegrationError
from poissonkit.numerics.solution import Solution


#: Most fixed steps one call may ask for (10^7 steps of a small system take minutes; 10^10
#: would take days, and a step of 1e-300 overflows the step counter).
MAX_STEPS = 10**10


def make_integrator(method: Any, options: Mapping[str, Any] | None = None) -> Any:
    """Integrator object for a registry name (validated ``options``) or pass one through."""
    if hasattr(method, "integrate"):
        if options:
            raise InputError("options are only accepted with a registry name")
        return method
    if not isinstance(method, str):
        raise InputError(f"method must be a registry name or an integrator, got {method!r}")
    from poissonkit.plugin import integrator

    entry = integrator(method)
    return entry.factory(**entry.resolve_params(dict(options or {})))


def _finite_number(value: Any, name: str) -> float:
    """``float(value)``; :class:`InputError` naming ``name`` unless a finite number."""
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):  # 10**400 overflows
        raise InputError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    return v


def solve(system: Any, y0: Any, t_end: float, method: Any = "splitting6", step: float | None = None,
          tol: float | None = None, events: Sequence[Any] = (), progress: bool = False,
          save_every: int = 1, options: Mapping[str, Any] | None = None, t0: float = 0.0,
          checkpoint: Any = None, resume: bool = False, stream: Any = None,
          stop: Any = None) -> Solution:
    """Integrate ``system`` from ``y0`` at ``t0`` to ``t_end``.

    Parameters
    ----------
    system
        A numerics system (:class:`~poissonkit.numerics.nbody.NBodySystem`,
        :class:`~poissonkit.numerics.twobody.TwoBodySystem`,
        :class:`~poissonkit.numerics.system.CompiledSystem`, …).
    y0
        Initial state in the system's layout (internal units).
    t_end
        Final time (internal unit).
    method
        Integrator registry name (``poissonkit plugins`` lists them; unknown names raise
        :class:`~poissonkit.errors.UnknownNameError`) or an integrator object.
    step
        Step size of fixed-step methods (initial/base step of adaptive splitting).
    tol
        Tolerance of adaptive methods (scipy: ``rtol = atol = tol``; midpoint: Newton tolerance).
    events
        :class:`~poissonkit.numerics.events.Collision`, :class:`~poissonkit.numerics.events.Contact`,
        :class:`~poissonkit.numerics.events.Escape`,
        :class:`~poissonkit.numerics.events.ClosestApproach` — located inside the step to their
        ``time_tol`` (see :mod:`poissonkit.numerics.events`).
    progress
        Show a tqdm progress bar.
    save_every
        Save every n-th step (start and end are always saved).
    options
        Parameters of the integrator's registry entry (e.g. ``{"adaptive": True}``).
    t0
        Start time.
    checkpoint
        :class:`~poissonkit.numerics.checkpoint.Checkpoint` (folder, every ``n`` steps): atomic,
        checksummed checkpoints. Fixed-step methods only (splittings, midpoint).
    resume
        Continue from the newest valid checkpoint of ``checkpoint.folder``; the final state is
        bit-identical to an uninterrupted run's.
    stream
        Folder or :class:`~poissonkit.numerics.checkpoint.TrajectoryStream`: saved rows go to disk
        in parts (memory stays bounded for the fixed-step methods; scipy methods write their rows
        when they finish); the returned solution then holds only the start and the final state,
        ``extra["stream"]`` names the folder
        (:func:`~poissonkit.numerics.checkpoint.read_trajectory` reads it).
    stop
        Callable checked between chunks of steps; when it returns true the run stops cleanly
        (``extra["interrupted"]``, ``message`` says where), writing a last checkpoint. Not
        honoured by the scipy methods.

    Returns
    -------
    Solution

    Raises
    ------
    InputError
        Bad arguments (named); checkpoint/stream/stop with a method that cannot honour them.
    CheckpointError
        ``resume`` without a valid checkpoint, or one of another problem.
    """
    try:
        y0 = np.array(y0, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"y0 must be a flat sequence of numbers, got {y0!r} ({exc})") from None
    dim = getattr(system, "dim", y0.size)
    if y0.ndim != 1 or y0.size != dim:
        raise DimensionError(f"y0 has shape {y0.shape}, the system needs ({dim},)")
    if not np.all(np.isfinite(y0)):
        raise InputError("y0 contains NaN or inf")
    t0 = _finite_number(t0, "t0")
    t_end = _finite_number(t_end, "t_end")
    if not t_end > t0:
        raise InputError(f"t_end must be > t0 = {t0}, got {t_end!r}")
    if not isinstance(save_every, (int, np.integer)) or save_every < 1:
        raise InputError(f"save_every must be a positive int, got {save_every!r}")
    if save_every > MAX_STEPS:  # compiled loops count in int64: 2**63 overflows inside
        raise InputError(f"save_every must be at most {MAX_STEPS:.0e}, got {save_every!r}")
    if step is not None:
        step = _finite_number(step, "step")
        if not step > 0:
            raise InputError(f"step must be positive, got {step!r}")
        if step > t_end - t0:  # scipy refuses a first step beyond the interval
            raise InputError(f"step {step!r} is longer than t_end - t0 = {t_end - t0!r}")
        if (t_end - t0) / step > MAX_STEPS:  # 1e-300: an overflow deep inside, or a hang
            raise InputError(f"step {step!r} would take more than {MAX_STEPS:.0e} steps to "
                             f"reach t_end = {t_end!r}")
    if tol is not None:
        tol = _finite_number(tol, "tol")
        if not tol > 0:
            raise InputError(f"tol must be positive, got {tol!r}")
    overlap = getattr(system, "check_overlap", None)
    if callable(overlap):  # coincident bodies: singular forces whatever the method
        overlap(y0)
    from poissonkit.numerics.events import check_events

    events = check_events(events)
    integ = make_integrator(method, options)
    kwargs: dict[str, Any] = {}
    control = _control(checkpoint, resume, stream, stop)
    late_stream = None
    if control is not None:
        if getattr(integ, "supports_control", False):
            kwargs["control"] = control
        elif control.checkpoint is not None or control.resume:
            raise InputError(f"checkpoint/resume need a fixed-step method "
                             f"(splitting2/4/6/8, midpoint); {getattr(integ, 'name', method)} "
                             "cannot be checkpointed")
        else:  # e.g. scipy: rows are streamed once the run is over, stop is not honoured
            late_stream = control.stream
    start = time.perf_counter()
    try:
        raw = integ.integrate(system, y0, t_end, step=step, tol=tol, events=events,
                              progress=progress, save_every=int(save_every), t0=t0, **kwargs)
    except ZeroDivisionError:
        # built-in integrators name the step themselves; this catches third-party ones
        raise IntegrationError(f"{getattr(integ, 'name', method)}: division by zero in a "
                               "compiled kernel (two bodies at the same place?)") from None
    wall = time.perf_counter() - start
    if late_stream is not None:
        late_stream.write(raw.t, raw.y)
        raw.extra.update(stream=str(late_stream.folder), streamed_rows=late_stream.rows,
                         interrupted=False)
        raw.t, raw.y = raw.t[[0, -1]], raw.y[[0, -1]]
    return Solution(t=raw.t, y=raw.y, method=getattr(integ, "name", str(method)), steps=raw.steps,
                    wall_time=wall, system=system, nfev=raw.nfev, events=raw.events, step=step,
                    tol=tol, message=raw.message, extra=raw.extra)


def _control(checkpoint: Any, resume: bool, stream: Any, stop: Any) -> Any:
    """The driver's :class:`~poissonkit.numerics.integrators.driver.Control`, or ``None``."""
    if checkpoint is None and not resume and stream is None and stop is None:
        return None
    from poissonkit.numerics.checkpoint import Checkpoint, TrajectoryStream
    from poissonkit.numerics.integrators.driver import Control

    if checkpoint is not None and not isinstance(checkpoint, Checkpoint):
        raise InputError(f"checkpoint must be a Checkpoint(folder, every), got {checkpoint!r}")
    if resume and checkpoint is None:
        raise InputError("resume=True needs checkpoint=Checkpoint(folder, every)")
    if stream is not None and not isinstance(stream, TrajectoryStream):
        if not isinstance(stream, (str, bytes)) and not hasattr(stream, "__fspath__"):
            raise InputError(f"stream must be a folder or a TrajectoryStream, got {stream!r}")
        stream = TrajectoryStream(stream)
    if stop is not None and not callable(stop):
        raise InputError(f"stop must be a callable returning a bool, got {stop!r}")
    return Control(checkpoint=checkpoint, resume=bool(resume), stream=stream, stop=stop)
