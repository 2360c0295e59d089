"""The compiled force loop of an N-body system and the kernels built on it.

:func:`_build_kernels` composes, around one pair of potential dispatchers, the pair terms
(:mod:`~poissonkit.numerics.nbody.pairterms`), the cell-list loop
(:mod:`~poissonkit.numerics.nbody.celllists`) and the potential-free pieces
(:mod:`~poissonkit.numerics.nbody.state`) into the :class:`~poissonkit.numerics.kernels.Kernels`
every integrator uses. Kernels are cached per dispatcher, so systems with the same potentials
share one compilation.

``data`` is the system's :class:`~poissonkit.numerics.nbody.data.SystemData` and ``work`` its
:class:`~poissonkit.numerics.nbody.data.Work` (``pos, nu, F, T`` and, for a system with a skin,
its neighbour lists, :mod:`~poissonkit.numerics.nbody.verlet`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import Kernels, kahan_add, zero2
from poissonkit.numerics.nbody.celllists import cell_loops
from poissonkit.numerics.nbody.pairterms import pair_terms
from poissonkit.numerics.nbody.state import (
    apply_forces,
    drift,
    drift_compensated,
    gather,
    gather_inl,
    max_radius,
    min_distance,
)
from poissonkit.numerics.nbody.verlet import verlet_loops


class ForceLoops(NamedTuple):
    """One force loop compiled twice (see :func:`force_loops`)."""

    #: ``forces(pos, nu, data, F, T, lists) -> U``, a separate compiled function
    plain: Dispatcher
    #: the same, inlined into its callers (the hot kick)
    inline: Dispatcher


def force_loops(pair_term: Dispatcher, pair_r: Dispatcher, all_pairs_r: Dispatcher,
                set_pairs: Dispatcher) -> ForceLoops:
    """``forces(pos, nu, data, F, T, lists) -> U``: every pair of the system, forces into ``F``
    and torques into ``T`` (rows: all bodies; ``T`` untouched for point masses only).

    ``set_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, lists, s)`` is the
    pair loop of all-pairs set ``s`` with a cutoff: the cell loop (``lists`` is ``None``) or
    the neighbour-list loop (``lists``: the system's Verlet state, ``work.lists``).
    """

    def forces_py(pos, nu, data, F, T, lists):
        pairs = data.pairs
        cmembers = data.set_members
        coffs = data.set_offsets
        cgid = data.set_kernel
        cutoff = data.cutoff
        B = data.table
        rpairs = data.radial_pairs
        ccentral = data.set_central
        axes = data.any_tops
        for b in range(F.shape[0]):
            F[b, 0] = 0.0
            F[b, 1] = 0.0
            F[b, 2] = 0.0
        if axes:
            zero2(T)
        cut2 = cutoff * cutoff if np.isfinite(cutoff) else np.inf
        rs = data.switch_start
        # (cutoff², switch start², switch start, 1 / switch width); no switch: start = inf
        cut = (cut2, rs * rs, rs, 1.0 / (cutoff - rs) if rs < cutoff else 0.0)
        u = 0.0
        for k in range(pairs.shape[0]):
            i = pairs[k, 0]
            j = pairs[k, 1]
            u += pair_term(pairs[k, 2], i, j, pos, nu, F, T, cut, B, i, j)
        for k in range(rpairs.shape[0]):
            i = rpairs[k, 0]
            j = rpairs[k, 1]
            u += pair_r(rpairs[k, 2], i, j, pos, F, cut, B, i, j)
        for g in range(cgid.shape[0]):
            gid = cgid[g]
            central = ccentral[g] != 0
            lo = coffs[g]
            hi = coffs[g + 1]
            if np.isfinite(cutoff):
                u += set_pairs(gid, central, cmembers[lo:hi], pos, nu, F, T, cutoff, B, cut,
                               data.parallel_min, lists, g)
            elif central:
                u += all_pairs_r(gid, cmembers, lo, hi, pos, F, B)
            else:
                for a in range(lo, hi):
                    for b in range(a + 1, hi):
                        ia = cmembers[a]
                        ib = cmembers[b]
                        u += pair_term(gid, ia, ib, pos, nu, F, T, cut, B, ia, ib)
        return u

    # two compilations, as for ``gather`` (see state.py): inlined into the hot kick, plain
    # for the other kernels
    return ForceLoops(plain=jit(forces_py), inline=jit(inline="always")(forces_py))


#: (id of kern_any, parallel, verlet) -> kernels
_kernel_cache: dict[tuple[int, bool, bool], Kernels] = {}


def _build_kernels(kern_any: Dispatcher, kern_r: Dispatcher, parallel: bool = False,
                   verlet: bool = False) -> Kernels:
    """Compile the N-body kernels around one pair of potential dispatchers (cached).

    ``parallel`` adds the multi-threaded pair loop (chosen at run time by the number of
    members, ``data.parallel_min``); without it only the serial loop exists. ``verlet`` walks
    neighbour lists kept in ``work.lists`` (:mod:`~poissonkit.numerics.nbody.verlet`) instead of
    building a cell list at every evaluation.
    """
    hit = _kernel_cache.get((id(kern_any), parallel, verlet))
    if hit is not None:
        return hit
    terms = pair_terms(kern_any, kern_r)
    if verlet:
        set_pairs = verlet_loops(terms.one, terms.radial_one, parallel)
    else:
        cells = cell_loops(terms.one, terms.radial_one, parallel)

        @jit(inline="always")
        def set_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, lists, s):
            return cells(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n)
    forces, forces_inl = force_loops(terms.term, terms.radial, terms.all_radial, set_pairs)

    @jit
    def rhs(y, data, work, out):
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        mass = data.mass
        alpha = data.alpha
        bslot = data.body_slot
        tslot = data.top_slot
        nm = mass.shape[0]
        gather(y, data, pos, nu)
        forces(pos, nu, data, F, T, work.lists)
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
    def kick(y, h, data, work):
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        gather_inl(y, data, pos, nu)
        forces_inl(pos, nu, data, F, T, work.lists)
        apply_forces(y, h, data, work)

    @jit
    def kick_compensated(y, c, h, data, work):
        # as kick, every increment added with Kahan summation (c: rounding errors so far)
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        mass = data.mass
        bslot = data.body_slot
        tslot = data.top_slot
        nm = mass.shape[0]
        gather_inl(y, data, pos, nu)
        forces_inl(pos, nu, data, F, T, work.lists)
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    kahan_add(y, c, 6 * s + 3 + d, h * F[b, d])
            t = tslot[b]
            if t >= 0:
                q = 6 * nm + 6 * t + 3
                for d in range(3):
                    kahan_add(y, c, q + d, h * T[b, d])

    @jit
    def energy(y, data, work):
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        mass = data.mass
        alpha = data.alpha
        nm = mass.shape[0]
        gather(y, data, pos, nu)
        e = forces(pos, nu, data, F, T, work.lists)
        for s in range(nm):
            p2 = y[6 * s + 3] ** 2 + y[6 * s + 4] ** 2 + y[6 * s + 5] ** 2
            e += 0.5 * p2 / mass[s]
        for t in range(alpha.shape[0]):
            q = 6 * nm + 6 * t + 3
            e += 0.5 * alpha[t] * (y[q] ** 2 + y[q + 1] ** 2 + y[q + 2] ** 2)
        return e

    @jit(inline="always")
    def forces_of(y, data, work):
        """Forces and torques into ``work.F``, ``work.T`` (rows: all bodies); returns U."""
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        gather_inl(y, data, pos, nu)
        return forces_inl(pos, nu, data, F, T, work.lists)

    out = Kernels(rhs=rhs, drift=drift, kick=kick, energy=energy, min_distance=min_distance,
                  max_radius=max_radius, jac=None, splittable=True, forces=forces_of,
                  drift_compensated=drift_compensated, kick_compensated=kick_compensated)
    _kernel_cache[(id(kern_any), parallel, verlet)] = out
    return out
