"""Locating events inside a step by re-integrating it with a shorter step.

The compiled loops hand over a *window* of one or two consecutive steps, each given by its start
state, start time and length. ``advance(y, s)`` re-integrates one step of length ``s`` from ``y``
with the same method (a fresh copy; the run's state is not touched), so any point of the window
can be reached; ``g(φ_s(y))`` is a continuous function of ``s``.

* A terminal event's first sign change is bracketed by sampling the window and bisecting the
  first bracket until it is shorter than the time tolerance.
* A dip that does not show at the step ends (a *grazing* encounter) is found by minimising the
  event function (golden-section search around the smallest sample) before bisecting.
* A :class:`~poissonkit.numerics.events.ClosestApproach` is the minimum of the smallest centre
  distance over the window, found the same way.

The compiled loops flag a two-step window for the grazing search when the smallest centre
distance ``D`` has a local minimum at the middle step end and could reach the watched distance
inside the window: ``D_b ≤ D_a``, ``D_c > D_b`` and ``D_b − 2 max(D_a − D_b, D_c − D_b) <
watch`` (:func:`graze_suspect`). The factor 2 allows the relative speed inside the window to be
up to twice the secant speed; an encounter faster than that within one step is a step too long
for the dynamics anyway.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
import numpy as np

from poissonkit.contracts import HasCompiledKernels
from poissonkit.numerics.events import (DEFAULT_RELATIVE_TIME_TOL, ClosestApproach, Event,
                                        EventRecord, centre_distance, name_bodies)

#: Samples per step of the window before bisection / golden-section search.
SAMPLES_PER_STEP = 8
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def graze_suspect(d_a: float, d_b: float, d_c: float, watch: float) -> bool:
    """The compiled loops' grazing test on three consecutive step-end distances (see module)."""
    return d_b <= d_a and d_c > d_b and d_b - 2.0 * max(d_a - d_b, d_c - d_b) < watch


class Window:
    """Consecutive step segments ``(y_start, t_start, length)`` parametrised by ``u ≥ 0``."""

    def __init__(self, segments: Sequence[tuple[np.ndarray, float, float]],
                 advance: Callable[[np.ndarray, float], np.ndarray]) -> None:
        self.segments = [(np.array(y, dtype=float), float(t), float(h)) for y, t, h in segments
                         if h > 0]
        self.advance = advance
        self.starts = np.cumsum([0.0] + [h for _, _, h in self.segments])
        self.length = float(self.starts[-1])
        self.t0 = self.segments[0][1] if self.segments else 0.0

    def state(self, u: float) -> np.ndarray:
        """The state at window parameter ``u`` (one re-integrated step)."""
        i = int(np.searchsorted(self.starts, u, side="right") - 1)
        i = min(max(i, 0), len(self.segments) - 1)
        y, _, h = self.segments[i]
        s = min(max(u - self.starts[i], 0.0), h)
        return y.copy() if s == 0.0 else self.advance(y, s)

    def time(self, u: float) -> float:
        """Time of parameter ``u``."""
        i = int(np.searchsorted(self.starts, u, side="right") - 1)
        i = min(max(i, 0), len(self.segments) - 1)
        return self.segments[i][1] + (u - self.starts[i])

    def segment_of(self, u: float) -> int:
        """Index of the segment containing ``u``."""
        i = int(np.searchsorted(self.starts, u, side="left") - 1)
        return min(max(i, 0), len(self.segments) - 1)


def _golden_min(f: Callable[[float], float], lo: float, hi: float, tol: float
                ) -> tuple[float, float]:
    """Minimum ``(u, f(u))`` of a unimodal ``f`` on ``[lo, hi]`` to ``tol``."""
    c = hi - _GOLDEN * (hi - lo)
    d = lo + _GOLDEN * (hi - lo)
    fc, fd = f(c), f(d)
    while hi - lo > tol:
        if fc <= fd:
            hi, d, fd = d, c, fc
            c = hi - _GOLDEN * (hi - lo)
            fc = f(c)
        else:
            lo, c, fc = c, d, fd
            d = lo + _GOLDEN * (hi - lo)
            fd = f(d)
    u = 0.5 * (lo + hi)
    return u, f(u)


def _bisect(g: Callable[[float], float], lo: float, hi: float, tol: float) -> tuple[float, float]:
    """Shrink ``[lo, hi]`` (``g(lo) ≥ 0 > g(hi)``) below ``tol``; return ``(lo, hi)``."""
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:  # round-off floor
            break
        if g(mid) < 0:
            hi = mid
        else:
            lo = mid
    return lo, hi


def locate(system: HasCompiledKernels, events: Sequence[Event], window: Window,
           last_step: int, graze: bool
           ) -> tuple[list[tuple[Event, EventRecord]],
                      tuple[Event, EventRecord, np.ndarray] | None]:
    """Search ``window`` for events.

    Parameters
    ----------
    system
        The system integrated.
    events
        The run's events.
    window
        One or two step segments ending at the current step end.
    last_step
        Global index of the window's last step.
    graze
        Also search for dips between samples (the grazing test flagged the window).

    Returns
    -------
    (recorded, terminal)
        ``recorded``: ``(event, record)`` of closest approaches found; ``terminal``: the first
        terminal event ``(event, record, state)`` or ``None``.
    """
    if window.length <= 0:
        return [], None
    h_ref = max(h for _, _, h in window.segments)
    cache: dict[float, np.ndarray] = {}

    def state(u: float) -> np.ndarray:
        if u not in cache:
            cache[u] = window.state(u)
        return cache[u]

    def tol_of(ev: Event) -> float:
        return ev.time_tol if ev.time_tol is not None else DEFAULT_RELATIVE_TIME_TOL * h_ref

    def step_index(u: float) -> int:
        return last_step - (len(window.segments) - 1 - window.segment_of(u))

    terminal = [ev for ev in events if ev.terminal]
    approaches = [ev for ev in events if isinstance(ev, ClosestApproach)]
    n = SAMPLES_PER_STEP * len(window.segments)
    us = [window.length * j / n for j in range(n + 1)]
    found: tuple[Event, EventRecord, np.ndarray] | None = None
    best_u = math.inf
    for ev in terminal:
        g = [ev.value(system, state(u)) for u in us]
        hit = next((j for j, v in enumerate(g) if v < 0 and j > 0), None)
        lo_u = hi_u = None
        if hit is not None:
            lo_u, hi_u = us[hit - 1], us[hit]
        elif graze and ev.kind != "escape":
            j = int(np.argmin(g))
            a, b = us[max(j - 1, 0)], us[min(j + 1, n)]
            um, gm = _golden_min(lambda u: ev.value(system, window.state(u)), a, b, tol_of(ev))
            if gm < 0:
                lo_u, hi_u = a, um
        if lo_u is None or hi_u >= best_u:
            continue
        lo, hi = _bisect(lambda u: ev.value(system, state(u)), lo_u, hi_u, tol_of(ev))
        y_hit = state(hi)
        if ev.kind == "escape":
            value = ev.radius - ev.value(system, y_hit)
        else:  # collision and contact: the smallest centre distance there
            value = centre_distance(system, y_hit)
        rec = EventRecord(ev.kind, step_index(hi), float(window.time(hi)), float(value),
                          time_error=float(hi - lo))
        best_u = hi
        found = (ev, rec, y_hit)
    recorded: list[tuple[Event, EventRecord]] = []
    for ev in approaches:
        d = [centre_distance(system, state(u)) for u in us]
        j = int(np.argmin(d))
        a, b = us[max(j - 1, 0)], us[min(j + 1, n)]
        um, dm = _golden_min(lambda u: centre_distance(system, window.state(u)), a, b, tol_of(ev))
        if dm < ev.distance and um < best_u and 0.0 < um < window.length:
            rec = EventRecord(ev.kind, step_index(um), float(window.time(um)), float(dm),
                              time_error=tol_of(ev))
            name_bodies(rec, system, state(um))  # which pair came closest
            recorded.append((ev, rec))
    return recorded, found
