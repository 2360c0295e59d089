"""The one definition of each run diagnostic: energy error, Casimir drift, linear and angular
momentum drift.

Every figure comes as an *absolute* error (in the system's own units) and a *relative* one, the
absolute error divided by a stated *scale* fixed at the first state ``y(0)``:

=========================  ==============================  ======================================
quantity                   absolute at time t              scale (at t = 0)
=========================  ==============================  ======================================
``energy_error``           ``|H(t) − H(0)|``               ``|H(0)|``
``casimir_drift``          ``max_k |C_k(t) − C_k(0)|``     per Casimir: the system's natural size
                                                           ``casimir_scales(y0)`` (magnets:
                                                           ``|ν|² → 1``, ``(ν, m) → |m|``), else
                                                           ``|C_k(0)|``; the relative figure is
                                                           ``max_k |ΔC_k| / s_k``
``linear_momentum_drift``  ``|P(t) − P(0)|``               ``max_i |p_i(0)|``, the largest
                                                           single-body momentum
``angular_momentum_drift`` ``|j(t) − j(0)|``               ``Σ_i |r_i × p_i| + Σ_k |m_k|``, the
                                                           sum of the magnitudes of j's terms
=========================  ==============================  ======================================

None of these scales is round-off sized when the motion is not: a symmetric start whose total
momentum ``P(0)`` cancels to ``1e-16`` still has bodies with momentum of order one. A scale that
is *exactly* zero (every body at rest, a Casimir equal to 0 with no natural size) is replaced by
:data:`SCALE_FLOOR` ``= 1`` (internal units): the relative figure is then the absolute one, and
the ``*_scale`` entry of the report says so by reading 1.

The report keys are the same wherever a run is summarised (``Solution.summary()``, the
``summary.json`` of ``poissonkit run``, sweep outcomes, work-precision reports):
``max_abs_<quantity>``, ``max_rel_<quantity>`` and ``<quantity>_scale``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

# what a system offers: declared once in the contracts, re-exported here
from poissonkit.contracts import HasBodyMomenta, HasCasimirs, HasCasimirScales, HasEnergy
from poissonkit.errors import DimensionError, InputError
from poissonkit.traits import offers

#: The diagnosed quantities, in report order.
QUANTITIES: tuple[str, ...] = ("energy_error", "casimir_drift", "linear_momentum_drift",
                               "angular_momentum_drift")

#: What a scale that is exactly zero is replaced by (internal units).
SCALE_FLOOR = 1.0

#: Unpacked state entries holding spin angular momenta (``m`` of n-body tops, ``m1``/``m2`` of
#: the two-body form).
_SPIN_KEY = re.compile(r"^m\d*$")

__all__ = [
    "QUANTITIES", "SCALE_FLOOR", "Drift", "HasBodyMomenta", "HasCasimirScales", "HasCasimirs",
    "HasEnergy", "angular_momentum_drift", "angular_momentum_scale", "casimir_drift", "drifts",
    "energy_error", "energy_error_of", "linear_momentum_drift", "linear_momentum_scale", "report",
]


# --------------------------------------------------------------------------- one drift
@dataclass(frozen=True)
class Drift:
    """The error of one invariant along a trajectory.

    Attributes
    ----------
    name
        One of :data:`QUANTITIES`.
    absolute
        Absolute error at each saved time, shape ``(n,)``; 0 at ``t = 0``.
    relative
        ``absolute / scale`` at each saved time (for Casimirs: ``max_k |ΔC_k| / s_k``).
    scale
        What the relative figure was divided by: a float, or one float per Casimir.
    """

    name: str
    absolute: np.ndarray
    relative: np.ndarray
    scale: float | tuple[float, ...]

    @property
    def max_absolute(self) -> float:
        """Largest absolute error over the run."""
        return float(np.max(self.absolute))

    @property
    def max_relative(self) -> float:
        """Largest relative error over the run."""
        return float(np.max(self.relative))

    def report(self) -> dict[str, float | list[float]]:
        """``{max_abs_<name>, max_rel_<name>, <name>_scale}``."""
        scale = list(self.scale) if isinstance(self.scale, tuple) else self.scale
        return {f"max_abs_{self.name}": self.max_absolute,
                f"max_rel_{self.name}": self.max_relative,
                f"{self.name}_scale": scale}


def _floored(scale: float) -> float:
    return scale if scale > 0 else SCALE_FLOOR


def _rows(y: ArrayLike) -> np.ndarray:
    rows = np.asarray(y, dtype=float)
    if rows.ndim != 2:
        raise DimensionError(f"diagnostics need rows of states (t × dim), got shape {rows.shape}")
    if rows.shape[0] == 0:
        raise InputError("diagnostics of an empty trajectory")
    return rows


def _per_row(values: ArrayLike, n: int, what: str, width: int | None = None) -> np.ndarray:
    v = np.asarray(values, dtype=float)
    shape = (n,) if width is None else (n, width)
    if v.size != int(np.prod(shape)):
        raise DimensionError(f"{what} gave shape {v.shape} for {n} states")
    return v.reshape(shape)


# --------------------------------------------------------------------------- the definitions
def energy_error_of(H: ArrayLike) -> Drift:
    """Energy error of a series of energies ``H(t)`` (``H[0]`` is the reference).

    Absolute ``|H(t) − H(0)|``, scale ``|H(0)|`` (:data:`SCALE_FLOOR` if ``H(0) = 0``).
    """
    H = np.asarray(H, dtype=float).reshape(-1)
    if H.size == 0:
        raise InputError("energy error of an empty series")
    absolute = np.abs(H - H[0])
    scale = _floored(abs(float(H[0])))
    return Drift("energy_error", absolute, absolute / scale, scale)


def energy_error(system: HasEnergy, y: ArrayLike, energies: ArrayLike | None = None) -> Drift:
    """Energy error along the rows ``y`` (t × dim) of ``system``; see :func:`energy_error_of`.

    ``energies``: ``system.energy(y)`` if the caller has it already (each row costs a force
    evaluation, as much as a kick of a large system).
    """
    rows = _rows(y)
    H = system.energy(rows) if energies is None else energies
    return energy_error_of(_per_row(H, rows.shape[0], "energy"))


def casimir_drift(system: HasCasimirs, y: ArrayLike) -> Drift | None:
    """Casimir drift along the rows ``y``; ``None`` if the system claims no Casimirs.

    Absolute ``max_k |C_k(t) − C_k(0)|``; relative ``max_k |C_k(t) − C_k(0)| / s_k`` with the
    system's ``casimir_scales(y0)`` when it states them, else ``s_k = |C_k(0)|``; a zero
    ``s_k`` is replaced by :data:`SCALE_FLOOR`.
    """
    rows = _rows(y)
    C = np.asarray(system.casimirs(rows), dtype=float).reshape(rows.shape[0], -1)
    if C.shape[1] == 0:
        return None
    if offers(system, HasCasimirScales):
        s = np.asarray(system.casimir_scales(rows[0]), dtype=float).reshape(-1)
        if s.shape[0] != C.shape[1]:
            raise DimensionError(f"{s.shape[0]} Casimir scales for {C.shape[1]} Casimirs")
    else:
        s = np.abs(C[0])
    s = np.where(s > 0, s, SCALE_FLOOR)
    delta = np.abs(C - C[0])
    return Drift("casimir_drift", delta.max(axis=1), (delta / s).max(axis=1),
                 tuple(float(v) for v in s))


def linear_momentum_scale(system: HasBodyMomenta, y0: ArrayLike) -> float:
    """``max_i |p_i(y0)|``, the largest single-body momentum (:data:`SCALE_FLOOR` if all are 0)."""
    p = np.asarray(system.unpack(np.asarray(y0, dtype=float))["p"], dtype=float).reshape(-1, 3)
    return _floored(float(np.max(np.linalg.norm(p, axis=1))) if p.size else 0.0)


def angular_momentum_scale(system: HasBodyMomenta, y0: ArrayLike) -> float:
    """``Σ_i |r_i × p_i| + Σ_k |m_k|`` at ``y0`` (:data:`SCALE_FLOOR` if 0)."""
    parts = system.unpack(np.asarray(y0, dtype=float))
    r = np.asarray(parts["r"], dtype=float).reshape(-1, 3)
    p = np.asarray(parts["p"], dtype=float).reshape(-1, 3)
    total = float(np.sum(np.linalg.norm(np.cross(r, p), axis=1)))
    for key in sorted(k for k in parts if _SPIN_KEY.match(k)):
        m = np.asarray(parts[key], dtype=float).reshape(-1, 3)
        total += float(np.sum(np.linalg.norm(m, axis=1)))
    return _floored(total)


def _vector_drift(name: str, values: np.ndarray, scale: float) -> Drift:
    absolute = np.linalg.norm(values - values[0], axis=1)
    return Drift(name, absolute, absolute / scale, scale)


def linear_momentum_drift(system: HasBodyMomenta, y: ArrayLike) -> Drift:
    """``|P(t) − P(0)|`` of the total linear momentum, scale :func:`linear_momentum_scale`."""
    rows = _rows(y)
    P = _per_row(system.linear_momentum(rows), rows.shape[0], "linear_momentum", 3)
    return _vector_drift("linear_momentum_drift", P, linear_momentum_scale(system, rows[0]))


def angular_momentum_drift(system: HasBodyMomenta, y: ArrayLike) -> Drift:
    """``|j(t) − j(0)|`` of the total angular momentum, scale :func:`angular_momentum_scale`."""
    rows = _rows(y)
    j = _per_row(system.angular_momentum(rows), rows.shape[0], "angular_momentum", 3)
    return _vector_drift("angular_momentum_drift", j, angular_momentum_scale(system, rows[0]))


def drifts(system: HasEnergy, y: ArrayLike, energies: ArrayLike | None = None
           ) -> dict[str, Drift]:
    """Every diagnostic the system defines along the rows ``y``, keyed by quantity name.

    Energy always; Casimir drift if the system claims Casimirs; both momentum drifts if it is a
    system of bodies (:class:`HasBodyMomenta`). ``energies``: as for :func:`energy_error`.
    """
    out = {"energy_error": energy_error(system, y, energies)}
    if offers(system, HasCasimirs):
        c = casimir_drift(system, y)
        if c is not None:
            out["casimir_drift"] = c
    if offers(system, HasBodyMomenta):
        out["linear_momentum_drift"] = linear_momentum_drift(system, y)
        out["angular_momentum_drift"] = angular_momentum_drift(system, y)
    return out


def report(found: Mapping[str, Drift]) -> dict[str, float | list[float]]:
    """The report entries (``max_abs_*``, ``max_rel_*``, ``*_scale``) of several drifts, in
    :data:`QUANTITIES` order."""
    out: dict[str, float | list[float]] = {}
    for name in QUANTITIES:
        if name in found:
            out.update(found[name].report())
    return out
