"""The outcome registry: what one run is reduced to in a sweep.

Every entry has a name, a numpy dtype, SI units, a fill value for points not computed, a
description, and a function of the :class:`~poissonkit.sweeps.scenes.RunRecord`. Choose them with
``sweep(..., outcomes=[...])`` or ``poissonkit sweep --outcomes a,b``; unknown names fail with the
list of available ones. Drifts are the maxima over the run of the relative diagnostics of
:mod:`poissonkit.numerics.diagnostics`, under the same names as in ``summary.json``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from poissonkit.errors import UnknownNameError
from poissonkit.sweeps.scenes import FATES, RunRecord


@dataclass(frozen=True)
class Outcome:
    """A registered outcome.

    Attributes
    ----------
    name
        Variable name in the dataset.
    dtype
        numpy dtype of the variable.
    units
        SI units (``"1"`` for dimensionless).
    fill
        Value of points not (yet) computed or failed.
    description
        One line, stored as the variable's ``long_name``.
    compute
        ``RunRecord -> value``.
    """

    name: str
    dtype: str
    units: str
    fill: Any
    description: str
    compute: Callable[[RunRecord], Any]


def _max(a: np.ndarray) -> float:
    a = np.asarray(a, dtype=float)
    return float(np.max(a)) if a.size else math.nan


def _final_angular_momentum(rec: RunRecord) -> float:
    sys = rec.solution.system
    if not hasattr(sys, "angular_momentum"):
        return math.nan
    j = np.asarray(sys.angular_momentum(np.asarray(rec.solution.y)[-1:]), dtype=float)
    return float(np.linalg.norm(j)) * rec.angular_momentum_unit


def _megno(rec: RunRecord) -> float:
    from poissonkit.sweeps.chaos import megno

    system, y0, t_end, method, step = rec.megno_inputs
    if not t_end > 0:
        return math.nan
    return megno(system, y0, t_end, method=method, step=step)


_ENTRIES = (
    Outcome("fate", "i1", "1", -1,
            "fate of the run: 0 bounded, 1 collision, 2 escape (-1 not computed)",
            lambda r: FATES.index(r.fate)),
    Outcome("fate_time", "f8", "s", math.nan,
            "time of the collision or escape (nan if bounded)", lambda r: r.fate_time),
    Outcome("end_time", "f8", "s", math.nan, "time the run reached (the event time if one fired)",
            lambda r: float(np.asarray(r.solution.t)[-1]) * r.time_unit),
    Outcome("min_distance", "f8", "m", math.nan,
            "smallest centre distance between two bodies during the run",
            lambda r: float(np.min(r.distance)) if len(r.distance) else math.nan),
    Outcome("max_rel_energy_error", "f8", "1", math.nan,
            "largest relative energy error |H(t) - H(0)| / |H(0)|",
            lambda r: _max(r.solution.energy_error())),
    Outcome("max_rel_casimir_drift", "f8", "1", math.nan,
            "largest relative Casimir drift max_k |C_k(t) - C_k(0)| / s_k (|nu|^2 -> 1, "
            "nu.m -> |m| of every top)",
            lambda r: _max(r.solution.casimir_drift())),
    Outcome("max_rel_angular_momentum_drift", "f8", "1", math.nan,
            "largest drift of the total angular momentum |j(t) - j(0)| / "
            "(sum |r_i x p_i| + sum |m_k| at t = 0)",
            lambda r: _max(r.solution.angular_momentum_drift())),
    Outcome("final_energy", "f8", "J", math.nan, "total energy at the end of the run",
            lambda r: float(np.asarray(r.solution.energy())[-1]) * r.energy_unit),
    Outcome("final_angular_momentum", "f8", "kg m^2/s", math.nan,
            "|total angular momentum| at the end of the run", _final_angular_momentum),
    Outcome("megno", "f8", "1", math.nan,
            "mean MEGNO <Y> from two nearby runs (about 2 regular, grows when chaotic)", _megno),
)

#: Every outcome by name.
OUTCOMES: Mapping[str, Outcome] = {o.name: o for o in _ENTRIES}

#: Outcomes computed when none are chosen (MEGNO doubles the cost; ask for it).
DEFAULT_OUTCOMES: tuple[str, ...] = tuple(n for n in OUTCOMES if n != "megno")


def resolve_outcomes(names: Iterable[str] | str | None) -> tuple[str, ...]:
    """Validated outcome names (``fate`` always included, first).

    Raises
    ------
    UnknownNameError
        For a name not in :data:`OUTCOMES`, listing the available ones.
    """
    if names is None:
        return DEFAULT_OUTCOMES
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    out = ["fate"]
    for n in names:
        if n not in OUTCOMES:
            raise UnknownNameError("sweep outcome", n, OUTCOMES)
        if n not in out:
            out.append(n)
    return tuple(out)


def reduce_run(rec: RunRecord, names: Iterable[str]) -> dict[str, Any]:
    """Every chosen outcome of one run."""
    return {n: OUTCOMES[n].compute(rec) for n in names}
