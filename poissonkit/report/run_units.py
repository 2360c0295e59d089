"""What a run's system says about its units, its state layout and the two-body distance.

Small readers shared by ``poissonkit run`` (:mod:`poissonkit.commands.run`) and the writers of
its files (:mod:`poissonkit.report.run_output`): each looks at the system through a capability
protocol of :mod:`poissonkit.contracts` and has a neutral answer for a system without it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from poissonkit.contracts import HasBodies, HasLayout, HasScales, HasUnpack, Trajectory
from poissonkit.numerics.units import Scales
from poissonkit.traits import offers

if TYPE_CHECKING:
    from poissonkit.numerics.runspec import RunSpec


def scales_of(system: object) -> Scales | None:
    """The internal units of ``system`` (:class:`~poissonkit.contracts.HasScales`), ``None``
    for a system in SI units."""
    s = system.scales if offers(system, HasScales) else None
    return s if isinstance(s, Scales) else None


def layout_of(system: object) -> tuple[str, ...]:
    """Names of the state's components (:class:`~poissonkit.contracts.HasLayout`), or ()."""
    return tuple(system.layout) if offers(system, HasLayout) else ()


def time_unit(spec: RunSpec) -> float:
    """The SI value [s] of the run's internal time unit (1 for a run in SI units)."""
    sc = spec.metadata.get("scales") if spec.metadata else None
    if isinstance(sc, dict) and "time" in sc:
        return float(sc["time"])
    s = scales_of(spec.system)
    return float(s.time) if s is not None else 1.0


def trajectory_rows(sol: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """``(t, y)`` of a solution with ``y`` as rows (one state per saved time)."""
    t = np.asarray(sol.t, dtype=float)
    y = np.asarray(sol.y, dtype=float)
    if y.ndim == 2 and y.shape[0] != t.shape[0] and y.shape[1] == t.shape[0]:
        y = y.T
    return t, y


def relative_position(spec: RunSpec, y: np.ndarray) -> np.ndarray | None:
    """Relative position ``r_2 - r_1`` of a two-body run (internal units), or ``None``."""
    system = spec.system
    # bodies in the state (N-body form): the first two moving ones, or the first one
    n_moving = system.n_moving if offers(system, HasBodies) else 0
    if offers(system, HasUnpack) and n_moving == 2:
        r = system.unpack(y)["r"]
        diff: np.ndarray = r[:, 1] - r[:, 0]
        return diff
    if layout_of(system)[:3] and y.shape[1] == 18:  # the seed's centre-of-mass form
        rel: np.ndarray = y[:, 0:3]
        return rel
    if offers(system, HasUnpack) and n_moving >= 1:
        first: np.ndarray = system.unpack(y)["r"][:, 0]
        return first
    return None
