"""Built-in plugin registering poissonkit's own integrators (filled by the numerics layer)."""

from __future__ import annotations

from poissonkit.plugin.contributions import IntegratorEntry
from poissonkit.plugin.hookspecs import hookimpl


@hookimpl
def poissonkit_integrators() -> list[IntegratorEntry]:
    """poissonkit's integrators."""
    return []
