"""The contracts between poissonkit's layers, as :class:`typing.Protocol` classes.

Each concept that one layer hands to another (a numerics system, its compiled kernels, an
integrator, a sweep scene, a model family) is declared here once. Code that dispatches on a
contract uses ``isinstance`` with a ``runtime_checkable`` protocol, never ``hasattr`` probes;
what an integrator *can* do (checkpoint, stream, events, ...) is declared on its registry entry
(:class:`poissonkit.plugin.contributions.IntegratorEntry`), not discovered.
"""

from __future__ import annotations

# --------------------------------------------------------------------------- numerics systems

# --------------------------------------------------------------------------- integrators

# --------------------------------------------------------------------------- model families

# --------------------------------------------------------------------------- sweep scenes
