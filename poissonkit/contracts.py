"""The contracts between poissonkit's layers, as :class:`typing.Protocol` classes.

Each concept that one layer hands to another (a numerics system, its compiled kernels, an
integrator, a sweep scene, a model family) is declared here once. Code that dispatches on a
contract uses ``isinstance`` with a ``runtime_checkable`` protocol, never ``hasattr`` probes;
what an integrator *can* do (checkpoint, stream, events, ...) is declared on its registry entry
(:class:`poissonkit.plugin.contributions.IntegratorEntry`), not discovered.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Protocol, runtime_checkable

if TYPE_CHECKING:
    from poissonkit.sweeps.scenes import RunRecord

# --------------------------------------------------------------------------- numerics systems

# --------------------------------------------------------------------------- integrators

# --------------------------------------------------------------------------- model families

# --------------------------------------------------------------------------- sweep scenes


@runtime_checkable
class SweepScene(Protocol):
    """What a sweep runs: a small picklable description of a scene, sent to every worker.

    :func:`poissonkit.sweeps.sweep` accepts any object with these members (a TOML scene,
    :class:`poissonkit.sweeps.scenes.TomlScene`, or a plugin's, e.g. the ``sweep`` factory of a
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
