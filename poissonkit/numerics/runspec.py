"""What a run needs, independent of where it came from (built-in scene, TOML file, Python)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from poissonkit.contracts import Event, System


@dataclass(frozen=True)
class RunSpec:
    """A ready-to-integrate problem.

    Parameters
    ----------
    name
        Scene name, for reports.
    system
        A numerics system (:class:`poissonkit.contracts.NumericsSystem`: ``dim``, ``rhs(t, y)``,
        ``energy(y)``, and the capability protocols it offers: compiled kernels, bodies,
        invariants...).
    y0
        Initial state in the system's (nondimensional) layout.
    t_end
        Duration, in the system's internal time unit.
    method
        Integrator registry name.
    step
        Fixed step for fixed-step methods (internal time unit), or ``None``.
    tol
        Tolerance for adaptive methods, or ``None``.
    metadata
        Anything reports should carry (SI parameters, derived quantities, time scale ...).
    events
        Events of the run (e.g. the geometric :class:`~poissonkit.numerics.events.Contact` of
        finite-size bodies, which scenes add by default).
    energy_tol
        Largest acceptable relative energy error ``max |ΔH|/|H(0)|``; ``poissonkit run`` warns
        and exits non-zero above it. ``None``: the run command's default.
    save_every
        Keep every ``save_every``-th step (a scene's ``run.save_every``); ``None``: every
        step unless the caller says otherwise (``--save-every``).
    max_steps
        Refuse a run of more fixed steps than this before it starts (a scene's
        ``run.max_steps``, :func:`poissonkit.numerics.workload.plan_run`); ``None``: no limit.
    save_dt
        Save the state at multiples of this interval (internal time unit) instead of every
        ``save_every``-th step (a scene's ``run.save_dt``; ``solve(t_eval=...)``).
    options
        The integrator's own options (a scene's ``[run.options]``, ``--option NAME=VALUE``;
        ``solve(options=...)``), checked against its registry entry.
    """

    name: str
    system: System
    y0: np.ndarray
    t_end: float
    method: str = "splitting6"
    step: float | None = None
    tol: float | None = None
    metadata: Mapping[str, Any] = field(default_factory=dict)
    events: tuple[Event, ...] = ()
    energy_tol: float | None = None
    save_every: int | None = None
    max_steps: int | None = None
    save_dt: float | None = None
    options: Mapping[str, Any] = field(default_factory=dict)
