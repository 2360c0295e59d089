"""Checks of ``poissonkit run``'s times made before it starts, in the scene's time unit.

The numerics check their arguments in internal units ("step 100.0 is longer than t_end − t0 =
5.0"); a user who wrote ``--step 1 --duration 0.05`` must read their own unit (seconds for an
SI scene, the ``[units]`` table's otherwise). These checks run first,
at the command layer that knows the time unit, so the user sees their own numbers; the
numerics' checks stay as the last guard. :func:`save_dt_cost` says what a ``--save-dt`` run
will keep before it starts.
"""

from __future__ import annotations

import math

from poissonkit.errors import InputError
from poissonkit.numerics.unitsystem import SI, UnitSystem

#: Saved rows above which ``--save-dt`` prints what the run will keep before it starts.
SAVE_DT_NOTE_ROWS = 10**5


def _shown(seconds: float, units: UnitSystem) -> str:
    """``seconds`` as a message shows it: ``"0.5 s"``, ``"12 yr"`` (the scene's time unit)."""
    return f"{float(units.from_si(seconds, 'time')):.6g} {units.label('time')}"


def check_times(step: float | None, t_end: float, save_dt: float | None, time_unit: float,
                units: UnitSystem = SI) -> None:
    """Refuse a step or a sampling interval not shorter than the run, in the scene's time unit.

    Parameters
    ----------
    step
        The fixed step (internal units), ``None`` for an adaptive method.
    t_end
        The end time (internal units; the run starts at 0).
    save_dt
        ``--save-dt`` in seconds, or ``None``.
    time_unit
        Seconds per internal time unit.
    units
        The scene's units: the messages quote times in its time unit (seconds for SI).
    """
    duration = float(t_end) * time_unit
    if step is not None and math.isfinite(step) and step > t_end:
        raise InputError(f"the step {_shown(step * time_unit, units)} is longer than the run's "
                         f"duration {_shown(duration, units)}; choose a shorter --step or a "
                         "longer --duration")
    if save_dt is not None and save_dt >= duration:
        raise InputError(f"--save-dt {_shown(save_dt, units)} is not shorter than the run's "
                         f"duration {_shown(duration, units)}: no state would be saved between "
                         "the first and the last; choose a shorter interval")
    if save_dt is not None:
        from poissonkit.numerics.sample_times import MAX_SAMPLES

        count = duration / save_dt
        if count > MAX_SAMPLES:
            raise InputError(f"--save-dt {_shown(save_dt, units)} over "
                             f"{_shown(duration, units)} gives "
                             f"{count:.3g} samples; at most {MAX_SAMPLES} (choose a longer "
                             "interval)")


def save_dt_rows(save_dt: float, t_end: float, time_unit: float) -> int:
    """Rows a ``--save-dt`` run keeps: the samples plus the first and last state."""
    return math.floor(float(t_end) * time_unit / save_dt) + 2


def save_dt_cost(save_dt: float, t_end: float, time_unit: float, dim: int,
                 units: UnitSystem = SI) -> str | None:
    """A note of what a ``--save-dt`` run keeps (rows, memory), when more than
    :data:`SAVE_DT_NOTE_ROWS` rows; ``None`` otherwise (``save_dt`` in seconds, quoted in the
    scene's time unit)."""
    rows = save_dt_rows(save_dt, t_end, time_unit)
    if rows <= SAVE_DT_NOTE_ROWS:
        return None
    size = rows * (dim + 1) * 8
    return (f"--save-dt {_shown(save_dt, units)} keeps {rows:,} rows of {dim} numbers "
            f"(about {size / 2**20:,.0f} MiB in memory and in trajectory.npz)")
