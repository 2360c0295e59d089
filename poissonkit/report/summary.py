"""Diagnostics over a trajectory and the ``summary.json`` / ``trajectory.npz`` writers."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from poissonkit.errors import DimensionError, InputError


@dataclass(frozen=True)
class Diagnostics:
    """Invariant errors along a trajectory (arrays over the saved times).

    Attributes
    ----------
    t
        Saved times (internal units).
    energy_error
        ``(H(t) - H(0)) / |H(0)|`` (absolute error if ``H(0) = 0``).
    casimir_drift
        ``max_k |C_k(t) - C_k(0)| / s_k`` with the natural size ``s_k`` of each Casimir
        (1 for ``|ν|²``, ``|m|`` for ``(ν, m)``) — 0 for systems without Casimirs.
    angular_momentum_drift
        ``|j(t) - j(0)| / |j(0)|`` (absolute ``|j(t) - j(0)|`` when ``j(0) = 0``).
    linear_momentum_drift
        ``|P(t) - P(0)|`` divided by the momentum scale ``max_t |p_i|`` (0 if not available).
    angular_momentum
        ``j(t)`` itself, shape ``(n, 3)``.
    energy_reference, angular_momentum_reference, linear_momentum_reference
        ``H(0)``, ``|j(0)|``, ``|P(0)|`` (internal units): absolute figure = relative × reference
        (when the reference is 0 the relative arrays hold the absolute error).
    linear_momentum_scale
        The momentum scale the linear drift is divided by.
    overall
        Maxima over *all* saved states when the arrays hold only a thinned copy (streamed runs);
        :meth:`maxima` returns it then.
    """

    t: np.ndarray
    energy_error: np.ndarray
    casimir_drift: np.ndarray
    angular_momentum_drift: np.ndarray
    linear_momentum_drift: np.ndarray
    angular_momentum: np.ndarray
    energy_reference: float = math.nan
    angular_momentum_reference: float = math.nan
    linear_momentum_reference: float = math.nan
    linear_momentum_scale: float = 1.0
    overall: Mapping[str, float] | None = None

    def maxima(self) -> dict[str, float]:
        """The largest value of each drift (what ``summary.json`` reports)."""
        if self.overall is not None:
            return dict(self.overall)
        return {
            "max_rel_energy_error": float(np.max(np.abs(self.energy_error))),
            "max_casimir_drift": float(np.max(self.casimir_drift)),
            "max_rel_angular_momentum_drift": float(np.max(self.angular_momentum_drift)),
            "max_linear_momentum_drift": float(np.max(self.linear_momentum_drift)),
        }


def diagnostics(system: Any, t: np.ndarray, y: np.ndarray) -> Diagnostics:
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
    H = np.asarray(system.energy(y), dtype=float).reshape(-1)
    if H.shape[0] != y.shape[0]:  # system.energy does not take rows
        H = np.array([float(system.energy(row)) for row in y])
    h0 = abs(H[0]) if H[0] != 0 else 1.0
    ee = (H - H[0]) / h0
    if hasattr(system, "casimirs"):
        C = np.asarray(system.casimirs(y), dtype=float).reshape(y.shape[0], -1)
        if C.shape[1]:
            sc = (np.asarray(system.casimir_scales(y[0]), dtype=float)
                  if hasattr(system, "casimir_scales") else np.ones(C.shape[1]))
            sc = np.where(sc > 0, sc, 1.0)
            cd = np.max(np.abs(C - C[0]) / sc, axis=1)
        else:
            cd = np.zeros(y.shape[0])
    else:
        cd = np.zeros(y.shape[0])
    j = np.asarray(system.angular_momentum(y), dtype=float).reshape(y.shape[0], 3)
    jn = np.linalg.norm(j[0]) or 1.0
    jd = np.linalg.norm(j - j[0], axis=1) / jn
    if hasattr(system, "linear_momentum"):
        P = np.asarray(system.linear_momentum(y), dtype=float).reshape(y.shape[0], 3)
        # natural scale: the largest single-body momentum at t = 0
        if hasattr(system, "unpack"):
            pscale = float(np.max(np.linalg.norm(system.unpack(y[0])["p"], axis=-1)))
        else:
            pscale = float(np.max(np.abs(y[0])))
        pscale = pscale if pscale > 0 else 1.0
        ld = np.linalg.norm(P - P[0], axis=1) / pscale
    else:
        ld = np.zeros(y.shape[0])
        P = np.zeros((y.shape[0], 3))
        pscale = 1.0
    return Diagnostics(t=t, energy_error=ee, casimir_drift=cd, angular_momentum_drift=jd,
                       linear_momentum_drift=ld, angular_momentum=j,
                       energy_reference=float(H[0]),
                       angular_momentum_reference=float(np.linalg.norm(j[0])),
                       linear_momentum_reference=float(np.linalg.norm(P[0])),
                       linear_momentum_scale=pscale)


def conserved_quantities(system: Any) -> dict[str, str]:
    """Which invariants the system really has: ``{name: reason}`` of those *not* conserved.

    Energy and the Casimirs are invariants of every autonomous Hamiltonian system here. Total
    linear and angular momentum are conserved only by a closed system: fixed bodies (or external
    fields, declared by a system attribute ``external_fields``) exert outside forces and torques.
    A system may declare ``not_conserved`` (a mapping name → reason) itself.
    """
    declared = getattr(system, "not_conserved", None)
    if declared is not None:
        return dict(declared)
    out: dict[str, str] = {}
    bodies = getattr(system, "bodies", None) or ()
    fixed = [getattr(b, "name", "?") for b in bodies if getattr(b, "fixed", False)]
    external = getattr(system, "external_fields", None)
    reason = (f"fixed bodies ({', '.join(fixed)}) exert outside forces and torques" if fixed
              else "external fields act on the bodies" if external else None)
    if reason:
        out["linear_momentum"] = reason
        out["angular_momentum"] = reason
    if not hasattr(system, "linear_momentum"):
        out.setdefault("linear_momentum", "the system does not define it")
    return out


def invariant_report(system: Any, diag: Diagnostics) -> dict[str, Any]:
    """The summary's invariant figures: only invariants the system has, each with an absolute
    and a relative figure (the relative one is ``None`` when its reference value is 0 — then
    only the absolute figure means something) and the list of quantities left out, with why."""
    m = diag.maxima()
    out: dict[str, Any] = {}
    ref = diag.energy_reference
    out["energy_reference"] = ref
    if ref != 0:
        out["max_rel_energy_error"] = m["max_rel_energy_error"]
        out["max_abs_energy_error"] = m["max_rel_energy_error"] * abs(ref)
    else:
        out["max_abs_energy_error"] = m["max_rel_energy_error"]
        out["max_rel_energy_error"] = m["max_rel_energy_error"]
        out["energy_note"] = "H(0) = 0: max_rel_energy_error is the absolute error"
    if hasattr(system, "casimirs"):
        out["max_casimir_drift"] = m["max_casimir_drift"]
    skipped = conserved_quantities(system)
    if "angular_momentum" not in skipped:
        jref = diag.angular_momentum_reference
        absolute = m["max_rel_angular_momentum_drift"] * (jref if jref > 0 else 1.0)
        out["max_abs_angular_momentum_drift"] = absolute
        out["max_rel_angular_momentum_drift"] = (m["max_rel_angular_momentum_drift"]
                                                 if jref > 0 else None)
        out["angular_momentum_reference"] = jref
        out["max_rel_angular_momentum_drift_note"] = (
            "|Δj|/|j(0)|, j = Σ r×p + Σ m (seed eq. 21)" if jref > 0 else
            "|j(0)| = 0: only the absolute drift |Δj| is meaningful")
    if "linear_momentum" not in skipped:
        out["max_abs_linear_momentum_drift"] = (m["max_linear_momentum_drift"]
                                                * diag.linear_momentum_scale)
        out["max_linear_momentum_drift"] = m["max_linear_momentum_drift"]
        out["max_linear_momentum_drift_note"] = (
            "|ΔP| divided by the largest single-body momentum at t = 0 (|P(0)| = "
            f"{diag.linear_momentum_reference:.3g})")
    out["not_reported"] = skipped
    return out


def streamed_diagnostics(system: Any, folder: str | Path, plot_rows: int = 20000
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
    overall: dict[str, float] = {}
    keep_t: list[np.ndarray] = []
    keep_y: list[np.ndarray] = []
    offset = 0
    for f in files:
        with np.load(f, allow_pickle=False) as z:
            t, y = z["t"], z["y"]
        if first is None:
            first_t, first = t[:1], y[:1]
        d = diagnostics(system, np.concatenate([first_t, t]), np.vstack([first, y]))
        for k, v in d.maxima().items():
            overall[k] = max(overall.get(k, 0.0), v)
        sel = np.arange((-offset) % every, len(t), every)
        keep_t.append(t[sel])
        keep_y.append(y[sel])
        offset += len(t)
        last_t, last_y = t[-1:], y[-1:]
    t_all, y_all = np.concatenate(keep_t), np.concatenate(keep_y)
    if t_all[-1] != last_t[0]:
        t_all, y_all = np.concatenate([t_all, last_t]), np.vstack([y_all, last_y])
    d = diagnostics(system, t_all, y_all)
    from dataclasses import replace

    return replace(d, overall=overall), t_all, y_all


def _jsonable(x: Any) -> Any:
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


def write_summary(path: str | Path, summary: Mapping[str, Any]) -> Path:
    """Write ``summary`` as pretty JSON (numpy values converted, non-finite floats as strings),
    atomically."""
    from poissonkit.report.atomic import write_json

    return write_json(path, _jsonable(summary))


def write_trajectory(path: str | Path, t: np.ndarray, y: np.ndarray, *,
                     layout: tuple[str, ...] = (), time_unit: float = 1.0,
                     **extra: np.ndarray) -> Path:
    """Write ``t`` (internal), ``t_si`` (``t * time_unit``), ``y`` (rows), ``layout`` and any
    extra arrays to a compressed ``.npz``, atomically."""
    from poissonkit.report.atomic import atomic_path

    path = Path(path)
    t = np.asarray(t, dtype=float)
    with atomic_path(path) as tmp:
        np.savez_compressed(tmp, t=t, t_si=t * float(time_unit), y=np.asarray(y, dtype=float),
                            layout=np.array(layout, dtype=str), **extra)
    return path
