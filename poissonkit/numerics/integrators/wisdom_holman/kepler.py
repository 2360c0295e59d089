"""The exact Kepler flow of the Jacobi rows: Stumpff functions and a universal-variable solver.

Danby's f and g functions in universal variables; Halley's iteration from a series solution,
bisection as a safeguard (see :func:`kepler_drift`).
"""

from __future__ import annotations

import math

import numba

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
