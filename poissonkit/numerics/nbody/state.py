"""Compiled pieces of the N-body kernels that do not depend on the potentials.

They read or move the state vector alone: gather the bodies' positions and axes, kick by
forces already computed, the free flight and free rotation (drift, also Kahan-compensated),
and the distances that events test. Every system shares one compilation of each; the
potential-dependent kernels are assembled around them in
:mod:`~poissonkit.numerics.nbody.loops`.

``data`` is the system's constant tuple (:attr:`NBodySystem.data`): ``data[0]`` masses of the
moving bodies, ``data[1]`` ``alpha`` of the moving tops, ``data[2]``/``data[3]`` the state slot
of each body / top (``-1``: none), ``data[4]``/``data[5]`` positions and axes of fixed bodies,
``data[14]`` whether any body is a top.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import kahan_add, rotate_slot, rotate_slot_compensated


@numba.njit(cache=True, error_model="numpy")
def apply_forces(y, h, data, work):
    """Kick every moving body's ``p`` and top's ``m`` by ``h`` times the forces ``work[2]`` and
    torques ``work[3]`` (left there by the force loop)."""
    F = work[2]
    T = work[3]
    nm = data[0].shape[0]
    bslot = data[2]
    tslot = data[3]
    for b in range(bslot.shape[0]):
        s = bslot[b]
        if s >= 0:
            for d in range(3):
                y[6 * s + 3 + d] += h * F[b, d]
        t = tslot[b]
        if t >= 0:
            q = 6 * nm + 6 * t + 3
            for d in range(3):
                y[q + d] += h * T[b, d]


def _gather(y, data, pos, nu):
    """Positions and axes of every body (moving ones from ``y``, fixed ones from ``data``)."""
    mass = data[0]
    bslot = data[2]
    tslot = data[3]
    fpos = data[4]
    fnu = data[5]
    nm = mass.shape[0]
    axes = data[14]
    for b in range(bslot.shape[0]):
        s = bslot[b]
        if s >= 0:
            for d in range(3):
                pos[b, d] = y[6 * s + d]
        else:
            for d in range(3):
                pos[b, d] = fpos[b, d]
        if not axes:  # point masses only: ν and torques are never read
            continue
        t = tslot[b]
        if t >= 0:
            for d in range(3):
                nu[b, d] = y[6 * nm + 6 * t + d]
        else:
            for d in range(3):
                nu[b, d] = fnu[b, d]


# two compilations: inlined into the hot kick (numba does not inline calls between separately
# compiled functions, and the call costs as much as a small system's pair loop) and a plain
# one for the other kernels (inlining everywhere only lengthens compilation)
gather = jit(_gather)
gather_inl = jit(inline="always")(_gather)


@jit
def drift(y, h, data):
    """Exact flow of the kinetic part for time ``h``: ``r += h p/M``, ``ν`` rotated about ``m``."""
    mass = data[0]
    alpha = data[1]
    nm = mass.shape[0]
    for s in range(nm):
        c = h / mass[s]
        for d in range(3):
            y[6 * s + d] += c * y[6 * s + 3 + d]
    for t in range(alpha.shape[0]):
        q = 6 * nm + 6 * t
        rotate_slot(y, q, q + 3, alpha[t] * h)


@jit
def drift_compensated(y, c, h, data):
    """:func:`drift` with every increment added by Kahan summation (``c``: rounding errors)."""
    mass = data[0]
    alpha = data[1]
    nm = mass.shape[0]
    for s in range(nm):
        cc = h / mass[s]
        for d in range(3):
            kahan_add(y, c, 6 * s + d, cc * y[6 * s + 3 + d])
    for t in range(alpha.shape[0]):
        q = 6 * nm + 6 * t
        rotate_slot_compensated(y, c, q, q + 3, alpha[t] * h)


@jit
def min_distance(y, data, work):
    """Smallest distance between two bodies, not both fixed (``inf`` if there is no pair)."""
    pos = work[0]
    nu = work[1]
    gather(y, data, pos, nu)
    bslot = data[2]
    n = pos.shape[0]
    best = np.inf
    for a in range(n):
        for b in range(a + 1, n):
            if bslot[a] < 0 and bslot[b] < 0:
                continue
            d2 = ((pos[a, 0] - pos[b, 0]) ** 2 + (pos[a, 1] - pos[b, 1]) ** 2
                  + (pos[a, 2] - pos[b, 2]) ** 2)
            best = min(best, d2)
    return math.sqrt(best)


@jit
def max_radius(y, data):
    """Largest distance of a moving body from the moving bodies' centre of mass."""
    mass = data[0]
    nm = mass.shape[0]
    mt = 0.0
    c = np.zeros(3)
    for s in range(nm):
        mt += mass[s]
        for d in range(3):
            c[d] += mass[s] * y[6 * s + d]
    best = 0.0
    for s in range(nm):
        d2 = 0.0
        for d in range(3):
            d2 += (y[6 * s + d] - c[d] / mt) ** 2
        best = max(best, d2)
    return math.sqrt(best)
