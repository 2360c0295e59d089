"""pluggy hook implementations of the magnets plugin."""

from __future__ import annotations

from poissonkit.plugin.hookspecs import hookimpl  # noqa: F401
