"""pluggy hook implementations of the nonholonomic plugin."""

from __future__ import annotations

from poissonkit.plugin.contributions import SystemEntry
from poissonkit.plugin.hookspecs import hookimpl


@hookimpl
def poissonkit_systems() -> list[SystemEntry]:
    """The systems of Borisov–Mamaev–Tsiganov's survey (tag ``"nonholonomic"``)."""
    from poissonkit_nonholonomic.systems import entries

    return entries()
