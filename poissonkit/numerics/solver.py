"""``solve``: one entry point for every integrator in the registry."""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from contextlib import AbstractContextManager, nullcontext
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from poissonkit.contracts import (Event, HasBodies, HasCompiledKernels, HasOverlapCheck, Integrator,
                                  NumericsSystem, System)
from poissonkit.errors import CapabilityError, DimensionError, InputError, IntegrationError
from poissonkit.numerics.fields.contact import refuse_inside
from poissonkit.numerics.solution import Solution
from poissonkit.plugin.contributions import Capabilities
from poissonkit.traits import offers

if TYPE_CHECKING:
    from poissonkit.numerics.checkpoint import Checkpoint, TrajectoryStream
    from poissonkit.numerics.integrators.driver import Control

#: Most fixed steps one call may ask for (10^7 steps of a small system take minutes; 10^10
#: would take days, and a step of 1e-300 overflows the step counter).
MAX_STEPS = 10**10

#: Option values a registry entry's parameters accept (checked against their declared types).
OptionValue = float | int | str | bool | Sequence[float]


def make_integrator(method: str | Integrator,
                    options: Mapping[str, OptionValue] | None = None) -> Integrator:
    """Integrator object for a registry name (validated ``options``) or pass one through.

    An object must follow :class:`poissonkit.contracts.Integrator` (``name``, ``order``,
    ``capabilities``, ``integrate``).
    """
    return _integrator_and_capabilities(method, options)[0]


def _integrator_and_capabilities(method: str | Integrator,
                                 options: Mapping[str, OptionValue] | None
                                 ) -> tuple[Integrator, Capabilities]:
    """The integrator and what it declares it can do: a registry name's entry, or the
    object's own ``capabilities``."""
    if isinstance(method, str):
        from poissonkit.plugin import integrator

        from poissonkit.numerics.solve_options import check_options

        entry = integrator(method)
        return entry.factory(**check_options(entry, options or {})), entry.capabilities
    if isinstance(method, Integrator):
        if options:
            raise InputError("options are only accepted with a registry name")
        caps = method.capabilities
        if not isinstance(caps, Capabilities):
            raise InputError(f"integrator {method.name!r}: capabilities must be a "
                             f"poissonkit.plugin.Capabilities, got {caps!r}")
        return method, caps
    raise InputError(f"method must be a registry name or an integrator (name, order, "
                     f"capabilities, integrate: poissonkit.contracts.Integrator), got {method!r}")


def _finite_number(value: object, name: str) -> float:
    """``float(value)``; :class:`InputError` naming ``name`` unless a finite number."""
    try:
        v = float(value)  # type: ignore[arg-type]  # any number-like; others are refused here
    except (TypeError, ValueError, OverflowError):  # 10**400 overflows
        raise InputError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    return v


#: A step longer than ``t_end - t0`` by at most this relative amount is the whole span: such
#: spans are differences of sample times, short of the step by round-off.
STEP_SPAN_RTOL = 1e-9


def _check_arguments(system: System, y0: ArrayLike, t0: float, t_end: float,
                     save_every: int, step: float | None, tol: float | None
                     ) -> tuple[np.ndarray, float, float, float | None, float | None]:
    """:func:`solve`'s numbers checked (:class:`InputError` / :class:`DimensionError` naming
    the argument) and converted: ``(y0, t0, t_end, step, tol)``."""
    try:
        y0 = np.array(y0, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"y0 must be a flat sequence of numbers, got {y0!r} ({exc})") from None
    # a bare set of compiled kernels (no ``dim``) takes the state's length
    dim = system.dim if offers(system, NumericsSystem) else y0.size
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
        span = t_end - t0
        if step > span:  # scipy refuses a first step beyond the interval
            if step > span * (1.0 + STEP_SPAN_RTOL):
                raise InputError(f"step {step!r} is longer than t_end - t0 = {span!r}")
            step = span  # longer by round-off only (a span computed as a difference of times)
        if (t_end - t0) / step > MAX_STEPS:  # 1e-300: an overflow deep inside, or a hang
            raise InputError(f"step {step!r} would take more than {MAX_STEPS:.0e} steps to "
                             f"reach t_end = {t_end!r}")
    if tol is not None:
        tol = _finite_number(tol, "tol")
        if not tol > 0:
            raise InputError(f"tol must be positive, got {tol!r}")
    return y0, t0, t_end, step, tol


def solve(system: System, y0: ArrayLike, t_end: float, method: str | Integrator = "splitting6",
          step: float | None = None, tol: float | None = None, events: Sequence[Event] = (),
          progress: bool = False, save_every: int = 1,
          options: Mapping[str, OptionValue] | None = None, t0: float = 0.0,
          checkpoint: Checkpoint | None = None, resume: bool = False,
          stream: TrajectoryStream | str | os.PathLike[str] | None = None,
          stop: Callable[[], bool] | None = None,
          t_eval: ArrayLike | None = None) -> Solution:
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
        The registry entry's options (``{"table": "10_6_4"}`` for ``wisdom_holman``), checked
        against its declaration (:func:`~poissonkit.numerics.solve_options.check_options`): an
        unknown name is an :class:`~poissonkit.errors.InputError` listing the valid ones.
    t0
        Start time.
    checkpoint
        :class:`~poissonkit.numerics.checkpoint.Checkpoint` (folder, every ``n`` steps): atomic,
        checksummed checkpoints. Methods whose capabilities include ``checkpoint`` (the compiled
        loops: splittings, logh, midpoint, Wisdom–Holman; not scipy).
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
        (``extra["interrupted"]``, ``message`` says where), writing a last checkpoint. A request,
        not a demand: methods without the ``stop`` capability (scipy) run to their end.
    t_eval
        Times (internal unit, increasing, in ``[t0, t_end]``) at which to save the state,
        reached exactly by every method: fixed-step methods step exactly to each sample time
        (at most ``step`` per step), adaptive ones restart at each
        (:mod:`poissonkit.numerics.sample_times`). The solution holds ``t0``, these times and
        the end. Not with ``save_every``, ``checkpoint`` or ``resume``; ``stop`` is honoured
        between samples, a ``stream`` receives the rows at the end.

    Returns
    -------
    Solution

    Raises
    ------
    InputError
        Bad arguments (named).
    CapabilityError
        The run asks the method for something its declared
        :class:`~poissonkit.plugin.contributions.Capabilities` exclude (checkpoint/resume,
        events, located events, a system it cannot integrate); raised before any work.
    CheckpointError
        ``resume`` without a valid checkpoint, or one of another problem.
    """
    y0, t0, t_end, step, tol = _check_arguments(system, y0, t0, t_end, save_every, step, tol)
    if progress:
        with _bar_in_system_units(system):
            return _solve_checked(system, y0, t0, t_end, method, step, tol, events, progress,
                                  save_every, options, t_eval, stop, stream, checkpoint, resume)
    return _solve_checked(system, y0, t0, t_end, method, step, tol, events, progress,
                          save_every, options, t_eval, stop, stream, checkpoint, resume)


def _bar_in_system_units(system: System) -> AbstractContextManager[None]:
    """A bar that counts the time unit of a system given in other units than SI
    (``NBodySystem(units=...)``: its numbers are in those units), unless a caller chose one."""
    from poissonkit.numerics.integrators.base import progress_in_unit, progress_unit_set
    from poissonkit.numerics.unitsystem import units_of

    units = units_of(system)
    if units.is_si or progress_unit_set():
        return nullcontext()
    return progress_in_unit(1.0, units.label("time"))


def _solve_checked(system: System, y0: np.ndarray, t0: float, t_end: float,
                   method: str | Integrator, step: float | None, tol: float | None,
                   events: Sequence[Event], progress: bool, save_every: int,
                   options: Mapping[str, OptionValue] | None, t_eval: ArrayLike | None,
                   stop: Callable[[], bool] | None,
                   stream: TrajectoryStream | str | os.PathLike[str] | None,
                   checkpoint: Checkpoint | None, resume: bool) -> Solution:
    """:func:`solve` after its arguments are checked."""
    from poissonkit.numerics.events import check_events

    events = check_events(events)
    integ, caps = _integrator_and_capabilities(method, options)
    refuse_inside(system, y0)  # a body inside a magnet or on a wire: the field is not valid
    if t_eval is not None:
        return _solve_at_times(integ, caps, system, y0, t0, t_end, t_eval, step=step, tol=tol,
                               events=events, progress=progress, stop=stop, stream=stream,
                               save_every=save_every, checkpointed=checkpoint is not None
                               or resume)
    control = _control(checkpoint, resume, stream, stop)
    refuse_beyond(caps, integ.name, system, events, control)
    if offers(system, HasOverlapCheck):  # coincident bodies: singular forces whatever
        system.check_overlap(y0)              # the method
    return _run(integ, caps, system, y0, t0, t_end, control, step=step, tol=tol, events=events,
                progress=progress, save_every=int(save_every))


def _run(integ: Integrator, caps: Capabilities, system: System, y0: np.ndarray, t0: float,
         t_end: float, control: Control | None, *, step: float | None, tol: float | None,
         events: Sequence[Event], progress: bool, save_every: int) -> Solution:
    """Run the checked problem with the controls the integrator honours; a stream it cannot
    fill is written once it is done."""
    control, late_stream = _within(caps, control)
    kwargs = {"control": control} if control is not None else {}  # older integrators: none
    start = time.perf_counter()
    try:
        raw = integ.integrate(system, y0, t_end, step=step, tol=tol, events=events,
                              progress=progress, save_every=save_every, t0=t0, **kwargs)
    except ZeroDivisionError:
        # built-in integrators name the step themselves; this catches third-party ones
        raise IntegrationError(f"{integ.name}: division by zero in a compiled kernel (two "
                               "bodies at the same place?)") from None
    wall = time.perf_counter() - start
    if late_stream is not None:
        late_stream.write(raw.t, raw.y)
        raw.extra.update(stream=str(late_stream.folder), streamed_rows=late_stream.rows,
                         interrupted=False)
        raw.t, raw.y = raw.t[[0, -1]], raw.y[[0, -1]]
    return Solution(t=raw.t, y=raw.y, method=integ.name, steps=raw.steps,
                    wall_time=wall, system=system, nfev=raw.nfev, events=raw.events, step=step,
                    tol=tol, message=raw.message, extra=raw.extra)


def _solve_at_times(integ: Integrator, caps: Capabilities, system: System, y0: np.ndarray,
                    t0: float, t_end: float, t_eval: ArrayLike, *, step: float | None,
                    tol: float | None, events: Sequence[Event], progress: bool,
                    stop: Callable[[], bool] | None,
                    stream: TrajectoryStream | str | os.PathLike[str] | None,
                    save_every: int, checkpointed: bool) -> Solution:
    """``solve`` with ``t_eval``: piece by piece through the sample times."""
    from poissonkit.numerics.sample_times import check_sample_times, integrate_at_times

    if save_every != 1:
        raise InputError("give t_eval or save_every, not both (t_eval chooses the saved "
                         "states)")
    if checkpointed:
        raise InputError("t_eval cannot be combined with checkpoint/resume: a run saving "
                         "states at given times is not checkpointed; use save_every")
    times = check_sample_times(t_eval, t0, t_end)
    refuse_beyond(caps, integ.name, system, events, None)
    if offers(system, HasOverlapCheck):
        system.check_overlap(y0)

    if stop is not None and not callable(stop):
        raise InputError(f"stop must be a callable returning a bool, got {stop!r}")
    control = _control(None, False, stream, None)
    start = time.perf_counter()
    try:
        raw = integrate_at_times(integ, system, y0, t0, t_end, times, step=step, tol=tol,
                                 events=events, progress=progress, stop=stop,
                                 max_save_every=MAX_STEPS)
    except ZeroDivisionError:
        raise IntegrationError(f"{integ.name}: division by zero in a compiled kernel (two "
                               "bodies at the same place?)") from None
    wall = time.perf_counter() - start
    if control is not None and control.stream is not None:
        control.stream.write(raw.t, raw.y)
        raw.extra.update(stream=str(control.stream.folder), streamed_rows=control.stream.rows)
        raw.t, raw.y = raw.t[[0, -1]], raw.y[[0, -1]]
    return Solution(t=raw.t, y=raw.y, method=integ.name, steps=raw.steps,
                    wall_time=wall, system=system, nfev=raw.nfev, events=raw.events, step=step,
                    tol=tol, message=raw.message, extra=raw.extra)


def _control(checkpoint: Checkpoint | None, resume: bool,
             stream: TrajectoryStream | str | os.PathLike[str] | None,
             stop: Callable[[], bool] | None) -> Control | None:
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
        if not isinstance(stream, (str, bytes, os.PathLike)):
            raise InputError(f"stream must be a folder or a TrajectoryStream, got {stream!r}")
        stream = TrajectoryStream(os.fsdecode(stream))
    if stop is not None and not callable(stop):
        raise InputError(f"stop must be a callable returning a bool, got {stop!r}")
    return Control(checkpoint=checkpoint, resume=bool(resume), stream=stream, stop=stop)


def refuse_beyond(caps: Capabilities, name: str, system: System, events: Sequence[Event],
                  control: Control | None) -> None:
    """Raise :class:`~poissonkit.errors.CapabilityError` for the first thing a run asks of
    the integrator ``name`` that its capabilities ``caps`` exclude (nothing is computed)."""
    if control is not None and control.checkpoint is not None and not caps.checkpoint:
        raise CapabilityError(name, "checkpoint", "checkpoint/resume need a compiled "
                              "fixed-step loop (splitting2/4/6/8, logh2–8, midpoint, "
                              "wisdom_holman); this method cannot be checkpointed")
    if events and not caps.events:
        raise CapabilityError(name, "events", f"events {[e.kind for e in events]} need a method "
                              "with the events capability")
    inside = [e.kind for e in events if not e.terminal]
    if inside and not caps.located_events:
        raise CapabilityError(name, "located_events", f"{inside[0]} events are located inside "
                              "the step; use a splitting, logh, midpoint or wisdom_holman "
                              "(this method locates sign changes only)")
    if caps.point_masses_only and offers(system, HasBodies) and (
            system.n_tops or system.n_moving != len(system.bodies)):
        raise CapabilityError(name, "point_masses_only", "the system has tops or fixed "
                              "bodies; this method needs moving point masses only")
    if not (caps.needs_kernels or caps.needs_splitting):
        return
    if not offers(system, HasCompiledKernels):
        raise CapabilityError(name, "needs_kernels", f"{type(system).__name__} has no compiled "
                              "kernels (kernels, data, work()); compile it with "
                              "compile_system or use a scipy method")
    if caps.needs_splitting and not system.kernels.splittable:
        raise CapabilityError(name, "needs_splitting", "this method needs a system with exact "
                              f"kinetic/potential flows (NBodySystem, TwoBodySystem); "
                              f"{type(system).__name__} has none — use 'midpoint' or a scipy "
                              "method")


def _within(caps: Capabilities, control: Control | None
            ) -> tuple[Control | None, TrajectoryStream | None]:
    """The controls the integrator honours, and a stream ``solve`` fills after the run when
    the integrator cannot stream (a stop request it cannot honour is dropped: a request)."""
    if control is None:
        return None, None
    late = None
    if control.stream is not None and not caps.stream:
        late, control = control.stream, replace(control, stream=None)
    if control.stop is not None and not caps.stop:
        control = replace(control, stop=None)
    if control.checkpoint is None and control.stream is None and control.stop is None:
        return None, late  # (resume without checkpoint was refused by _control)
    return control, late
