"""Built-in plugin: the sweep outcomes of :mod:`poissonkit.sweeps.outcomes`, registered through
the same hook (``poissonkit_outcomes``) a third-party plugin uses for its own."""

from __future__ import annotations

from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.plugin.hookspecs import hookimpl


@hookimpl
def poissonkit_outcomes() -> list[OutcomeEntry]:
    """The built-in sweep outcomes (fate, times, distances, drifts, MEGNO)."""
    from poissonkit.sweeps.outcomes import BUILTIN_OUTCOMES

    return list(BUILTIN_OUTCOMES)
