"""The unit system a scene (or a Python user) speaks: length, time and mass units by name.

A :class:`UnitSystem` names the units of a scene's numbers (REBOUND's names, any case; see
:mod:`poissonkit.conventions` for the constants) and converts quantities of any mechanical
dimension ``L^a M^b T^c`` to and from SI. SI (``UnitSystem()``) is the default and converts
nothing. N-body units (``UnitSystem(G=1)``) have no SI meaning: numbers are taken as they are
and gravity uses the given ``G``.

This is not :class:`~poissonkit.numerics.units.Scales`: scales are the internal units the
integrators work in (chosen per run for round-off), a unit system is what the user reads and
writes.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from poissonkit import conventions as cv
from poissonkit.errors import InputError

#: SI value of each length, time and mass unit, by canonical name (lookup ignores case).
LENGTHS: Mapping[str, float] = {"m": 1.0, "cm": 0.01, "mm": 1e-3, "km": 1e3,
                                "AU": cv.ASTRONOMICAL_UNIT, "pc": cv.PARSEC}
TIMES: Mapping[str, float] = {"s": 1.0, "min": 60.0, "hr": 3600.0, "day": cv.DAY,
                              "yr": cv.JULIAN_YEAR, "kyr": 1e3 * cv.JULIAN_YEAR,
                              "Myr": 1e6 * cv.JULIAN_YEAR, "Gyr": 1e9 * cv.JULIAN_YEAR}
MASSES: Mapping[str, float] = {"kg": 1.0, "g": 1e-3, "Msun": cv.SOLAR_MASS,
                               "Mearth": cv.GM_EARTH / cv.NEWTON_G,
                               "Mjupiter": cv.GM_JUPITER / cv.NEWTON_G}
#: Other spellings REBOUND accepts, mapped to the canonical name.
ALIASES: Mapping[str, str] = {"au": "AU", "aus": "AU", "parsec": "pc", "d": "day",
                              "days": "day", "year": "yr", "years": "yr", "yrs": "yr",
                              "jyr": "yr", "h": "hr", "solarmass": "Msun", "msolar": "Msun",
                              "sunmass": "Msun", "gram": "g"}
#: How a unit is printed in figures and messages (ASCII names elsewhere).
SYMBOLS: Mapping[str, str] = {"Msun": "M☉", "Mearth": "M⊕", "Mjupiter": "M_J"}

#: Exponents ``(length, mass, time)`` of the quantity kinds a unit system converts.
DIMENSIONS: Mapping[str, tuple[int, int, int]] = {
    "length": (1, 0, 0), "mass": (0, 1, 0), "time": (0, 0, 1), "velocity": (1, 0, -1),
    "momentum": (1, 1, -1), "angular_momentum": (2, 1, -1), "energy": (2, 1, -2),
    "alpha": (-2, -1, 0), "inertia": (2, 1, 0), "force": (1, 1, -2), "torque": (2, 1, -2),
    "frequency": (0, 0, -1), "dimensionless": (0, 0, 0), "G": (3, -1, -2),
    "acceleration": (1, 0, -2), "magnetic_moment": (2, 0, 0), "magnetization": (-1, 0, 0),
    "magnetic_field": (0, 1, -2),
}
#: Tokens of a registry unit string a unit system converts (:func:`dimension_of`): metre,
#: kilogram, second; ampere and radian are dimensionless here (no current unit). Named units
#: (``T``, ``rpm``, ``J``) are not converted: a parameter in tesla stays in tesla.
_TOKENS: Mapping[str, tuple[int, int, int]] = {
    "m": (1, 0, 0), "kg": (0, 1, 0), "s": (0, 0, 1), "A": (0, 0, 0), "rad": (0, 0, 0),
    "1": (0, 0, 0)}


def _canonical(name: object, table: Mapping[str, float], what: str) -> str:
    """The canonical name of a ``what`` unit, found without regard to case."""
    if not isinstance(name, str):
        raise InputError(f"{what} unit must be a name, got {name!r}; one of "
                         f"{', '.join(table)}")
    by_lower = {k.lower(): k for k in table}
    key = ALIASES.get(name, ALIASES.get(name.lower(), name))
    found = by_lower.get(key.lower())
    if found is None:
        raise InputError(f"unknown {what} unit {name!r}; one of {', '.join(table)}")
    return found


@dataclass(frozen=True)
class UnitSystem:
    """Units of a scene's numbers.

    Parameters
    ----------
    length, time, mass
        Unit names (REBOUND's, any case: ``"AU"``, ``"day"``, ``"Msun"``, ...); SI by default.
    G
        Alone (every name left at its SI default): N-body units, in which Newton's constant is
        ``G``. With unit names it is refused: ``G`` follows from them.

    Examples
    --------
    >>> u = UnitSystem("AU", "day", "Msun")
    >>> round(u.G, 13)
    0.0002959122082
    >>> u.from_si(149597870700.0, "length")
    1.0
    """

    length: str = "m"
    time: str = "s"
    mass: str = "kg"
    G_nbody: float | None = None

    def __init__(self, length: str = "m", time: str = "s", mass: str = "kg", *,
                 G: float | None = None) -> None:
        object.__setattr__(self, "length", _canonical(length, LENGTHS, "length"))
        object.__setattr__(self, "time", _canonical(time, TIMES, "time"))
        object.__setattr__(self, "mass", _canonical(mass, MASSES, "mass"))
        if G is not None:
            if isinstance(G, bool) or not isinstance(G, (int, float)) or not (
                    math.isfinite(G) and G > 0):
                raise InputError(f"G must be a positive finite number, got {G!r}")
            if (self.length, self.time, self.mass) != ("m", "s", "kg"):
                raise InputError("G follows from the length, time and mass units; give G "
                                 "alone for N-body units, or the unit names alone")
            G = float(G)
        object.__setattr__(self, "G_nbody", G)

    @classmethod
    def from_mapping(cls, table: Mapping[str, object]) -> UnitSystem:
        """A unit system from a ``[units]`` table (keys ``length``, ``time``, ``mass``,
        ``G``)."""
        unknown = set(table) - {"length", "time", "mass", "G"}
        if unknown:
            raise InputError(f"unknown key {sorted(unknown)[0]!r}; allowed: length, time, "
                             "mass, G")
        return cls(**{k: v for k, v in table.items() if k != "G"},  # type: ignore[arg-type]
                   G=table.get("G"))  # type: ignore[arg-type]

    @property
    def is_si(self) -> bool:
        """True for SI units (nothing to convert)."""
        return self.G_nbody is None and (self.length, self.time, self.mass) == ("m", "s", "kg")

    @property
    def is_nbody(self) -> bool:
        """True for N-body units (``G`` given, no SI meaning)."""
        return self.G_nbody is not None

    @property
    def base_si(self) -> tuple[float, float, float]:
        """SI values of one length, mass and time unit (1, 1, 1 for N-body units)."""
        if self.is_nbody:
            return 1.0, 1.0, 1.0
        return LENGTHS[self.length], MASSES[self.mass], TIMES[self.time]

    @property
    def G(self) -> float:
        """Newton's constant in these units."""
        if self.G_nbody is not None:
            return self.G_nbody
        L, M, T = self.base_si
        return cv.NEWTON_G * M * T * T / L ** 3

    @property
    def G_si(self) -> float:
        """The ``G`` gravity uses once the scene's numbers are in SI (CODATA for physical
        units, the given ``G`` for N-body units, whose numbers are not converted)."""
        return self.G_nbody if self.G_nbody is not None else cv.NEWTON_G

    def si_per_unit(self, kind: str | tuple[int, int, int]) -> float:
        """SI value of one unit of ``kind`` (a :data:`DIMENSIONS` key or exponents)."""
        a, b, c = dimension(kind)
        L, M, T = self.base_si
        return L ** a * M ** b * T ** c

    def to_si(self, value, kind: str | tuple[int, int, int]):
        """Value(s) in these units → SI (the same object for SI units)."""
        if self.is_si:
            return value
        factor = self.si_per_unit(kind)
        return np.asarray(value, dtype=float) * factor if np.ndim(value) else \
            float(value) * factor

    def from_si(self, value, kind: str | tuple[int, int, int]):
        """SI value(s) → these units (the same object for SI units)."""
        if self.is_si:
            return value
        factor = self.si_per_unit(kind)
        return np.asarray(value, dtype=float) / factor if np.ndim(value) else \
            float(value) / factor

    def label(self, kind: str | tuple[int, int, int], *, text: bool = True) -> str:
        """The unit of ``kind`` as a string: ``"AU/day"``, ``"M☉ AU²/day²"`` (``text``) or
        CF style ``"Msun AU day-1"`` (``text=False``, ASCII, for datasets). SI systems give
        the SI names (``"kg m/s"``); N-body units give ``L``, ``M``, ``T`` (``"L/T"``)."""
        if self.is_si and text and isinstance(kind, str) and kind in _SI_NAMED:
            return _SI_NAMED[kind]
        a, b, c = dimension(kind)
        if self.is_nbody:
            names = ("L", "M", "T")
        elif text:
            names = (self.length, SYMBOLS.get(self.mass, self.mass), self.time)
        else:
            names = (self.length, self.mass, self.time)
        order = ((b, names[1]), (a, names[0]), (c, names[2]))  # mass, length, time
        if not text:
            parts = [n if e == 1 else f"{n}{e}" for e, n in order if e]
            return " ".join(parts) or "1"
        num = " ".join(_power(n, e) for e, n in order if e > 0)
        den = " ".join(_power(n, -e) for e, n in order if e < 0)
        if not den:
            return num or "1"
        den = f"({den})" if " " in den else den
        return f"{num or '1'}/{den}"

    def describe(self) -> str:
        """One line for messages and summaries: ``"AU, day, Msun (G = 2.959e-04)"``."""
        if self.is_nbody:
            return f"N-body units (G = {self.G:g})"
        return f"{self.length}, {self.time}, {self.mass} (G = {self.G:.10g})"

    def as_dict(self) -> dict[str, object]:
        """JSON-ready: names, SI values of one unit and ``G`` in these units."""
        L, M, T = self.base_si
        return {"length": self.length, "time": self.time, "mass": self.mass,
                "length_si": L, "time_si": T, "mass_si": M, "G": self.G,
                "nbody": self.is_nbody}

    def attributes(self) -> dict[str, str | float]:
        """Dataset attributes naming these units (``units_length``, ``units_time``,
        ``units_mass``, ``units_G`` and, for physical units, ``units_<kind>_in_si``), as in
        ``trajectory.nc``."""
        out: dict[str, str | float] = {
            "units_length": self.label("length", text=False),
            "units_time": self.label("time", text=False),
            "units_mass": self.label("mass", text=False), "units_G": float(self.G)}
        if not self.is_nbody:
            L, M, T = self.base_si
            out.update(units_length_in_si=L, units_time_in_si=T, units_mass_in_si=M)
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, object]) -> UnitSystem:
        """Inverse of :meth:`as_dict`."""
        if d.get("nbody"):
            return cls(G=float(d["G"]))  # type: ignore[arg-type]
        return cls(str(d["length"]), str(d["time"]), str(d["mass"]))


#: Named SI units of derived kinds, for labels.
_SI_NAMED: Mapping[str, str] = {"energy": "J", "force": "N", "torque": "N m", "frequency": "Hz"}


def _power(name: str, e: int) -> str:
    sup = {2: "²", 3: "³", 4: "⁴"}
    return name if e == 1 else name + sup.get(e, f"^{e}")


#: The default, SI.
SI = UnitSystem()


def units_of(system: object) -> UnitSystem:
    """The units a system's numbers are given in (``NBodySystem(units=...)``); SI for every
    other system."""
    from poissonkit.numerics.nbody.system import NBodySystem

    return system.units if isinstance(system, NBodySystem) else SI


def dimension(kind: str | tuple[int, int, int]) -> tuple[int, int, int]:
    """Exponents ``(length, mass, time)`` of a :data:`DIMENSIONS` kind (or exponents as given).

    Raises
    ------
    InputError
        For an unknown kind (the message lists them).
    """
    if isinstance(kind, tuple):
        return kind
    try:
        return DIMENSIONS[kind]
    except KeyError:
        raise InputError(f"unknown quantity kind {kind!r}; one of {', '.join(DIMENSIONS)}"
                         ) from None


_TOKEN = re.compile(r"\s*([A-Za-z]+|1)(?:\^(-?\d+))?\s*")


def dimension_of(unit: str) -> tuple[int, int, int] | None:
    """Exponents ``(length, mass, time)`` of a registry unit string made of ``m``, ``kg``,
    ``s`` (and the dimensionless ``A``, ``rad``), such as ``"m^3/(kg s^2)"`` or ``"A m^2"``;
    ``None`` for anything else (named units such as ``"T"`` or ``"rpm"``, which a unit system
    leaves as they are)."""
    num, _, den = unit.partition("/")
    den = den.strip()
    if den.startswith("(") and den.endswith(")"):
        den = den[1:-1]
    total = [0, 0, 0]
    for part, sign in ((num, 1), (den, -1)):
        pos = 0
        while pos < len(part):
            m = _TOKEN.match(part, pos)
            if m is None or m.end() == pos or m.group(1) not in _TOKENS:
                return None
            a, b, c = _TOKENS[m.group(1)]
            e = sign * int(m.group(2) or 1)
            total = [total[0] + a * e, total[1] + b * e, total[2] + c * e]
            pos = m.end()
    return (total[0], total[1], total[2])
