"""Seed 000's two-body system in centre-of-mass form (Zub's seed, eq. (20)).

State ``x = (r, p, ν', m', ν'', m'') ∈ R^18`` with ``r = r_2 − r_1``, reduced mass
``μ = m_1 m_2/(m_1 + m_2)``; bracket ``canonical(3) ⊕ e3 ⊕ e3``;
``H = p²/2μ + α'|m'|²/2 + α''|m''|²/2 + U(r, c', c'', c''')``::

    ṙ   = p/μ
    ṗ   = −U_r e − (1/r)[U_c' (ν' − c' e) + U_c'' (ν'' − c'' e)]
    ν̇'  = α' m' × ν'          ṁ'  = U_c' e × ν'  − U_c''' ν' × ν''
    ν̇'' = α'' m'' × ν''       ṁ'' = U_c'' e × ν'' + U_c''' ν' × ν''

Total angular momentum ``j = r × p + m' + m''`` (eq. 21) is conserved.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from poissonkit.contracts import CompiledFunction, KineticSplit
from poissonkit.errors import DimensionError, InputError
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import (Kernels, kahan_add, pair_forces, rotate_slot,
                                        rotate_slot_compensated)
from poissonkit.numerics.nbody import (NonUnitAxisError, OverlapError, evaluate_energy,
                                       evaluate_rhs, resolve_kernel)
from poissonkit.numerics.nbody.bodies import BODY_SYSTEM_TRAITS, PotentialLike
from poissonkit.numerics.potentials import scaled_kernel
from poissonkit.numerics.units import Scales
from poissonkit.validation import positive_number

LAYOUT: tuple[str, ...] = tuple(
    f"{v}_{a}" for v in ("r", "p", "nu1", "m1", "nu2", "m2") for a in "xyz")

class TwoBodyData(NamedTuple):
    """The constants the two-body kernels read (internal units)."""

    #: ``μ = m_1 m_2/(m_1 + m_2)``
    reduced_mass: float
    #: ``α'`` of the first top
    alpha1: float
    #: ``α''`` of the second top
    alpha2: float
    #: ``max(m_1, m_2)/(m_1 + m_2)``: a body's largest distance from the centre of mass per ``|r|``
    escape: float


class TwoBodyWork(NamedTuple):
    """Scratch of the two-body kernels."""

    #: ``(ṗ, ṁ', ṁ'')``, left here by ``kernels.forces``
    partials: np.ndarray


#: id of a potential kernel -> (its kernels, the kernel, kept alive so its id stays unique)
_cache: dict[int, tuple[Kernels, CompiledFunction]] = {}


def _build(kern: CompiledFunction) -> Kernels:
    hit = _cache.get(id(kern))
    if hit is not None:
        return hit[0]

    @jit(inline="always")
    def pair(x0, x1, x2, a0, a1, a2, b0, b1, b2):
        """``(U, ṗ, ṁ', ṁ'')`` (ten floats) from ``r = (x0, x1, x2)`` and the axes ``ν' = a``,
        ``ν'' = b``.

        Scalars in, a tuple out, inlined: the kick built on it is one flat function (no call,
        no reference counting, no scratch array); ``partials`` stores the same values."""
        r2 = x0 * x0 + x1 * x1 + x2 * x2
        r = math.sqrt(r2)
        inv = 1.0 / r
        ex = x0 * inv
        ey = x1 * inv
        ez = x2 * inv
        c1 = ex * a0 + ey * a1 + ez * a2
        c2 = ex * b0 + ey * b1 + ez * b2
        c3 = a0 * b0 + a1 * b1 + a2 * b2
        u, ur, u1, u2, u3 = kern(r, c1, c2, c3)
        return pair_forces(u, ur, u1, u2, u3, ex, ey, ez, inv, c1, c2, a0, a1, a2, b0, b1, b2)

    @jit
    def partials(y, out):
        """Force ``ṗ`` (out[0:3]) and torques ``ṁ'`` (out[3:6]), ``ṁ''`` (out[6:9]); returns U."""
        u, f0, f1, f2, f3, f4, f5, f6, f7, f8 = pair(y[0], y[1], y[2], y[6], y[7], y[8],
                                                     y[12], y[13], y[14])
        out[0] = f0
        out[1] = f1
        out[2] = f2
        out[3] = f3
        out[4] = f4
        out[5] = f5
        out[6] = f6
        out[7] = f7
        out[8] = f8
        return u

    @jit
    def rhs(y, data, work, out):
        mu, al1, al2 = data.reduced_mass, data.alpha1, data.alpha2
        f = work.partials
        partials(y, f)
        for d in range(3):
            out[d] = y[3 + d] / mu
            out[3 + d] = f[d]
            out[9 + d] = f[3 + d]
            out[15 + d] = f[6 + d]
        for q, a in ((6, al1), (12, al2)):
            n0, n1, n2 = y[q], y[q + 1], y[q + 2]
            m0, m1, m2 = y[q + 3], y[q + 4], y[q + 5]
            out[q] = a * (m1 * n2 - m2 * n1)
            out[q + 1] = a * (m2 * n0 - m0 * n2)
            out[q + 2] = a * (m0 * n1 - m1 * n0)

    @jit
    def kick(y, h, data, work):
        # the increments straight from pair(): no scratch array, no reference counting
        u, f0, f1, f2, f3, f4, f5, f6, f7, f8 = pair(y[0], y[1], y[2], y[6], y[7], y[8],
                                                     y[12], y[13], y[14])
        y[3] += h * f0
        y[9] += h * f3
        y[15] += h * f6
        y[4] += h * f1
        y[10] += h * f4
        y[16] += h * f7
        y[5] += h * f2
        y[11] += h * f5
        y[17] += h * f8

    @jit
    def drift(y, h, data):
        c = h / data.reduced_mass
        y[0] += c * y[3]
        y[1] += c * y[4]
        y[2] += c * y[5]
        rotate_slot(y, 6, 9, data.alpha1 * h)
        rotate_slot(y, 12, 15, data.alpha2 * h)

    @jit
    def kick_compensated(y, c, h, data, work):
        # forces at the leading part y (y − c differs by a rounding: no effect on accuracy)
        u, f0, f1, f2, f3, f4, f5, f6, f7, f8 = pair(y[0], y[1], y[2], y[6], y[7], y[8],
                                                     y[12], y[13], y[14])
        kahan_add(y, c, 3, h * f0)
        kahan_add(y, c, 9, h * f3)
        kahan_add(y, c, 15, h * f6)
        kahan_add(y, c, 4, h * f1)
        kahan_add(y, c, 10, h * f4)
        kahan_add(y, c, 16, h * f7)
        kahan_add(y, c, 5, h * f2)
        kahan_add(y, c, 11, h * f5)
        kahan_add(y, c, 17, h * f8)

    @jit
    def drift_compensated(y, c, h, data):
        cc = h / data.reduced_mass
        for d in range(3):
            kahan_add(y, c, d, cc * y[3 + d])
        rotate_slot_compensated(y, c, 6, 9, data.alpha1 * h)
        rotate_slot_compensated(y, c, 12, 15, data.alpha2 * h)

    @jit
    def energy(y, data, work):
        u = partials(y, work.partials)
        e = 0.5 * (y[3] ** 2 + y[4] ** 2 + y[5] ** 2) / data.reduced_mass
        e += 0.5 * data.alpha1 * (y[9] ** 2 + y[10] ** 2 + y[11] ** 2)
        e += 0.5 * data.alpha2 * (y[15] ** 2 + y[16] ** 2 + y[17] ** 2)
        return e + u

    @jit
    def min_distance(y, data, work):
        return math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])

    @jit
    def max_radius(y, data):
        # distance of each body from the centre of mass: r m_other/(m1+m2) <= r
        return math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]) * data.escape

    @jit
    def forces(y, data, work):
        """Force and torques (``ṗ, ṁ', ṁ''``) into ``work.partials``; returns ``U``."""
        return partials(y, work.partials)

    out = Kernels(rhs=rhs, drift=drift, kick=kick, energy=energy, min_distance=min_distance,
                  max_radius=max_radius, jac=None, splittable=True, forces=forces,
                  drift_compensated=drift_compensated, kick_compensated=kick_compensated)
    _cache[id(kern)] = (out, kern)
    return out


def _positive(value: object, name: str) -> float:
    """``value`` as a positive finite float, else :class:`InputError` naming it."""
    return positive_number(value, f"TwoBodySystem: {name}")


class TwoBodySystem:
    """Two interacting symmetric tops in centre-of-mass form (18 variables).

    Parameters
    ----------
    mass1, mass2
        Masses of the two bodies (the reduced mass ``μ`` is computed at full precision).
    alpha1, alpha2
        ``1/I_⊥`` of each top.
    potential
        :class:`~poissonkit.plugin.PairPotential`, registry name, sympy expression in
        ``r, c1, c2, c3`` or numba kernel ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``.
    params
        Parameters of the potential (SI).
    scales
        Optional :class:`~poissonkit.numerics.units.Scales`; then masses, alphas and the
        potential are SI and the state is internal (convert with ``pack(..., si=True)``).
    reduced_mass
        Give ``μ`` directly instead of ``mass1, mass2`` (then ``mass1 = mass2 = 2μ`` is used
        only for the escape radius).
    """

    #: the contracts this class fulfils, declared once (:mod:`poissonkit.traits`)
    traits = BODY_SYSTEM_TRAITS

    def __init__(self, mass1: float | None, mass2: float | None, alpha1: float, alpha2: float,
                 potential: PotentialLike, params: Mapping[str, object] | None = None,
                 scales: Scales | None = None, reduced_mass: float | None = None) -> None:
        if reduced_mass is not None:
            mu = _positive(reduced_mass, "reduced_mass")
            m1 = m2 = 2.0 * mu
        else:
            if mass1 is None or mass2 is None:
                raise InputError("TwoBodySystem: give mass1 and mass2 (or reduced_mass)")
            m1, m2 = _positive(mass1, "mass1"), _positive(mass2, "mass2")
            mu = m1 * m2 / (m1 + m2)
        alpha1, alpha2 = _positive(alpha1, "alpha1"), _positive(alpha2, "alpha2")
        self.scales = scales
        L = scales.length if scales else 1.0
        M = scales.mass if scales else 1.0
        self.reduced_mass = mu
        kern, _ = resolve_kernel(potential, params or {})
        self._kern = scaled_kernel(kern, L, scales.energy) if scales else kern
        self.data = TwoBodyData(mu / M, float(alpha1) * M * L * L, float(alpha2) * M * L * L,
                                max(m1, m2) / (m1 + m2))
        self._kernels: Kernels | None = None

    layout = LAYOUT
    dim = 18

    @property
    def kernels(self) -> Kernels:
        """Compiled kernels (compiled on first use, shared per potential)."""
        if self._kernels is None:
            self._kernels = _build(self._kern)
        return self._kernels

    def work(self) -> TwoBodyWork:
        """Scratch arrays for the kernels."""
        return TwoBodyWork(np.zeros(9))

    def _state(self, y: ArrayLike) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.shape != (18,):
            raise DimensionError(f"two-body state must have shape (18,), got {y.shape}")
        return np.ascontiguousarray(y)

    def rhs(self, t: float, y: ArrayLike) -> np.ndarray:
        """``ẋ = J∇H`` at ``y`` (eq. (20)); :class:`OverlapError` if ``r = 0``."""
        return evaluate_rhs(self, y)

    def energy(self, y: ArrayLike) -> float | np.ndarray:
        """``H(y)``; rows of a 2-D array give one value each; :class:`OverlapError` if ``r = 0``."""
        return evaluate_energy(self, y)

    def casimirs(self, y: ArrayLike) -> np.ndarray:
        """``[|ν'|², (ν', m'), |ν''|², (ν'', m'')]`` (rows if 2-D)."""
        y = np.asarray(y, dtype=float)
        n1, m1, n2, m2 = y[..., 6:9], y[..., 9:12], y[..., 12:15], y[..., 15:18]
        return np.stack([np.sum(n1 * n1, -1), np.sum(n1 * m1, -1), np.sum(n2 * n2, -1),
                         np.sum(n2 * m2, -1)], axis=-1)

    def casimir_scales(self, y: ArrayLike) -> np.ndarray:
        """Natural sizes of the Casimirs: ``1, |m'|, 1, |m''|``."""
        y = np.asarray(y, dtype=float)
        one = np.ones(y.shape[:-1])
        return np.stack([one, np.linalg.norm(y[..., 9:12], axis=-1), one,
                         np.linalg.norm(y[..., 15:18], axis=-1)], axis=-1)

    def linear_momentum(self, y: ArrayLike) -> np.ndarray:
        """Total linear momentum in the centre-of-mass frame: zero by construction."""
        y = np.asarray(y, dtype=float)
        return np.zeros(y.shape[:-1] + (3,))

    def angular_momentum(self, y: ArrayLike) -> np.ndarray:
        """``j = r × p + m' + m''`` (eq. 21)."""
        y = np.asarray(y, dtype=float)
        return np.cross(y[..., 0:3], y[..., 3:6]) + y[..., 9:12] + y[..., 15:18]

    def min_distance(self, y: ArrayLike) -> float:
        """``|r|``."""
        return float(np.linalg.norm(self._state(y)[:3]))

    def pack(self, r: ArrayLike, p: ArrayLike, nu1: ArrayLike, m1: ArrayLike, nu2: ArrayLike,
             m2: ArrayLike, *, si: bool = False,
             normalize: bool = False) -> np.ndarray:
        """State vector from its six 3-vectors (SI if ``si``); axes must be unit vectors unless
        ``normalize`` (else :class:`~poissonkit.numerics.nbody.NonUnitAxisError`)."""
        s = self.scales if si else None
        vecs = []
        for name, v in (("r", r), ("p", p), ("nu1", nu1), ("m1", m1), ("nu2", nu2), ("m2", m2)):
            try:
                a = np.asarray(v, dtype=float)
            except (TypeError, ValueError):
                raise InputError(f"{name} must be a 3-vector of numbers, got {v!r}") from None
            if a.shape != (3,):
                raise DimensionError(f"{name} must be a 3-vector, got shape {a.shape}")
            if not np.all(np.isfinite(a)):
                raise InputError(f"{name} is not finite: {a}")
            vecs.append(a)
        if not np.any(vecs[0]):
            raise OverlapError("r = r2 - r1 is zero: the two bodies are at the same position")
        if s:
            vecs[0] = vecs[0] / s.unit("length")
            vecs[1] = vecs[1] / s.unit("momentum")
            vecs[3] = vecs[3] / s.unit("angular_momentum")
            vecs[5] = vecs[5] / s.unit("angular_momentum")
        for k in (2, 4):
            n = np.linalg.norm(vecs[k])
            if normalize:
                if n == 0:
                    raise NonUnitAxisError("cannot normalise a zero axis")
                vecs[k] = vecs[k] / n
            elif abs(n - 1.0) > 1e-12:
                raise NonUnitAxisError(f"axis {'nu1' if k == 2 else 'nu2'} has |ν| = {n:.3g} "
                                       f"(off by {n - 1:.1e}); pass normalize=True")
        return np.concatenate(vecs)

    def unpack(self, y: ArrayLike, *, si: bool = False) -> dict[str, np.ndarray]:
        """Split a state (or rows) into ``r, p, nu1, m1, nu2, m2`` (SI if ``si``)."""
        y = np.asarray(y, dtype=float)
        out = {k: y[..., 3 * i:3 * i + 3] for i, k in enumerate(("r", "p", "nu1", "m1", "nu2", "m2"))}
        if si and self.scales:
            s = self.scales
            out["r"] = out["r"] * s.unit("length")
            out["p"] = out["p"] * s.unit("momentum")
            out["m1"] = out["m1"] * s.unit("angular_momentum")
            out["m2"] = out["m2"] * s.unit("angular_momentum")
        return out

    def kinetic_split(self) -> KineticSplit:
        """``T = |p|²/2μ + α₁|m₁|²/2 + α₂|m₂|²/2`` over the slots of ``p``, ``m1``, ``m2``."""
        d = self.data
        mu, a1, a2 = float(d.reduced_mass), float(d.alpha1), float(d.alpha2)
        return KineticSplit("two_body", np.array([3, 4, 5, 9, 10, 11, 15, 16, 17], dtype=np.int64),
                            np.array([1 / mu] * 3 + [a1] * 3 + [a2] * 3))

    def check_overlap(self, y: ArrayLike) -> None:
        """Raise :class:`~poissonkit.numerics.nbody.OverlapError` if ``r = 0`` in state ``y``."""
        if not np.any(self._state(y)[:3]):
            raise OverlapError("r = r2 - r1 is zero: the two bodies are at the same position")

    def check_state(self, y: ArrayLike, tol: float = 1e-10) -> None:
        """Raise :class:`NonUnitAxisError` if an axis of ``y`` is not a unit vector and
        :class:`~poissonkit.numerics.nbody.OverlapError` if the bodies coincide."""
        self.check_overlap(y)
        c = self.casimirs(self._state(y))
        for k, name in ((0, "nu1"), (2, "nu2")):
            if abs(c[k] - 1.0) > tol:
                raise NonUnitAxisError(f"axis {name} has |ν|² = {c[k]:.3g} (off by "
                                       f"{c[k] - 1:.1e}); normalise it")

    def to_structure(self):
        """Symbolic ``canonical(3) ⊕ e3 ⊕ e3`` in the state order (blocks ``orbit, top1, top2``)."""
        from poissonkit.structure import canonical, direct_sum, e3

        return direct_sum(("orbit", canonical(3)), ("top1", e3()), ("top2", e3()))

    def __repr__(self) -> str:
        return f"TwoBodySystem(mu={self.reduced_mass!r}, data={self.data!r})"
