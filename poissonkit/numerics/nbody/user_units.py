"""An N-body system written in a unit system of the user's: ``NBodySystem(..., units=...)``.

As in REBOUND (``sim.units = ('AU', 'yr', 'Msun')``), the numbers are taken in those units as
they are — masses, positions, momenta, the cutoff, the step and the times of ``solve`` — and
gravity's ``G`` is Newton's constant in them. Nothing is converted to SI: the state, the
solution's times, its energies and its orbital elements come out in the same units.

A registered potential's parameters that are left out and have a dimension made of metres,
kilograms and seconds (gravity's ``G`` [m³/(kg s²)], a softening length [m]) get their SI
default converted to the units; parameters that are given are taken in the units too, and
parameters in named units (tesla, rpm) stay in them. In N-body units (``G = 1``) only
gravity's ``G`` is set (the others have no SI value to convert).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace

from poissonkit.errors import InputError
from poissonkit.numerics.nbody.bodies import AllPairs, Interaction
from poissonkit.numerics.nbody.pairkernels import _registry_entry
from poissonkit.numerics.unitsystem import LENGTHS, MASSES, SI, TIMES, UnitSystem, dimension_of

#: What ``units=`` may be: a :class:`UnitSystem`, a ``[units]``-style mapping (``length``,
#: ``time``, ``mass`` or ``G``), or three unit names in any order (REBOUND's tuple).
UnitsLike = UnitSystem | Mapping[str, object] | Sequence[str] | None


def _kind_of(name: str) -> str:
    """``"length"``, ``"time"`` or ``"mass"``: the table a unit name belongs to."""
    for kind, table in (("length", LENGTHS), ("time", TIMES), ("mass", MASSES)):
        try:
            UnitSystem(length=name) if kind == "length" else (
                UnitSystem(time=name) if kind == "time" else UnitSystem(mass=name))
        except InputError:
            continue
        return kind
    raise InputError(f"unknown unit {name!r}; lengths: {', '.join(LENGTHS)}; times: "
                     f"{', '.join(TIMES)}; masses: {', '.join(MASSES)}")


def as_unit_system(units: UnitsLike) -> UnitSystem:
    """The :class:`UnitSystem` ``units`` names (``None``: SI).

    Raises
    ------
    InputError
        An unknown name, two names of one kind, or anything else.
    """
    if units is None:
        return SI
    if isinstance(units, UnitSystem):
        return units
    if isinstance(units, Mapping):
        return UnitSystem.from_mapping(units)
    if isinstance(units, (list, tuple)) and all(isinstance(u, str) for u in units):
        named: dict[str, str] = {}
        for name in units:
            kind = _kind_of(name)
            if kind in named:
                raise InputError(f"units: two {kind} units, {named[kind]!r} and {name!r}")
            named[kind] = name
        return UnitSystem(named.get("length", "m"), named.get("time", "s"),
                          named.get("mass", "kg"))
    raise InputError("units must be a UnitSystem, a mapping {length, time, mass} or {G}, or "
                     f"unit names such as ('AU', 'yr', 'Msun'); got {units!r}")


def _filled(params: Mapping[str, object], potential: object, units: UnitSystem
            ) -> dict[str, object]:
    """``params`` with the left-out dimensional parameters of a registered potential set to
    their SI defaults in ``units`` (gravity's ``G`` alone in N-body units)."""
    entry = _registry_entry(potential)  # type: ignore[arg-type]
    out = dict(params)
    if entry is None:
        return out
    for p in entry.params:
        if p.name in out or p.default is None or isinstance(p.default, (bool, str)):
            continue
        dims = dimension_of(p.unit) if p.unit else None
        if dims is None or dims == (0, 0, 0):
            continue
        if dims == (3, -1, -2):  # Newton's constant: the units' own (CODATA, or the given G)
            out[p.name] = units.G
        elif not units.is_nbody:
            out[p.name] = units.from_si(p.default, dims)
    return out


def interactions_in(interactions: Sequence[Interaction | AllPairs], units: UnitSystem
                    ) -> tuple[Interaction | AllPairs, ...]:
    """The interactions with their left-out dimensional parameters in ``units`` (the same
    objects for SI)."""
    if units.is_si:
        return tuple(interactions)
    return tuple(replace(it, params=_filled(it.params, it.potential, units))
                 if isinstance(it, (Interaction, AllPairs)) else it for it in interactions)
