"""Times on ``poissonkit run``'s command line: ``--step``, ``--duration``, ``--save-dt``.

A bare number is in the scene's time unit (its ``[units]`` table; seconds for an SI scene, as
before); a number with a unit suffix is in that unit: ``100yr``, ``3day``, ``0.5s``, ``2 hr``.
The suffix is read against the allow-list of time units of
:data:`poissonkit.numerics.unitsystem.TIMES` (and REBOUND's other spellings), nothing is
evaluated. A scene in N-body units (``G = 1``) has no time in seconds: it takes bare numbers
only.

The parsed value (:class:`CliTime`) is a ``float`` (the number as written), so the checks
that read options as numbers keep working; :func:`scene_seconds` gives its value in seconds
once the scene's units are known, and :func:`in_scene_unit` the number a summary records (in
the scene's time unit, so that ``--from-summary`` runs the same times again).
"""

from __future__ import annotations

import argparse
import re

from poissonkit.errors import InputError
from poissonkit.numerics.unitsystem import ALIASES, TIMES, UnitSystem

__all__ = ["CliTime", "in_scene_unit", "parse_time", "scene_seconds", "time_argument"]

#: A number (decimal or exponent form) and an optional unit name: nothing else is accepted.
_TIME = re.compile(r"\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*([A-Za-z]*)\s*\Z")


class CliTime(float):
    """A time as written on the command line: its number (the ``float`` value) and the unit
    it was given in (``unit``; ``None``: the scene's time unit)."""

    unit: str | None

    def __new__(cls, value: float, unit: str | None = None) -> CliTime:
        obj = super().__new__(cls, value)
        obj.unit = unit
        return obj

    def __repr__(self) -> str:  # as in messages: "-1.0", "-1.0yr"
        return f"{float(self)!r}{self.unit or ''}"

    def __str__(self) -> str:
        return f"{float(self):g}{self.unit or ''}"


def _unit_name(text: str) -> str:
    """The canonical time unit of ``text`` (any case, REBOUND's spellings)."""
    key = ALIASES.get(text, ALIASES.get(text.lower(), text))
    for name in TIMES:
        if name == key or name.lower() == key.lower():
            return name
    raise InputError(f"unknown time unit {text!r}; one of {', '.join(TIMES)} (or none: the "
                     "scene's time unit)")


def parse_time(text: str) -> CliTime:
    """``"100yr"`` → ``CliTime(100.0, "yr")``; ``"0.01"`` → ``CliTime(0.01, None)``.

    Raises
    ------
    InputError
        Not a number followed by an optional time unit of the allow-list.
    """
    found = _TIME.match(text) if isinstance(text, str) else None
    if found is None:
        raise InputError(f"not a time: {text!r}; give a number in the scene's time unit "
                         "(0.01) or with a unit (100yr, 3day, 0.5s)")
    return CliTime(float(found.group(1)), _unit_name(found.group(2)) if found.group(2)
                   else None)


def time_argument(text: str) -> CliTime:
    """:func:`parse_time` as an ``argparse`` type (usage errors name the option)."""
    try:
        return parse_time(text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def scene_seconds(value: float | str | None, units: UnitSystem, option: str) -> float | None:
    """SI seconds of an option's time for a scene in ``units`` (``None`` stays ``None``).

    ``value`` is a :class:`CliTime`, text (a summary's, read again) or a plain number (in the
    scene's time unit). For an SI scene a bare number is returned as it is (bit for bit).

    Raises
    ------
    InputError
        A unit suffix for a scene in N-body units, or text that is not a time.
    """
    if value is None:
        return None
    t = parse_time(value) if isinstance(value, str) else (
        value if isinstance(value, CliTime) else CliTime(float(value)))
    if t.unit is None:
        return float(units.to_si(float(t), "time"))
    if units.is_nbody:
        raise InputError(f"{option} {t}: the scene is in N-body units (G = {units.G:g}), "
                         "whose time has no value in seconds; give a number in its time unit "
                         "T")
    return float(t) * TIMES[t.unit]


def in_scene_unit(seconds: float | None, units: UnitSystem) -> float | None:
    """``seconds`` in the scene's time unit (what a summary records of a time option)."""
    return None if seconds is None else float(units.from_si(seconds, "time"))
