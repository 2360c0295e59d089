"""Injected kill points: a test hook that makes the process SIGKILL itself at a named phase.

Set ``POISSONKIT_KILL_AT=<phase>`` (the first time the phase is reached) or
``POISSONKIT_KILL_AT=<phase>@<n>`` (the ``n``-th time) and the process kills itself there with
SIGKILL (``os._exit(137)`` where there is no SIGKILL) — no cleanup, no ``finally``, as a kill
from outside at that instant would. Unset (the normal case) it costs one dictionary look-up.
The phases are listed in :data:`PHASES`; ``tests/reliability/test_kill_points.py`` kills a run
at each of them, resumes it and compares the trajectory with an uninterrupted run's.
"""

from __future__ import annotations

import os
import signal

ENV = "POISSONKIT_KILL_AT"

#: Every phase boundary of a streamed, checkpointed ``poissonkit run`` (in the order reached).
PHASES = (
    "part-tmp",            # a trajectory part's temporary file is written, not yet renamed
    "part-written",        # a part is in place, the checkpoint pointing past it not yet written
    "checkpoint-tmp",      # a checkpoint's temporary file is written, not yet renamed
    "checkpoint-written",  # a checkpoint is in place, older ones not yet pruned
    "truncate",            # resuming: one stale part (written after the checkpoint) removed
    "gather-tmp",          # the gathered trajectory.npz is half-written (temporary file)
    "gather-written",      # trajectory.npz is in place, summary.json not yet written
    "summary-written",     # summary.json is in place, trajectory.parts/ not yet removed
    "parts-removing",      # one part of trajectory.parts/ removed, the others not yet
)

_seen: dict[str, int] = {}


def kill_point(phase: str) -> None:
    """SIGKILL this process if ``POISSONKIT_KILL_AT`` names ``phase`` (see the module)."""
    target = os.environ.get(ENV)
    if not target:
        return
    name, _, nth = target.partition("@")
    if name != phase:
        return
    _seen[phase] = _seen.get(phase, 0) + 1
    if _seen[phase] == (int(nth) if nth else 1):
        if hasattr(signal, "SIGKILL"):
            os.kill(os.getpid(), signal.SIGKILL)
        os._exit(137)
