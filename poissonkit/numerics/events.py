"""Typed events checked after every step: collision and escape.

Events are terminal: integration stops at the end of the first step where one fires. With
``error=True`` a :class:`~poissonkit.errors.CollisionError` / :class:`~poissonkit.errors.EscapeError`
is raised instead of recording the event in :attr:`Solution.events`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from poissonkit.errors import CollisionError, EscapeError, InputError


@dataclass(frozen=True)
class Collision:
    """Fires when two bodies come closer than ``distance`` (internal length unit).

    The splitting integrators check the state after each full step, so an encounter that
    dips below ``distance`` only inside a step is missed; pick the step accordingly.
    """

    distance: float
    error: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.distance) and self.distance > 0):
            raise InputError(f"Collision distance must be positive, got {self.distance!r}")


@dataclass(frozen=True)
class Escape:
    """Fires when a moving body is farther than ``radius`` from the moving bodies' centre of
    mass (two-body form: from the centre of mass of the pair)."""

    radius: float
    error: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.radius) and self.radius > 0):
            raise InputError(f"Escape radius must be positive, got {self.radius!r}")


@dataclass(frozen=True)
class EventRecord:
    """An event that happened: ``kind`` ("collision"/"escape"), step index, time, value."""

    kind: str
    step: int
    time: float
    value: float


def event_thresholds(events: Sequence[Collision | Escape]) -> tuple[float, float, bool, bool]:
    """``(contact, escape, contact_error, escape_error)``; 0 disables a check."""
    contact = escape = 0.0
    cerr = eerr = False
    for ev in events:
        if isinstance(ev, Collision):
            contact = max(contact, ev.distance)
            cerr = cerr or ev.error
        elif isinstance(ev, Escape):
            escape = ev.radius if escape == 0.0 else min(escape, ev.radius)
            eerr = eerr or ev.error
        else:
            raise InputError(f"unknown event {ev!r}; use numerics.events.Collision or Escape")
    return contact, escape, cerr, eerr


def raise_or_record(kind: str, step: int, time: float, value: float, as_error: bool,
                    records: list[EventRecord]) -> None:
    """Raise the typed error of an event, or append its record."""
    if as_error:
        if kind == "collision":
            raise CollisionError(f"bodies came within {value:.6g} at step {step} (t = {time:.6g})")
        raise EscapeError(f"a body reached distance {value:.6g} at step {step} (t = {time:.6g})")
    records.append(EventRecord(kind, step, time, value))
