"""The scene schema: a frozen :class:`Scene` validated from a plain mapping (parsed TOML).

Every error is a :class:`~poissonkit.errors.SceneError` whose message starts with the path of
the offending field, e.g. ``bodies[1].mass: must be > 0, got -1.0``. A scene is validated in
the units it is written in (``[units]``, SI by default) and held in SI
(:mod:`poissonkit.scene.units`).
The file format is documented field by field in ``docs/scenes.md``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from poissonkit.errors import PoissonkitError, SceneError
from poissonkit.numerics.unitsystem import SI, UnitSystem
from poissonkit.scene.limits import held_pairs
from poissonkit.scene.overrides import BodyOverride
from poissonkit.scene.units import scene_in_si, scene_units, si_params, with_orbits

TOP_KEYS = ("name", "description", "defaults", "bodies", "assembly", "interactions", "run",
            "planner", "fields", "units")
BODY_KEYS = ("name", "mass", "alpha", "inertia", "r", "p", "nu", "m", "fixed", "moment",
             "magnetization", "radius", "length", "half_length")
INTERACTION_KEYS = ("potential", "params", "pairs", "cutoff", "pair")
PAIR_KEYS = ("bodies", "potential", "params")
ASSEMBLY_KEYS = ("name", "params", "overrides", "body")
RUN_KEYS = ("method", "step", "tol", "duration", "save_every", "energy_tol", "contact",
            "max_steps", "save_dt", "options")
PLANNER_KEYS = ("tol", "models", "replan_every", "hysteresis", "cutoff")
#: More bodies than any memory holds: refused before the memory estimate (which counts in
#: floats and would overflow for ``n = 1e300``).
MAX_COUNT = 10**15
#: Integer assembly parameters that count bodies (their product is the assembly's size).
_COUNT_PARAMS = ("n", "nx", "ny", "nz")

_FLOAT_FIELDS = ("mass", "alpha", "inertia", "moment", "magnetization", "radius", "length",
                 "half_length")
_VECTOR_FIELDS = ("r", "p", "nu", "m")


@dataclass(frozen=True)
class PairDecl:
    """An explicitly listed interaction: two body names, a potential and its parameters."""

    bodies: tuple[str, str]
    potential: str
    params: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class FieldDecl:
    """A ``[[fields]]`` table: a registered external field and its parameters (validated)."""

    source: str
    params: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class PlannerSpec:
    """The ``[planner]`` table: force tolerance, candidate models, re-planning cadence."""

    tol: float
    #: Candidate potentials; ``None``: the default models of every registered model family.
    models: tuple[str, ...] | None = None
    replan_every: int = 100
    hysteresis: float = 0.5
    cutoff: float | None = None


@dataclass(frozen=True)
class RunSettings:
    """The ``[run]`` table: integrator name, step [s] or tolerance, duration [s], the accepted
    relative energy error and what to do when finite-size bodies touch (``contact``:
    ``"stop"``, the default, or ``"ignore"`` for scenes that declare overlapping bodies
    meaningful), the most fixed steps the run may take (``max_steps``; ``None``: no
    limit), and the interval [s] at which states are saved instead of every ``save_every``-th
    step (``save_dt``; reached exactly by every method); ``options``: the integrator's own
    options (``[run.options]``, :mod:`poissonkit.scene.run_options`)."""

    duration: float
    method: str = "splitting4"
    step: float | None = None
    tol: float | None = None
    save_every: int = 1
    energy_tol: float = 1e-6
    contact: str = "stop"
    max_steps: int | None = None
    save_dt: float | None = None
    options: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Scene:
    """A validated scene (frozen). Build one with :func:`poissonkit.scene.load_scene`.

    Attributes
    ----------
    name, description
        For reports.
    bodies
        Body attribute mappings (SI), one per body, in file order (``defaults`` merged in);
        empty when the scene uses an ``assembly``.
    assembly
        ``(name, params)`` of a registered assembly, or ``None``.
    assembly_overrides
        Extra node attributes applied to every body the assembly builds (e.g. ``fixed``;
        ``spin`` sets each top's angular momentum about its axis).
    potential, potential_params
        Default pair potential (used for every pair when ``pairs = "all"``).
    pairs_mode
        ``"all"`` (every pair, listed pairs override) or ``"listed"`` (only listed pairs).
    pairs
        Explicitly listed interactions.
    cutoff
        Pairs farther apart than this are skipped [m], or ``None``.
    run
        Integration settings.
    planner
        Model-fidelity planner settings, or ``None``.
    source
        Path the scene was read from ('' for an in-memory scene).
    fields
        External fields (``[[fields]]`` tables): gravity, magpylib sources, ...
    """

    name: str
    description: str
    bodies: tuple[Mapping[str, Any], ...]
    assembly: tuple[str, Mapping[str, Any]] | None
    assembly_overrides: Mapping[str, Any]
    potential: str | None
    potential_params: Mapping[str, Any]
    pairs_mode: str
    pairs: tuple[PairDecl, ...]
    cutoff: float | None
    run: RunSettings
    planner: PlannerSpec | None = None
    source: str = ""
    #: External fields (``[[fields]]``), see ``docs/fields.md``.
    fields: tuple[FieldDecl, ...] = ()
    #: Per-body overrides of an assembly (``[[assembly.body]]``, by index or name pattern).
    assembly_bodies: tuple[BodyOverride, ...] = ()
    #: The units the scene was written in (``[units]``, ``docs/units.md``); the numbers above
    #: are SI (converted by :func:`poissonkit.scene.units.scene_in_si`).
    units: UnitSystem = SI


# ---------------------------------------------------------------- small validators

def _table(value: Any, where: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise SceneError(f"{where}: must be a table, got {type(value).__name__}")
    return value


def _keys(table: Mapping[str, Any], allowed: tuple[str, ...], where: str) -> None:
    for key in table:
        if key not in allowed:
            prefix = f"{where}." if where else ""
            raise SceneError(f"{prefix}{key}: unknown key; allowed: {', '.join(allowed)}")


def _number(value: Any, where: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(f"{where}: must be a number, got {value!r}")
    try:
        x = float(value)
    except OverflowError:  # an integer beyond float range (10**400)
        raise SceneError(f"{where}: must be finite, got {value!r}") from None
    if not math.isfinite(x):
        raise SceneError(f"{where}: must be finite, got {value!r}")
    if positive and not x > 0:
        raise SceneError(f"{where}: must be > 0, got {value!r}")
    if nonnegative and x < 0:
        raise SceneError(f"{where}: must be >= 0, got {value!r}")
    return x


def _integer(value: Any, where: str, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise SceneError(f"{where}: must be an integer >= {minimum}, got {value!r}")
    return value


def _string(value: Any, where: str) -> str:
    if not isinstance(value, str) or not value:
        raise SceneError(f"{where}: must be a non-empty string, got {value!r}")
    return value


def _vector(value: Any, where: str) -> tuple[float, float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise SceneError(f"{where}: must be a list of 3 numbers, got {value!r}")
    return tuple(_number(v, f"{where}[{k}]") for k, v in enumerate(value))  # type: ignore[return-value]


def _body_keys(table: Mapping[str, Any], where: str) -> None:
    """Every key of a body table is a body field or an attribute a registered potential
    declares (``PairPotential.body_params``); the error names the key and lists those."""
    from poissonkit.scene.bodies import allowed_attributes, declared_attributes

    for key in table:
        if key not in BODY_KEYS and key not in declared_attributes():
            prefix = f"{where}.{key}" if where else key
            raise SceneError(f"{prefix}: unknown key; {allowed_attributes()}")


def _attribute(value: Any, where: str) -> float | tuple[float, ...]:
    """A declared body attribute: a number or a non-empty list of numbers."""
    if isinstance(value, list) and value:
        return tuple(_number(v, f"{where}[{k}]") for k, v in enumerate(value))
    if isinstance(value, list):
        raise SceneError(f"{where}: must be a number or a non-empty list of numbers, got []")
    return _number(value, where)


def _params(value: Any, where: str) -> dict[str, Any]:
    table = _table(value, where)
    out: dict[str, Any] = {}
    for k, v in table.items():
        if isinstance(v, (bool, int, float, str)):
            out[k] = v
        elif isinstance(v, list) and all(isinstance(x, (int, float)) for x in v):
            out[k] = tuple(v)
        else:
            raise SceneError(f"{where}.{k}: must be a number, string, boolean or list of numbers,"
                             f" got {v!r}")
    return out


def _lookup(kind: str, name: str, where: str):
    from poissonkit.plugin import lookup

    try:
        return lookup(kind, name)
    except PoissonkitError as exc:
        raise SceneError(f"{where}: {exc}") from None


# ---------------------------------------------------------------- sections

def _body(raw: Any, defaults: Mapping[str, Any], where: str) -> dict[str, Any]:
    table = _table(raw, where)
    _body_keys(table, where)
    merged = {**defaults, **table}
    out: dict[str, Any] = {}
    if "name" in merged:
        out["name"] = _string(merged["name"], f"{where}.name")
    if "mass" not in merged:
        raise SceneError(f"{where}.mass: missing (kg; give it on the body or in [defaults])")
    for key in _FLOAT_FIELDS:
        if key in merged:
            # moment/magnetization = 0 marks a non-magnet (overriding [defaults])
            zero_ok = key in ("moment", "magnetization")
            out[key] = _number(merged[key], f"{where}.{key}", positive=not zero_ok,
                               nonnegative=zero_ok)
    if "alpha" in out and "inertia" in out:
        raise SceneError(f"{where}: give alpha or inertia, not both")
    for key in _VECTOR_FIELDS:
        if key in merged:
            out[key] = _vector(merged[key], f"{where}.{key}")
    if "r" not in out:
        raise SceneError(f"{where}.r: missing initial position (m)")
    is_top = "alpha" in out or "inertia" in out
    if is_top:
        if "nu" not in out:
            raise SceneError(f"{where}.nu: missing axis (a body with alpha/inertia is a top)")
        if math.fsum(x * x for x in out["nu"]) == 0.0:
            raise SceneError(f"{where}.nu: the axis must not be zero")
    else:
        for key in ("nu", "m"):
            if key in table:
                raise SceneError(f"{where}.{key}: only a top has an axis and angular momentum; "
                                 "give alpha or inertia, or remove it")
    if "fixed" in merged:
        if not isinstance(merged["fixed"], bool):
            raise SceneError(f"{where}.fixed: must be true or false, got {merged['fixed']!r}")
        out["fixed"] = merged["fixed"]
    for key in merged:
        if key not in BODY_KEYS:  # declared by a potential (checked by _body_keys)
            out[key] = _attribute(merged[key], f"{where}.{key}")
    return out


def _optional_positive(table: Mapping[str, Any], key: str, where: str) -> float | None:
    """``table[key]`` as a positive number, or ``None`` when the key is absent."""
    return _number(table[key], f"{where}.{key}", positive=True) if key in table else None


def _run(raw: Any, units: UnitSystem = SI) -> RunSettings:
    table = _table(raw, "run")
    _keys(table, RUN_KEYS, "run")
    tu = units.label("time")  # the scene's time unit: values here are not converted yet
    if "duration" not in table:
        raise SceneError(f"run.duration: missing ({tu})")
    duration = _number(table["duration"], "run.duration", positive=True)
    method = _string(table.get("method", "splitting4"), "run.method")
    _lookup("integrator", method, "run.method")
    step = _optional_positive(table, "step", "run")
    tol = _optional_positive(table, "tol", "run")
    if step is not None and step > duration:
        raise SceneError(f"run.step: {step:g} {tu} is longer than run.duration {duration:g} {tu}")
    save_every = _integer(table.get("save_every", 1), "run.save_every")
    energy_tol = _number(table.get("energy_tol", 1e-6), "run.energy_tol", positive=True)
    contact = _string(table.get("contact", "stop"), "run.contact")
    if contact not in ("stop", "ignore"):
        raise SceneError(f"run.contact: must be \"stop\" or \"ignore\", got {contact!r}")
    max_steps = (_integer(table["max_steps"], "run.max_steps") if "max_steps" in table
                 else None)
    save_dt = _optional_positive(table, "save_dt", "run")
    if save_dt is not None and "save_every" in table:
        raise SceneError("run.save_dt and run.save_every both choose the saved states: give one")
    from poissonkit.scene.run_options import run_options

    return RunSettings(duration, method, step, tol, save_every, energy_tol, contact, max_steps,
                       save_dt, run_options(table.get("options"), method))


def _planner(raw: Any) -> PlannerSpec:
    table = _table(raw, "planner")
    _keys(table, PLANNER_KEYS, "planner")
    if "tol" not in table:
        raise SceneError("planner.tol: missing (relative force tolerance)")
    tol = _number(table["tol"], "planner.tol", positive=True)
    models = table.get("models")  # absent: each registered model family's defaults
    if models is not None and (not isinstance(models, list) or not models):
        raise SceneError(f"planner.models: must be a non-empty list of potential names, got {models!r}")
    for k, name in enumerate(models or ()):
        _lookup("potential", _string(name, f"planner.models[{k}]"), f"planner.models[{k}]")
    replan = _integer(table.get("replan_every", 100), "planner.replan_every")
    hyst = _number(table.get("hysteresis", 0.5), "planner.hysteresis", nonnegative=True)
    if hyst >= 1:
        raise SceneError(f"planner.hysteresis: must be in [0, 1), got {hyst!r}")
    cutoff = _number(table["cutoff"], "planner.cutoff", positive=True) if "cutoff" in table else None
    return PlannerSpec(tol, None if models is None else tuple(models), replan, hyst, cutoff)


def _fields(raw: Any, units: UnitSystem = SI) -> tuple[FieldDecl, ...]:
    """The ``[[fields]]`` tables, each checked against its registered field's parameters."""
    if not isinstance(raw, list):
        raise SceneError("fields: must be an array of tables ([[fields]])")
    out = []
    for k, item in enumerate(raw):
        where = f"fields[{k}]"
        table = dict(_table(item, where))
        name = _string(table.pop("source", None), f"{where}.source")
        entry = _lookup("field", name, f"{where}.source")
        params = {key: tuple(v) if isinstance(v, list) and key not in entry.tables else v
                  for key, v in table.items()}
        params = si_params(entry, params, units)  # before the SI defaults are filled in
        try:
            resolved = entry.resolve_params(params)
        except PoissonkitError as exc:
            raise SceneError(f"{where}: {exc}") from None
        out.append(FieldDecl(name, resolved))
    return tuple(out)


def scene_from_mapping(data: Mapping[str, Any], source: str = "") -> Scene:
    """Validate a parsed scene (e.g. from TOML) into a frozen :class:`Scene`.

    Raises
    ------
    SceneError
        Naming the offending field: unknown keys, wrong types, negative masses, missing axes,
        unknown potentials / integrators / assemblies, overlapping bodies at t = 0, ...
        Huge values (``1e308``) overflow inside the geometric checks without numpy warnings;
        the checks refuse the non-finite results.
    """
    import numpy as np

    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
            return _scene_from_mapping(data, source)
    except ArithmeticError as exc:  # ZeroDivisionError, OverflowError of huge Python numbers
        raise SceneError(f"a value is out of floating-point range ({exc})") from None


def _scene_from_mapping(data: Mapping[str, Any], source: str) -> Scene:
    data = _table(data, "scene")
    _keys(data, TOP_KEYS, "")
    name = _string(data.get("name", "scene"), "name")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise SceneError(f"description: must be a string, got {description!r}")
    defaults = _table(data.get("defaults", {}), "defaults")
    _body_keys(defaults, "defaults")
    units = scene_units(data.get("units"))
    if "bodies" in data and "assembly" in data:
        raise SceneError("bodies, assembly: give one of them, not both")
    if "bodies" not in data and "assembly" not in data:
        raise SceneError("bodies: missing (or give an assembly)")

    bodies: tuple[dict[str, Any], ...] = ()
    assembly = None
    overrides: dict[str, Any] = {}
    per_body: tuple[BodyOverride, ...] = ()
    if "bodies" in data:
        bodies = _bodies(data, defaults, units)
    else:
        assembly, overrides, per_body = _assembly(data)
    potential, pot_params, mode, cutoff, pairs = _interactions(data, bodies, assembly)
    if "run" not in data:
        raise SceneError("run: missing ([run] with at least duration)")
    run = _run(data["run"], units)
    planner = _planner(data["planner"]) if "planner" in data else None
    if planner is not None and "fields" in data:  # re-planned runs rebuild the pair system
        raise SceneError("fields: [[fields]] with a [planner] is not supported yet; drop one")
    scene = Scene(name=name, description=description, bodies=bodies, assembly=assembly,
                  assembly_overrides=overrides, assembly_bodies=per_body,
                  potential=potential, potential_params=pot_params,
                  pairs_mode=mode, pairs=pairs, cutoff=cutoff, run=run, planner=planner,
                  source=source, units=units,
                  fields=_fields(data["fields"], units) if "fields" in data else ())
    if bodies:
        check_overlaps(bodies, "bodies")
    else:
        from poissonkit.scene.build import scene_graph

        try:
            graph = scene_graph(scene, edges=False)
        except (OverflowError, ZeroDivisionError):  # body_radius = 1e300 or 1e-320: the
            # volume overflows or underflows to zero
            raise SceneError("assembly.params: a size or moment is out of range") from None
        check_overlaps([graph.nodes[n] for n in graph.nodes], "assembly")
    return scene_in_si(scene)


def _bodies(data: Mapping[str, Any], defaults: Mapping[str, Any], units: UnitSystem = SI
            ) -> tuple[dict[str, Any], ...]:
    """The ``[[bodies]]`` tables, completed by ``defaults``, each with a unique name (bodies
    given by orbital elements placed, in the scene's units)."""
    raw = data["bodies"]
    if not isinstance(raw, list) or not raw:
        raise SceneError("bodies: must be a non-empty array of tables ([[bodies]])")
    raw = with_orbits(raw, defaults, units)
    check_size(len(raw), _pair_count(raw, data), "bodies")
    bodies = tuple(_body(b, defaults, f"bodies[{k}]") for k, b in enumerate(raw))
    seen: dict[str, int] = {}
    for k, b in enumerate(bodies):
        b.setdefault("name", f"b{k}")
        if b["name"] in seen:
            raise SceneError(f"bodies[{k}].name: {b['name']!r} is already used by "
                             f"bodies[{seen[b['name']]}]")
        seen[b["name"]] = k
    return bodies


def _assembly(data: Mapping[str, Any]
              ) -> tuple[tuple[str, dict[str, Any]], dict[str, Any], tuple[BodyOverride, ...]]:
    """``((name, params), overrides, per-body overrides)`` of the ``[assembly]`` table, its
    size checked (:mod:`poissonkit.scene.overrides`)."""
    table = _table(data["assembly"], "assembly")
    _keys(table, ASSEMBLY_KEYS, "assembly")
    aname = _string(table.get("name"), "assembly.name")
    entry = _lookup("assembly", aname, "assembly.name")
    aparams = _params(table.get("params", {}), "assembly.params")
    try:
        resolved = entry.resolve_params(aparams)
    except PoissonkitError as exc:
        raise SceneError(f"assembly.params: {exc}") from None
    except ArithmeticError as exc:  # n = 10**400: beyond float range
        raise SceneError(f"assembly.params: a value is out of range ({exc})") from None
    size = 1
    for key in _COUNT_PARAMS:
        value = resolved.get(key)
        if isinstance(value, int) and not isinstance(value, bool) and value > 0:
            size *= value
    if size > MAX_COUNT:  # beyond any memory, and beyond float range in the estimate
        raise SceneError(f"assembly.params: {len(str(size))}-digit body count, more than "
                         f"{MAX_COUNT:.0e} bodies")
    check_size(size, held_pairs(size, data, assembly=resolved), "assembly.params")
    assembly = (aname, aparams)
    from poissonkit.scene.overrides import body_fields, per_body

    overrides = body_fields(table.get("overrides", {}), "assembly.overrides")
    return assembly, overrides, per_body(table.get("body"))


def _interactions(data: Mapping[str, Any], bodies: tuple[dict[str, Any], ...],
                  assembly: tuple[str, dict[str, Any]] | None
                  ) -> tuple[Any, dict[str, Any], Any, float | None, tuple[PairDecl, ...]]:
    """``(potential, params, pairs mode, cutoff, listed pairs)`` of the ``[interactions]``
    table (listed pairs name known bodies unless an assembly makes them)."""
    inter = _table(data.get("interactions", {}), "interactions")
    _keys(inter, INTERACTION_KEYS, "interactions")
    potential = inter.get("potential")
    if potential is not None:
        _lookup("potential", _string(potential, "interactions.potential"), "interactions.potential")
    pot_params = _params(inter.get("params", {}), "interactions.params")
    mode = inter.get("pairs", "all")
    if mode not in ("all", "listed"):
        raise SceneError(f"interactions.pairs: must be 'all' or 'listed', got {mode!r}")
    cutoff = (_number(inter["cutoff"], "interactions.cutoff", positive=True)
              if "cutoff" in inter else None)
    names = {b["name"] for b in bodies}
    pairs: list[PairDecl] = []
    raw_pairs = inter.get("pair", [])
    if not isinstance(raw_pairs, list):
        raise SceneError("interactions.pair: must be an array of tables ([[interactions.pair]])")
    for k, raw in enumerate(raw_pairs):
        where = f"interactions.pair[{k}]"
        table = _table(raw, where)
        _keys(table, PAIR_KEYS, where)
        ends = table.get("bodies")
        if (not isinstance(ends, list) or len(ends) != 2 or ends[0] == ends[1]
                or not all(isinstance(e, str) for e in ends)):
            raise SceneError(f"{where}.bodies: must name two different bodies, got {ends!r}")
        if assembly is None:
            for e in ends:
                if e not in names:
                    raise SceneError(f"{where}.bodies: unknown body {e!r}; available: "
                                     + ", ".join(sorted(names)))
        pname = table.get("potential", potential)
        if pname is None:
            raise SceneError(f"{where}.potential: missing (and no interactions.potential)")
        _lookup("potential", _string(pname, f"{where}.potential"), f"{where}.potential")
        pairs.append(PairDecl((ends[0], ends[1]), pname, _params(table.get("params", {}),
                                                                 f"{where}.params")))
    if mode == "all" and potential is None and assembly is None and len(bodies) > 1:
        planner_given = "planner" in data
        if not planner_given:
            raise SceneError("interactions.potential: missing (needed when pairs = 'all'; "
                             "or use pairs = 'listed' or a [planner])")
    return potential, pot_params, mode, cutoff, tuple(pairs)


def _pair_count(raw: list[Any], data: Mapping[str, Any]) -> int:
    """Pairs a scene of these body tables holds while it is built
    (:func:`poissonkit.scene.limits.held_pairs`)."""
    defaults = data.get("defaults", {})
    defaults = defaults if isinstance(defaults, Mapping) else {}
    tables = [{**defaults, **b} if isinstance(b, Mapping) else {} for b in raw]
    return held_pairs(len(raw), data, tables)


def check_size(bodies: int, pairs: int, where: str) -> None:
    """Refuse a scene whose set-up would not fit in memory (:mod:`poissonkit.scene.limits`).

    Raises
    ------
    SceneTooLargeError
        Naming the estimate and the memory it was compared with.
    """
    from poissonkit.scene.limits import check_memory

    check_memory(bodies, pairs, where)


#: Up to this many bodies, :func:`check_overlaps` compares every pair directly.
_DIRECT_OVERLAP_CHECK = 64


def check_overlaps(bodies, where: str = "bodies") -> None:
    """Raise :class:`SceneError` naming the first two bodies that overlap at t = 0.

    ``bodies`` are attribute mappings (``r``, optional ``nu``, ``radius``, ``length`` /
    ``half_length``, ``name``). Only pairs whose bounding spheres meet (or whose centres
    coincide) get the exact shape test, found with a k-d tree, so large scenes check fast.
    """
    import numpy as np

    from poissonkit.scene.geometry import overlapping, shape_of

    bodies = list(bodies)
    shapes = []
    for b in bodies:
        half = b.get("half_length", b.get("length", 0.0) / 2)
        shapes.append(shape_of(b["r"], b.get("nu"), b.get("radius", 0.0), half))
    if len(shapes) < 2:
        return
    centers = np.array([s.center for s in shapes], dtype=float)
    bound = np.array([s.bounding_radius for s in shapes], dtype=float)
    reach = 2 * float(bound.max())
    # the tree finds every pair within reach (coincident centres at distance 0 included);
    # a small relative pad keeps round-off from hiding a touching pair
    reach += 1e-9 * (reach + float(np.abs(centers).max()))
    # in the max-norm (a superset of the Euclidean pairs within reach): no squares, so
    # coordinates up to the float limit do not overflow inside the tree
    if len(shapes) <= _DIRECT_OVERLAP_CHECK:
        # a few bodies: every pair at once, without loading scipy's tree (a run's start-up)
        gap = np.abs(centers[:, None, :] - centers[None, :, :]).max(axis=2)
        near = np.argwhere(np.triu(gap <= reach, k=1))
    else:
        from scipy.spatial import cKDTree

        near = cKDTree(centers).query_pairs(reach, p=np.inf, output_type="ndarray")
    for i, j in sorted((int(a), int(b)) for a, b in near):  # (i, j) order: first pair named
        a, c = shapes[i], shapes[j]
        coincident = bool(np.all(a.center == c.center))
        if coincident or ((a.kind != "point" or c.kind != "point") and overlapping(a, c)):
            raise SceneError(
                f"{where}[{j}].r: body {bodies[j].get('name', j)!r} overlaps body "
                f"{bodies[i].get('name', i)!r} ({where}[{i}]) at t = 0 (their r, radius "
                "and length decide)")
