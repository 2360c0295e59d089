"""The result of :func:`~poissonkit.numerics.solve`, with its diagnostics."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.numerics.events import EventRecord


def _relative(values: np.ndarray, ref: np.ndarray, scale: np.ndarray | float) -> np.ndarray:
    scale = np.where(np.asarray(scale) > 0, scale, 1.0)
    return np.abs(values - ref) / scale


@dataclass
class Solution:
    """Saved states of a run plus what produced them.

    Attributes
    ----------
    t
        Saved times, shape ``(n,)`` (internal time unit; always includes start and end).
    y
        Saved states, shape ``(n, dim)``.
    method
        Integrator name.
    steps
        Number of steps taken.
    wall_time
        Seconds spent integrating (excluding compilation when the kernels were warm).
    system
        The system integrated (for the diagnostics).
    nfev
        Right-hand-side / force evaluations.
    events
        :class:`~poissonkit.numerics.events.EventRecord` of events that stopped the run.
    step, tol
        What was asked for.
    message
        Integrator status message.
    """

    t: np.ndarray
    y: np.ndarray
    method: str
    steps: int
    wall_time: float
    system: Any = None
    nfev: int = 0
    events: list[EventRecord] = field(default_factory=list)
    step: float | None = None
    tol: float | None = None
    message: str = ""
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def y_final(self) -> np.ndarray:
        """The last saved state."""
        return self.y[-1]

    # ------------------------------------------------------------------ diagnostics
    def energy(self) -> np.ndarray:
        """``H`` at every saved state."""
        return np.asarray(self.system.energy(self.y), dtype=float)

    def energy_error(self) -> np.ndarray:
        """Relative energy error ``|H(t) − H(0)| / |H(0)|`` over time (absolute if ``H(0) = 0``)."""
        e = self.energy()
        return _relative(e, e[0], abs(e[0]))

    def casimir_drift(self) -> np.ndarray:
        """Largest Casimir drift at each saved time, relative to each Casimir's natural size
        (``|ν|²`` absolute; ``(ν, m)`` relative to ``|m(0)|``); zeros if the system has none."""
        if not hasattr(self.system, "casimirs"):
            return np.zeros(len(self.t))
        c = np.asarray(self.system.casimirs(self.y), dtype=float)
        if c.ndim < 2 or c.shape[1] == 0:
            return np.zeros(len(self.t))
        if hasattr(self.system, "casimir_scales"):
            scale = np.asarray(self.system.casimir_scales(self.y[0]), dtype=float)
        else:
            scale = np.maximum(np.abs(c[0]), 1.0)
        return _relative(c, c[0], scale).max(axis=1)

    def _vector_drift(self, name: str, companion: str | None = None) -> np.ndarray:
        fn = getattr(self.system, name, None)
        if fn is None:
            return np.zeros(len(self.t))
        v = np.asarray(fn(self.y), dtype=float)
        ref = v[0]
        scale = np.linalg.norm(ref)
        if scale == 0.0:
            scale = max(float(np.max(np.abs(self.y[0]))), 1.0)
        return np.linalg.norm(v - ref, axis=1) / scale

    def momentum_drift(self) -> np.ndarray:
        """``|P(t) − P(0)| / |P(0)|`` of total linear momentum (scaled by the state size if
        ``P(0) = 0``)."""
        return self._vector_drift("linear_momentum")

    def angular_momentum_drift(self) -> np.ndarray:
        """``|j(t) − j(0)| / |j(0)|`` of total angular momentum (seed 000 eq. 21)."""
        return self._vector_drift("angular_momentum")

    def summary(self) -> dict[str, Any]:
        """Plain-data summary: method, steps, wall time, max errors and drifts, events."""
        out: dict[str, Any] = {
            "method": self.method,
            "steps": int(self.steps),
            "nfev": int(self.nfev),
            "wall_time": float(self.wall_time),
            "t_start": float(self.t[0]),
            "t_end": float(self.t[-1]),
            "saved": len(self.t),
            "step": self.step,
            "tol": self.tol,
            "message": self.message,
            "events": [e.__dict__ for e in self.events],
        }
        if self.system is not None:
            out["max_energy_error"] = float(np.max(self.energy_error()))
            out["final_energy_error"] = float(self.energy_error()[-1])
            out["max_casimir_drift"] = float(np.max(self.casimir_drift()))
            out["max_momentum_drift"] = float(np.max(self.momentum_drift()))
            out["max_angular_momentum_drift"] = float(np.max(self.angular_momentum_drift()))
        return out
