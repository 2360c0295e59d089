"""Shared pieces of the integrators: the raw result, status codes, progress bars."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.events import EventRecord

# status codes returned by the compiled loops
RUNNING, NONFINITE, COLLISION, ESCAPE, BUFFER_FULL, DONE, NO_CONVERGENCE = 0, 1, 2, 3, 4, 5, 6


@dataclass
class RawResult:
    """What an integrator returns to :func:`~poissonkit.numerics.solve`."""

    t: np.ndarray
    y: np.ndarray
    steps: int
    nfev: int = 0
    events: list[EventRecord] = field(default_factory=list)
    message: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


class SaveBuffer:
    """Growable (t, y) storage filled by compiled loops in chunks."""

    def __init__(self, dim: int, chunk: int) -> None:
        self.dim = dim
        self.chunk = max(int(chunk), 2)
        self.ts: list[np.ndarray] = []
        self.ys: list[np.ndarray] = []
        self.new()

    def new(self) -> None:
        self.cur_t = np.empty(self.chunk)
        self.cur_y = np.empty((self.chunk, self.dim))

    def commit(self, n: int) -> None:
        if n:
            self.ts.append(self.cur_t[:n].copy())
            self.ys.append(self.cur_y[:n].copy())
        self.new()

    def add(self, t: float, y: np.ndarray) -> None:
        self.ts.append(np.array([t]))
        self.ys.append(np.asarray(y, dtype=float).reshape(1, -1).copy())

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        if not self.ts:
            return np.empty(0), np.empty((0, self.dim))
        return np.concatenate(self.ts), np.concatenate(self.ys)

    @property
    def last_time(self) -> float:
        return float(self.ts[-1][-1]) if self.ts else float("nan")


def progress_bar(enabled: bool, total: float, desc: str):
    """A tqdm bar (or a no-op) measuring progress in ``total`` units."""
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        from poissonkit.errors import MissingDependencyError

        raise MissingDependencyError("progress bars need tqdm: pip install tqdm") from None
    return tqdm(total=total, desc=desc, unit="t", leave=False)


def check_step(step: float | None, t_end: float, name: str) -> float:
    """Validate a fixed step size."""
    if step is None:
        raise InputError(f"{name} is a fixed-step method: give step=... (internal time unit)")
    step = float(step)
    if not (np.isfinite(step) and step > 0):
        raise InputError(f"{name}: step must be positive and finite, got {step!r}")
    return step
