"""Wisdom–Holman splitting in Jacobi coordinates for systems with one dominant mass.

For ``N`` point masses with Newtonian gravity (plus any other orientation-free pair potential)
the Hamiltonian is split as ``H = H_K + H_I``:

* ``H_K = Σ_{i≥1} [p'_i²/(2 m'_i) − G m'_i η_i / |x'_i|] + P²/(2 M)`` — independent Kepler
  problems of the Jacobi coordinates ``x'_i = r_i − R_{i−1}`` (``R_{i−1}`` the centre of mass of
  bodies ``0 … i−1``, ``η_i = m_0 + … + m_i``, ``m'_i = m_i η_{i−1}/η_i``) and the free motion of
  the centre of mass. Its flow is exact: a universal-variable Kepler solver (Stumpff functions
  with argument halving, Halley's iteration safeguarded by bisection) per body.
* ``H_I = V(r) + Σ_{i≥1} G m'_i η_i / |x'_i|`` — the full pair potential minus the Keplerian
  parts. It depends on positions only, so its flow is an exact kick; for a hierarchical system
  it is of the size ``ε`` of the planet-to-star mass ratio.

(J. Wisdom & M. Holman, AJ 102 (1991) 1528; the Jacobi form as in H. Rein & D. Tamayo,
MNRAS 452 (2015) 376, WHFast.) The steps are the ``SABA_n`` compositions of J. Laskar &
P. Robutel, Celest. Mech. Dyn. Astron. 80 (2001) 39: Kepler drifts between the Gauss–Legendre
nodes of ``[0, h]`` and kicks with the Gauss weights, error ``O(ε h^{2n} + ε² h²)``; ``n = 1`` is
the classical Wisdom–Holman map. With ``corrector=True`` the ``ε² h²`` term is removed by the
kick of ``−g_n h³ ε² {{A,B},B}/2`` on both sides of each step (``SABAC_n``, same paper;
consecutive steps share one), whose force is a Hessian-vector product of ``H_I``: for gravity
alone the analytic derivative of the kick (the "jerk"), otherwise a central difference of the
kick acceleration (three force evaluations; its relative error ~1e-10 multiplies a term that
is already ``O(ε² h²)``, and the angular momentum it changes is ``O(δ²)``, below round-off).

Further tables (:mod:`~poissonkit.numerics.integrators.wh_tables`): the ``ABA``/``ABAH``
methods of Blanes, Casas, Farrés, Laskar, Makazaga & Murua (2013), and the symplectic
correctors of Wisdom, Holman & Touma (1996) as in WHFast: the state is carried in processed
coordinates and corrected where it is written out; with the corrector kick the one-stage step
becomes WHT96's modified-kick kernel (the kick in the middle of the step, half SABAC₁'s
coefficient, which removes the ``ε² h²`` term left by the conjugation).

When Newtonian gravity is the system's only interaction, the kick is a dedicated pair loop
that leaves out the star–first-planet pair (it cancels the first Kepler term exactly, as in
WHFast), and the steps between two write-outs run in one tight compiled loop.

Every sub-flow is the exact flow of a rotation- and translation-invariant Hamiltonian, so
total linear and angular momentum are kept to round-off and the map is symplectic; the energy
error stays bounded without drift.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import lru_cache

import numba
import numpy as np

from poissonkit.contracts import (
    CompiledFunction,
    CompiledKernels,
    Event,
    HasBodies,
    HasCompiledKernels,
    HasGravity,
    System,
)
from poissonkit.errors import InputError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import (
    RawResult,
    SaveBuffer,
    StepFn,
    check_step,
    locate_division,
    state_digest,
    step_end_kernels,
)
from poissonkit.numerics.integrators.capabilities import WISDOM_HOLMAN
from poissonkit.numerics.integrators.driver import Control, LoopState, drive
from poissonkit.numerics.integrators.wh_tables import (
    TABLE_ORDERS,
    blanes_coefficients,
    corrector_operators,
)
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import all_finite, copy_row

#: ``g_n`` of the ``ε² h²`` error term of ``SABA_n`` (Laskar & Robutel 2001, Table 1).
CORRECTOR_G = {
    1: 1.0 / 12.0,
    2: (2.0 - math.sqrt(3.0)) / 24.0,
    3: (54.0 - 13.0 * math.sqrt(15.0)) / 648.0,
    4: 0.003396775048208601331532157783492144,
}


def saba_coefficients(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Drift fractions ``c`` (``n + 1``) and kick fractions ``d`` (``n``) of ``SABA_n``.

    Drifts go from node to node of the ``n``-point Gauss–Legendre rule on ``[0, 1]`` (and to the
    ends), kicks carry its weights; ``Σ c = Σ d = 1`` and the scheme is symmetric.
    """
    if n not in CORRECTOR_G:
        raise InputError(f"Wisdom–Holman stages must be 1 … 4, got {n!r}")
    c, d = _saba_table(n)
    return np.array(c), np.array(d)


@lru_cache(maxsize=None)
def _saba_table(n: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
    x, w = np.polynomial.legendre.leggauss(n)  # costly next to a short run: computed once
    x = 0.5 * (x + 1.0)
    c = np.diff(np.concatenate([[0.0], x, [1.0]]))
    return tuple(c.tolist()), tuple((0.5 * w).tolist())


# --------------------------------------------------------------------------- Kepler flow
# 1/(2k+2)! and 1/(2k+3)! with alternating signs: c2 and c3 as polynomials in z (|z| ≤ 0.5)
_C2 = tuple((-1.0) ** k / math.factorial(2 * k + 2) for k in range(9))
_C3 = tuple((-1.0) ** k / math.factorial(2 * k + 3) for k in range(9))


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def stumpff(z):
    """Stumpff functions ``c0 … c3`` of ``z`` (argument quartered until ``|z| ≤ 1/2``, series
    to ``z⁸`` by Horner's rule — the next term is below 1e-19 — then doubled back; for
    ``|z| ≤ 0.1``, the usual case of a planetary step, the series to ``z⁵`` is as exact)."""
    if abs(z) <= 0.1:
        c3 = _C3[0] + z * (_C3[1] + z * (_C3[2] + z * (_C3[3] + z * (_C3[4] + z * _C3[5]))))
        c2 = _C2[0] + z * (_C2[1] + z * (_C2[2] + z * (_C2[3] + z * (_C2[4] + z * _C2[5]))))
        return 1.0 - z * c2, 1.0 - z * c3, c2, c3
    n = 0
    while abs(z) > 0.5:
        z *= 0.25
        n += 1
    c3 = _C3[8]
    c2 = _C2[8]
    for k in range(7, -1, -1):  # unrolled by numba: the tuples are compile-time constants
        c3 = _C3[k] + z * c3
        c2 = _C2[k] + z * c2
    c1 = 1.0 - z * c3
    c0 = 1.0 - z * c2
    for _ in range(n):
        c3 = (c2 + c0 * c3) * 0.25
        c2 = 0.5 * c1 * c1
        c1 = c0 * c1
        c0 = 2.0 * c0 * c0 - 1.0
    return c0, c1, c2, c3


@numba.njit(cache=True, error_model="numpy")
def _kepler_time(s, r0, eta0, mu, beta):
    """``(t(s), r(s), r'(s))`` of the universal Kepler equation at universal anomaly ``s``."""
    c0, c1, c2, c3 = stumpff(beta * s * s)
    g1 = s * c1
    g2 = s * s * c2
    g3 = s * s * s * c3
    t = r0 * g1 + eta0 * g2 + mu * g3
    r = r0 * c0 + eta0 * g1 + mu * g2
    dr = eta0 * c0 + (mu - beta * r0) * g1
    return t, r, dr


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def kepler_drift(x, v, i, mu, dt):
    """Advance row ``i`` of positions ``x`` and velocities ``v`` along a Kepler orbit.

    Universal variables (Danby's f and g functions): Halley's iteration on the universal Kepler
    equation from its third-order series solution (two iterations for a planetary step); if it
    has not converged after 30 iterations, a bracketing bisection finishes (never needed for
    steps shorter than the period, but it makes the solver total). Returns False only for a
    degenerate state (``r0 = 0``).
    """
    x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
    v0, v1, v2 = v[i, 0], v[i, 1], v[i, 2]
    r0 = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    if r0 == 0.0 or dt == 0.0:
        return r0 != 0.0
    r0i = 1.0 / r0
    eta0 = x0 * v0 + x1 * v1 + x2 * v2
    beta = 2.0 * mu * r0i - (v0 * v0 + v1 * v1 + v2 * v2)
    zeta0 = mu - beta * r0
    tau = dt * r0i
    # fourth-order series solution (reversion) of dt/r0 = s + p1 s² + p2 s³ + p3 s⁴ + …, from
    # t(s) = r0 s + η0 s²/2 + ζ0 s³/6 − β η0 s⁴/24 + … (error O(dt⁵): one Halley iteration
    # for the outer planets' steps), unless the step is too long for the series
    p1 = 0.5 * eta0 * r0i
    p2 = zeta0 * r0i / 6.0
    p3 = -beta * eta0 * r0i / 24.0
    corr = tau * (-p1 + tau * (2.0 * p1 * p1 - p2 + tau * (p1 * (5.0 * p2 - 5.0 * p1 * p1) - p3)))
    s = tau * (1.0 + corr) if abs(corr) < 0.2 else tau
    ok = False
    g0 = g1 = g2 = g3 = 0.0
    for _ in range(30):  # Halley's iteration: cubic convergence
        c0, c1, c2, c3 = stumpff(beta * s * s)
        g0 = c0
        g1 = s * c1
        g2 = s * s * c2
        g3 = s * s * c3 * s
        f = r0 * g1 + eta0 * g2 + mu * g3 - dt
        r = r0 * g0 + eta0 * g1 + mu * g2
        dr = eta0 * g0 + zeta0 * g1
        den = r - 0.5 * f * dr / r
        ds = -f / (den if den != 0.0 else r)
        s += ds
        if abs(ds) <= 1e-6 * abs(s) or f == 0.0:
            # the root is now within O(ds³) ≈ 1e-18 (relative); move the g-functions to it by
            # their Taylor series (g0' = −β g1, g_k' = g_{k−1}; error O(ds⁴)) instead of a
            # fresh Stumpff evaluation
            d2 = 0.5 * ds * ds
            d3 = d2 * ds / 3.0
            n3 = g3 + g2 * ds + g1 * d2 + g0 * d3
            n2 = g2 + g1 * ds + g0 * d2 - beta * g1 * d3
            n1 = g1 + g0 * ds - beta * (g1 * d2 + g0 * d3)
            g0 = g0 - beta * (g1 * ds + g0 * d2 - beta * g1 * d3)
            g1, g2, g3 = n1, n2, n3
            ok = True
            break
    if not ok:
        # bisection: t(s) is increasing (t' = r > 0); expand a bracket around the root
        lo = 0.0
        hi = dt / r0
        while (_kepler_time(hi, r0, eta0, mu, beta)[0] - dt) * (1.0 if dt > 0 else -1.0) < 0.0:
            lo = hi
            hi *= 2.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid == lo or mid == hi:
                break
            if (_kepler_time(mid, r0, eta0, mu, beta)[0] - dt) * (1.0 if dt > 0 else -1.0) < 0.0:
                lo = mid
            else:
                hi = mid
        s = 0.5 * (lo + hi)
        c0, c1, c2, c3 = stumpff(beta * s * s)
        g0 = c0
        g1 = s * c1
        g2 = s * s * c2
        g3 = s * s * c3 * s
    ri = 1.0 / (r0 * g0 + eta0 * g1 + mu * g2)
    fm1 = -mu * g2 * r0i  # f − 1
    g = dt - mu * g3
    fd = -mu * g1 * r0i * ri
    gdm1 = -mu * g2 * ri  # ġ − 1
    x[i, 0] = x0 + fm1 * x0 + g * v0
    x[i, 1] = x1 + fm1 * x1 + g * v1
    x[i, 2] = x2 + fm1 * x2 + g * v2
    v[i, 0] = v0 + fd * x0 + gdm1 * v0
    v[i, 1] = v1 + fd * x1 + gdm1 * v1
    v[i, 2] = v2 + fd * x2 + gdm1 * v2
    return True


# --------------------------------------------------------------------------- Jacobi coordinates
@numba.njit(cache=True, error_model="numpy")
def to_jacobi(r, u, m, xj, uj):
    """Inertial positions ``r`` / velocities ``u`` (rows) → Jacobi ``xj``, ``uj``; row 0 = centre
    of mass."""
    n = m.shape[0]
    eta = m[0]
    for d in range(3):
        sx = m[0] * r[0, d]
        su = m[0] * u[0, d]
        eta = m[0]
        for i in range(1, n):
            xj[i, d] = r[i, d] - sx / eta
            uj[i, d] = u[i, d] - su / eta
            sx += m[i] * r[i, d]
            su += m[i] * u[i, d]
            eta += m[i]
        xj[0, d] = sx / eta
        uj[0, d] = su / eta


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def from_jacobi(xj, mfrac, r):
    """Jacobi rows ``xj`` (row 0 = centre of mass) → inertial rows ``r`` (positions or
    velocities alike); ``mfrac[i] = m_i / η_i``.

    With ``R_i`` the centre of mass of bodies ``0 … i``: ``R_{i−1} = R_i − (m_i/η_i) x'_i`` and
    ``r_i = x'_i + R_{i−1}``, from ``R_{n−1}`` = row 0 down (multiplications only).
    """
    n = xj.shape[0]
    for d in range(3):
        R = xj[0, d]
        for i in range(n - 1, 0, -1):
            R -= mfrac[i] * xj[i, d]
            r[i, d] = xj[i, d] + R
        r[0, d] = R


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"})
def jacobi_of_inertial(a, m, inv_eta, aj):
    """Jacobi transform of inertial accelerations (row 0, the centre of mass's, set to 0);
    ``inv_eta[i] = 1/η_i``."""
    n = m.shape[0]
    for d in range(3):
        s = m[0] * a[0, d]
        for i in range(1, n):
            aj[i, d] = a[i, d] - s * inv_eta[i - 1]
            s += m[i] * a[i, d]
        aj[0, d] = 0.0  # internal forces: the centre of mass is not accelerated


# --------------------------------------------------------------------------- pure gravity kick
@numba.njit(cache=True, error_model="numpy", fastmath={"contract"}, inline="always")
def gravity_kick_accel(xj, m, mfrac, inv_eta, gm, gmass, r, a, aj):
    """Jacobi kick accelerations of ``H_I`` for Newtonian gravity alone (no other potential).

    The pair (0, 1) is left out and so is the Kepler term of planet 1: both are
    ``−G m_0 m_1/|x'_1|`` (``m'_1 η_1 = m_0 m_1``), so they cancel exactly in ``H_I`` — as in
    WHFast (``REB_GRAVITY_IGNORE_TERMS_BETWEEN_0_AND_1``). ``gmass[i] = G m_i``.
    """
    n = m.shape[0]
    from_jacobi(xj, mfrac, r)
    for i in range(n):
        a[i, 0] = 0.0
        a[i, 1] = 0.0
        a[i, 2] = 0.0
    for i in range(n):
        xi0, xi1, xi2 = r[i, 0], r[i, 1], r[i, 2]
        for j in range(2 if i == 0 else i + 1, n):
            dx = r[j, 0] - xi0
            dy = r[j, 1] - xi1
            dz = r[j, 2] - xi2
            q2 = dx * dx + dy * dy + dz * dz
            s = 1.0 / (q2 * math.sqrt(q2))
            si = s * gmass[j]
            sj = s * gmass[i]
            a[i, 0] += si * dx
            a[i, 1] += si * dy
            a[i, 2] += si * dz
            a[j, 0] -= sj * dx
            a[j, 1] -= sj * dy
            a[j, 2] -= sj * dz
    jacobi_of_inertial(a, m, inv_eta, aj)
    for i in range(2, n):  # remove the Kepler parts: + G η_i x'_i / |x'_i|³
        q2 = xj[i, 0] * xj[i, 0] + xj[i, 1] * xj[i, 1] + xj[i, 2] * xj[i, 2]
        c = gm[i] / (q2 * math.sqrt(q2))
        aj[i, 0] += c * xj[i, 0]
        aj[i, 1] += c * xj[i, 1]
        aj[i, 2] += c * xj[i, 2]


@numba.njit(cache=True, error_model="numpy", fastmath={"contract"}, inline="always")
def gravity_kick_jerk(xj, w, m, mfrac, inv_eta, gm, gmass, r, dr, da, jerk):
    """Derivative of :func:`gravity_kick_accel` along the Jacobi displacement ``w`` (row 0
    zero) into ``jerk``; ``r`` holds the inertial positions of ``xj`` (as the kick leaves
    them). For each pair, ``∂/∂d (d/|d|³) δd = δd/|d|³ − 3 d (d·δd)/|d|⁵``."""
    n = m.shape[0]
    from_jacobi(w, mfrac, dr)
    for i in range(n):
        da[i, 0] = 0.0
        da[i, 1] = 0.0
        da[i, 2] = 0.0
    for i in range(n):
        for j in range(2 if i == 0 else i + 1, n):
            dx = r[j, 0] - r[i, 0]
            dy = r[j, 1] - r[i, 1]
            dz = r[j, 2] - r[i, 2]
            ex = dr[j, 0] - dr[i, 0]
            ey = dr[j, 1] - dr[i, 1]
            ez = dr[j, 2] - dr[i, 2]
            q2 = dx * dx + dy * dy + dz * dz
            s = 1.0 / (q2 * math.sqrt(q2))
            t = 3.0 * (dx * ex + dy * ey + dz * ez) / q2
            tx = s * (ex - t * dx)
            ty = s * (ey - t * dy)
            tz = s * (ez - t * dz)
            da[i, 0] += gmass[j] * tx
            da[i, 1] += gmass[j] * ty
            da[i, 2] += gmass[j] * tz
            da[j, 0] -= gmass[i] * tx
            da[j, 1] -= gmass[i] * ty
            da[j, 2] -= gmass[i] * tz
    jacobi_of_inertial(da, m, inv_eta, jerk)
    for i in range(2, n):  # the Kepler parts' derivative
        x0, x1, x2 = xj[i, 0], xj[i, 1], xj[i, 2]
        q2 = x0 * x0 + x1 * x1 + x2 * x2
        c = gm[i] / (q2 * math.sqrt(q2))
        t = 3.0 * (x0 * w[i, 0] + x1 * w[i, 1] + x2 * w[i, 2]) / q2
        jerk[i, 0] += c * (w[i, 0] - t * x0)
        jerk[i, 1] += c * (w[i, 1] - t * x1)
        jerk[i, 2] += c * (w[i, 2] - t * x2)


@numba.njit(cache=True, error_model="numpy", inline="always")
def gravity_corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, w, da):
    """Kick ``2 τ (∂a/∂x') w`` with ``w = −a``, ``aj`` holding the gravity-only kick
    acceleration ``a`` at ``xj`` and ``r`` its inertial positions (overwrites ``aj``)."""
    n = m.shape[0]
    for d in range(3):
        w[0, d] = 0.0
    for i in range(1, n):
        for d in range(3):
            w[i, d] = -aj[i, d]
    gravity_kick_jerk(xj, w, m, mfrac, inv_eta, gm, gmass, r, a, da, aj)
    f = 2.0 * tau
    for i in range(1, n):
        for d in range(3):
            uj[i, d] += f * aj[i, d]


@numba.njit(cache=True, error_model="numpy", inline="always")
def gravity_kick(xj, uj, hk, m, mfrac, inv_eta, gm, gmass, r, a, aj):
    """Kick the Jacobi velocities by ``hk`` times the gravity-only kick acceleration."""
    gravity_kick_accel(xj, m, mfrac, inv_eta, gm, gmass, r, a, aj)
    for i in range(1, m.shape[0]):
        uj[i, 0] += hk * aj[i, 0]
        uj[i, 1] += hk * aj[i, 1]
        uj[i, 2] += hk * aj[i, 2]


@numba.njit(cache=True, error_model="numpy", inline="always")
def gravity_modified_kick(xj, uj, hk, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, w, da):
    """:func:`gravity_kick` and :func:`gravity_corrector_kick` at the same positions."""
    gravity_kick(xj, uj, hk, m, mfrac, inv_eta, gm, gmass, r, a, aj)
    gravity_corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, w, da)


@numba.njit(cache=True, error_model="numpy", inline="always")
def gravity_correct(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, w, da):
    """The corrector kick ``τ`` alone (the SABAC_n ends), gravity only."""
    gravity_kick_accel(xj, m, mfrac, inv_eta, gm, gmass, r, a, aj)
    gravity_corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, w, da)


@numba.njit(cache=True, error_model="numpy", inline="always")
def drift_planets(xj, uj, gm, dt):
    """Kepler drift of every Jacobi row ``i ≥ 1`` by ``dt``; False if one is degenerate."""
    ok = True
    for i in range(1, xj.shape[0]):
        ok = kepler_drift(xj, uj, i, gm[i], dt) and ok
    return ok


@numba.njit(cache=True, error_model="numpy", inline="always")
def drift_all(xj, uj, gm, dt):
    """Kepler drifts and the free motion of the centre of mass (row 0) by ``dt``."""
    for d in range(3):
        xj[0, d] += dt * uj[0, d]
    return drift_planets(xj, uj, gm, dt)


@numba.njit(cache=True, error_model="numpy")
def gravity_steps(xj, uj, count, pending, c, dk, h, tau_mid, m, mfrac, inv_eta, gm, gmass, r, a,
                  aj, w, da):
    """``count`` whole gravity-only steps with nothing to write out between them: the hot loop
    of :func:`_runner`'s ``run``, kept small so the compiler keeps it tight. Same arithmetic as
    ``run`` (the last drift of a step merged into the next one's first), so where a stretch
    starts or ends never changes the result. Returns (pending drift, no degenerate drift)."""
    ok = True
    ns = dk.shape[0]
    for _ in range(count):
        ok = drift_all(xj, uj, gm, pending + c[0] * h) and ok
        for s in range(ns):
            if tau_mid != 0.0:
                gravity_modified_kick(xj, uj, dk[s] * h, tau_mid, m, mfrac, inv_eta, gm, gmass,
                                      r, a, aj, w, da)
            else:
                gravity_kick(xj, uj, dk[s] * h, m, mfrac, inv_eta, gm, gmass, r, a, aj)
            if s + 1 < ns:
                ok = drift_all(xj, uj, gm, c[s + 1] * h) and ok
        pending = c[ns] * h
    return pending, ok


# --------------------------------------------------------------------------- compiled loop
_runners: dict[tuple[int, bool], tuple[CompiledFunction, CompiledFunction, CompiledKernels]] = {}


def _runner(kernels: CompiledKernels, pure_gravity: bool
            ) -> tuple[CompiledFunction, CompiledFunction]:
    """The compiled Wisdom–Holman loop and corrector around one system's kernels (cached).

    ``pure_gravity``: the interaction is Newtonian gravity alone, so the kick is the dedicated
    pair loop :func:`gravity_kick_accel` instead of the system's general force kernel.
    """
    key = (id(kernels.forces), pure_gravity)
    hit = _runners.get(key)
    if hit is not None:
        return hit[0], hit[1]
    forces = kernels.forces
    remember, check = step_end_kernels(kernels)

    if pure_gravity:
        @jit(inline="always")
        def accel(xj, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work):
            gravity_kick_accel(xj, m, mfrac, inv_eta, gm, gmass, r, a, aj)
    else:
        @jit(inline="always")
        def accel(xj, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work):
            """Jacobi kick accelerations of ``H_I`` at Jacobi positions ``xj`` into ``aj``."""
            n = m.shape[0]
            from_jacobi(xj, mfrac, r)
            for i in range(n):
                for d in range(3):
                    ybuf[6 * i + d] = r[i, d]
            forces(ybuf, data, work)
            F = work[2]
            for i in range(n):
                for d in range(3):
                    a[i, d] = F[i, d] / m[i]
            jacobi_of_inertial(a, m, inv_eta, aj)
            for i in range(1, n):  # remove the Kepler parts: + G η_i x'_i / |x'_i|³
                q2 = xj[i, 0] ** 2 + xj[i, 1] ** 2 + xj[i, 2] ** 2
                c = gm[i] / (q2 * math.sqrt(q2))
                for d in range(3):
                    aj[i, d] += c * xj[i, d]

    @jit(inline="always")
    def kick(xj, uj, hk, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work):
        accel(xj, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work)
        for i in range(1, m.shape[0]):
            uj[i, 0] += hk * aj[i, 0]
            uj[i, 1] += hk * aj[i, 1]
            uj[i, 2] += hk * aj[i, 2]

    if pure_gravity:
        @jit(inline="always")
        def corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt,
                           a_plus, data, work):
            """Kick ``2 τ (∂a/∂x') w``, ``w = −a`` (``aj`` holds ``a`` at ``xj``, ``r`` its
            inertial positions): the analytic jerk of the gravity-only kick. Overwrites
            ``aj``."""
            gravity_corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, xt,
                                   a_plus)
    else:
        @jit(inline="always")
        def corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt,
                           a_plus, data, work):
            """Kick ``2 τ (∂a/∂x') w``, ``w = −a`` (``aj`` holds ``a`` at ``xj``), the
            Hessian-vector product taken as a central difference of ``a`` along ``w``. Central,
            not forward: the angular momentum it changes is ``O(τ δ²)`` instead of ``O(τ δ)``
            (``w_i ∥ a_i`` cancels the first order), i.e. below round-off. Overwrites ``aj``."""
            n = m.shape[0]
            big = 0.0  # δ makes the largest relative displacement 1e-5
            for i in range(1, n):
                q = math.sqrt(xj[i, 0] ** 2 + xj[i, 1] ** 2 + xj[i, 2] ** 2)
                w = math.sqrt(aj[i, 0] ** 2 + aj[i, 1] ** 2 + aj[i, 2] ** 2)
                big = max(big, w / q)
            if big == 0.0:
                return
            delta = 1e-5 / big
            for i in range(n):
                for d in range(3):
                    xt[i, d] = xj[i, d] - delta * aj[i, d]
            accel(xt, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, a_plus, data, work)
            for i in range(n):
                for d in range(3):
                    xt[i, d] = 2.0 * xj[i, d] - xt[i, d]  # x − δw
            accel(xt, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work)
            f = tau / delta
            for i in range(1, n):
                for d in range(3):
                    uj[i, d] += f * (a_plus[i, d] - aj[i, d])

    @jit
    def correct(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt, a_plus, data,
                work):
        """Kick of the corrector potential ``τ Σ |∂H_I/∂x'_i|²/m'_i``: its acceleration is
        ``2 τ (∂a/∂x') w`` with ``a`` the kick acceleration and ``w = −a`` (a Hessian-vector
        product of ``H_I``)."""
        accel(xj, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work)
        corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt, a_plus,
                       data, work)

    @jit
    def modified_kick(xj, uj, hk, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt,
                      a_plus, data, work):
        """Kick by ``hk`` and the corrector kick ``τ`` at the same positions (one force
        evaluation shared): Wisdom, Holman & Touma's modified kick."""
        accel(xj, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work)
        for i in range(1, m.shape[0]):
            uj[i, 0] += hk * aj[i, 0]
            uj[i, 1] += hk * aj[i, 1]
            uj[i, 2] += hk * aj[i, 2]
        corrector_kick(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt, a_plus,
                       data, work)

    @jit
    def process(xj, uj, proc, sign, h, m, mfrac, inv_eta, gm, gmass, data, work):
        """Apply the symplectic corrector ``proc`` (rows ``(a, b)`` of ``Z`` operators, step
        units) with kicks of sign ``sign``: ``+1`` processed → physical, ``−1`` the start.

        ``Z(a, b) = e^{aA} e^{−bB} e^{−2aA} e^{bB} e^{aA}`` (Wisdom, Holman & Touma 1996; as
        ``reb_whfast_corrector_Z``). The centre of mass does not move (its drifts cancel).
        Returns False for a degenerate Kepler state.
        """
        n = m.shape[0]
        ybuf = np.empty(6 * n)
        r = np.empty((n, 3))
        a = np.empty((n, 3))
        aj = np.empty((n, 3))
        ok = True
        pend = 0.0  # the closing drift of one Z merged into the opening drift of the next
        for k in range(proc.shape[0]):
            da = proc[k, 0] * h
            db = sign * proc[k, 1] * h
            ok = drift_planets(xj, uj, gm, pend + da) and ok
            if pure_gravity:
                gravity_kick(xj, uj, -db, m, mfrac, inv_eta, gm, gmass, r, a, aj)
            else:
                kick(xj, uj, -db, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work)
            ok = drift_planets(xj, uj, gm, -2.0 * da) and ok
            if pure_gravity:
                gravity_kick(xj, uj, db, m, mfrac, inv_eta, gm, gmass, r, a, aj)
            else:
                kick(xj, uj, db, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data, work)
            pend = da
        ok = drift_planets(xj, uj, gm, pend) and ok
        return ok

    @jit
    def sync(xj, uj, m, mfrac, inv_eta, y, r, u):
        """Write the inertial state ``(r, p)`` of Jacobi ``xj, uj`` into ``y``."""
        from_jacobi(xj, mfrac, r)
        from_jacobi(uj, mfrac, u)
        for i in range(m.shape[0]):
            for d in range(3):
                y[6 * i + d] = r[i, d]
                y[6 * i + 3 + d] = m[i] * u[i, d]

    @jit
    def sync_processed(xj, uj, proc, h, m, mfrac, inv_eta, gm, gmass, data, work, y, r, u):
        """:func:`sync` of the physical state: the corrector applied to copies of ``xj, uj``."""
        if proc.shape[0] == 0:
            sync(xj, uj, m, mfrac, inv_eta, y, r, u)
            return True
        xc = xj.copy()
        uc = uj.copy()
        ok = process(xc, uc, proc, 1.0, h, m, mfrac, inv_eta, gm, gmass, data, work)
        sync(xc, uc, m, mfrac, inv_eta, y, r, u)
        return ok

    @jit
    def run(y, xj, uj, carried, m, mfrac, inv_eta, gm, gmass, t_orig, h, n_total, c, dk, tau,
            proc, data, work, save_every, step0, max_steps, out_t, out_y, contact, escape,
            watch, prev, prev2, hist):
        """Advance the Jacobi state ``xj, uj`` (written to ``y`` at every save and on return).

        Returns (status, t, steps done, saved, value). Without corrector the last drift of a
        step is merged into the first drift of the next; with it, the closing corrector of a
        step and the opening one of the next are one kick (both depend on positions only).
        ``carried = [pending drift, corrector opened]`` is that merge's state between calls:
        a call ends by writing into ``y`` the state at ``t`` computed from *copies*, so where
        a chunk ends never changes the arithmetic (resumed runs are bit-identical). With a
        symplectic corrector ``proc`` (rows of ``Z`` operators), ``xj, uj`` are the processed
        coordinates and every state written to ``y`` is corrected first.

        With events, every step end is synchronised into ``y`` and checked; ``prev``, ``prev2``
        and ``hist`` are the event-search memory (see :mod:`poissonkit.numerics.locate`).
        """
        n = m.shape[0]
        ybuf = y.copy()
        r = np.empty((n, 3))
        u = np.empty((n, 3))
        a = np.empty((n, 3))
        aj = np.empty((n, 3))
        xt = np.empty((n, 3))
        a_plus = np.empty((n, 3))
        ns = dk.shape[0]
        nsave = 0
        pending = carried[0]
        opened = carried[1] != 0.0
        track = contact > 0.0 or escape > 0.0 or watch > 0.0
        # the corrector kick: with a symplectic corrector in the middle of the (one-stage)
        # step, sharing the kick's force evaluation; else on both ends (SABAC_n)
        mid = tau != 0.0 and proc.shape[0] > 0
        ends = tau != 0.0 and not mid
        ok = True
        t = t_orig + step0 * h
        next_save = (step0 // save_every + 1) * save_every
        k = 0
        while k < max_steps:
            if pure_gravity and not track and not ends:
                # the steps before the next one that writes out, in one tight call
                free = min(max_steps - k, next_save - (step0 + k) - 1,
                           n_total - (step0 + k) - 1)
                if free > 0:
                    pending, fine = gravity_steps(xj, uj, free, pending, c, dk, h,
                                                  2.0 * tau if mid else 0.0, m, mfrac, inv_eta,
                                                  gm, gmass, r, a, aj, xt, a_plus)
                    ok = fine and ok
                    k += free
                    t = t_orig + (step0 + k) * h
                    continue
            gstep = step0 + k + 1
            if track:
                remember(y, prev, prev2, hist, t)
            if ends and not opened:
                if pure_gravity:
                    gravity_correct(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, r, a, aj, xt,
                                    a_plus)
                else:
                    correct(xj, uj, tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt,
                            a_plus, data, work)
            ok = drift_all(xj, uj, gm, pending + c[0] * h) and ok
            pending = 0.0
            for s in range(ns):
                # (the gravity-only calls take no force-kernel tuple: passing it, even to an
                # inlined function, costs reference counting at every call)
                if pure_gravity and mid:
                    gravity_modified_kick(xj, uj, dk[s] * h, 2.0 * tau, m, mfrac, inv_eta, gm,
                                          gmass, r, a, aj, xt, a_plus)
                elif pure_gravity:
                    gravity_kick(xj, uj, dk[s] * h, m, mfrac, inv_eta, gm, gmass, r, a, aj)
                elif mid:
                    modified_kick(xj, uj, dk[s] * h, 2.0 * tau, m, mfrac, inv_eta, gm, gmass,
                                  ybuf, r, a, aj, xt, a_plus, data, work)
                else:
                    kick(xj, uj, dk[s] * h, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, data,
                         work)
                if s + 1 < ns:
                    ok = drift_all(xj, uj, gm, c[s + 1] * h) and ok
            last = gstep >= n_total
            k += 1
            t = t_orig + gstep * h
            saving = gstep == next_save  # (a counter: no integer division per step)
            if saving:
                next_save += save_every
            need = last or saving or track
            if ends:
                ok = drift_all(xj, uj, gm, c[ns] * h) and ok
                tau_end = tau if need else 2.0 * tau
                if pure_gravity:
                    gravity_correct(xj, uj, tau_end, m, mfrac, inv_eta, gm, gmass, r, a, aj, xt,
                                    a_plus)
                else:
                    correct(xj, uj, tau_end, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt,
                            a_plus, data, work)
                opened = not need
            elif need:
                ok = drift_all(xj, uj, gm, c[ns] * h) and ok
            else:
                pending = c[ns] * h
            if not need:
                continue
            ok = sync_processed(xj, uj, proc, h, m, mfrac, inv_eta, gm, gmass, data, work, y, r,
                                u) and ok
            if not ok or not all_finite(y):
                carried[0] = pending
                carried[1] = 1.0 if opened else 0.0
                return 1, t, k, nsave, 0.0
            flag, value = check(y, data, work, contact, escape, watch, hist)
            if last or saving:
                out_t[nsave] = t
                copy_row(y, out_y, nsave)
                nsave += 1
            if flag != 0:
                return flag, t, k, nsave, value
            if last:
                return 5, t, k, nsave, 0.0
            if nsave == out_t.shape[0]:
                return 4, t, k, nsave, 0.0
        # chunk done between saves: the state at t, from copies (the merge state is kept)
        carried[0] = pending
        carried[1] = 1.0 if opened else 0.0
        xc = xj.copy()
        uc = uj.copy()
        ok = drift_all(xc, uc, gm, pending) and ok
        if opened:
            correct(xc, uc, -tau, m, mfrac, inv_eta, gm, gmass, ybuf, r, a, aj, xt, a_plus, data,
                    work)
        ok = sync_processed(xc, uc, proc, h, m, mfrac, inv_eta, gm, gmass, data, work, y, r,
                            u) and ok
        return 0 if ok else 1, t, k, nsave, 0.0

    _runners[key] = (run, process, kernels)
    return run, process


class WisdomHolman:
    """Wisdom–Holman splittings in Jacobi coordinates (see the module docstring).

    Parameters
    ----------
    stages
        ``n`` = 1 … 4 kicks per step of ``SABA_n`` (``n = 1``: the classical Wisdom–Holman map).
    corrector
        Add the ``SABAC_n`` corrector (removes the ``ε² h²`` error term; 3 extra force
        evaluations per step).
    table
        ``""`` for ``SABA_n``, else one of the Blanes et al. (2013) methods ``"10_4"``,
        ``"8_6_4"``, ``"10_6_4"``, ``"h8_4_4"``, ``"h8_6_4"``, ``"h10_6_4"`` (see
        :mod:`~poissonkit.numerics.integrators.wh_tables`; ``stages`` is then ignored).
    correctors
        Order 3, 5, 7, 11 or 17 of the Wisdom–Holman–Touma symplectic corrector applied to the
        map with ``stages = 1`` (as WHFast's ``corrector``), 0 for none: the state is carried in
        processed coordinates and corrected only where it is written out.

    Notes
    -----
    Needs an :class:`~poissonkit.numerics.nbody.NBodySystem` of moving point masses (no tops, no
    fixed bodies) with orientation-free potentials including Newtonian gravity between every
    pair (``AllPairs("gravity")``); body 0 is the central mass. When gravity is the only
    interaction (and there is no cutoff) the kick is a dedicated pair loop.
    """

    family = "hierarchical"
    capabilities = WISDOM_HOLMAN

    def __init__(self, stages: int = 1, corrector: bool = False, table: str = "",
                 correctors: int = 0) -> None:
        self.table = str(table)
        self.correctors = int(correctors)
        self.stages = int(stages)
        self.corrector = bool(corrector)
        if self.table:
            if self.corrector or self.correctors:
                raise InputError("the Blanes et al. tables take no corrector")
            self.c, self.d = blanes_coefficients(self.table)
            self.order = min(TABLE_ORDERS[self.table])
        else:
            self.c, self.d = saba_coefficients(self.stages)
            self.order = 4 if (self.corrector and self.stages >= 2) else 2
        # corrector kick τ = g h³ on each side of a step (SABAC_n: g = −g_n/2). With the
        # symplectic corrector, the ε² h² term left by the conjugation is half the kernel's:
        # half the kick cancels both (as WHFast's modified kick, h²/12 of the jerk per step,
        # against SABACM_1's h²/6)
        self.g = -CORRECTOR_G[self.stages] / 2.0 if self.corrector else 0.0
        if self.corrector and self.correctors:
            self.g /= 2.0
        self.proc = np.zeros((0, 2))
        if self.correctors:
            if self.table or self.stages != 1:
                raise InputError("symplectic correctors (correctors=k) apply to the Wisdom–Holman"
                                 f" map, stages=1; got stages={self.stages}")
            self.proc = corrector_operators(self.correctors)
        base = "wisdom_holman" + ("_corrected" if corrector else "")
        if self.table:
            self.name = f"{base}_{self.table}"
        else:
            self.name = base + (f"{self.stages}" if self.stages != 1 else "")
        if self.correctors:
            self.name += f"_c{self.correctors}"

    def integrate(self, system: System, y0: np.ndarray, t_end: float, *,
                  step: float | None, tol: float | None, events: Sequence[Event] = (),
                  progress: bool = False, save_every: int = 1, t0: float = 0.0,
                  control: Control | None = None) -> RawResult:
        """Integrate from ``t0`` to ``t_end`` with fixed step ``step`` on the shared driver
        (:func:`~poissonkit.numerics.integrators.driver.drive`: located events, checkpoints,
        streaming, stop requests)."""
        from poissonkit.numerics.nbody.system import NBodySystem

        # (an NBodySystem has all three; the Protocol checks are slow next to a short run)
        if not (isinstance(system, NBodySystem) or (
                isinstance(system, HasGravity) and isinstance(system, HasBodies)
                and isinstance(system, HasCompiledKernels))) or system.kernels.forces is None:
            raise InputError(f"{self.name} needs an NBodySystem of point masses with gravity; "
                             f"{type(system).__name__} is not one — use a splitting instead")
        G = system.gravity_constant()  # raises a typed error naming what is missing
        if system.n_tops or system.n_moving != len(system.bodies):
            raise InputError(f"{self.name} needs moving point masses only (no tops, no fixed "
                             "bodies)")
        if isinstance(system, NBodySystem) and system.fields:
            # the Jacobi splitting lets the centre of mass drift freely: an external force on
            # it has no place in the kick
            raise InputError(f"{self.name} does not take external fields (the centre of mass "
                             "would drift freely); use a splitting instead")
        kernels = system.kernels
        h = check_step(step, t_end - t0, self.name)
        span = t_end - t0
        n_total = max(1, math.ceil(span / h - 1e-12))
        h = span / n_total
        contact, escape, watch = event_thresholds(events)
        run, process = _runner(kernels, _gravity_only(system))
        y = np.array(y0, dtype=float)
        m = np.ascontiguousarray(system.data[0], dtype=float)
        eta = np.cumsum(m)
        mfrac, inv_eta = m / eta, 1.0 / eta
        gm = G * eta
        gmass = G * m
        data, work = system.data, system.work()
        proc = self.proc
        xj, uj = _jacobi_of(y, m)
        if proc.shape[0]:  # physical → processed coordinates
            process(xj, uj, proc, -1.0, h, m, mfrac, inv_eta, gm, gmass, data, work)
        tau = self.g * h ** 3
        c, dk = self.c, self.d
        per_step = dk.shape[0] + (3 if self.corrector else 0)
        scratch = SaveBuffer(y.size, 4)
        no_hist = np.zeros(5)

        def chunk(st: LoopState, max_steps: int, buf: SaveBuffer
                  ) -> tuple[int, float, int, int, int, float]:
            start = {key: arr.copy() for key, arr in st.carry.items()}
            try:
                status, t_new, k, nsave, value = run(
                    st.y, st.carry["xj"], st.carry["uj"], st.carry["merge"], m, mfrac, inv_eta,
                    gm, gmass, t0, h, n_total, c, dk, tau, proc, data, work, save_every,
                    st.steps, max_steps, buf.cur_t, buf.cur_y, contact, escape, watch, st.prev,
                    st.prev2, st.hist)
            except ZeroDivisionError:
                raise locate_division(self.name, _replay(start), st.y, st.t, st.steps) from None
            return status, t_new, k, nsave, k * per_step, value

        def _replay(start: dict[str, np.ndarray]) -> StepFn:
            def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
                out = run(ys, start["xj"], start["uj"], start["merge"], m, mfrac, inv_eta, gm,
                          gmass, t0, h, n_total, c, dk, tau, proc, data, work, save_every, done,
                          1, scratch.cur_t, scratch.cur_y, 0.0, 0.0, 0.0, ys, ys, no_hist)
                return out[0], out[1]
            return one_step

        def advance(ys: np.ndarray, s: float) -> np.ndarray:
            # one whole step of length s from a state (event location)
            yc = np.array(ys, dtype=float)
            xs, us = _jacobi_of(yc, m)
            if proc.shape[0]:
                process(xs, us, proc, -1.0, s, m, mfrac, inv_eta, gm, gmass, data, work)
            ts = self.g * s ** 3
            run(yc, xs, us, np.zeros(2), m, mfrac, inv_eta, gm, gmass, 0.0, s, 1, c, dk, ts,
                proc, data, work, 1, 0, 1, scratch.cur_t, scratch.cur_y, 0.0, 0.0, 0.0, yc, yc,
                no_hist)
            return yc

        problem = {"method": self.name, "h": float(h).hex(), "t0": float(t0).hex(),
                   "t_end": float(t_end).hex(), "n_total": n_total, "save_every": save_every,
                   "dim": int(y.size), "G": float(G).hex(), "y0": state_digest(y)}
        raw = drive(self.name, system, y, t0, t_end, events=events, progress=progress,
                    save_every=save_every, control=control, chunk=chunk, advance=advance,
                    done=lambda st: st.steps >= n_total, failure=lambda status, st: None,
                    problem=problem, buffer_rows=min(n_total // save_every + 2, 4096),
                    carry={"xj": xj, "uj": uj, "merge": np.zeros(2)})
        raw.nfev = raw.steps * per_step
        raw.extra.update(step=h, stages=self.stages, corrector=self.corrector)
        if self.table:
            raw.extra["table"] = self.table
        if self.correctors:
            raw.extra["correctors"] = self.correctors
        return raw


def _gravity_only(system: System) -> bool:
    """True when Newtonian gravity over all bodies is the system's only interaction (no
    cutoff, no external field): the kick can then use :func:`gravity_kick_accel`."""
    from poissonkit.numerics.nbody.system import NBodySystem

    return (isinstance(system, NBodySystem) and len(system.interactions) == 1
            and system.cutoff is None and not system.fields)


def _jacobi_of(y: np.ndarray, m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Jacobi positions and velocities (row 0: centre of mass) of an N-body state ``y``."""
    n = m.shape[0]
    rp = y.reshape(n, 2, 3)
    xj, uj = np.empty((n, 3)), np.empty((n, 3))
    to_jacobi(np.ascontiguousarray(rp[:, 0]), np.ascontiguousarray(rp[:, 1] / m[:, None]),
              m, xj, uj)
    return xj, uj
