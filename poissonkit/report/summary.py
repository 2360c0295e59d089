"""Diagnostics over a trajectory and the ``summary.json`` / ``trajectory.npz`` writers."""

from __future__ import annotations

import json
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
    """

    t: np.ndarray
    energy_error: np.ndarray
    casimir_drift: np.ndarray
    angular_momentum_drift: np.ndarray
    linear_momentum_drift: np.ndarray
    angular_momentum: np.ndarray

    def maxima(self) -> dict[str, float]:
        """The largest value of each drift (what ``summary.json`` reports)."""
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
    return Diagnostics(t=t, energy_error=ee, casimir_drift=cd, angular_momentum_drift=jd,
                       linear_momentum_drift=ld, angular_momentum=j)


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
    """Write ``summary`` as pretty JSON (numpy values converted, non-finite floats as strings)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_jsonable(summary), indent=2) + "\n")
    return path


def write_trajectory(path: str | Path, t: np.ndarray, y: np.ndarray, *,
                     layout: tuple[str, ...] = (), time_unit: float = 1.0,
                     **extra: np.ndarray) -> Path:
    """Write ``t`` (internal), ``t_si`` (``t * time_unit``), ``y`` (rows), ``layout`` and any
    extra arrays to a compressed ``.npz``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    t = np.asarray(t, dtype=float)
    np.savez_compressed(path, t=t, t_si=t * float(time_unit), y=np.asarray(y, dtype=float),
                        layout=np.array(layout, dtype=str), **extra)
    return path
