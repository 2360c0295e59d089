"""What every compiled fixed-step integrator does around :func:`~.driver.drive`, once.

The step grid (:func:`fixed_grid`), the plain-data description checked on resume
(:func:`describe`), the scratch a one-step replay writes into (:class:`Scratch`) and the chunk
that names the step of a division by zero (:func:`guard_division`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from poissonkit.numerics.integrators.base import (SaveBuffer, StepFn, check_step, locate_division,
                                                  state_digest)
from poissonkit.numerics.integrators.driver import ChunkFn, LoopState

#: a chunk's result: (status, t, steps done, rows saved, evaluations, value)
ChunkResult = tuple[int, float, int, int, int, float]


def fixed_grid(name: str, step: float | None, t0: float, t_end: float) -> tuple[float, int]:
    """``(h, n)``: the number of steps ``n`` of at most ``step`` that reach ``t_end``, and the
    step ``h = (t_end − t0)/n`` that lands on it exactly."""
    h = check_step(step, t_end - t0, name)
    span = t_end - t0
    n_total = max(1, math.ceil(span / h - 1e-12))
    return span / n_total, n_total


def describe(name: str, h: float, t0: float, t_end: float, n_total: int, save_every: int,
             y0: np.ndarray, **more: Any) -> dict[str, Any]:
    """The plain-data description of a fixed-step run that a resumed run must match (floats
    as hex, so that they compare exactly; ``more`` the method's own settings)."""
    out: dict[str, Any] = {"method": name, "h": float(h).hex(), "t0": float(t0).hex(),
                           "t_end": float(t_end).hex(), "n_total": n_total,
                           "save_every": save_every, "dim": int(np.size(y0))}
    out.update(more)
    out["y0"] = state_digest(np.asarray(y0, dtype=float))
    return out


class Scratch:
    """Throw-away output of one-step calls (event location, replays): a four-row buffer and an
    event memory that records nothing."""

    def __init__(self, dim: int) -> None:
        buf = SaveBuffer(dim, 4)
        self.t, self.y = buf.cur_t, buf.cur_y
        self.hist = np.zeros(5)


def guard_division(name: str, chunk: Callable[[LoopState, int, SaveBuffer], ChunkResult],
                   replay: Callable[[LoopState], tuple[StepFn, np.ndarray]]) -> ChunkFn:
    """``chunk`` raising, for a ``ZeroDivisionError`` inside the compiled loop, the typed error
    of :func:`~.base.locate_division` naming the step: ``replay(st)``, called *before* the
    chunk, returns the one-step function and the start state to replay from."""

    def guarded(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
        one_step, start = replay(st)
        try:
            return chunk(st, max_steps, buf)
        except ZeroDivisionError:
            raise locate_division(name, one_step, start, st.t, st.steps) from None

    return guarded
