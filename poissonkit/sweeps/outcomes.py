"""The outcome registry: what one run is reduced to in a sweep.

Every entry (:class:`~poissonkit.plugin.contributions.OutcomeEntry`) has a name, a numpy dtype,
SI units, a fill value for points not computed, a description, and a function of the
:class:`~poissonkit.sweeps.targets.RunRecord`. Entries come from the plugin hook
``poissonkit_outcomes``: the built-in ones below are registered through it
(:mod:`poissonkit.sweeps.hooks`) like any plugin's. Choose them with
``sweep(..., outcomes=[...])`` or ``poissonkit sweep --outcomes a,b``; unknown names fail with the
list of available ones. Drifts are the maxima over the run of the relative diagnostics of
:mod:`poissonkit.numerics.diagnostics`, under the same names as in ``summary.json``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Mapping

import numpy as np

from poissonkit.contracts import HasMomenta
from poissonkit.errors import UnknownNameError
from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.sweeps.targets import FATES, RunRecord
from poissonkit.traits import offers


#: A registered outcome (the registry entry type; ``description`` and ``units`` read its
#: ``doc`` and ``unit``).
Outcome = OutcomeEntry


def _outcome(name: str, dtype: str, unit: str, fill: object, doc: str,
             compute: Callable[[RunRecord], object]) -> OutcomeEntry:
    return OutcomeEntry(name=name, doc=doc, dtype=dtype, unit=unit, fill=fill, compute=compute)


def _max(a: np.ndarray) -> float:
    a = np.asarray(a, dtype=float)
    return float(np.max(a)) if a.size else math.nan


def _final_angular_momentum(rec: RunRecord) -> float:
    sys = rec.solution.system
    if not offers(sys, HasMomenta):
        return math.nan
    j = np.asarray(sys.angular_momentum(np.asarray(rec.solution.y)[-1:]), dtype=float)
    return float(np.linalg.norm(j)) * rec.angular_momentum_unit


def _left_regime(rec: RunRecord) -> int:
    """1 when the integrator reported leaving its regime (``Solution.extra["status"]``)."""
    from poissonkit.numerics.integrators.base import LEFT_REGIME

    return int(rec.solution.extra.get("status") == LEFT_REGIME)


def _megno(rec: RunRecord) -> float:
    from poissonkit.sweeps.chaos import megno

    system, y0, t_end, method, step = rec.megno_inputs
    if not t_end > 0:
        return math.nan
    return megno(system, y0, t_end, method=method, step=step)


#: The built-in outcomes (registered by :mod:`poissonkit.sweeps.hooks`).
BUILTIN_OUTCOMES: tuple[OutcomeEntry, ...] = (
    _outcome("fate", "i1", "1", -1,
             "fate of the run: 0 bounded, 1 collision, 2 escape (-1 not computed)",
             lambda r: FATES.index(r.fate)),
    _outcome("fate_time", "f8", "s", math.nan,
             "time of the collision or escape (nan if bounded)", lambda r: r.fate_time),
    _outcome("end_time", "f8", "s", math.nan, "time the run reached (the event time if one fired)",
             lambda r: float(np.asarray(r.solution.t)[-1]) * r.time_unit),
    _outcome("min_distance", "f8", "m", math.nan,
             "smallest centre distance between two bodies during the run",
             lambda r: float(np.min(r.distance)) if len(r.distance) else math.nan),
    _outcome("max_rel_energy_error", "f8", "1", math.nan,
             "largest relative energy error |H(t) - H(0)| / |H(0)|",
             lambda r: _max(r.solution.energy_error())),
    _outcome("max_rel_casimir_drift", "f8", "1", math.nan,
             "largest relative Casimir drift max_k |C_k(t) - C_k(0)| / s_k (|nu|^2 -> 1, "
             "nu.m -> |m| of every top)",
             lambda r: _max(r.solution.casimir_drift())),
    _outcome("max_rel_angular_momentum_drift", "f8", "1", math.nan,
             "largest drift of the total angular momentum |j(t) - j(0)| / "
             "(sum |r_i x p_i| + sum |m_k| at t = 0)",
             lambda r: _max(r.solution.angular_momentum_drift())),
    _outcome("final_energy", "f8", "J", math.nan, "total energy at the end of the run",
             lambda r: float(np.asarray(r.solution.energy())[-1]) * r.energy_unit),
    _outcome("final_angular_momentum", "f8", "kg m^2/s", math.nan,
             "|total angular momentum| at the end of the run", _final_angular_momentum),
    _outcome("left_regime", "i1", "1", -1,
             "1 if the integrator reported that the run left its method's regime (e.g. "
             "Wisdom-Holman: a pericentre passage the step does not resolve), 0 if not, "
             "-1 not computed", _left_regime),
    _outcome("megno", "f8", "1", math.nan,
             "mean MEGNO <Y> from two nearby runs (about 2 regular, grows when chaotic)", _megno),
)



class _Registry(Mapping[str, OutcomeEntry]):
    """Every registered outcome by name (read from the plugin registry at each use)."""

    def _entries(self) -> dict[str, OutcomeEntry]:
        from poissonkit.plugin.manager import entries

        return {k: v for k, v in entries("outcome").items() if isinstance(v, OutcomeEntry)}

    def __getitem__(self, name: str) -> OutcomeEntry:
        return self._entries()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries())

    def __len__(self) -> int:
        return len(self._entries())


#: Every registered outcome by name (built-in and from plugins).
OUTCOMES: Mapping[str, OutcomeEntry] = _Registry()

#: Outcomes computed when none are chosen: the built-in ones but MEGNO (it doubles the cost).
DEFAULT_OUTCOMES: tuple[str, ...] = tuple(o.name for o in BUILTIN_OUTCOMES if o.name != "megno")


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


def outcome_entries(names: Iterable[str]) -> tuple[OutcomeEntry, ...]:
    """The registry entries of validated names (sent to the workers with each batch, so a
    plugin's outcome works on workers where that plugin is not installed as an entry point)."""
    found = dict(OUTCOMES)
    return tuple(found[n] for n in names)


def reduce_run(rec: RunRecord, names: Iterable[str | OutcomeEntry]) -> dict[str, object]:
    """Every chosen outcome of one run (by name or entry); an outcome that raises raises."""
    chosen = [n if isinstance(n, OutcomeEntry) else OUTCOMES[n] for n in names]
    return {o.name: o.compute(rec) for o in chosen}


def reduce_run_kept(rec: RunRecord, names: Iterable[str | OutcomeEntry]
                    ) -> tuple[dict[str, object], dict[str, str]]:
    """Every chosen outcome of one run, an outcome that raises recorded instead of raised.

    Returns
    -------
    values, errors
        ``values[name]`` for every outcome (its ``fill`` where it failed) and
        ``errors[name]`` = ``"ExceptionType: message"`` for each outcome that raised: one
        failing outcome (e.g. ``megno``) never discards the run's other outcomes (its fate).
    """
    values: dict[str, object] = {}
    errors: dict[str, str] = {}
    for n in names:
        o = n if isinstance(n, OutcomeEntry) else OUTCOMES[n]
        try:
            values[o.name] = o.compute(rec)
        except Exception as exc:  # noqa: BLE001 - any outcome's failure is recorded, not fatal
            values[o.name] = o.fill
            errors[o.name] = f"{type(exc).__name__}: {exc}"
    return values, errors
