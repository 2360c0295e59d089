"""Known solutions the integrator checks compare against, computed from first principles
(never by the numerics under test): a Kepler orbit, the free precession of a symmetric top's
axis, the radial free fall of two masses, and a DOP853 reference for point masses."""

from __future__ import annotations

import math

import numpy as np


def kepler_state(t: float, e: float, mu: float = 1.0, a: float = 1.0
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Relative position and velocity at ``t`` on the orbit with pericentre on +x at ``t = 0``,
    in the xy-plane (Kepler's equation by Newton's method from ``M + e sin M``; ``e < 0.8``)."""
    n = math.sqrt(mu / a ** 3)
    M = n * t
    E = M + e * math.sin(M)
    for _ in range(50):
        step = (E - e * math.sin(E) - M) / (1 - e * math.cos(E))
        E -= step
        if abs(step) < 1e-16 * max(1.0, abs(E)):
            break
    b = a * math.sqrt(1 - e * e)
    rate = n / (1 - e * math.cos(E))
    return (np.array([a * (math.cos(E) - e), b * math.sin(E), 0.0]),
            np.array([-a * math.sin(E) * rate, b * math.cos(E) * rate, 0.0]))


def free_top_axis(axis: np.ndarray, m: np.ndarray, inertia: float, t: float) -> np.ndarray:
    """Axis of a free symmetric top at ``t``: it precesses about the fixed angular momentum
    ``m`` at the rate ``|m| / inertia`` (Rodrigues' rotation)."""
    L = float(np.linalg.norm(m))
    k = m / L
    angle = t * L / inertia
    c, s = math.cos(angle), math.sin(angle)
    return axis * c + np.cross(k, axis) * s + k * float(k @ axis) * (1 - c)


def free_fall_time(r0: float, d: float, mu: float) -> float:
    """Time for two masses released at rest ``r0`` apart to close to ``d``
    (``r'' = −mu/r²``): ``√(r0³/2mu) [√(x(1−x)) + arccos √x]``, ``x = d/r0``."""
    x = d / r0
    return math.sqrt(r0 ** 3 / (2 * mu)) * (math.sqrt(x * (1 - x)) + math.acos(math.sqrt(x)))


def point_masses_reference(m: np.ndarray, x: np.ndarray, v: np.ndarray, t_end: float,
                           G: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities at ``t_end`` of point masses under Newtonian gravity, Newton's
    equations written out here and solved by scipy's DOP853 at rtol 1e-13."""
    from scipy.integrate import solve_ivp

    n = len(m)

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        pos = y[:3 * n].reshape(n, 3)
        d = pos[None, :, :] - pos[:, None, :]
        r3 = np.linalg.norm(d, axis=-1) ** 3
        np.fill_diagonal(r3, np.inf)
        acc = G * (m[None, :, None] * d / r3[:, :, None]).sum(axis=1)
        return np.concatenate([y[3 * n:], acc.ravel()])

    sol = solve_ivp(rhs, (0.0, t_end), np.concatenate([x.ravel(), v.ravel()]),
                    method="DOP853", rtol=1e-13, atol=1e-15)
    return sol.y[:3 * n, -1].reshape(n, 3), sol.y[3 * n:, -1].reshape(n, 3)
