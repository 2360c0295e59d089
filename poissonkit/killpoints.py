"""Injected kill points; moved to :mod:`poissonkit.files.killpoints` (this path keeps working)."""

from poissonkit.files.killpoints import ENV, PHASES, kill_point

__all__ = ["ENV", "PHASES", "kill_point"]
