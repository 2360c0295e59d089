"""States at requested times: ``solve(t_eval=...)`` and ``poissonkit run --save-dt``.

Every method reaches a requested time exactly, without interpolation: the run is split at the
sample times and each piece is integrated to its end. A fixed-step method then takes
``ceil(piece / step)`` equal steps of at most ``step`` inside each piece (exact stepping to the
sample times, so the order of the method is untouched); an adaptive method (scipy, adaptive
splitting) restarts its step-size control at each sample, starting from ``step`` if given. The
result holds the start, every sample time and the end — the start and end are always saved, as
with ``save_every``.

Events are located inside the pieces as in a plain run; a terminal event ends the run at its
located time (the last row). A ``stop`` request is honoured between pieces.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from poissonkit.contracts import Event, Integrator, System
from poissonkit.errors import InputError
from poissonkit.numerics.events import EventRecord
from poissonkit.numerics.integrators.base import RawResult, note_left_regime, progress_bar

#: Samples closer than this fraction of the span to the end time are the end time itself (a
#: grid ``t0 + k dt`` rarely hits ``t_end`` to the last bit).
END_SLACK = 1e-9
#: Most sample times one run may ask for (each piece costs one integrator call).
MAX_SAMPLES = 10**6


def check_sample_times(t_eval: ArrayLike, t0: float, t_end: float) -> np.ndarray:
    """The requested sample times strictly between ``t0`` and ``t_end`` (validated).

    Parameters
    ----------
    t_eval
        Increasing times in ``[t0, t_end]`` (internal unit). ``t0`` and ``t_end`` may be
        included; they are always part of the result anyway.
    t0, t_end
        The run's start and end.

    Returns
    -------
    numpy.ndarray
        The interior times, strictly increasing.

    Raises
    ------
    InputError
        Not a 1-D array of finite numbers, not strictly increasing, outside ``[t0, t_end]``
        or more than :data:`MAX_SAMPLES` times.
    """
    try:
        times = np.asarray(t_eval, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"t_eval must be a sequence of times, got {t_eval!r} ({exc})") from None
    if times.ndim != 1 or times.size == 0:
        raise InputError(f"t_eval must be a non-empty 1-D sequence of times, got shape "
                         f"{times.shape}")
    if times.size > MAX_SAMPLES:
        raise InputError(f"t_eval asks for {times.size} times; at most {MAX_SAMPLES} "
                         "(save fewer states or use save_every)")
    if not np.all(np.isfinite(times)):
        raise InputError("t_eval contains NaN or inf")
    if np.any(np.diff(times) <= 0):
        k = int(np.argmax(np.diff(times) <= 0))
        raise InputError(f"t_eval must be strictly increasing; t_eval[{k + 1}] = "
                         f"{times[k + 1]!r} follows {times[k]!r}")
    span = t_end - t0
    if times[0] < t0 or times[-1] > t_end + END_SLACK * span:
        raise InputError(f"t_eval must lie in [t0, t_end] = [{t0!r}, {t_end!r}]; got "
                         f"[{times[0]!r}, {times[-1]!r}]")
    return times[(times > t0) & (times < t_end - END_SLACK * span)]


def uniform_times(t0: float, t_end: float, dt: float) -> np.ndarray:
    """Sample times ``t0 + k dt`` (``k >= 1``) before ``t_end``; ``dt`` must be positive.

    Raises
    ------
    InputError
        ``dt`` not a positive finite number, or more than :data:`MAX_SAMPLES` samples.
    """
    if not (np.isfinite(dt) and dt > 0):
        raise InputError(f"the sampling interval must be a positive number, got {dt!r}")
    count = (t_end - t0) / dt
    if count > MAX_SAMPLES:
        raise InputError(f"a sampling interval of {dt!r} gives {count:.3g} samples; at most "
                         f"{MAX_SAMPLES} (choose a longer interval)")
    k = np.arange(1, int(np.floor(count)) + 1, dtype=float)
    times = t0 + k * dt
    return times[times < t_end - END_SLACK * (t_end - t0)]


def integrate_at_times(integ: Integrator, system: System, y0: np.ndarray, t0: float,
                       t_end: float, times: np.ndarray, *, step: float | None,
                       tol: float | None, events: Sequence[Event], progress: bool,
                       stop: Callable[[], bool] | None, max_save_every: int) -> RawResult:
    """Integrate piece by piece through ``times`` (see the module docstring).

    Parameters
    ----------
    integ
        The integrator.
    system, y0, t0, t_end
        The problem (internal units).
    times
        Interior sample times from :func:`check_sample_times`.
    step, tol, events
        As in :func:`~poissonkit.numerics.solve`; ``step`` is the largest step in a piece.
    progress
        One progress bar over the whole run.
    stop
        Checked between pieces; a true answer ends the run there (``extra["interrupted"]``).
    max_save_every
        A ``save_every`` larger than any piece's step count, so a piece saves its two ends.

    Returns
    -------
    RawResult
        Rows at ``t0``, each sample time and the end (or a terminal event's time).
    """
    bounds = np.concatenate(([t0], times, [t_end]))
    ts, ys = [float(t0)], [np.array(y0, dtype=float)]
    records: list[EventRecord] = []
    steps = nfev = 0
    message, interrupted = "done", False
    regime: list[str] = []  # the pieces' reasons for leaving the method's regime, in order
    bar = progress_bar(progress, t_end - t0, integ.name)
    try:
        for a, b in zip(bounds[:-1], bounds[1:]):
            piece_step = None if step is None else min(step, float(b - a))
            raw = integ.integrate(system, ys[-1], float(b), step=piece_step, tol=tol,
                                  events=events, progress=False, save_every=max_save_every,
                                  t0=float(a))
            records.extend(replace(r, step=r.step + steps) for r in raw.events)
            steps += int(raw.steps)
            nfev += int(raw.nfev)
            regime += [r for r in raw.extra.get("regime", []) if r not in regime]
            t_last = float(raw.t[-1])
            ts.append(t_last)
            ys.append(np.array(raw.y[-1], dtype=float))
            if bar is not None:
                bar.update(t_last - a)
            if t_last < b:  # a terminal event ended the piece early
                message = raw.message
                break
            if stop is not None and b < t_end and stop():
                interrupted = True
                message = f"interrupted at step {steps} (t = {b:.10g})"
                break
    finally:
        if bar is not None:
            bar.close()
    out = RawResult(np.array(ts), np.vstack(ys), steps, nfev=nfev, events=records,
                    message=message, extra={"interrupted": interrupted,
                                            "sample_times": len(times)})
    note_left_regime(out, integ.name, regime)
    return out
