"""pluggy hook implementations of the nbody plugin."""

from __future__ import annotations

from poissonkit.plugin.hookspecs import hookimpl  # noqa: F401
