"""Diagnostics over a trajectory and the ``summary.json`` / ``trajectory.npz`` writers."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from poissonkit.contracts import (DeclaresNotConserved, HasBodies, HasBodyMomenta, HasEnergy,
                                  HasExternalFields)
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.diagnostics import QUANTITIES, Drift, drifts
from poissonkit.numerics.diagnostics import report as report_drifts
from poissonkit.traits import offers


@dataclass(frozen=True)
class Diagnostics:
    """Invariant errors along a trajectory (the saved times), as defined once in
    :mod:`poissonkit.numerics.diagnostics`.

    Attributes
    ----------
    t
        Saved times (internal units).
    drifts
        :class:`~poissonkit.numerics.diagnostics.Drift` of each quantity the system defines,
        keyed by name (``energy_error``, ``casimir_drift``, ``linear_momentum_drift``,
        ``angular_momentum_drift``).
    angular_momentum
        ``j(t)`` itself, shape ``(n, 3)`` (zeros for a system that is not made of bodies).
    energy_reference
        ``H(0)`` (internal units).
    overall
        Report entries over *all* saved states when the arrays hold only a thinned copy
        (streamed runs); :meth:`maxima` returns it then.
    """

    t: np.ndarray
    drifts: Mapping[str, Drift]
    angular_momentum: np.ndarray
    energy_reference: float = math.nan
    overall: Mapping[str, float | list[float]] | None = None

    def _relative(self, name: str) -> np.ndarray:
        found = self.drifts.get(name)
        return np.zeros(len(self.t)) if found is None else found.relative

    @property
    def energy_error(self) -> np.ndarray:
        """Relative energy error at each saved time."""
        return self._relative("energy_error")

    @property
    def casimir_drift(self) -> np.ndarray:
        """Relative Casimir drift at each saved time (0 without Casimirs)."""
        return self._relative("casimir_drift")

    @property
    def angular_momentum_drift(self) -> np.ndarray:
        """Relative angular-momentum drift at each saved time."""
        return self._relative("angular_momentum_drift")

    @property
    def linear_momentum_drift(self) -> np.ndarray:
        """Relative linear-momentum drift at each saved time."""
        return self._relative("linear_momentum_drift")

    def maxima(self) -> dict[str, float | list[float]]:
        """``max_abs_*``, ``max_rel_*`` and ``*_scale`` of each drift (what ``summary.json``
        reports)."""
        if self.overall is not None:
            return dict(self.overall)
        return report_drifts(self.drifts)


def diagnostics(system: HasEnergy, t: np.ndarray, y: np.ndarray) -> Diagnostics:
    """Invariant errors of the trajectory ``y`` (rows = saved states) of ``system``.

    Raises
    ------
    DimensionError
        If ``t`` and ``y`` do not match.
    InputError
        If the trajectory is empty or not finite.
    """
    t = np.asarray(t, dtype=float)
    y = np.atleast_2d(np.asarray(y, dtype=float))
    if y.shape[0] != t.shape[0]:
        raise DimensionError(f"{t.shape[0]} times but {y.shape[0]} states")
    if y.shape[0] == 0:
        raise InputError("empty trajectory")
    if not np.all(np.isfinite(y)):
        raise InputError("trajectory contains non-finite values")
    # one energy per row (each costs a force evaluation): H(0) is the first of them
    H = np.asarray(system.energy(y), dtype=float).reshape(-1)
    found = drifts(system, y, energies=H)
    if offers(system, HasBodyMomenta):
        j = np.asarray(system.angular_momentum(y), dtype=float).reshape(y.shape[0], 3)
    else:
        j = np.zeros((y.shape[0], 3))
    return Diagnostics(t=t, drifts=found, angular_momentum=j, energy_reference=float(H[0]))


def conserved_quantities(system: HasEnergy) -> dict[str, str]:
    """Which invariants the system really has: ``{name: reason}`` of those *not* conserved.

    Energy and the Casimirs are invariants of every autonomous Hamiltonian system here. Total
    linear and angular momentum are conserved only by a closed system: fixed bodies (or external
    fields, declared by a system attribute ``external_fields``:
    :class:`~poissonkit.contracts.HasExternalFields`) exert outside forces and torques. A system
    may declare ``not_conserved`` (a mapping name → reason) itself
    (:class:`~poissonkit.contracts.DeclaresNotConserved`).
    """
    declared = system.not_conserved if offers(system, DeclaresNotConserved) else None
    if declared is not None:
        return dict(declared)
    out: dict[str, str] = {}
    bodies = system.bodies if offers(system, HasBodies) else ()
    fixed = [b.name for b in bodies or () if b.fixed]
    external = system.external_fields if offers(system, HasExternalFields) else None
    reason = (f"fixed bodies ({', '.join(fixed)}) exert outside forces and torques" if fixed
              else "external fields act on the bodies" if external else None)
    if reason:
        out["linear_momentum"] = reason
        out["angular_momentum"] = reason
    if not offers(system, HasBodyMomenta):
        out.setdefault("linear_momentum", "the system does not define it")
        out.setdefault("angular_momentum", "the system does not define it")
    return out


#: How each relative figure of the summary was made (definitions: docs/numerics.md).
SCALES_NOTE = ("max_rel_* = max_abs_* / *_scale, scales taken at t = 0: energy |H(0)|; "
               "Casimirs the natural size of each (|ν|² → 1, (ν, m) → |m|; else |C(0)|); "
               "linear momentum the largest single-body |p_i|; angular momentum "
               "Σ|r_i × p_i| + Σ|m_k|; a scale exactly 0 is replaced by 1")


def invariant_report(system: HasEnergy, diag: Diagnostics) -> dict[str, object]:
    """The summary's invariant figures: ``energy_reference`` ``H(0)``, then for each invariant
    the system really has ``max_abs_*``, ``max_rel_*`` and ``*_scale``
    (:mod:`poissonkit.numerics.diagnostics`), a note on the scales, and the list of quantities
    left out, with why."""
    m = diag.maxima()
    skipped = conserved_quantities(system)
    out: dict[str, object] = {"energy_reference": diag.energy_reference}
    for name in QUANTITIES:
        if name.removesuffix("_drift") in skipped:
            continue
        for key in (f"max_abs_{name}", f"max_rel_{name}", f"{name}_scale"):
            if key in m:
                out[key] = m[key]
    out["drift_scales_note"] = SCALES_NOTE
    out["not_reported"] = skipped
    return out


def _combine(overall: dict[str, float | list[float]], part: Mapping[str, float | list[float]]
             ) -> None:
    """Fold one part's report entries into ``overall``: maxima grow, scales (all taken at the
    same first state) stay."""
    for k, v in part.items():
        if k.startswith("max_"):
            overall[k] = max(overall.get(k, 0.0), v)
        else:
            overall.setdefault(k, v)


def _rows_of(d: Diagnostics, rows: np.ndarray) -> Diagnostics:
    """``d`` at the saved states ``rows`` only."""
    found = {name: Drift(name, v.absolute[rows], v.relative[rows], v.scale)
             for name, v in d.drifts.items()}
    return Diagnostics(t=d.t[rows], drifts=found, angular_momentum=d.angular_momentum[rows],
                       energy_reference=d.energy_reference)


def streamed_diagnostics(system: HasEnergy, folder: str | Path, plot_rows: int = 20000
                         ) -> tuple[Diagnostics, np.ndarray, np.ndarray]:
    """Diagnostics of a streamed trajectory (``part-*.npz`` of
    :class:`~poissonkit.numerics.checkpoint.TrajectoryStream`), one part in memory at a time.

    Returns ``(diagnostics, t, y)`` where ``t, y`` (and the diagnostics' arrays) are every k-th
    saved row, at most ``plot_rows`` of them, plus the last row; the maxima cover every row.
    """
    files = sorted(Path(folder).glob("part-*.npz"))
    if not files:
        raise InputError(f"no trajectory parts in {folder}")
    total = 0
    for f in files:
        with np.load(f, allow_pickle=False) as z:
            total += len(z["t"])
    every = max(1, math.ceil(total / plot_rows))
    first: np.ndarray | None = None
    overall: dict[str, float | list[float]] = {}
    keep_t: list[np.ndarray] = []
    keep_y: list[np.ndarray] = []
    kept: list[Diagnostics] = []  # the kept rows' diagnostics, cut from each part's
    offset = 0
    for f in files:
        with np.load(f, allow_pickle=False) as z:
            t, y = z["t"], z["y"]
        # each part's figures against the first state, which leads every part but the first
        lead = 0 if first is None else 1
        if first is None:
            first_t, first = t[:1], y[:1]
            d = diagnostics(system, t, y)
        else:
            d = diagnostics(system, np.concatenate([first_t, t]), np.vstack([first, y]))
        _combine(overall, d.maxima())
        sel = np.arange((-offset) % every, len(t), every)
        if offset + len(t) == total and (len(sel) == 0 or sel[-1] != len(t) - 1):
            sel = np.append(sel, len(t) - 1)  # the last row is always kept
        keep_t.append(t[sel])
        keep_y.append(y[sel])
        kept.append(_rows_of(d, sel + lead))
        offset += len(t)
    # the kept rows' figures are those computed above (every part is measured against the
    # same first state): no energy is evaluated twice
    found = {name: Drift(name, np.concatenate([k.drifts[name].absolute for k in kept]),
                         np.concatenate([k.drifts[name].relative for k in kept]),
                         kept[0].drifts[name].scale) for name in kept[0].drifts}
    t_all = np.concatenate(keep_t)
    d = Diagnostics(t=t_all, drifts=found,
                    angular_momentum=np.concatenate([k.angular_momentum for k in kept]),
                    energy_reference=kept[0].energy_reference, overall=overall)
    return d, t_all, np.concatenate(keep_y)


def _jsonable(x: object) -> object:
    if isinstance(x, Mapping):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, (np.floating, float)):
        v = float(x)
        return v if math.isfinite(v) else str(v)
    if isinstance(x, (np.integer, int, bool, str)) or x is None:
        return x.item() if isinstance(x, np.generic) else x
    return str(x)


def write_summary(path: str | Path, summary: Mapping[str, object]) -> Path:
    """Write ``summary`` as pretty JSON (numpy values converted, non-finite floats as strings),
    atomically."""
    from poissonkit.files.atomic import write_json

    return write_json(path, _jsonable(summary))


def write_trajectory(path: str | Path, t: np.ndarray, y: np.ndarray, *,
                     layout: tuple[str, ...] = (), time_unit: float = 1.0,
                     **extra: np.ndarray) -> Path:
    """Write ``t`` (internal), ``t_si`` (``t * time_unit``), ``y`` (rows), ``layout`` and any
    extra arrays to a compressed ``.npz``, atomically."""
    from poissonkit.files.atomic import atomic_path

    path = Path(path)
    t = np.asarray(t, dtype=float)
    with atomic_path(path) as tmp:
        arrays: dict[str, Any] = dict(t=t, t_si=t * float(time_unit),
                                      y=np.asarray(y, dtype=float),
                                      layout=np.array(layout, dtype=str), **extra)
        np.savez_compressed(tmp, **arrays)
    return path
