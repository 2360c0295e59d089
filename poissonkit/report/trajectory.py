"""The trajectory of a run as a self-describing :class:`xarray.Dataset` (``trajectory.nc``).

Bodies (N-body and two-body systems) get variables with dimensions ``time × body × component``
in SI units — ``position``, ``momentum`` (moving bodies), ``axis``, ``angular_momentum`` (tops;
NaN for a moving body that is not a top) — with body names as the ``body`` coordinate. Fixed
bodies are there too, at their place (``fixed`` = 1; NaN momenta), with their sizes when known
(``radius``, ``half_length``). The
two-body centre-of-mass form has ``relative_position``/``relative_momentum`` (``time ×
component``) instead of per-body positions. Every dataset also holds the raw state ``y`` (``time
× state``, internal units, component names from the system's layout), so nothing is lost.

Units are in each variable's ``units`` attribute: SI, or the scene's own units when it declares
them (``[units]``: e.g. ``AU``, ``Msun AU day-1``; the dataset attributes ``units_length``,
``units_time``, ``units_mass``, ``units_G`` and ``units_<kind>_in_si`` say which). Bodies also
get their ``mass`` (so velocities are ``momentum / mass``) and, for moving point masses with
Newtonian gravity, the osculating orbital elements ``a``, ``e``, ``inc``, ``Omega``, ``omega``,
``M``, ``f`` (``time × body``; radians) about the dominant body (ten times heavier than all
the others together) or Jacobi elements when there is none, as each variable's ``long_name``
says (:func:`poissonkit.numerics.elements.system_elements`; up to :data:`MAX_ELEMENT_BODIES`
bodies). The internal scales (SI value of one
internal unit of length, mass, time, ...) are dataset attributes ``internal_unit_<kind>`` with
``internal_unit_<kind>_units``. The file is NetCDF 3 written by scipy's engine (scipy is a
dependency of poissonkit, and so is xarray): no extra package is needed. The dataset is
described once, as plain data (:func:`trajectory_description`); ``poissonkit run`` writes the
file from that description with scipy alone (:mod:`poissonkit.report.netcdf_writer`, the same
bytes as xarray's engine), in-memory users get the :class:`xarray.Dataset` of it.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Final

import numpy as np

from poissonkit.contracts import HasBodies, HasLayout, HasUnpack
from poissonkit.errors import DimensionError
from poissonkit.numerics.unitsystem import SI, UnitSystem
from poissonkit.report.netcdf_writer import (
    DatasetDescription,
    VariableSpec,
    _xarray,
    write_netcdf,
)
from poissonkit.report.provenance import SI_UNITS
from poissonkit.traits import offers

if TYPE_CHECKING:
    import xarray as xr

    from poissonkit.numerics.units import Scales

#: Names of the two bodies of the two-body centre-of-mass form.
TWO_BODY_BLOCKS = (("nu1", "m1"), ("nu2", "m2"))
COMPONENTS = ("x", "y", "z")
#: NetCDF engine used (part of scipy: NetCDF 3 classic).
ENGINE: Final = "scipy"


def _names_with(layout: tuple[str, ...], suffix: str) -> list[str]:
    """Body names whose block ``<name>.<suffix>`` is in the layout (state order)."""
    return [c[: -len(suffix) - 1] for c in layout if c.endswith("." + suffix)]


def _by_body(values: np.ndarray, have: list[str], bodies: list[str]) -> np.ndarray:
    """``(time, len(have), 3)`` rows spread to ``(time, len(bodies), 3)``, NaN elsewhere."""
    out = np.full((values.shape[0], len(bodies), 3), np.nan)
    column = {name: k for k, name in enumerate(bodies)}  # not bodies.index: O(N) per body
    out[:, [column[name] for name in have]] = values[:, :len(have)]
    return out


def _body_variables(system: object, y: np.ndarray, layout: tuple[str, ...]
                    ) -> tuple[dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]],
                               list[str]]:
    """Per-body variables (SI) and the body names, or ``({}, [])`` for a system without
    bodies."""
    if not offers(system, HasUnpack):
        return {}, []
    parts = system.unpack(y, si=True)
    tbc = ("time", "body", "component")
    if offers(system, HasBodies) and {"r", "p", "nu", "m"} <= set(parts):
        moving = _names_with(layout, "r_x")
        tops = _names_with(layout, "nu_x")
        in_state = set(moving) | set(tops)
        fixed = [b for b in system.bodies if b.fixed and b.name not in in_state]
        known = set(moving)
        bodies = moving + [n for n in tops if n not in known] + [b.name for b in fixed]
        position = _by_body(parts["r"], moving, bodies)
        axis = _by_body(parts["nu"], tops, bodies)
        first_fixed = len(bodies) - len(fixed)
        for k, b in enumerate(fixed, start=first_fixed):  # no degrees of freedom: where the
            # scene put them, all the time
            # (a fixed body of the N-body form has a position and maybe an axis)
            placed, pointing = getattr(b, "position", None), getattr(b, "axis", None)
            if placed is not None:
                position[:, k] = placed
            if pointing is not None:
                axis[:, k] = pointing
        return {
            "position": (tbc, position,
                         {"units": SI_UNITS["length"], "long_name": "position"}),
            "momentum": (tbc, _by_body(parts["p"], moving, bodies),
                         {"units": SI_UNITS["momentum"], "long_name": "linear momentum"}),
            "axis": (tbc, axis,
                     {"units": SI_UNITS["dimensionless"], "long_name": "unit symmetry axis"}),
            "fixed": (("body",), (np.arange(len(bodies)) >= first_fixed).astype(np.int8),
                      {"units": SI_UNITS["dimensionless"],
                       "long_name": "1: a fixed body (position and axis from the scene)"}),
            "angular_momentum": (tbc, _by_body(parts["m"], tops, bodies),
                                 {"units": SI_UNITS["angular_momentum"],
                                  "long_name": "spin angular momentum (body's own)"}),
        }, bodies
    if {"r", "p", "nu1", "m1", "nu2", "m2"} <= set(parts):
        from poissonkit.numerics.events import TWO_BODY_NAMES

        tc = ("time", "component")
        axes = np.stack([parts[a] for a, _ in TWO_BODY_BLOCKS], axis=1)
        spins = np.stack([parts[m] for _, m in TWO_BODY_BLOCKS], axis=1)
        return {
            "relative_position": (tc, parts["r"], {"units": SI_UNITS["length"],
                                                   "long_name": "r = r2 - r1"}),
            "relative_momentum": (tc, parts["p"], {"units": SI_UNITS["momentum"],
                                                   "long_name": "momentum conjugate to r"}),
            "axis": (tbc, axes, {"units": SI_UNITS["dimensionless"],
                                 "long_name": "unit symmetry axis"}),
            "angular_momentum": (tbc, spins, {"units": SI_UNITS["angular_momentum"],
                                              "long_name": "spin angular momentum"}),
        }, list(TWO_BODY_NAMES)
    return {}, []


def trajectory_dataset(system: object, t: np.ndarray, y: np.ndarray, *,
                       scales: Scales | None, time_unit: float = 1.0,
                       attrs: Mapping[str, str | int | float] | None = None,
                       shapes: Mapping[str, tuple[float, float]] | None = None,
                       units: UnitSystem | None = None) -> xr.Dataset:
    """The trajectory ``(t, y)`` of ``system`` as an :class:`xarray.Dataset`: the
    :class:`xarray.Dataset` of :func:`trajectory_description` (same parameters).

    Raises
    ------
    DimensionError
        If ``t`` and ``y`` do not match.
    MissingDependencyError
        If xarray is not installed.
    """
    return trajectory_description(system, t, y, scales=scales, time_unit=time_unit,
                                  attrs=attrs, shapes=shapes, units=units).to_xarray()


def trajectory_description(system: object, t: np.ndarray, y: np.ndarray, *,
                           scales: Scales | None, time_unit: float = 1.0,
                           attrs: Mapping[str, str | int | float] | None = None,
                           shapes: Mapping[str, tuple[float, float]] | None = None,
                           units: UnitSystem | None = None) -> DatasetDescription:
    """The trajectory ``(t, y)`` of ``system`` as plain data: the one description of the
    dataset, from which :func:`trajectory_dataset` makes the :class:`xarray.Dataset` and
    :func:`write_description` the file (without xarray).

    Parameters
    ----------
    system
        The integrated system (bodies are read through
        :class:`~poissonkit.contracts.HasUnpack`, :class:`~poissonkit.contracts.HasBodies`,
        :class:`~poissonkit.contracts.HasLayout`).
    t, y
        Saved times (internal units) and states (rows, internal units).
    scales
        The system's internal units (``None``: the system is in SI).
    time_unit
        Seconds per internal time unit.
    attrs
        Further dataset attributes (e.g. scene name, method).
    shapes
        ``{body name: (radius, half_length)}`` [m] of finite-size bodies: stored as the
        variables ``radius`` and ``half_length`` (``body``; NaN for a body without a size).

    units
        The scene's units (:func:`poissonkit.report.run_units.unit_system`); ``None``: SI.

    Returns
    -------
    DatasetDescription
        Coordinates ``time`` [s or the scene's time unit], ``time_internal``, ``body`` (names), ``component`` (x, y, z),
        ``state`` (layout names); variables as the module describes.

    Raises
    ------
    DimensionError
        If ``t`` and ``y`` do not match.
    """
    t = np.asarray(t, dtype=float)
    y = np.atleast_2d(np.asarray(y, dtype=float))
    if y.shape[0] != t.shape[0]:
        raise DimensionError(f"{t.shape[0]} times but {y.shape[0]} states")
    layout = tuple(system.layout) if offers(system, HasLayout) else ()
    if len(layout) != y.shape[1]:
        layout = tuple(f"y{k}" for k in range(y.shape[1]))
    units = SI if units is None else units
    variables, bodies = _body_variables(system, y, layout)
    if not units.is_si:
        variables = in_units(variables, units)
    variables.update(mass_and_elements(system, y, bodies, units))
    data: dict[str, VariableSpec] = dict(variables)
    data["y"] = (("time", "state"), y, {
        "units": "internal (see internal_unit_* attributes)",
        "long_name": "state vector as integrated"})
    coords: dict[str, VariableSpec] = {
        "time": (("time",), units.from_si(t * float(time_unit), "time"),
                 {"units": units.label("time", text=False), "long_name": "time"}),
        "time_internal": (("time",), t, {
            "units": f"{float(time_unit)!r} s", "long_name": "time in the internal unit"}),
        "state": (("state",), np.array(layout, dtype=str), {}),
    }
    if bodies:
        coords["body"] = (("body",), np.array(bodies, dtype=str), {})
        if shapes:
            for k, (name, long_name) in enumerate((("radius", "radius of the body's shape"),
                                                   ("half_length", "half-length along the "
                                                    "symmetry axis (0: a sphere)"))):
                values = np.array([shapes[b][k] if b in shapes else np.nan for b in bodies],
                                  dtype=float)
                data[name] = (("body",), units.from_si(values, "length"), {
                    "units": units.label("length", text=False), "long_name": long_name})
        coords["component"] = (("component",), np.array(COMPONENTS, dtype=str), {})
    from poissonkit._version import __version__

    ds_attrs: dict[str, str | int | float] = {
        "title": "poissonkit trajectory", "poissonkit_version": __version__,
        "time_unit_s": float(time_unit), "system_in_si": int(scales is None),
        "conventions": "values in SI units (variable attribute 'units'); 'y' in the "
                       "internal units: si = internal * internal_unit_<kind>"}
    if scales is not None:
        for kind, unit in SI_UNITS.items():
            ds_attrs[f"internal_unit_{kind}"] = float(scales.unit(kind))
            ds_attrs[f"internal_unit_{kind}_units"] = unit
    if not units.is_si:
        ds_attrs["conventions"] = ("values in the scene's units (variable attribute 'units'; "
                                   "units_<kind>_in_si: SI value of one unit); 'y' in the "
                                   "internal units: si = internal * internal_unit_<kind>")
        ds_attrs.update(unit_attributes(units))
    ds_attrs.update(dict(attrs or {}))
    return DatasetDescription(data, coords, ds_attrs)


def open_trajectory(path: str | Path) -> xr.Dataset:
    """Read a trajectory dataset written by :func:`write_dataset` (loaded into memory).

    Raises
    ------
    InputError
        The file cannot be read as a dataset.
    MissingDependencyError
        If xarray is not installed.
    """
    xr = _xarray()
    try:
        with xr.open_dataset(path, engine=ENGINE) as ds:
            return ds.load()
    except (OSError, ValueError, TypeError) as exc:
        from poissonkit.errors import InputError

        raise InputError(f"cannot read the trajectory dataset {str(path)!r}: {exc}") from None


def write_dataset(path: str | Path, dataset: xr.Dataset) -> Path:
    """Write ``dataset`` as NetCDF (scipy's NetCDF 3 engine), atomically."""
    from poissonkit.files.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        dataset.to_netcdf(tmp, engine=ENGINE)
    return path


def write_description(path: str | Path, description: DatasetDescription) -> Path:
    """Write ``description`` atomically as the file :func:`write_dataset` writes of its
    dataset (the same bytes), without importing xarray
    (:func:`poissonkit.report.netcdf_writer.write_netcdf`)."""
    from poissonkit.files.atomic import atomic_path

    path = Path(path)
    with atomic_path(path) as tmp:
        write_netcdf(tmp, description)
    return path


def scale_arrays(scales: Scales | None, time_unit: float) -> dict[str, np.ndarray]:
    """Arrays that put the internal scales and SI units inside ``trajectory.npz``:
    ``scale_kinds``, ``scale_si`` (SI value of one internal unit of each kind) and
    ``scale_units``."""
    kinds = list(SI_UNITS)
    values = [float(scales.unit(k)) if scales is not None else 1.0 for k in kinds]
    if scales is None:
        values[kinds.index("time")] = float(time_unit)
    return {"scale_kinds": np.array(kinds, dtype=str), "scale_si": np.array(values),
            "scale_units": np.array([SI_UNITS[k] for k in kinds], dtype=str)}


#: Most bodies whose orbital elements the dataset holds (Jacobi elements cost O(N²) a state).
MAX_ELEMENT_BODIES = 64
#: The quantity kind of each per-body variable (for the scene's units).
_KINDS = {"position": "length", "momentum": "momentum", "angular_momentum": "angular_momentum",
          "relative_position": "length", "relative_momentum": "momentum"}


def in_units(variables: dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]],
             units: UnitSystem) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]]:
    """The SI variables of :func:`_body_variables` in the scene's units."""
    out: dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]] = {}
    for name, (dims, values, attrs) in variables.items():
        kind = _KINDS.get(name)
        if kind is not None:
            values = units.from_si(values, kind)
            attrs = {**attrs, "units": units.label(kind, text=False)}
        out[name] = (dims, values, attrs)
    return out


def unit_attributes(units: UnitSystem) -> dict[str, str | float]:
    """Dataset attributes naming the scene's units and their SI values."""
    d = units.as_dict()
    out: dict[str, str | float] = {
        "units_length": units.label("length", text=False),
        "units_time": units.label("time", text=False),
        "units_mass": units.label("mass", text=False), "units_G": float(units.G)}
    if not units.is_nbody:
        for kind in ("length", "time", "mass"):
            out[f"units_{kind}_in_si"] = float(d[f"{kind}_si"])  # type: ignore[arg-type]
    return out


def mass_and_elements(system: object, y: np.ndarray, bodies: list[str], units: UnitSystem
                      ) -> dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]]:
    """``mass`` (``body``) of an N-body system's bodies, and their orbital elements
    (``time × body``) when they are moving point masses with Newtonian gravity."""
    from poissonkit.numerics.elements import dominant_body, gravity_si, system_elements

    if not (bodies and offers(system, HasBodies)):
        return {}
    by_name = {b.name: b for b in system.bodies}
    if set(bodies) - set(by_name):
        return {}
    masses = np.array([float(by_name[n].mass) for n in bodies])  # type: ignore[attr-defined]
    out: dict[str, tuple[tuple[str, ...], np.ndarray, dict[str, str]]] = {"mass": (("body",), units.from_si(masses, "mass"),
                    {"units": units.label("mass", text=False), "long_name": "mass"})}
    if (len(bodies) > MAX_ELEMENT_BODIES or gravity_si(system) is None
            or list(bodies) != [b.name for b in system.bodies]):
        return out
    primary = dominant_body(masses)
    el = system_elements(system, y, primary)
    frame = (f"about {bodies[primary]}" if primary is not None
             else "Jacobi (about the centre of mass of the bodies before it)")
    for name, long_name in (("a", "semi-major axis"), ("e", "eccentricity"),
                            ("inc", "inclination"), ("Omega", "longitude of ascending node"),
                            ("omega", "argument of pericentre"), ("M", "mean anomaly"),
                            ("f", "true anomaly")):
        values = getattr(el, name)
        unit = "1" if name == "e" else "rad"
        if name == "a":
            values, unit = units.from_si(values, "length"), units.label("length", text=False)
        out[name] = (("time", "body"), np.asarray(values, dtype=float),
                     {"units": unit, "long_name": f"osculating {long_name}, {frame}"})
    return out
