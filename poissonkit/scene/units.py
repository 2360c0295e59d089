"""A scene's ``[units]`` table and bodies given by orbital elements.

A scene is validated in its own units (so every message quotes the numbers as written), then
converted once to SI (:func:`scene_in_si`) for the numerics; the unit system travels with the
scene (:attr:`~poissonkit.scene.schema.Scene.units`) to the run's outputs, which convert back.

What converts: body masses, positions, momenta, spins, inertias, sizes and magnet moments;
``run.step``, ``run.duration``, ``run.save_dt``; cutoffs; and every parameter of a potential,
field or assembly whose registered unit is made of ``m``, ``kg``, ``s`` (e.g. ``spacing`` [m],
``G`` [m^3/(kg s^2)], ``g`` [m/s^2]). Parameters in named units (tesla, rpm) stay in them. In
N-body units (``G = 1``) nothing converts and gravity takes that ``G``.

Bodies by elements (REBOUND's ``sim.add``): ``a`` (required), ``e``, ``inc``, ``Omega``,
``omega`` (default 0) and ``M`` or ``f`` (default ``f = 0``), angles in radians, about the body
named by ``primary`` or, without one, Jacobi elements about the centre of mass of every body
before it in the file. ``mu = G (m_primary + m)`` with ``G`` of the scene's units.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from poissonkit.errors import InputError, PoissonkitError, SceneError
from poissonkit.numerics.unitsystem import SI, UnitSystem, dimension_of

if TYPE_CHECKING:
    from poissonkit.plugin.contributions import Entry
    from poissonkit.scene.schema import Scene

#: Keys of a body given by orbital elements (REBOUND's names).
ELEMENT_KEYS = ("primary", "a", "e", "inc", "Omega", "omega", "M", "f")
#: The quantity kind of each body field a unit system converts.
BODY_KINDS: Mapping[str, str] = {
    "mass": "mass", "r": "length", "p": "momentum", "m": "angular_momentum",
    "alpha": "alpha", "inertia": "inertia", "radius": "length", "length": "length",
    "half_length": "length", "moment": "magnetic_moment", "magnetization": "magnetization",
    "spin": "angular_momentum",
}


def scene_units(raw: object) -> UnitSystem:
    """The unit system of a ``[units]`` table (``None``: SI), errors as ``units.<key>``."""
    if raw is None:
        return SI
    if not isinstance(raw, Mapping):
        raise SceneError(f"units: must be a table, got {type(raw).__name__}")
    for key in raw:
        if key not in ("length", "time", "mass", "G"):
            raise SceneError(f"units.{key}: unknown key; allowed: length, time, mass, G")
    try:
        return UnitSystem.from_mapping(raw)
    except InputError as exc:
        bad = next((k for k in ("G", "length", "time", "mass") if k in raw and k in str(exc)),
                   None)
        raise SceneError(f"units{'.' + bad if bad else ''}: {exc}") from None


# ---------------------------------------------------------------- orbital elements

def _float(value: Any, where: str) -> float:
    bad = SceneError(f"{where}: must be a finite number, got {value!r}")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise bad
    try:
        x = float(value)  # an integer beyond the float range overflows here
    except OverflowError:
        raise bad from None
    if not math.isfinite(x):
        raise bad
    return x


def _elements(table: Mapping[str, Any], where: str) -> dict[str, float]:
    """The keyword arguments of :func:`~poissonkit.numerics.elements.cartesian`."""
    if "a" not in table:
        raise SceneError(f"{where}.a: missing (a body given by orbital elements needs its "
                         "semi-major axis)")
    if "M" in table and "f" in table:
        raise SceneError(f"{where}: give the mean anomaly M or the true anomaly f, not both")
    for key in ("r", "p"):
        if key in table:
            raise SceneError(f"{where}.{key}: a body given by orbital elements takes no {key}")
    return {k: _float(table[k], f"{where}.{k}") for k in ELEMENT_KEYS[1:] if k in table}


def _velocity(body: Any, defaults: Mapping[str, Any], where: str) -> Any:
    """A body table given a velocity ``v`` (as REBOUND's ``vx, vy, vz``) with ``p = mass v``
    instead."""
    if not isinstance(body, Mapping) or "v" not in body:
        return body
    if "p" in body:
        raise SceneError(f"{where}.v: give the velocity v or the momentum p, not both")
    mass = {**defaults, **body}.get("mass")
    mass = _float(mass, f"{where}.mass") if mass is not None else None
    if mass is None or mass <= 0:
        raise SceneError(f"{where}.mass: a positive mass is needed with a velocity v")
    v = body["v"]
    if not isinstance(v, (list, tuple)) or len(v) != 3:
        raise SceneError(f"{where}.v: must be a list of 3 numbers, got {v!r}")
    p = [mass * _float(x, f"{where}.v[{k}]") for k, x in enumerate(v)]
    return {**{k: x for k, x in body.items() if k != "v"}, "p": p}


def with_orbits(raw: list[Any], defaults: Mapping[str, Any], units: UnitSystem
                ) -> list[Any]:
    """The body tables with orbital elements (and velocities ``v``) replaced by ``r`` and
    ``p`` (scene units).

    Bodies given by a state keep it (their ``p`` defaults to 0); each body given by elements is
    placed about its primary (an earlier body named by ``primary``) or about the centre of mass
    of the bodies before it, as REBOUND's ``sim.add`` does. The other keys of each table are
    validated later by the schema.
    """
    raw = [_velocity(b, defaults, f"bodies[{k}]") for k, b in enumerate(raw)]
    if not any(isinstance(b, Mapping) and any(k in b for k in ELEMENT_KEYS) for b in raw):
        return raw
    from poissonkit.numerics.elements import cartesian

    out: list[Any] = []
    masses: list[float] = []
    states: list[tuple[np.ndarray, np.ndarray]] = []
    names: dict[str, int] = {}
    for k, body in enumerate(raw):
        where = f"bodies[{k}]"
        if not isinstance(body, Mapping):
            return raw  # the schema names the error
        merged = {**defaults, **body}
        mass = _float(merged.get("mass"), f"{where}.mass") if "mass" in merged else None
        if mass is None or mass <= 0:
            raise SceneError(f"{where}.mass: a positive mass is needed to place bodies by "
                             f"orbital elements, got {merged.get('mass')!r}")
        names[str(body.get("name", f"b{k}"))] = k
        if not any(key in body for key in ELEMENT_KEYS):
            r_raw, p_raw = body.get("r", (0, 0, 0)), body.get("p", (0, 0, 0))
            if not (isinstance(r_raw, (list, tuple)) and isinstance(p_raw, (list, tuple))
                    and len(r_raw) == 3 and len(p_raw) == 3):
                return raw  # the schema names the error
            r = np.array([_float(x, f"{where}.r") for x in r_raw])
            p = np.array([_float(x, f"{where}.p") for x in p_raw])
            masses.append(mass)
            states.append((r, p / mass))
            out.append(body)
            continue
        if k == 0:
            raise SceneError(f"{where}: the first body has nothing to orbit; give its r")
        kwargs = _elements(body, where)
        primary = body.get("primary")
        if primary is not None:
            if primary not in names or names[primary] == k:
                raise SceneError(f"{where}.primary: {primary!r} is not an earlier body; "
                                 f"available: {', '.join(list(names)[:-1])}")
            j = names[primary]
            mp, rp, vp = masses[j], states[j][0], states[j][1]
        else:  # Jacobi: the centre of mass of the bodies before this one
            m = np.array(masses)
            mp = float(m.sum())
            rp = sum(mi * s[0] for mi, s in zip(m, states)) / mp
            vp = sum(mi * s[1] for mi, s in zip(m, states)) / mp
        try:
            dr, dv = cartesian(units.G * (mp + mass), **kwargs)
        except InputError as exc:
            raise SceneError(f"{where}: {exc}") from None
        r, v = rp + dr, vp + dv
        masses.append(mass)
        states.append((r, v))
        table = {key: value for key, value in body.items() if key not in ELEMENT_KEYS}
        out.append({**table, "r": [float(x) for x in r], "p": [float(x) for x in mass * v]})
    return out


# ---------------------------------------------------------------- to SI

def _convert_body(body: Mapping[str, Any], units: UnitSystem) -> dict[str, Any]:
    out = dict(body)
    for key, kind in BODY_KINDS.items():
        if key in out and not isinstance(out[key], bool):
            value = units.to_si(out[key], kind)
            out[key] = tuple(float(x) for x in value) if np.ndim(value) else value
    return out


def _convert_params(params: Mapping[str, Any], declared: Mapping[str, str],
                    units: UnitSystem) -> dict[str, Any]:
    """Parameters whose declared unit is made of m, kg, s, converted to SI."""
    out = dict(params)
    for key, unit in declared.items():
        dims = dimension_of(unit) if unit else None
        value = out.get(key)
        if dims is None or dims == (0, 0, 0) or value is None or isinstance(value, (bool, str)):
            continue
        converted = units.to_si(value, dims)
        out[key] = tuple(float(x) for x in converted) if np.ndim(converted) else converted
    return out


def si_params(entry: Entry, params: Mapping[str, Any], units: UnitSystem) -> dict[str, Any]:
    """A registered entry's given parameters (``entry.params`` declare their units) in SI:
    for tables whose defaults are filled in later, in SI (``[[fields]]``)."""
    if units.is_si:
        return dict(params)
    declared = {p.name: p.unit for p in entry.params if p.unit}
    return _convert_params(params, declared, units)


def _units_of(kind: str, name: str) -> dict[str, str]:
    """``{parameter: unit}`` of a registered potential, field or assembly."""
    from poissonkit.plugin import lookup

    try:
        entry = lookup(kind, name)
    except PoissonkitError:
        return {}
    return {p.name: p.unit for p in entry.params if p.unit}


def scene_in_si(scene: Scene) -> Scene:
    """``scene`` with every number in SI (the scene itself when its units are SI); for
    N-body units, gravity (the default potential and listed pairs) gets the scene's ``G``."""
    units = scene.units
    if units.is_si:
        return scene
    gravity_G = {"G": units.G_si} if units.is_nbody else {}

    def pot_params(name: str | None, params: Mapping[str, Any]) -> dict[str, Any]:
        if name is None:
            return dict(params)
        out = _convert_params(params, _units_of("potential", name), units)
        return {**gravity_G, **out} if name == "gravity" else out

    # the pairs' default potential: the scene's, else the one its assembly names
    default_potential = scene.potential
    if default_potential is None and scene.assembly is not None:
        named = scene.assembly[1].get("potential")
        default_potential = named if isinstance(named, str) else None
    run = scene.run
    run = dataclasses.replace(
        run, duration=units.to_si(run.duration, "time"),
        step=None if run.step is None else units.to_si(run.step, "time"),
        save_dt=None if run.save_dt is None else units.to_si(run.save_dt, "time"))
    assembly = scene.assembly
    if assembly is not None:
        assembly = (assembly[0], _convert_params(assembly[1], _units_of("assembly", assembly[0]),
                                                 units))
    pairs = tuple(dataclasses.replace(p, params=pot_params(p.potential, p.params))
                  for p in scene.pairs)
    planner = scene.planner
    if planner is not None and planner.cutoff is not None:
        planner = dataclasses.replace(planner, cutoff=units.to_si(planner.cutoff, "length"))
    return dataclasses.replace(
        scene, bodies=tuple(_convert_body(b, units) for b in scene.bodies),
        assembly=assembly, assembly_overrides=_convert_body(scene.assembly_overrides, units),
        assembly_bodies=tuple(dataclasses.replace(b, values=_convert_body(b.values, units))
                              for b in scene.assembly_bodies),
        potential_params=pot_params(default_potential, scene.potential_params), pairs=pairs,
        cutoff=None if scene.cutoff is None else units.to_si(scene.cutoff, "length"),
        run=run, planner=planner)


def run_metadata(scene: Scene) -> dict[str, object]:
    """What a run's metadata records of a scene's units: the unit system
    (:meth:`~poissonkit.numerics.unitsystem.UnitSystem.as_dict`) and the duration and step in
    those units (``duration``, ``step``)."""
    units = scene.units
    step = scene.run.step
    return {"units": units.as_dict(), "duration": units.from_si(scene.run.duration, "time"),
            "step": None if step is None else units.from_si(step, "time")}
