"""Direct-sum kernels: the lean form of a system of moving point masses.

When every body moves, none is a top, there is no cutoff and every interaction is an
orientation-free :class:`~poissonkit.numerics.nbody.AllPairs` set (gravity, any ``U(r)``), a
step needs little of the general N-body machinery: no fixed bodies to gather, no axes or
torques, no listed pairs, no cell list. The kernels here take the short
:class:`~poissonkit.numerics.nbody.data.DirectData` (masses, the members, offsets and kernel of
each all-pairs set, the per-body attribute table) and the scratch
:class:`~poissonkit.numerics.nbody.data.DirectWork` (``pos, F``). The kick is inlined into the
compiled time loop that calls it, so the loop reads the arrays once per chunk of steps instead
of copying the general data and its reference counts at every kick.

The kernels come from the same generator as the general ones
(:mod:`~poissonkit.numerics.nbody.assemble`), on the point-mass layout :data:`POINT_MASSES`
with the direct-sum term; the arithmetic is the general kernels' operation for
operation — the same all-pairs loop of the same pair terms, the same order of sums — so a run
gives the same numbers bit for bit; a test compares both on every kernel.
"""

from __future__ import annotations

import math

from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import Kernels, kahan_add, plain_add
from poissonkit.numerics.nbody.assemble import Layout, Term, assemble
from poissonkit.numerics.nbody.pairterms import pair_terms
from poissonkit.numerics.nbody.state import max_radius


@jit(inline="always")
def _drift(y, h, data):
    mass = data.mass
    for s in range(mass.shape[0]):
        c = h / mass[s]
        for d in range(3):
            y[6 * s + d] += c * y[6 * s + 3 + d]


@jit(inline="always")
def _drift_compensated(y, c, h, data):
    mass = data.mass
    for s in range(mass.shape[0]):
        cc = h / mass[s]
        for d in range(3):
            kahan_add(y, c, 6 * s + d, cc * y[6 * s + 3 + d])


@jit
def _min_distance(y, data, work):
    n = data.mass.shape[0]
    best = math.inf
    for a in range(n):
        for b in range(a + 1, n):
            d2 = ((y[6 * a] - y[6 * b]) ** 2 + (y[6 * a + 1] - y[6 * b + 1]) ** 2
                  + (y[6 * a + 2] - y[6 * b + 2]) ** 2)
            best = min(best, d2)
    return math.sqrt(best)


@jit(inline="always")
def _gather(y, data, work):
    pos = work.pos
    for b in range(pos.shape[0]):
        for d in range(3):
            pos[b, d] = y[6 * b + d]


@jit(inline="always")
def _clear(data, work):
    F = work.F
    for b in range(F.shape[0]):
        for d in range(3):
            F[b, d] = 0.0


def _pusher(add: Dispatcher) -> Dispatcher:
    """``push(y, c, h, data, work)``: every ``p`` += ``h F`` through ``add(y, c, i, v)``."""

    @jit(inline="always")
    def push(y, c, h, data, work):
        F = work.F
        for b in range(F.shape[0]):
            for d in range(3):
                add(y, c, 6 * b + 3 + d, h * F[b, d])

    return push


@jit(inline="always")
def _rhs_write(y, data, work, out):
    mass = data.mass
    F = work.F
    for s in range(mass.shape[0]):
        for d in range(3):
            out[6 * s + d] = y[6 * s + 3 + d] / mass[s]
            out[6 * s + 3 + d] = F[s, d]


@jit(inline="always")
def _kinetic(y, data, e):
    mass = data.mass
    for s in range(mass.shape[0]):
        p2 = y[6 * s + 3] ** 2 + y[6 * s + 4] ** 2 + y[6 * s + 5] ** 2
        e += 0.5 * p2 / mass[s]
    return e


#: The point-mass layout: every body moves, none is a top, no fixed bodies. Its kick is
#: inlined into the compiled time loop that calls it.
POINT_MASSES = Layout(gather=_gather, gather_inline=_gather, clear=_clear,
                      push_plain=_pusher(plain_add), push_compensated=_pusher(kahan_add),
                      rhs_write=_rhs_write, kinetic=_kinetic, drift=_drift,
                      drift_compensated=_drift_compensated, min_distance=_min_distance,
                      max_radius=max_radius, inline_kick=True)

#: id of the radial dispatcher -> (the direct-sum term, dispatchers kept alive so the id
#: stays unique)
_cache: dict[int, tuple[Term, Dispatcher, Dispatcher]] = {}


def direct_term(kern_any: Dispatcher, kern_r: Dispatcher) -> Term:
    """The direct sum over every all-pairs set, orientation-free, no cutoff (cached):
    ``forces(data, work) -> U`` adding to ``work.F``."""
    hit = _cache.get(id(kern_r))
    if hit is not None:
        return hit[0]
    all_pairs_r = pair_terms(kern_any, kern_r).all_radial

    @jit(inline="always")
    def forces(data, work):
        members = data.set_members
        offs = data.set_offsets
        gids = data.set_kernel
        B = data.table
        pos = work.pos
        F = work.F
        u = 0.0
        for g in range(gids.shape[0]):
            u += all_pairs_r(gids[g], members, offs[g], offs[g + 1], pos, F, B)
        return u

    out = Term(plain=forces, inline=forces, allocates=False)
    _cache[id(kern_r)] = (out, kern_any, kern_r)
    return out


def direct_kernels(kern_any: Dispatcher, kern_r: Dispatcher) -> Kernels:
    """The direct-sum kernels around a system's potential dispatchers (cached).

    ``kern_any``/``kern_r`` are the dispatchers of
    :func:`~poissonkit.numerics.nbody.pairkernels._dispatcher`; only the orientation-free
    ``kern_r`` is evaluated. Signatures are those of :mod:`poissonkit.numerics.kernels`, with
    the short ``data`` and ``work`` of the module docstring: the generator of
    :mod:`~poissonkit.numerics.nbody.assemble` specialised to :data:`POINT_MASSES`.
    """
    return assemble(POINT_MASSES, (direct_term(kern_any, kern_r),))
