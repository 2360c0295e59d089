"""Compiled pieces of the N-body kernels that do not depend on the potentials.

They read or move the state vector alone: gather the bodies' positions and axes, kick by
forces already computed (plain or Kahan-compensated: one source, two ``add`` functions), the
free flight and free rotation (drift, also compensated), the kinetic energy and the distances
that events test. Together they are the general :data:`GENERAL` layout on which
:mod:`~poissonkit.numerics.nbody.assemble` builds the kernels of any sum of force terms. Every
system shares one compilation of each.

``data`` is the system's :class:`~poissonkit.numerics.nbody.data.SystemData` and ``work`` its
:class:`~poissonkit.numerics.nbody.data.Work`.
"""

from __future__ import annotations

import math

import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import (kahan_add, plain_add, rotate_slot, rotate_slot_compensated,
                                         zero2)
from poissonkit.numerics.nbody.assemble import Layout


def _gather(y, data, pos, nu):
    """Positions and axes of every body (moving ones from ``y``, fixed ones from ``data``)."""
    mass = data.mass
    bslot = data.body_slot
    tslot = data.top_slot
    fpos = data.fixed_pos
    fnu = data.fixed_axis
    nm = mass.shape[0]
    axes = data.any_tops
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


def _pusher(add: Dispatcher) -> Dispatcher:
    """``push(y, c, h, data, work)``: every moving body's ``p`` and top's ``m`` += ``h`` times
    the forces ``work.F`` and torques ``work.T``, each increment through ``add(y, c, i, v)``
    (:func:`~poissonkit.numerics.kernels.plain_add` or
    :func:`~poissonkit.numerics.kernels.kahan_add`)."""

    @jit(inline="always")
    def push(y, c, h, data, work):
        F = work.F
        T = work.T
        nm = data.mass.shape[0]
        bslot = data.body_slot
        tslot = data.top_slot
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    add(y, c, 6 * s + 3 + d, h * F[b, d])
            t = tslot[b]
            if t >= 0:
                q = 6 * nm + 6 * t + 3
                for d in range(3):
                    add(y, c, q + d, h * T[b, d])

    return push


push_plain = _pusher(plain_add)
push_compensated = _pusher(kahan_add)


@jit
def apply_forces(y, h, data, work):
    """Kick every moving body's ``p`` and top's ``m`` by ``h`` times the forces ``work.F`` and
    torques ``work.T`` (left there by the force loop)."""
    push_plain(y, y, h, data, work)


@jit(inline="always")
def gather_work(y, data, work):
    """:func:`gather` into the scratch ``work``."""
    gather(y, data, work.pos, work.nu)


@jit(inline="always")
def gather_work_inl(y, data, work):
    """:func:`gather_work`, inlined into its caller (the hot kick and ``forces``)."""
    gather_inl(y, data, work.pos, work.nu)


@jit(inline="always")
def clear(data, work):
    """Forces (and, with tops, torques) to zero before a force term adds to them."""
    F = work.F
    for b in range(F.shape[0]):
        F[b, 0] = 0.0
        F[b, 1] = 0.0
        F[b, 2] = 0.0
    if data.any_tops:
        zero2(work.T)


@jit(inline="always")
def kinetic(y, data, e):
    """``e`` plus the kinetic energy ``Σ p²/2M + Σ α m²/2``, summed in state order."""
    mass = data.mass
    alpha = data.alpha
    nm = mass.shape[0]
    for s in range(nm):
        p2 = y[6 * s + 3] ** 2 + y[6 * s + 4] ** 2 + y[6 * s + 5] ** 2
        e += 0.5 * p2 / mass[s]
    for t in range(alpha.shape[0]):
        q = 6 * nm + 6 * t + 3
        e += 0.5 * alpha[t] * (y[q] ** 2 + y[q + 1] ** 2 + y[q + 2] ** 2)
    return e


@jit(inline="always")
def rhs_write(y, data, work, out):
    """``out = ẏ`` with the forces and torques in ``work``: ``ṙ = p/M``, ``ṗ = F``,
    ``ν̇ = α m × ν``, ``ṁ = T``."""
    F = work.F
    T = work.T
    mass = data.mass
    alpha = data.alpha
    bslot = data.body_slot
    tslot = data.top_slot
    nm = mass.shape[0]
    for b in range(bslot.shape[0]):
        s = bslot[b]
        if s >= 0:
            for d in range(3):
                out[6 * s + d] = y[6 * s + 3 + d] / mass[s]
                out[6 * s + 3 + d] = F[b, d]
        t = tslot[b]
        if t >= 0:
            q = 6 * nm + 6 * t
            a = alpha[t]
            n0, n1, n2 = y[q], y[q + 1], y[q + 2]
            m0, m1, m2 = y[q + 3], y[q + 4], y[q + 5]
            out[q] = a * (m1 * n2 - m2 * n1)
            out[q + 1] = a * (m2 * n0 - m0 * n2)
            out[q + 2] = a * (m0 * n1 - m1 * n0)
            for d in range(3):
                out[q + 3 + d] = T[b, d]


@jit
def drift(y, h, data):
    """Exact flow of the kinetic part for time ``h``: ``r += h p/M``, ``ν`` rotated about ``m``."""
    mass = data.mass
    alpha = data.alpha
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
    mass = data.mass
    alpha = data.alpha
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
    pos = work.pos
    nu = work.nu
    gather(y, data, pos, nu)
    bslot = data.body_slot
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
    mass = data.mass
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


#: The general layout: moving and fixed bodies, point masses and tops (the kernels of
#: :mod:`~poissonkit.numerics.nbody.loops`).
GENERAL = Layout(gather=gather_work, gather_inline=gather_work_inl, clear=clear,
                 push_plain=push_plain, push_compensated=push_compensated, rhs_write=rhs_write,
                 kinetic=kinetic, drift=drift, drift_compensated=drift_compensated,
                 min_distance=min_distance, max_radius=max_radius, inline_kick=False)
