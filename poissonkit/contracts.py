"""The contracts between poissonkit's layers, as :class:`typing.Protocol` classes.

Each concept that one layer hands to another (a numerics system, its compiled kernels, an
integrator, a sweep scene, a model family) is declared here once. Code that dispatches on a
contract uses ``isinstance`` with a ``runtime_checkable`` protocol, never ``hasattr`` probes;
what an integrator *can* do (checkpoint, stream, events, ...) is declared on its registry entry
(:class:`poissonkit.plugin.contributions.IntegratorEntry`), not discovered.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, Union, runtime_checkable

import numpy as np

# Only for annotations: types that hold objects of their own implementation (RawResult: event
# records; Control: a checkpoint and a stream; Bivector: the symbolic algebra; RunRecord: a
# Solution and its system), so they cannot move here (tests/test_layers.py lists them).
if TYPE_CHECKING:
    import networkx as nx
    import sympy as sp

    from poissonkit.numerics.integrators.base import RawResult
    from poissonkit.numerics.integrators.driver import Control
    from poissonkit.structure import Bivector
    from poissonkit.sweeps.targets import RunRecord

# --------------------------------------------------------------------------- numerics systems
#: A compiled (numba) function; its signature is fixed by the slot it fills in
#: :class:`CompiledKernels` (see :mod:`poissonkit.numerics.kernels`). numba dispatchers are
#: dynamically typed, so their results are ``Any`` to a static checker.
CompiledFunction = Callable[..., Any]

#: The plain data every compiled kernel receives (floats and numpy arrays, in a system's order).
KernelData = tuple[object, ...]


@runtime_checkable
class CompiledKernels(Protocol):
    """The compiled functions of one system that the compiled time loops call.

    :class:`poissonkit.numerics.kernels.Kernels` is the built-in implementation; the signatures
    are listed in :mod:`poissonkit.numerics.kernels`. Optional kernels are ``None`` when absent:
    ``jac`` (Jacobian, for Newton iterations), ``forces`` (forces into the work arrays, returning
    the potential energy: Wisdom–Holman, the time-transformed splitting), and the compensated
    ``drift_compensated``/``kick_compensated``. ``splittable`` says whether ``drift``/``kick``
    are the exact kinetic and potential flows (else placeholders).
    """

    @property
    def rhs(self) -> CompiledFunction: ...
    @property
    def drift(self) -> CompiledFunction: ...
    @property
    def kick(self) -> CompiledFunction: ...
    @property
    def energy(self) -> CompiledFunction: ...
    @property
    def min_distance(self) -> CompiledFunction: ...
    @property
    def max_radius(self) -> CompiledFunction: ...
    @property
    def jac(self) -> CompiledFunction | None: ...
    @property
    def splittable(self) -> bool: ...
    @property
    def forces(self) -> CompiledFunction | None: ...
    @property
    def drift_compensated(self) -> CompiledFunction | None: ...
    @property
    def kick_compensated(self) -> CompiledFunction | None: ...


@runtime_checkable
class NumericsSystem(Protocol):
    """The core of a numerics system: what :func:`~poissonkit.numerics.solve`, a
    :class:`~poissonkit.numerics.Solution` and the scipy integrators need.

    ``dim`` is the state length; ``rhs(t, y)`` the vector field ``ẏ = P(y)∇H(y)``;
    ``energy(y)`` the Hamiltonian of one state or of rows of states. Everything else a system
    may offer is one of the small capability protocols below, checked with ``isinstance``.
    """

    @property
    def dim(self) -> int: ...

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray: ...

    def energy(self, y: np.ndarray) -> float | np.ndarray: ...


@runtime_checkable
class HasCompiledKernels(Protocol):
    """Compiled kernels, their data and scratch arrays: the compiled time loops need these.

    (Under Python 3.11, ``isinstance`` evaluates the ``kernels`` property, which may compile:
    check it where the kernels are about to be used anyway.)
    """

    @property
    def kernels(self) -> CompiledKernels: ...

    @property
    def data(self) -> KernelData: ...

    def work(self) -> tuple[np.ndarray, ...]: ...


@runtime_checkable
class HasLayout(Protocol):
    """Names of the state's components, in order (``top1.nu_x``...)."""

    @property
    def layout(self) -> tuple[str, ...]: ...


@runtime_checkable
class HasStateCheck(Protocol):
    """``check_state(y)``: raise a typed error for a state the system cannot integrate
    (non-unit axis, coincident bodies)."""

    def check_state(self, y: np.ndarray, tol: float = ...) -> None: ...


@runtime_checkable
class HasOverlapCheck(Protocol):
    """``check_overlap(y)``: raise :class:`~poissonkit.numerics.nbody.OverlapError` if two
    bodies coincide (singular forces whatever the method)."""

    def check_overlap(self, y: np.ndarray) -> None: ...


@runtime_checkable
class HasCasimirs(Protocol):
    """Casimir functions of the bracket, one column per Casimir (``casimirs(rows)``)."""

    def casimirs(self, y: np.ndarray) -> np.ndarray: ...


@runtime_checkable
class HasCasimirScales(Protocol):
    """Natural scale of each Casimir at a state, to make drifts relative."""

    def casimir_scales(self, y: np.ndarray) -> np.ndarray: ...


@runtime_checkable
class HasIntegrals(Protocol):
    """Further first integrals declared by the system (columns, like :class:`HasCasimirs`)."""

    def integrals(self, y: np.ndarray) -> np.ndarray: ...


@runtime_checkable
class HasMomenta(Protocol):
    """Total linear and angular momentum (3 components per state)."""

    def linear_momentum(self, y: np.ndarray) -> np.ndarray: ...

    def angular_momentum(self, y: np.ndarray) -> np.ndarray: ...


@runtime_checkable
class HasEnergy(Protocol):
    """A Hamiltonian: ``energy(rows)`` gives one value per row (a float for one state).

    The least a system needs for the run diagnostics (:mod:`poissonkit.numerics.diagnostics`).
    """

    def energy(self, y: np.ndarray) -> float | np.ndarray: ...


@runtime_checkable
class HasBodyMomenta(HasMomenta, Protocol):
    """A system of bodies: total momenta of rows (:class:`HasMomenta`) and the per-body parts
    of a state, ``unpack(y)`` with at least ``r`` and ``p`` (one row per body, or one vector)
    and the spin angular momenta under keys ``m``, ``m1``, ``m2``, … (the momentum drift
    scales of :mod:`poissonkit.numerics.diagnostics` are made of them)."""

    def unpack(self, y: np.ndarray, *, si: bool = False) -> dict[str, np.ndarray]: ...


@runtime_checkable
class DeclaresNotConserved(Protocol):
    """A system that states which of the usual invariants it does *not* conserve, with why
    (``{"angular_momentum": "a rotor drives the ball"}``); ``None`` leaves it to the run
    summary's own rule (fixed bodies, external fields)."""

    @property
    def not_conserved(self) -> Mapping[str, str] | None: ...


@runtime_checkable
class DeclaresGravityOnly(Protocol):
    """A system that says whether Newtonian gravity over all its bodies is its only interaction
    (no other pair term, no cutoff, no external field): a hierarchical method may then use the
    gravity-only kick."""

    @property
    def gravity_only(self) -> bool: ...


@runtime_checkable
class HasExternalFields(Protocol):
    """A system acted on by external fields (truthy when it is): its total linear and angular
    momentum are not conserved."""

    @property
    def external_fields(self) -> object: ...


@runtime_checkable
class HasName(Protocol):
    """A name to show (a symbolic system's ``name``; may be empty)."""

    @property
    def name(self) -> str: ...


@runtime_checkable
class CompiledFrom(Protocol):
    """A compiled system that keeps the symbolic system it was compiled from."""

    @property
    def hamiltonian_system(self) -> object: ...


class SymbolicForm(NamedTuple):
    """``ẋ = N P ∇H`` of a compiled system with its parameter values substituted.

    What :meth:`HasSymbolicForm.symbolic_form` returns (also importable from
    :mod:`poissonkit.numerics.system`, where :class:`~poissonkit.numerics.system.CompiledSystem`
    builds it).

    Attributes
    ----------
    coords
        Coordinate symbols in state order.
    hamiltonian, multiplier
        ``H`` and ``N`` (sympy expressions in ``coords`` only).
    structure
        The bivector's matrix ``P`` (sympy, in ``coords`` only).
    key
        Cache key of the compiled system's generated sources (derived kernels extend it).
    """

    coords: tuple[sp.Symbol, ...]
    hamiltonian: sp.Expr
    multiplier: sp.Expr
    structure: sp.Matrix
    key: str


@runtime_checkable
class HasSymbolicForm(Protocol):
    """A compiled system that hands out its symbolic ``ẋ = N P ∇H`` with parameter values
    substituted (``symbolic_form()``: coordinates, ``H``, ``N``, ``P`` and a cache key), for
    integrators that need the bracket and the Hamiltonian separately (discrete gradients)."""

    def symbolic_form(self) -> SymbolicForm: ...


@runtime_checkable
class HasPoissonStructure(Protocol):
    """A numerics system that hands out its symbolic Poisson structure in state order
    (``to_structure()``: a :class:`~poissonkit.structure.Bivector` whose coordinates are the
    state's, in internal units), e.g. for the linearisation on the Poisson manifold."""

    def to_structure(self) -> Bivector: ...


@runtime_checkable
class HasJacobian(Protocol):
    """``jacobian(t, y)``: the matrix ``∂ẏ/∂y`` (implicit scipy methods use it)."""

    def jacobian(self, t: float, y: np.ndarray) -> np.ndarray: ...


@runtime_checkable
class HasUnpack(Protocol):
    """``unpack(y)``: the state's named blocks (``r``, ``p``, ``nu1``...), optionally in SI."""

    def unpack(self, y: np.ndarray, *, si: bool = False) -> dict[str, np.ndarray]: ...


@runtime_checkable
class HasScales(Protocol):
    """Internal units (:class:`~poissonkit.numerics.units.Units`), or ``None`` if SI."""

    @property
    def scales(self) -> object | None: ...


class Body(Protocol):
    """What the numerics read of one body of a system with bodies."""

    @property
    def name(self) -> str: ...

    @property
    def fixed(self) -> bool: ...


@runtime_checkable
class HasBodies(Protocol):
    """Named bodies in the state: the N-body form (``bodies``, ``n_moving`` bodies that move,
    ``n_tops`` of them oriented); the two-body centre-of-mass form has none."""

    @property
    def bodies(self) -> Sequence[Body]: ...

    @property
    def n_moving(self) -> int: ...

    @property
    def n_tops(self) -> int: ...


@runtime_checkable
class HasGravity(Protocol):
    """``gravity_constant()``: Newton's constant of the system's all-pairs gravity (internal
    units); raises a typed error when the system has none (hierarchical integrators)."""

    def gravity_constant(self) -> float: ...


class KineticSplit(NamedTuple):
    """The kinetic energy of a system of bodies, ``T = ½ Σ_k weights[k] y[momenta[k]]²``, and
    the layout of its forces kernel: ``"two_body"`` (relative position and momentum, two
    tops) or ``"bodies"`` (the N-body work arrays). What a time-transformed method needs to
    split a step into exact kinetic and potential flows."""

    layout: str
    momenta: np.ndarray
    weights: np.ndarray


@runtime_checkable
class HasKineticSplit(Protocol):
    """``kinetic_split()``: the system's :class:`KineticSplit`."""

    def kinetic_split(self) -> KineticSplit: ...


#: What :func:`~poissonkit.numerics.solve` accepts: a full numerics system, or a bare set of
#: compiled kernels (enough for the compiled time loops).
System = Union[NumericsSystem, HasCompiledKernels]

# --------------------------------------------------------------------------- integrators
@dataclass(frozen=True)
class Capabilities:
    """What an integrator can do, declared once (on its registry entry and on the object).

    :func:`~poissonkit.numerics.solve` reads it and refuses, before any work and with
    :class:`~poissonkit.errors.CapabilityError`, a run that asks for more. (Also importable
    from :mod:`poissonkit.plugin` and :mod:`poissonkit.plugin.contributions`.)

    Attributes
    ----------
    checkpoint
        Writes checkpoints and resumes from them, bit-identically to an uninterrupted run.
    stream
        Streams saved rows to disk while it runs (memory bounded). Without it a stream still
        works: ``solve`` writes the rows once the run is over.
    stop
        Honours a stop request between chunks of steps (a clean partial result). Without it the
        request is not looked at (the run goes to its end).
    events
        Terminal events (collision, contact, escape) stop the run where they happen.
    located_events
        Events are located inside the step to their time tolerance, including grazing
        encounters and the non-terminal :class:`~poissonkit.numerics.events.ClosestApproach`.
    adaptive
        Can choose its own step (from ``tol``, or a step-size rule among its options).
    point_masses_only
        Needs an N-body system of moving point masses (no tops, no fixed bodies).
    needs_kernels
        Needs a system with compiled kernels (``kernels``, ``data``, ``work()``).
    needs_splitting
        Needs kernels whose drift and kick are the exact kinetic and potential flows
        (``kernels.splittable``).
    """

    checkpoint: bool = False
    stream: bool = False
    stop: bool = False
    events: bool = False
    located_events: bool = False
    adaptive: bool = False
    point_masses_only: bool = False
    needs_kernels: bool = False
    needs_splitting: bool = False

    def names(self) -> tuple[str, ...]:
        """The names of the capabilities that are true (for listings)."""
        return tuple(f.name for f in fields(self) if getattr(self, f.name))


@runtime_checkable
class Event(Protocol):
    """An event of :mod:`poissonkit.numerics.events`: a continuous function ``value(system, y)``
    positive while nothing happens; ``terminal`` ones stop the run (or raise, with ``error``)."""

    @property
    def kind(self) -> str: ...

    @property
    def terminal(self) -> bool: ...

    @property
    def error(self) -> bool: ...

    def value(self, system: HasCompiledKernels, y: np.ndarray) -> float: ...


@runtime_checkable
class Integrator(Protocol):
    """A time integrator, as :func:`~poissonkit.numerics.solve` calls it.

    ``capabilities`` declares what it can do
    (:class:`~poissonkit.plugin.contributions.Capabilities`); ``solve`` refuses a run that asks
    for more, before any work, with :class:`~poissonkit.errors.CapabilityError`. ``control``
    (checkpoint, resume, stream, stop: :class:`~poissonkit.numerics.integrators.driver.Control`)
    is passed only when the capabilities say the integrator honours it; otherwise it is
    ``None``. ``integrate`` returns a :class:`~poissonkit.numerics.integrators.base.RawResult`.
    """

    @property
    def name(self) -> str: ...

    @property
    def order(self) -> int: ...

    @property
    def capabilities(self) -> Capabilities: ...

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *, step: float | None,
                  tol: float | None, events: Sequence[Event] = (), progress: bool = False,
                  save_every: int = 1, t0: float = 0.0, control: Control | None = None
                  ) -> RawResult: ...


@runtime_checkable
class Trajectory(Protocol):
    """Saved times and states of a run: a :class:`~poissonkit.numerics.Solution` (rows of
    states) or another solver's result such as scipy's ``solve_ivp`` (columns)."""

    @property
    def t(self) -> np.ndarray: ...

    @property
    def y(self) -> np.ndarray: ...


@runtime_checkable
class HasRunCost(Protocol):
    """What a run cost: steps taken and seconds spent integrating (a
    :class:`~poissonkit.numerics.Solution` has both; scipy's results have neither)."""

    @property
    def steps(self) -> int: ...

    @property
    def wall_time(self) -> float: ...


class Solver(Protocol):
    """A solver as the work-precision sweeps call it (:func:`~poissonkit.numerics.solve`):
    ``solver(system, y0, t_end, method=..., step=... or tol=..., progress=False,
    save_every=...)``; further keywords are the solver's own."""

    def __call__(self, system: Any, y0: np.ndarray, t_end: float, /, **options: Any
                 ) -> Trajectory: ...

# --------------------------------------------------------------------------- model families


@runtime_checkable
class ErrorEstimator(Protocol):
    """A model family's error estimate (:attr:`poissonkit.plugin.ModelFamily.estimate`).

    ``estimator(model, r, body1, body2)``: estimated worst-case relative force error of the
    registered potential ``model`` for two bodies, given as attribute mappings (``radius``,
    ``length``, ``moment``, ... as the family declares in ``reads``), at centre distance
    ``r`` [m]; ``inf`` where the model is not trusted. Non-increasing in ``r``.
    """

    def __call__(self, model: str, r: float, body1: Mapping[str, Any],
                 body2: Mapping[str, Any]) -> float: ...


# --------------------------------------------------------------------------- registry callables
# The callables plugins put into registry entries (:mod:`poissonkit.plugin.contributions`).
# Builders and loaders take the entry's resolved ``params`` as keywords, whose names differ per
# entry, so their parameters stay ``...``; what they return is fixed.

#: ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``: a pair potential and its partials.
PairFunction = Callable[[float, float, float, float], tuple[float, float, float, float, float]]
#: ``f(r, c1, c2, c3, P)``: a :data:`PairFunction` reading run-time parameters from ``P``.
ParamPairFunction = Callable[[float, float, float, float, tuple[float, ...]],
                             tuple[float, float, float, float, float]]
#: ``expr(params) -> U``: the pair energy as a sympy expression in ``r, c1, c2, c3``.
SymbolicEnergy = Callable[[dict[str, Any]], "sp.Expr"]
#: ``kernel(params) -> f``: a compiled :data:`PairFunction` for resolved parameters.
KernelFactory = Callable[[dict[str, Any]], PairFunction]
#: ``evaluate(params) -> f``: a plain-float :data:`PairFunction` (no compilation).
EvaluatorFactory = Callable[[Mapping[str, Any]], PairFunction]
#: ``param_kernel(params) -> f``: a compiled :data:`ParamPairFunction`.
ParamKernelFactory = Callable[[Mapping[str, Any]], ParamPairFunction]
#: ``param_values(params) -> P``: the run-time values read by a :data:`ParamPairFunction`.
ParamValues = Callable[[Mapping[str, Any]], Sequence[float]]
#: ``complete_params(given) -> params``: parameters derived from per-body quantities.
ParamCompleter = Callable[[Mapping[str, Any]], dict[str, Any]]
#: ``build(**params) -> graph``: an N-body arrangement (an :class:`~poissonkit.plugin.Assembly`).
AssemblyBuilder = Callable[..., "nx.Graph"]
#: ``claim(built) -> (holds, detail, method)`` about what a :data:`SystemBuilder` returned.
Claim = Callable[[Any], tuple[bool, str, str]]
#: ``sweep(**options)``: the scene's :class:`SweepScene` adapter.
SweepFactory = Callable[..., "SweepScene"]
#: ``applies(body1, body2)``: a model family models this pair.
PairPredicate = Callable[[Mapping[str, Any], Mapping[str, Any]], bool]
#: ``energy_bound(r, body1, body2)``: a bound on ``|U|`` [J] at distance ``r``.
EnergyBound = Callable[[float, Mapping[str, Any], Mapping[str, Any]], float]
#: ``compute(record) -> value``: one sweep outcome of a finished run.
OutcomeFunction = Callable[["RunRecord"], object]
#: ``accepts(source)``: an external-field entry builds fields from this Python object.
SourcePredicate = Callable[[object], bool]


class BodyAttributes(Protocol):
    """What an ``energy_scale`` reads of a body of a scene
    (:class:`poissonkit.scene.bodies.BodyModel`): its attributes by name."""

    def attr(self, name: str) -> float | tuple[float, ...] | None: ...


class EnergyScale(Protocol):
    """``energy_scale(bodies, length) -> float or None``: the energy unit [J] of a scene of
    ``bodies`` whose length unit is ``length`` [m] (``None`` when it does not apply)."""

    def __call__(self, bodies: Sequence[BodyAttributes], length: float, /) -> float | None: ...


# --------------------------------------------------------------------------- sweep scenes


@runtime_checkable
class SweepScene(Protocol):
    """What a sweep runs: a small picklable description of a scene, sent to every worker.

    :func:`poissonkit.sweeps.sweep` accepts any object with these members (a TOML scene,
    :class:`poissonkit.sweeps.targets.TomlScene`, or a plugin's, e.g. the ``sweep`` factory of a
    :class:`~poissonkit.plugin.SceneEntry`).
    """

    @property
    def key(self) -> str:
        """Identifies what :meth:`prepare` builds: workers cache it under this key."""
        ...

    def settings(self) -> dict[str, object]:
        """Attributes recorded in the dataset (scene name, method, step, ...)."""
        ...

    def check(self, path: str) -> str:
        """Validate a swept parameter path (raise a typed error naming it); return it."""
        ...

    def units(self, path: str) -> str:
        """SI units of the values of a parameter path."""
        ...

    def prepare(self) -> Mapping[str, object]:
        """Build what every run shares (system, compiled kernels, units), once per worker."""
        ...

    def run(self, prep: Mapping[str, object], values: Mapping[str, float]) -> RunRecord:
        """Integrate one point (``values`` by path) and classify its fate."""
        ...
