"""Pair geometry for the checks: random configurations, the invariants and the loads.

Signs follow :mod:`poissonkit.conventions` (``r = r2 − r1``, ``e = r/|r|``, ``c1 = (e, ν1)``,
``c2 = (e, ν2)``, ``c3 = (ν1, ν2)``): from the partials of ``U(r, c1, c2, c3)`` the force on
body 2 is ``F = −[U_r e + U_c1 (ν1 − c1 e)/r + U_c2 (ν2 − c2 e)/r]`` and the torques are
``T2 = U_c2 e × ν2 + U_c3 ν1 × ν2``, ``T1 = U_c1 e × ν1 + U_c3 ν2 × ν1``. The kit restates
them here on purpose: it checks the host's contract from the conventions, not from its code.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

#: ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``
Partials = Callable[[float, float, float, float], tuple[float, float, float, float, float]]


@dataclass(frozen=True)
class PairConfig:
    """Two bodies: ``r = r2 − r1`` [m] and unit axes ``nu1``, ``nu2``."""

    r: np.ndarray
    nu1: np.ndarray
    nu2: np.ndarray

    def invariants(self) -> tuple[float, float, float, float]:
        """``(r, c1, c2, c3)``."""
        d = float(np.linalg.norm(self.r))
        e = self.r / d
        return d, float(e @ self.nu1), float(e @ self.nu2), float(self.nu1 @ self.nu2)

    def describe(self) -> str:
        """A short description for messages: distance and cosines."""
        r, c1, c2, c3 = self.invariants()
        return f"r = {r:.4g} m, c1 = {c1:.3f}, c2 = {c2:.3f}, c3 = {c3:.3f}"


def unit(v: np.ndarray) -> np.ndarray:
    """``v / |v|``."""
    return v / np.linalg.norm(v)


def configurations(count: int, distances: tuple[float, float], seed: int = 0
                   ) -> Iterator[PairConfig]:
    """``count`` random configurations, distances uniform in ``distances`` [m], axes uniform
    on the sphere, cosines kept away from ±1 (where one-sided invariants are singular)."""
    rng = np.random.default_rng(seed)
    made = 0
    while made < count:
        r = unit(rng.normal(size=3)) * rng.uniform(*distances)
        n1, n2 = unit(rng.normal(size=3)), unit(rng.normal(size=3))
        cfg = PairConfig(r, n1, n2)
        if max(abs(c) for c in cfg.invariants()[1:]) < 0.98:
            made += 1
            yield cfg


def loads(f: Partials, cfg: PairConfig) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """``(U, force on body 2, torque on body 1, torque on body 2)`` from the partials."""
    r, c1, c2, c3 = cfg.invariants()
    u, ur, u1, u2, u3 = (float(v) for v in f(r, c1, c2, c3))
    e = cfg.r / r
    force = -(ur * e + u1 * (cfg.nu1 - c1 * e) / r + u2 * (cfg.nu2 - c2 * e) / r)
    t2 = u2 * np.cross(e, cfg.nu2) + u3 * np.cross(cfg.nu1, cfg.nu2)
    t1 = u1 * np.cross(e, cfg.nu1) + u3 * np.cross(cfg.nu2, cfg.nu1)
    return u, force, t1, t2


def energy(f: Partials, cfg: PairConfig) -> float:
    """``U`` alone."""
    return float(f(*cfg.invariants())[0])


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix by ``angle`` about the unit vector ``axis`` (Rodrigues)."""
    k = unit(np.asarray(axis, float))
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def numerical_loads(f: Partials, cfg: PairConfig, step: float = 1e-4
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Force on body 2, force on body 1 and both torques as central differences of ``U``:
    ``F_k = −∂U/∂x_k`` (steps ``step·|r|``) and ``T_k = −∂U/∂θ_k`` for a rotation of the
    body's axis by ``θ`` about the axis ``k`` (steps ``step`` rad)."""
    h = step * float(np.linalg.norm(cfg.r))
    f2, f1, t1, t2 = (np.zeros(3) for _ in range(4))
    for k in range(3):
        dx = np.zeros(3)
        dx[k] = h
        f2[k] = -(energy(f, PairConfig(cfg.r + dx, cfg.nu1, cfg.nu2))
                  - energy(f, PairConfig(cfg.r - dx, cfg.nu1, cfg.nu2))) / (2 * h)
        # moving body 1 by +dx moves r by -dx
        f1[k] = -(energy(f, PairConfig(cfg.r - dx, cfg.nu1, cfg.nu2))
                  - energy(f, PairConfig(cfg.r + dx, cfg.nu1, cfg.nu2))) / (2 * h)
        axis = np.eye(3)[k]
        plus, minus = rotation(axis, step), rotation(axis, -step)
        t1[k] = -(energy(f, PairConfig(cfg.r, plus @ cfg.nu1, cfg.nu2))
                  - energy(f, PairConfig(cfg.r, minus @ cfg.nu1, cfg.nu2))) / (2 * step)
        t2[k] = -(energy(f, PairConfig(cfg.r, cfg.nu1, plus @ cfg.nu2))
                  - energy(f, PairConfig(cfg.r, cfg.nu1, minus @ cfg.nu2))) / (2 * step)
    return f2, f1, t1, t2
