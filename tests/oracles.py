"""Exact solutions the tests compare against, computed here from first principles (never by
poissonkit): the Kepler two-body orbit and the free rigid body.

* :class:`KeplerOrbit`: a two-body orbit from its elements, solved with a robust solver of
  Kepler's equation (:func:`solve_kepler`); :func:`kepler_step_mp` advances any state along
  its exact conic in arbitrary precision (universal variables), an independent formulation.
* :func:`nbody_gravity_reference`: point masses under gravity, Newton's equations solved by
  DOP853 at rtol 1e-13 (a reference, not a closed form: for three bodies there is none);
* :func:`free_top_axis`: the figure axis of a free symmetric top (precession about the fixed
  angular momentum); :func:`euler_top`: the body-frame angular momentum of a free asymmetric
  rigid body (Jacobi elliptic functions).

``tests/test_oracles.py`` checks each against a high-precision numerical solve and its
conservation laws. Import as ``from oracles import ...`` (``tests/`` is on ``sys.path``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath
import numpy as np
from scipy.special import ellipj, ellipk, ellipkinc

_EPS = np.finfo(float).eps


# ------------------------------------------------------------------------------ Kepler
def solve_kepler(mean_anomaly: np.ndarray | float, e: float) -> np.ndarray:
    """Eccentric anomaly ``E`` with ``E - e sin E = M`` (elliptic orbits, ``0 <= e < 1``).

    Any real ``M`` (reduced to one revolution, the revolutions added back); Newton's method
    from Danby's start ``M + 0.85 e sign(sin M)``, kept inside the bracket ``[M - e, M + e]``
    that holds the root, until the step is at round-off. Converges for every ``e < 1``,
    including ``e`` near 1 at the pericentre where plain Newton from ``M`` overshoots.
    """
    if not 0.0 <= e < 1.0:
        raise ValueError(f"elliptic orbits only: e = {e}")
    M = np.asarray(mean_anomaly, dtype=float)
    turns = np.round(M / (2 * math.pi))
    m = M - 2 * math.pi * turns  # in [-pi, pi]
    lo, hi = m - e, m + e  # E - M = e sin E lies in [-e, e]
    E = np.clip(m + 0.85 * e * np.sign(np.sin(m)), lo, hi)
    for _ in range(100):
        f = E - e * np.sin(E) - m
        step = f / (1.0 - e * np.cos(E))
        E_new = E - step
        # Newton can leave the bracket near the pericentre with e -> 1: bisect instead
        outside = (E_new < lo) | (E_new > hi)
        lo = np.where(f < 0, np.maximum(lo, E), lo)
        hi = np.where(f > 0, np.minimum(hi, E), hi)
        E_new = np.where(outside, 0.5 * (lo + hi), E_new)
        # converged: the step, or the residual itself, is at round-off (near the pericentre
        # with e -> 1 the derivative is small and the last step flips at a few ulps)
        done = (np.abs(E_new - E) <= 4 * _EPS * (1.0 + np.abs(E))) \
            | (np.abs(f) <= 4 * _EPS * (1.0 + np.abs(m)))
        E = E_new
        if np.all(done):
            break
    else:  # pragma: no cover - the bracket guarantees convergence
        raise RuntimeError("Kepler's equation did not converge")
    return E + 2 * math.pi * turns


def _rotation(inclination: float, node: float, periapsis: float) -> np.ndarray:
    """Perifocal → reference frame: Rz(node) Rx(inclination) Rz(periapsis)."""
    def rz(a: float) -> np.ndarray:
        c, s = math.cos(a), math.sin(a)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    c, s = math.cos(inclination), math.sin(inclination)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return rz(node) @ rx @ rz(periapsis)


@dataclass(frozen=True)
class KeplerOrbit:
    """Relative orbit of two point masses, ``r'' = -mu r / |r|^3``, from its elements.

    ``mu = G (m0 + m1)``; semi-major axis ``a``, eccentricity ``e < 1``; the orbit plane and
    pericentre direction by ``inclination``, ``node`` (longitude of the ascending node) and
    ``periapsis`` (argument of pericentre), radians; ``mean_anomaly`` at ``t = 0`` (0: at the
    pericentre, on the +x axis when the angles are 0; pi: at the apocentre, on -x).
    """

    mu: float = 1.0
    a: float = 1.0
    e: float = 0.0
    inclination: float = 0.0
    node: float = 0.0
    periapsis: float = 0.0
    mean_anomaly: float = 0.0

    @property
    def mean_motion(self) -> float:
        return math.sqrt(self.mu / self.a**3)

    @property
    def period(self) -> float:
        return 2 * math.pi / self.mean_motion

    @property
    def energy(self) -> float:
        """Specific orbital energy ``|v|^2/2 - mu/|r|``."""
        return -self.mu / (2 * self.a)

    @property
    def angular_momentum(self) -> np.ndarray:
        """Specific angular momentum ``r x v`` (constant)."""
        h = math.sqrt(self.mu * self.a * (1 - self.e**2))
        return h * _rotation(self.inclination, self.node, self.periapsis)[:, 2]

    def state(self, t: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """Relative position and velocity at time(s) ``t``: arrays of shape ``t.shape + (3,)``."""
        t = np.asarray(t, dtype=float)
        n, a, e = self.mean_motion, self.a, self.e
        E = solve_kepler(self.mean_anomaly + n * t, e)
        cos_e, sin_e = np.cos(E), np.sin(E)
        b = a * math.sqrt(1 - e * e)
        rate = n / (1 - e * cos_e)  # dE/dt
        zero = np.zeros_like(E)
        x = np.stack([a * (cos_e - e), b * sin_e, zero], axis=-1)
        v = np.stack([-a * sin_e * rate, b * cos_e * rate, zero], axis=-1)
        R = _rotation(self.inclination, self.node, self.periapsis)
        return x @ R.T, v @ R.T

    def bodies(self, m0: float, m1: float,
               t: np.ndarray | float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Positions and velocities of both bodies (centre of mass at rest at the origin),
        shape ``t.shape + (2, 3)``; body 1 is at ``+m0/M`` of the relative vector."""
        x, v = self.state(t)
        w = np.array([-m1, m0]) / (m0 + m1)
        return w[:, None] * x[..., None, :], w[:, None] * v[..., None, :]


def kepler_step_mp(x: np.ndarray, v: np.ndarray, mu: float, dt: float,
                   dps: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Relative state after ``dt`` on the exact conic through ``(x, v)``, in ``dps``-digit
    arithmetic (universal variables, Stumpff-type G-functions; ellipses and hyperbolae)."""
    with mpmath.workdps(dps):
        x = [mpmath.mpf(float(c)) for c in x]
        v = [mpmath.mpf(float(c)) for c in v]
        mu_, dt_ = mpmath.mpf(float(mu)), mpmath.mpf(float(dt))
        r0 = mpmath.sqrt(sum(c * c for c in x))
        eta0 = sum(p * q for p, q in zip(x, v))
        beta = 2 * mu_ / r0 - sum(c * c for c in v)
        root = mpmath.sqrt(beta)  # imaginary on a hyperbola: cos, sin become cosh, sinh

        def g(s):
            q = root * s
            return (mpmath.cos(q), mpmath.sin(q) / root, (1 - mpmath.cos(q)) / beta,
                    (q - mpmath.sin(q)) / root**3)

        def kepler(s):
            _, g1, g2, g3 = g(s)
            return mpmath.re(r0 * g1 + eta0 * g2 + mu_ * g3) - dt_

        s = mpmath.findroot(kepler, dt_ / r0)
        g0, g1, g2, g3 = (mpmath.re(c) for c in g(s))
        r = r0 * g0 + eta0 * g1 + mu_ * g2
        f, gg = 1 - mu_ * g2 / r0, dt_ - mu_ * g3
        fd, gd = -mu_ * g1 / (r * r0), 1 - mu_ * g2 / r
        return (np.array([float(f * p + gg * q) for p, q in zip(x, v)]),
                np.array([float(fd * p + gd * q) for p, q in zip(x, v)]))


def nbody_gravity_reference(m: np.ndarray, x: np.ndarray, v: np.ndarray, t_end: float,
                            G: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities at ``t_end`` of point masses under Newtonian gravity: Newton's
    equations written out here, solved by scipy's DOP853 at rtol 1e-13 (no closed form for
    three bodies; about 1e-11 relative over a few orbits)."""
    from scipy.integrate import solve_ivp

    m = np.asarray(m, float)
    n = len(m)

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        pos = y[:3 * n].reshape(n, 3)
        d = pos[None, :, :] - pos[:, None, :]  # d[i, j] = x_j - x_i
        r3 = np.linalg.norm(d, axis=-1) ** 3
        np.fill_diagonal(r3, np.inf)
        acc = G * (m[None, :, None] * d / r3[:, :, None]).sum(axis=1)
        return np.concatenate([y[3 * n:], acc.ravel()])

    y0 = np.concatenate([np.ravel(x), np.ravel(v)])
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=1e-13, atol=1e-15)
    return sol.y[:3 * n, -1].reshape(n, 3), sol.y[3 * n:, -1].reshape(n, 3)


# ------------------------------------------------------------------------------ rigid bodies
def free_top_axis(axis: np.ndarray, m: np.ndarray, inertia: float,
                  t: np.ndarray | float) -> np.ndarray:
    """Figure axis of a free symmetric top at time(s) ``t``.

    The angular momentum ``m`` is fixed in space; the axis (unit vector, transverse moment of
    inertia ``inertia``) precesses about it at the rate ``|m| / inertia``:
    ``nu' = (m / inertia) x nu`` (Rodrigues' rotation). Shape ``t.shape + (3,)``.
    """
    axis, m = np.asarray(axis, float), np.asarray(m, float)
    L = float(np.linalg.norm(m))
    k = m / L if L > 0 else np.array([0.0, 0.0, 1.0])
    angle = np.asarray(t, float)[..., None] * (L / inertia)
    c, s = np.cos(angle), np.sin(angle)
    return axis * c + np.cross(k, axis) * s + k * np.dot(k, axis) * (1 - c)


def euler_top(m0: np.ndarray, inertia: np.ndarray, t: np.ndarray | float) -> np.ndarray:
    """Body-frame angular momentum of a free rigid body at time(s) ``t``.

    Euler's equations ``m' = m x omega``, ``omega = m / inertia`` (principal moments, all
    different), solved exactly with Jacobi's elliptic functions (Landau & Lifshitz, Mechanics
    §37). The constants of motion ``|m|^2`` and the energy pick the modulus and the axis the
    motion turns about; the phase is fitted to ``m0``. Shape ``t.shape + (3,)``.
    """
    m0, I = np.asarray(m0, float), np.asarray(inertia, float)
    if len(set(I.tolist())) != 3:
        raise ValueError("euler_top needs three different moments (use free_top_axis)")
    t = np.asarray(t, float)
    order = np.argsort(I)  # solve with I1 < I2 < I3, map back at the end
    I1, I2, I3 = I[order]
    w = m0[order] / I[order]  # angular velocity components
    M2 = float(np.dot(m0, m0))
    E2 = float(np.dot(m0, m0 / I))  # twice the energy
    # Landau's formulas turn about axis 3 when M^2 > 2E I2, else about axis 1 (indices 1 and 3
    # swapped; every factor under the roots changes sign in pairs, and tau still increases)
    if M2 > E2 * I2:
        A, B, C, (a, b, c) = I1, I2, I3, (0, 1, 2)
    else:
        A, B, C, (a, b, c) = I3, I2, I1, (2, 1, 0)
    amp_a = math.sqrt((E2 * C - M2) / (A * (C - A)))
    amp_b = math.sqrt((E2 * C - M2) / (B * (C - B)))
    amp_c = math.sqrt((M2 - E2 * A) / (C * (C - A)))
    rate = math.sqrt((C - B) * (M2 - E2 * A) / (A * B * C))
    k2 = (B - A) * (E2 * C - M2) / ((C - B) * (M2 - E2 * A))
    # the solution with w_c > 0 turns one way; with w_c < 0 flip w_b and w_c (a symmetry of
    # Euler's equations) and solve that one
    flip = -1.0 if w[c] < 0 else 1.0
    sn0, cn0 = flip * w[b] / amp_b, w[a] / amp_a
    phase = math.atan2(sn0, cn0)
    tau0 = float(ellipkinc(phase, k2)) if k2 < 1 else phase
    # an odd permutation of the axes reverses the cross product, so the sense of time
    parity = round(float(np.linalg.det(np.eye(3)[order])))
    tau = tau0 + parity * rate * t
    sn, cn, dn, _ = ellipj(tau, k2)
    out = np.empty(t.shape + (3,))
    out[..., a] = amp_a * cn
    out[..., b] = flip * amp_b * sn
    out[..., c] = flip * amp_c * dn
    result = np.empty_like(out)
    result[..., order] = out * I[order]
    return result


def euler_top_period(m0: np.ndarray, inertia: np.ndarray) -> float:
    """Period of the body-frame motion of :func:`euler_top` (``4 K(k^2) / rate``)."""
    m0, I = np.asarray(m0, float), np.sort(np.asarray(inertia, float))
    M2, E2 = float(np.dot(m0, m0)), float(np.dot(m0, m0 / np.asarray(inertia, float)))
    A, B, C = (I[0], I[1], I[2]) if M2 > E2 * I[1] else (I[2], I[1], I[0])
    rate = math.sqrt((C - B) * (M2 - E2 * A) / (A * B * C))
    k2 = (B - A) * (E2 * C - M2) / ((C - B) * (M2 - E2 * A))
    return 4 * float(ellipk(k2)) / rate
