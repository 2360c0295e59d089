"""Typed exceptions of poissonkit.

Every error poissonkit raises on purpose is a subclass of :class:`PoissonkitError`, so a caller
can catch all of them with one ``except`` clause. Where a built-in exception type is the natural
one (``ValueError`` for bad values, ``KeyError`` for unknown names) the poissonkit error also
derives from it, so generic handlers keep working.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # annotations only: the errors stay importable without numpy
    import numpy as np


class PoissonkitError(Exception):
    """Base class of every error raised by poissonkit."""


def _detailed(message: str, detail: str) -> str:
    """``message``, followed by ``: detail`` when there is one."""
    return f"{message}: {detail}" if detail else message


class InputError(PoissonkitError, ValueError):
    """A value given by the user is malformed (wrong shape, not antisymmetric, not finite, ...)."""


class DimensionError(InputError):
    """Sizes of two objects that must agree do not (matrix vs coordinates, state vs system)."""


class OverlapError(InputError):
    """Two bodies overlap, touch or sit at the same place, where the pair model is not defined
    (its forces are singular there)."""


class ParseError(InputError):
    """A string could not be parsed, or used a name outside the allow-list."""


class UnknownNameError(PoissonkitError, KeyError):
    """A registry entry, symbol or option was asked for by a name that does not exist.

    Parameters
    ----------
    kind
        What was looked up ("integrator", "potential", "symbol", ...).
    name
        The name that was asked for.
    available
        The names that do exist; they are listed in the message.
    """

    def __init__(self, kind: str, name: str, available: Iterable[str] = ()) -> None:
        self.kind = kind
        self.name = name
        self.available = sorted(available)
        msg = f"unknown {kind} {name!r}"
        if self.available:
            msg += "; available: " + ", ".join(self.available)
        super().__init__(msg)

    def __str__(self) -> str:  # KeyError would repr() the message
        return str(self.args[0])


class NotPoissonError(PoissonkitError):
    """A bivector required to be Poisson fails the Jacobi identity."""


class PluginError(PoissonkitError):
    """A plugin failed to load or returned a malformed contribution."""


class SceneError(InputError):
    """A scene file or scene description is invalid; the message names the offending field."""


@dataclass
class AbortState:
    """Where a compiled time loop stood when an error ended it: what a caller needs to keep
    the run's partial result (:attr:`IntegrationError.abort`).

    Attributes
    ----------
    held_rows
        The saved rows not yet handed to the trajectory stream, ``(t, y)`` (internal units).
    time_reached
        Internal time of the loop's state when it stopped.
    steps_done
        Steps taken when it stopped.
    bad_components
        Indices of the state's non-finite components (empty unless the state is not finite).
    body
        Name of the body at fault where the error knows it (e.g. the body that left a
        tabulated field's region), else ``None``.
    """

    held_rows: tuple[np.ndarray, np.ndarray]
    time_reached: float
    steps_done: int
    bad_components: list[int] = field(default_factory=list)
    body: str | None = None


class IntegrationError(PoissonkitError):
    """Numerical integration failed (non-finite state, step-size underflow, ...).

    Attributes
    ----------
    abort
        Where the loop stood when the error ended it (:class:`AbortState`); set by the compiled
        loops' driver as the error leaves it, ``None`` for an error raised elsewhere.
    """

    abort: AbortState | None = None


class InterruptedRun(KeyboardInterrupt):
    """A second Ctrl-C ended a compiled time loop (a :class:`KeyboardInterrupt`, so handlers of
    those still catch it), with where the loop stood.

    Attributes
    ----------
    abort
        Where the loop stood (:class:`AbortState`).
    """

    def __init__(self, abort: AbortState) -> None:
        self.abort = abort
        super().__init__()


class NonFiniteStateError(IntegrationError):
    """The state became NaN or infinite.

    Attributes
    ----------
    step
        Index of the step whose result was not finite.
    time
        Time at the start of that step.
    """

    def __init__(self, step: int, time: float, detail: str = "") -> None:
        self.step = step
        self.time = time
        super().__init__(_detailed(f"non-finite state produced at step {step} (t = {time:.6g})",
                                   detail))


class StepLimitReached(IntegrationError):
    """A run reached its step limit (``--max-steps`` / ``run.max_steps``) before its end time:
    a run whose step count is not known up front (adaptive steps) is cut there.

    Attributes
    ----------
    limit
        The step limit.
    time
        The (internal) time reached.
    """

    def __init__(self, limit: int, time: float, t_end: float) -> None:
        self.limit = limit
        self.time = time
        super().__init__(f"stopped at the step limit max_steps = {limit} (t = {time:.6g} of "
                         f"t = {t_end:.6g}): raise --max-steps / run.max_steps to go further")


class EventTerminated(PoissonkitError):
    """Base class of typed terminal events raised when the user asked events to be errors."""


class CollisionError(EventTerminated):
    """Two bodies overlapped during integration."""


class EscapeError(EventTerminated):
    """A body escaped beyond the configured radius."""


class MissingDependencyError(PoissonkitError, ImportError):
    """An optional dependency is needed for this feature; the message gives the install hint."""


class CapabilityError(InputError):
    """A run asks an integrator for something it cannot do (checkpoints from an adaptive scipy
    method, located events from a method without them, a system it cannot integrate).

    Attributes
    ----------
    method
        The integrator's name.
    capability
        The capability it lacks (a field of
        :class:`~poissonkit.plugin.contributions.Capabilities`).
    """

    def __init__(self, method: str, capability: str, detail: str = "") -> None:
        self.method = method
        self.capability = capability
        super().__init__(_detailed(f"{method} cannot do {capability!r}", detail))


class UnknownEntryError(UnknownNameError):
    """A registry entry was asked for by a name no loaded plugin provides.

    When plugins failed to load, the entry may be one of theirs: the message names them and
    their errors, and points to ``poissonkit plugins``.

    Parameters
    ----------
    kind, name, available
        As for :class:`UnknownNameError`.
    failed
        ``(plugin name, error)`` of every plugin that failed to load.
    """

    def __init__(self, kind: str, name: str, available: Iterable[str] = (),
                 failed: Iterable[tuple[str, str]] = ()) -> None:
        super().__init__(kind, name, available)
        self.failed = list(failed)
        if self.failed:
            notes = "; ".join(f"plugin {p!r} failed to load: {e}" for p, e in self.failed)
            self.args = (f"{self.args[0]} ({notes}; see `poissonkit plugins`)",)


class MissingStepError(InputError):
    """A fixed-step method was called without a step.

    Attributes
    ----------
    method
        The integrator's name.
    """

    def __init__(self, method: str, message: str) -> None:
        self.method = method
        super().__init__(message)
