"""The work a run asks for, known before it starts: steps, cost per step, a guard on steps.

A step of 1e-9 s on a scene of 0.05 s is 5·10⁷ steps; at a few milliseconds each that is days.
:func:`plan_run` tells it up front: it counts the steps a fixed-step run takes, refuses more than
``max_steps`` (``--max-steps`` / the scene's ``run.max_steps``) with a
:class:`StepLimitError` before any step is taken, and estimates the wall time as steps × cost
per step, with a warning past :data:`WARN_SECONDS`. The cost per step is measured on a few steps
of the run itself (its kernels already compiled), and only when an upper bound (e.g. the time of
the compile-and-one-step warm-up) does not already show the run is short.

Adaptive methods (``tol``) choose their steps as they go: their count is not known up front, so
neither the estimate nor the guard applies to them.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

from poissonkit.errors import InputError
from poissonkit.numerics.runspec import RunSpec

#: A run estimated to take longer than this (seconds of wall time) is warned about.
WARN_SECONDS = 600.0
#: Steps of the run timed for the estimate, at most (fewer if one step is already slow).
MEASURE_STEPS = 64
#: Wall time spent on measuring, at most about this much (seconds).
MEASURE_SECONDS = 0.5

__all__ = ["MEASURE_STEPS", "WARN_SECONDS", "RunPlan", "StepLimitError", "WorkloadWarning",
           "planned_steps", "plan_run"]


class StepLimitError(InputError):
    """A run would take more steps than its ``max_steps`` allows (raised before it starts)."""


class WorkloadWarning(UserWarning):
    """A run is estimated to take longer than :data:`WARN_SECONDS`."""


@dataclass(frozen=True)
class RunPlan:
    """What :func:`plan_run` found.

    Attributes
    ----------
    save_every
        Keep every ``save_every``-th step: the explicit value, else the scene's, else 1.
    steps
        Fixed steps the run takes, or ``None`` for an adaptive method.
    seconds_per_step
        Measured (or bounded) wall time of one step, or ``None`` if not measured.
    seconds
        ``steps × seconds_per_step``, or ``None``.
    """

    save_every: int
    steps: int | None
    seconds_per_step: float | None = None
    seconds: float | None = None

    def describe(self) -> str:
        """One line for users: steps and the estimated wall time."""
        if self.steps is None:
            return "adaptive steps: no estimate up front"
        if self.seconds is None:
            return f"{self.steps} steps"
        return (f"{self.steps} steps × {_duration(self.seconds_per_step or 0.0)} per step ≈ "
                f"{_duration(self.seconds)}")


def _duration(seconds: float) -> str:
    for unit, size in (("d", 86400.0), ("h", 3600.0), ("min", 60.0), ("s", 1.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds * 1e3:.3g} ms"


def planned_steps(spec: RunSpec) -> int | None:
    """Fixed steps ``spec`` takes to reach ``t_end`` (``None``: an adaptive run).

    Counted as the integrators do: ``ceil(t_end / step)`` with a relative slack of 1e-12, so
    that ``0.05 / 1e-4`` is 500 steps, not 501.
    """
    if spec.step is None or not spec.step > 0:
        return None
    ratio = float(spec.t_end) / float(spec.step)  # Python floats: inf, not a warning
    if not math.isfinite(ratio):
        return None
    return max(1, math.ceil(ratio * (1 - 1e-12)))


def _resolve_every(explicit: int | None, spec: RunSpec) -> int:
    every = explicit if explicit is not None else (spec.save_every or 1)
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        what = "--save-every" if explicit is not None else "run.save_every"
        raise InputError(f"{what} must be >= 1, got {every!r}")
    return every


def _resolve_limit(explicit: int | None, spec: RunSpec) -> int | None:
    limit = explicit if explicit is not None else spec.max_steps
    if limit is not None and (isinstance(limit, bool) or not isinstance(limit, int) or limit < 1):
        what = "--max-steps" if explicit is not None else "run.max_steps"
        raise InputError(f"{what} must be a positive integer, got {limit!r}")
    return limit


def _measure(spec: RunSpec, steps: int) -> float:
    """Wall time of one step of ``spec``, timed on up to :data:`MEASURE_STEPS` of its steps."""
    from poissonkit.numerics.solver import solve

    assert spec.step is not None

    def run(n: int) -> float:
        t0 = time.perf_counter()
        solve(spec.system, spec.y0, float(spec.step) * n, method=spec.method, step=spec.step,
              save_every=n, options=spec.options)
        return time.perf_counter() - t0

    run(1)  # compiles the kernels if nobody has yet (the command line's warm-up did)
    n = 1
    while True:
        per = run(n) / n
        if n >= min(steps, MEASURE_STEPS) or per * n * 4 > MEASURE_SECONDS:
            return per
        n = min(steps, MEASURE_STEPS, n * 8)


def plan_run(spec: RunSpec, save_every: int | None = None, max_steps: int | None = None, *,
             step_seconds_bound: float | None = None, warn_seconds: float = WARN_SECONDS,
             report: Callable[[str], None] | None = None, measure: bool = True) -> RunPlan:
    """Check a run against its step limit and estimate its wall time, before it starts.

    Parameters
    ----------
    spec
        The run (its ``save_every`` and ``max_steps`` are the scene's values).
    save_every, max_steps
        Explicit values (command-line options); ``None``: the scene's.
    step_seconds_bound
        An upper bound on the wall time of one step (e.g. the time of a compile-and-one-step
        warm-up); when ``steps × bound`` is below ``warn_seconds`` nothing is measured.
    warn_seconds
        Estimated wall times above this are reported.
    report
        Called with the warning text; default: :func:`warnings.warn` with
        :class:`WorkloadWarning`.
    measure
        ``False``: only resolve ``save_every`` and check the step limit (nothing runs; e.g.
        before output folders are touched); the estimate is then left out.

    Returns
    -------
    RunPlan

    Raises
    ------
    StepLimitError
        More fixed steps than ``max_steps`` (nothing has run yet).
    InputError
        ``save_every`` or ``max_steps`` not a positive integer.
    """
    every = _resolve_every(save_every, spec)
    limit = _resolve_limit(max_steps, spec)
    steps = planned_steps(spec)
    if steps is None:
        return RunPlan(every, None)
    if limit is not None and steps > limit:
        raise StepLimitError(
            f"the run takes {steps} steps (duration / step), more than max_steps = {limit}; "
            "use a longer step or a shorter duration, or raise --max-steps / run.max_steps")
    if not measure:
        return RunPlan(every, steps)
    if step_seconds_bound is not None and steps * step_seconds_bound <= warn_seconds:
        return RunPlan(every, steps, step_seconds_bound, steps * step_seconds_bound)
    per = _measure(spec, steps)
    plan = RunPlan(every, steps, per, steps * per)
    if plan.seconds is not None and plan.seconds > warn_seconds:
        text = (f"this run is estimated to take {plan.describe()} (more than "
                f"{_duration(warn_seconds)}); Ctrl-C stops it and keeps what was computed, "
                "--max-steps refuses long runs up front")
        if report is None:
            warnings.warn(text, WorkloadWarning, stacklevel=2)
        else:
            report(text)
    return plan
