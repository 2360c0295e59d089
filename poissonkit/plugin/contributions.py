"""Types of the things plugins contribute.

Every contribution is a named registry entry with a docstring and typed parameters. Plugins
return lists of these from the hooks in :mod:`poissonkit.plugin.hookspecs`.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol, SupportsInt, cast

from poissonkit.contracts import (AssemblyBuilder, Capabilities, Claim, EnergyBound, EnergyScale,
                                  ErrorEstimator, EvaluatorFactory, KernelFactory, OutcomeFunction,
                                  PairFunction, PairPredicate, ParamCompleter, ParamKernelFactory,
                                  ParamValues, SourcePredicate, SweepFactory, SymbolicEnergy)
from poissonkit.errors import InputError, UnknownNameError

if TYPE_CHECKING:  # annotations only: these layers sit above the plugin host
    from poissonkit.numerics.fields.base import CompiledField, FieldRequest
    from poissonkit.numerics.runspec import RunSpec
    from poissonkit.scene.schema import Scene
    from poissonkit.structure import Bivector, HamiltonianSystem

#: ``build(**params)`` of a :class:`SystemEntry`: a bivector or a Hamiltonian system.
SystemBuilder = Callable[..., "Bivector | HamiltonianSystem"]
#: ``load(**params)`` of a :class:`SceneEntry`: a scene or a ready run spec.
SceneLoader = Callable[..., "Scene | RunSpec"]
#: ``outcome(spec, t, y, events)`` of a :class:`SceneEntry`: what a finished run of the scene
#: came to (saved times and states in internal units, the event records), JSON-ready.
SceneOutcome = Callable[["RunSpec", Any, Any, Any], Mapping[str, Any]]


def _missing(*_: Any, **__: Any) -> Any:
    """The placeholder of a builder an entry was not given (returns ``None``)."""
    return None


class FieldBuilder(Protocol):
    """``build(params, request, source) -> CompiledField`` of an :class:`ExternalField`."""

    def __call__(self, params: dict[str, Any], request: FieldRequest, source: object = None, /
                 ) -> CompiledField: ...

_PARAM_TYPES = {"float": float, "int": int, "str": str, "bool": bool, "vector": tuple}


@dataclass(frozen=True)
class Param:
    """A typed, documented parameter of a registry entry.

    Parameters
    ----------
    name
        Parameter name as passed by users (keyword).
    type
        One of ``"float"``, ``"int"``, ``"str"``, ``"bool"``, ``"vector"``.
    doc
        One-line description, with the unit in brackets for physical quantities.
    default
        Default value; ``None`` means the parameter is required.
    unit
        SI unit, or ``""`` for dimensionless.
    positive
        If true, values must be > 0 (every component, for a vector).
    optional
        If true, a parameter without a default may be left out (it is then absent from the
        resolved parameters, and the entry chooses); otherwise it is required.
    """

    name: str
    type: str = "float"
    doc: str = ""
    default: Any = None
    unit: str = ""
    positive: bool = False
    optional: bool = False

    def coerce(self, value: Any, owner: str = "") -> Any:
        """Check and convert one user value; raise :class:`InputError` naming the parameter.

        ``"int"`` accepts integers, integral floats (``3.0``) and integer strings (``"3"``, as
        given on the command line) but never truncates (``2.7`` is an error); ``"float"`` and
        ``"vector"`` values must be finite; a ``"vector"`` is a non-empty sequence of numbers,
        never a bare string (its length is checked by the entry that uses it); ``"str"``
        accepts only strings; ``"bool"`` only ``True``/``False``.
        """
        where = f"{owner}: " if owner else ""
        if self.type not in _PARAM_TYPES:
            raise InputError(f"{where}parameter {self.name!r} has unknown type {self.type!r}")
        try:
            out = _CONVERT[self.type](value)
        except (TypeError, ValueError, OverflowError):
            raise InputError(
                f"{where}parameter {self.name!r} must be {self.type}, got {value!r}"
            ) from None
        if self.type == "vector":
            if not out:
                raise InputError(f"{where}parameter {self.name!r} must be a non-empty vector, "
                                 f"got {value!r}")
            values = out
        else:
            values = (out,) if self.type in ("float", "int") else ()
        if not all(math.isfinite(v) for v in values):
            raise InputError(f"{where}parameter {self.name!r} must be finite, got {value!r}")
        if self.positive and not all(v > 0 for v in values):  # numbers only: str/bool ignore it
            raise InputError(f"{where}parameter {self.name!r} must be > 0, got {value!r}")
        return out


def _to_int(value: Any) -> int:
    """An exact integer: never truncate a fractional value, never take a bool for a number."""
    if isinstance(value, bool):
        raise TypeError
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, str):
        return int(value.strip())  # "2.7" -> ValueError, as it should
    if isinstance(value, numbers.Real):
        if not math.isfinite(value) or not float(value).is_integer():
            raise ValueError
        return int(cast("SupportsInt", value))  # a Real with an integer value
    raise TypeError


def _to_float(value: Any) -> float:
    if isinstance(value, bool):
        raise TypeError
    return float(value)


def _to_vector(value: Any) -> tuple[float, ...]:
    # A bare string is iterable but is not a vector: "123" must not become (1.0, 2.0, 3.0).
    if isinstance(value, (str, bytes, Mapping)):
        raise TypeError
    return tuple(_to_float(v) for v in value)


def _to_str(value: Any) -> str:
    if not isinstance(value, str):
        raise TypeError
    return value


def _to_bool(value: Any) -> bool:
    if not isinstance(value, bool):
        raise TypeError
    return value


_CONVERT: dict[str, Callable[[Any], Any]] = {
    "float": _to_float, "int": _to_int, "str": _to_str, "bool": _to_bool, "vector": _to_vector,
}


@dataclass(frozen=True)
class Entry:
    """Base of every registry entry: a name, a doc string and typed parameters."""

    name: str
    doc: str
    params: tuple[Param, ...] = ()

    def resolve_params(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """Validate user parameters against :attr:`params`, fill defaults, reject unknown ones."""
        known = {p.name: p for p in self.params}
        unknown = set(given) - set(known)
        if unknown:
            raise UnknownNameError(f"parameter of {self.name!r}", sorted(unknown)[0], known)
        out: dict[str, Any] = {}
        for p in self.params:
            if p.name in given:
                out[p.name] = p.coerce(given[p.name], self.name)
            elif p.default is not None:
                out[p.name] = p.default
            elif not p.optional:
                raise InputError(f"{self.name}: missing required parameter {p.name!r} ({p.doc})")
        return out


@dataclass(frozen=True)
class PairPotential(Entry):
    """An interaction energy of two axisymmetric bodies, U(r, c1, c2, c3; params).

    ``r = |r_j - r_i|``, ``c1 = (e, nu_i)``, ``c2 = (e, nu_j)``, ``c3 = (nu_i, nu_j)``
    (see :mod:`poissonkit.conventions`). Plugins contribute energies, never forces: the
    numerics derive forces and torques from the partial derivatives.

    Attributes
    ----------
    expr
        ``expr(params) -> sympy.Expr`` in the symbols ``r, c1, c2, c3`` (``sympy.Symbol`` with
        those names, real). Provide it when U has closed form; the numerics differentiate it
        once and compile.
    kernel
        ``kernel(params) -> f`` returning a compiled (numba ``njit``) scalar function
        ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``. Required when there is no closed form
        (e.g. exact cylinders by quadrature); optional otherwise.
    orientation
        ``"both"`` if U depends on both axes, ``"first"``/``"second"`` if only on one, ``"none"``
        for a central potential (point masses).
    body_params
        ``((parameter, body attribute, 1 or 2), …)``: parameters that default to an attribute
        of the first or second body of each pair (e.g. gravity's ``("mass1", "mass", 1)``), so
        an all-pairs interaction needs no per-pair list. Needs ``expr``.
    energy_scale
        Optional ``energy_scale(bodies, length) -> float or None``: the energy unit [J] of a
        scene of these bodies (:class:`poissonkit.scene.bodies.BodyModel`) whose length unit is
        ``length`` [m], or ``None`` when it does not apply. Without it the automatic units use
        the largest ``|U|`` at that length (:func:`poissonkit.scene.assembly.auto_scales`).
    param_kernel
        Optional ``param_kernel(params) -> f``: a numba ``njit`` function ``f(r, c1, c2, c3, P)
        -> (U, U_r, U_c1, U_c2, U_c3)`` reading its run-time parameters from ``P``, a tuple of
        floats indexed like an array (``P[0]``, ``P[1]``, …; filled by :attr:`param_values`;
        a tuple rather than a view of an array, which would cost two atomic reference counts
        per call). It must return the *same* function for
        parameter sets that differ only in the values of ``P`` (cache it on the parameters
        that shape the code, e.g. integer node counts): the numerics then compile a system's
        force loops once for every value. Used before :attr:`kernel` when given.
    param_values
        ``param_values(params) -> sequence of floats``: the values of ``P`` of
        :attr:`param_kernel` for resolved parameters (required with it).
    constant_params
        Float parameters of :attr:`expr` compiled in as constants instead of passed at run
        time (a changed value then compiles again). Every other float parameter of an ``expr``
        is a kernel argument: ``expr(params)`` is called once with real sympy symbols (positive
        where the :class:`Param` says so) in their place, so it must not branch on their
        values; an ``expr`` that fails with symbols falls back to constants.
    """

    expr: SymbolicEnergy | None = None
    kernel: KernelFactory | None = None
    orientation: str = "both"
    body_params: tuple[tuple[str, str, int], ...] = ()
    # What pair_interaction uses (see "PairPotential: direct evaluation" in docs/plugins.md):
    #: ``evaluate(params) -> f`` with ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)`` as
    #: floats, for one-off evaluations without compiling a kernel per parameter set.
    evaluate: EvaluatorFactory | None = None
    #: ``complete_params(given) -> params``: derive this potential's parameters from other
    #: per-body quantities its plugin understands (magnets: moment from magnetisation through
    #: the cylinder volume), dropping those quantities where the potential does not take them.
    #: Unrecognised names must be left in place (they are reported as unknown).
    complete_params: ParamCompleter | None = None
    #: Per-body quantities (base names, without the ``1``/``2`` suffix) accepted besides the
    #: parameters, for :attr:`complete_params` or the overlap check (``radius``, ``length``).
    body_quantities: tuple[str, ...] = ()
    energy_scale: EnergyScale | None = None
    param_kernel: ParamKernelFactory | None = None
    param_values: ParamValues | None = None
    constant_params: tuple[str, ...] = ()


@dataclass(frozen=True)
class Assembly(Entry):
    """A builder of N-body arrangements (a networkx graph whose nodes carry bodies).

    ``build(**params) -> networkx.Graph``; node attributes and edge attributes are documented
    by the N-body plugin.
    """

    build: AssemblyBuilder = field(default=_missing)


@dataclass(frozen=True)
class SystemEntry(Entry):
    """A named Poisson structure or (conformally) Hamiltonian system, for ``poissonkit verify``.

    ``build(**params)`` returns a :class:`poissonkit.structure.Bivector` or a
    :class:`poissonkit.structure.HamiltonianSystem`. ``tags`` groups entries (``"lie-poisson"``,
    ``"nonholonomic"``, ...). ``claims`` are extra, system-specific statements that
    ``poissonkit verify`` checks after the generic ones: callables
    ``claim(built) -> (holds: bool, detail: str, method: str)`` whose docstring's first line
    names the claim (e.g. a decomposition of the field, or a Poisson map to e(3)).
    """

    build: SystemBuilder = field(default=_missing)
    tags: tuple[str, ...] = ()
    claims: tuple[Claim, ...] = ()


@dataclass(frozen=True)
class IntegratorOption:
    """One option of an integrator, as data (:meth:`IntegratorEntry.options`).

    Attributes
    ----------
    name, type, default, doc, unit
        As the entry's :class:`Param` declares them (``type``: ``"float"``, ``"int"``,
        ``"str"``, ``"bool"`` or ``"vector"``; ``default`` ``None``: required).
    choices
        The allowed values, or ``()`` when any value of the type is allowed.
    """

    name: str
    type: str
    default: Any
    doc: str
    unit: str = ""
    choices: tuple[Any, ...] = ()


@dataclass(frozen=True)
class IntegratorEntry(Entry):
    """A time integrator. ``factory(**params)`` returns an object following the integrator
    contract (:class:`poissonkit.contracts.Integrator`). ``order`` is the classical order (0 if
    adaptive with variable order); ``family`` is e.g. ``"splitting"``, ``"implicit"``,
    ``"scipy"``; ``capabilities`` declares what it can do (:class:`Capabilities`), which
    :func:`~poissonkit.numerics.solve` checks before it runs. ``choices`` maps an option
    (a name of :attr:`params`) to its allowed values; :meth:`options` lists the options as
    data (for scenes, the command line and the docs)."""

    factory: Callable[..., Any] = field(default=_missing)
    order: int = 0
    family: str = ""
    capabilities: Capabilities = field(default_factory=Capabilities)
    choices: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        names = {p.name for p in self.params}
        for key in self.choices:
            if key not in names:
                raise InputError(f"integrator {self.name!r}: choices for {key!r}, which is not "
                                 f"one of its options ({', '.join(sorted(names)) or 'none'})")

    def options(self) -> tuple[IntegratorOption, ...]:
        """Every option with its type, default, doc, unit and allowed values."""
        return tuple(IntegratorOption(p.name, p.type, p.default, p.doc, p.unit,
                                      tuple(self.choices.get(p.name, ())))
                     for p in self.params)

    def resolve_params(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """:meth:`Entry.resolve_params` (unknown names raise
        :class:`~poissonkit.errors.UnknownNameError` listing the valid options), then each value
        with declared choices must be one of them (:class:`~poissonkit.errors.InputError`)."""
        out = super().resolve_params(given)
        for key, allowed in self.choices.items():
            if key in given and out[key] not in allowed:
                raise InputError(f"{self.name}: option {key!r} must be one of "
                                 f"{', '.join(map(repr, allowed))}; got {given[key]!r}")
        return out


@dataclass(frozen=True)
class SceneEntry(Entry):
    """A built-in scene, runnable by name (``poissonkit run NAME``).

    ``load(**params)`` returns either a :class:`poissonkit.scene.Scene` (e.g.
    ``load_scene(path)`` of a TOML file shipped with the plugin) or a ready
    :class:`poissonkit.numerics.runspec.RunSpec`. Run options the entry declares in
    :attr:`params` (``method``, ``step`` [s], ``tol``, ``periods``, ``duration`` [s], or
    scene-specific ones such as ``tilt``) are handed to ``load``; the others are applied to
    the run it returns. ``default`` marks the scene ``poissonkit run`` uses without an argument
    (the first one flagged, built-in plugins first). ``sweep(**options)``, if given, returns the
    scene's sweep adapter for ``poissonkit sweep NAME`` (an object with ``key``, ``settings``,
    ``check``, ``units``, ``prepare`` and ``run``; see :mod:`poissonkit.sweeps.targets`).
    ``outcome(spec, t, y, events)``, if given, says what a finished run came to (e.g. the
    Levitron's fate): a JSON-ready mapping with at least ``"message"`` (one line), for the run's
    summary (``outcome``) and its printed report.
    """

    load: SceneLoader = field(default=_missing)
    default: bool = False
    sweep: SweepFactory | None = None
    outcome: SceneOutcome | None = None


@dataclass(frozen=True)
class ModelFamily(Entry):
    """Pair potentials that model the same physical pair at several fidelities.

    The planner (:mod:`poissonkit.scene.planner.choice`) and ``pair_interaction(\"auto\", ...)``
    pick per pair the cheapest model of the family whose estimated error is within a tolerance.

    Attributes
    ----------
    models
        Registered pair-potential names, cheapest first.
    costs
        Relative cost of one evaluation of each model (same order, non-decreasing); models of
        equal cost are ranked by accuracy. Empty: strictly increasing in the order given.
    defaults
        The models the planner uses when a scene does not list its own (empty: all).
    estimate
        ``estimate(model, r, body1, body2) -> float``: estimated worst-case relative force
        error of ``model`` for two bodies (attribute mappings) at centre distance ``r``;
        ``inf`` where the model is not trusted. It must not increase with ``r``.
    applies
        ``applies(body1, body2) -> bool``: the family models this pair.
    reads
        The body attributes ``estimate`` reads; two pairs that agree on them share cached
        thresholds, and ``pair_interaction("auto")`` requires them of both bodies.
    energy_bound
        ``energy_bound(r, body1, body2) -> float``: a bound on ``|U|`` [J] of the pair at
        distance ``r`` in any orientation, so that pairs beyond a cutoff can be dropped; ``None``
        if the family has none (its pairs are then never dropped).
    """

    models: tuple[str, ...] = ()
    costs: tuple[float, ...] = ()
    defaults: tuple[str, ...] = ()
    estimate: ErrorEstimator = field(default=lambda model, r, body1, body2: math.inf)
    applies: PairPredicate = field(default=lambda body1, body2: False)
    reads: tuple[str, ...] = ()
    energy_bound: EnergyBound | None = None

    def cost(self, model: str) -> float:
        """Relative cost of ``model`` (its index when no costs are given)."""
        k = self.models.index(model)
        return float(self.costs[k]) if self.costs else float(k)


@dataclass(frozen=True)
class OutcomeEntry(Entry):
    """A sweep outcome: what one run of a sweep is reduced to (``poissonkit sweep --outcomes``).

    Attributes
    ----------
    dtype
        numpy dtype of the dataset variable (``"f8"``, ``"i1"``, ...).
    unit
        SI unit of the values (``"1"`` for dimensionless).
    fill
        Value of points not (yet) computed or failed.
    compute
        ``compute(record) -> value`` of one finished run, a
        :class:`poissonkit.sweeps.targets.RunRecord` (solution, fate, distances, units).
    """

    dtype: str = "f8"
    unit: str = "1"
    fill: Any = math.nan
    compute: OutcomeFunction = field(default=lambda record: math.nan)

    @property
    def description(self) -> str:
        """The one-line doc string (the dataset variable's ``long_name``)."""
        return self.doc

    @property
    def units(self) -> str:
        """Same as :attr:`unit` (the dataset's attribute name)."""
        return self.unit


@dataclass(frozen=True)
class ExternalField(Entry):
    """An external field: a one-body energy ``U(r, ν; params)`` acting on every body that has
    the attribute :attr:`reads` (see ``docs/fields.md``).

    Plugins contribute energies, never forces: the numerics take ``F = −∂U/∂r`` and the torque
    ``ṁ = ∂U/∂ν × ν`` from the partials the compiled kernel returns, so the kick stays the exact
    flow of the potential and energy and Casimirs are kept as for pair potentials
    (:mod:`poissonkit.conventions`).

    Attributes
    ----------
    reads
        The body attribute the energy is proportional to (its *coupling*): ``"mass"`` for
        gravity, ``"moment"`` [A m²] for a magnetic field, or any attribute a pair potential
        declares. A body without it does not feel the field.
    orientation
        True if ``U`` depends on the body's axis ``ν`` (then every body that reads the field
        must be a top).
    build
        ``build(params, request, source) -> CompiledField``
        (:class:`poissonkit.numerics.fields.CompiledField`): the compiled SI kernel
        ``f(x, y, z, ν_x, ν_y, ν_z, c, P) -> (U, U_x, U_y, U_z, U_νx, U_νy, U_νz)`` (``c`` the
        body's coupling, ``P`` a float array of the field's data) and its data, for the
        resolved ``params`` and a :class:`poissonkit.numerics.fields.FieldRequest` (the region
        the scene needs and the tolerance of a tabulated field). ``source`` is the Python object
        given instead of a name (e.g. a magpylib source), else ``None``.
    accepts
        Optional ``accepts(source) -> bool``: this entry builds fields from such Python objects
        (``pk.field(obj)``).
    tables
        Names of parameters whose value is a table of numbers (``params`` of a magpylib
        source, whose keys the entry checks itself): a mapping of names to numbers or (nested)
        lists of numbers.
    """

    reads: str = "mass"
    orientation: bool = False
    build: FieldBuilder = field(default=_missing)
    accepts: SourcePredicate | None = None
    tables: tuple[str, ...] = ()

    def resolve_params(self, given: Mapping[str, Any]) -> dict[str, Any]:
        """As :meth:`Entry.resolve_params`, with :attr:`tables` checked as tables of numbers."""
        plain = {k: v for k, v in given.items() if k not in self.tables}
        out = super().resolve_params(plain)
        for key in self.tables:
            if key in given:
                out[key] = _number_table(given[key], f"{self.name}: parameter {key!r}")
        return out


def _number_table(value: Any, where: str) -> dict[str, Any]:
    """A mapping of names to finite numbers or (nested) lists of them, else InputError."""
    if not isinstance(value, Mapping):
        raise InputError(f"{where} must be a table of numbers, got {value!r}")

    def item(v: Any, path: str) -> Any:
        if isinstance(v, (list, tuple)):
            if not v:
                raise InputError(f"{path} must not be an empty list")
            return [item(x, f"{path}[{k}]") for k, x in enumerate(v)]
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise InputError(f"{path} must be a number or a list of numbers, got {v!r}")
        x = float(v)
        if not math.isfinite(x):
            raise InputError(f"{path} must be finite, got {v!r}")
        return x

    return {str(k): item(v, f"{where}.{k}") for k, v in value.items()}


__all__ = ["Assembly", "Capabilities", "Entry", "ExternalField", "FieldBuilder", "IntegratorEntry",
           "ModelFamily", "OutcomeEntry", "PairFunction", "PairPotential", "Param", "SceneEntry",
           "SceneLoader", "SceneOutcome", "SystemBuilder", "SystemEntry"]
