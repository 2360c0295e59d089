"""Verlet neighbour lists: the cell-list pairs kept between force evaluations.

A system built with ``NBodySystem(..., skin=s)`` lists, once, every pair of an
:class:`~poissonkit.numerics.nbody.AllPairs` set closer than ``cutoff + s`` (found with a cell
list of side ``cutoff + s``, :func:`verlet_build`), and later evaluations walk that list instead
of testing the 27-cell neighbourhood of every body again. Every evaluation first compares each
body's position with its position when the list was built; if any body has moved more than
``s/2`` the list is rebuilt before it is used, so a pair closer than the cutoff is always on the
list (two bodies that each moved at most ``s/2`` were at most ``s`` farther apart at the build).
The walk still tests every listed pair against the cutoff itself: the pairs evaluated, and so
the forces (the exact gradient of the same potential), are those of the cell-list loop.

The list keeps the cell loop's order and its x-slabs (:mod:`~poissonkit.numerics.nbody.celllists`):
pairs whose first slot lies in slab ``x`` have their second slot in slab ``x`` or ``x + 1``, so
the slabs can run on any threads with the same two accumulators per body and the same numbers
bit for bit, serial or parallel. The order is the one of the list's last build, so the last bits
of a force depend on when the list was built (a run and the same run resumed from its middle
may differ in round-off); a fresh list (``system.forces``, ``system.energy``) sums in the order
of a cell list of side ``cutoff + s`` at the current positions.

The list lives in the scratch of a system (``work().lists``, a
:class:`~poissonkit.numerics.nbody.data.VerletState`): ``(ints, nbrs, refs, skin)``,
per all-pairs set ``k`` the arrays ``ints[3k : 3k + 3]`` = slot → body, CSR offsets and first
slot of each slab, ``nbrs[k]`` the neighbour slots (32-bit: the list is the largest array a
walk reads) and ``refs[k]`` the positions at the build (slot order).
"""

from __future__ import annotations

import os
from collections.abc import Callable

import numba
import numpy as np
from numba.core.dispatcher import Dispatcher
from numba.typed import List

from poissonkit.numerics.jit import jit
from poissonkit.numerics.nbody.celllists import (
    cell_list,
    cell_list_par,
    forward_cells,
    slab_parts,
    slot_sums,
    threads_now,
)
from poissonkit.numerics.nbody.data import VerletState


@numba.njit(cache=True)
def _empty_lists(nsets):
    ints = List()
    nbrs = List()
    refs = List()
    for _ in range(nsets):
        for _ in range(3):
            ints.append(np.zeros(0, dtype=np.int64))
        nbrs.append(np.zeros(0, dtype=np.uint32))
        refs.append(np.zeros((0, 3)))
    return ints, nbrs, refs


def new_verlet_state(nsets: int, skin: float) -> VerletState:
    """An empty neighbour-list state for ``nsets`` all-pairs sets and skin ``skin``.

    The lists are built on the first force evaluation that uses them.
    """
    ints, nbrs, refs = _empty_lists(nsets)
    return VerletState(ints, nbrs, refs, float(skin))


def _builder(cells: Dispatcher) -> Callable:
    """The list builder around the cell-list builder ``cells`` (serial or parallel)."""

    def _build_py(members, pos, radius):
        """The pairs of ``members`` closer than ``radius``, in the cell loop's order.

        Returns ``(body, start, nbr, slab_first, ref)``: the body of each slot (slots sorted by
        cell of side ≥ ``radius``), the CSR offsets ``start[q]:start[q + 1]`` into ``nbr`` of the
        later slots listed for slot ``q`` (its own cell's later slots, then the 13 forward cells in
        increasing index), the first slot of each x-slab (one more entry than slabs) and the
        positions of the slots. Slabs are listed independently (on threads in the parallel
        compilation) into segments sized for every candidate pair, then packed in slab order: the
        list is the same whoever builds it.
        """
        n = members.shape[0]
        nc, count, _, sp_, _, body = cells(members, pos, pos, radius)
        r2 = radius * radius
        per_slab = nc[1] * nc[2]
        ns = nc[0]
        slab_first = np.empty(ns + 1, dtype=np.int64)
        for x in range(ns + 1):
            slab_first[x] = count[x * per_slab]
        # room for every candidate pair of each slab (an upper bound), so no list grows
        room = np.zeros(ns + 1, dtype=np.int64)
        for x in numba.prange(ns):
            fwd = np.empty(13, dtype=np.int64)
            cap = 0
            for c in range(x * per_slab, (x + 1) * per_slab):
                k_c = count[c + 1] - count[c]
                if k_c == 0:
                    continue
                nf = forward_cells(c, nc, fwd)
                around = 0
                for k in range(nf):
                    around += count[fwd[k] + 1] - count[fwd[k]]
                cap += k_c * (k_c - 1) // 2 + k_c * around
            room[x + 1] = cap
        for x in range(ns):
            room[x + 1] += room[x]
        buf = np.empty(room[ns] + 1, dtype=np.uint32)
        start = np.empty(n + 1, dtype=np.int64)
        kept = np.zeros(ns + 1, dtype=np.int64)
        for x in numba.prange(ns):
            fwd = np.empty(13, dtype=np.int64)
            m = room[x]
            for c in range(x * per_slab, (x + 1) * per_slab):
                if count[c] == count[c + 1]:
                    continue
                nf = forward_cells(c, nc, fwd)
                for qa in range(count[c], count[c + 1]):
                    start[qa] = m
                    xa, ya, za = sp_[qa, 0], sp_[qa, 1], sp_[qa, 2]
                    for k in range(-1, nf):
                        c2 = c if k < 0 else fwd[k]
                        for qb in range(qa + 1 if k < 0 else count[c2], count[c2 + 1]):
                            dx = sp_[qb, 0] - xa
                            dy = sp_[qb, 1] - ya
                            dz = sp_[qb, 2] - za
                            # branch-free: about one candidate in six is kept, a branch mispredicts
                            buf[m] = qb
                            m += 1 if dx * dx + dy * dy + dz * dz <= r2 else 0
            kept[x + 1] = m - room[x]
        for x in range(ns):
            kept[x + 1] += kept[x]
        nbr = np.empty(kept[ns], dtype=np.uint32)
        for x in numba.prange(ns):
            shift = room[x] - kept[x]
            for k in range(kept[x], kept[x + 1]):
                nbr[k] = buf[k + shift]
            for q in range(slab_first[x], slab_first[x + 1]):
                start[q] -= shift
        start[n] = kept[ns]
        return body, start, nbr, slab_first, sp_

    return _build_py


#: the list builder, one thread (numba.prange is range here)
verlet_build = jit(_builder(cell_list))
#: the list builder, slabs on numba's threads; the same list
verlet_build_par = jit(parallel=True)(_builder(cell_list_par))


@jit(inline="always")
def in_order(start, slab_first):
    """All slabs in one part, in order (the serial walk)."""
    ns = slab_first.shape[0] - 1
    return np.arange(ns), np.array([0, ns])


@jit(inline="always")
def per_thread(start, slab_first):
    """The slabs in one part per thread (:func:`~poissonkit.numerics.nbody.celllists.slab_parts`),
    a slab's work counted as its listed pairs plus its bodies."""
    ns = slab_first.shape[0] - 1
    w = np.empty(ns, dtype=np.int64)
    for x in range(ns):
        w[x] = (start[slab_first[x + 1]] - start[slab_first[x]]
                + slab_first[x + 1] - slab_first[x])
    return slab_parts(w, threads_now())


def verlet_loops(pair_one: Dispatcher, pair_r_one: Dispatcher, parallel: bool) -> Dispatcher:
    """The neighbour-list pair loop around the pair terms ``pair_one`` and ``pair_r_one``.

    Returns ``listed(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, state, s) -> U``,
    the drop-in counterpart of :func:`~poissonkit.numerics.nbody.celllists.cell_loops`'s
    ``cells`` for all-pairs set ``s`` of a system with neighbour lists ``state``. With
    ``parallel`` the slabs run on numba's threads once there are ``min_n`` members.
    """
    if parallel:
        # see cell_loops: OpenMP's spinning wait costs dearly on a shared machine
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    opened, add_pair, closed = slot_sums(pair_one, pair_r_one)

    @jit(inline="always")
    def slab_walk(x, g, central, slab_first, start, nbr, sp_, sn_, body, W, V, cut, B, cut2):
        """The listed pairs whose first slot lies in slab ``x``, as ``slab_pairs`` of the cell
        loop: one evaluation per pair, a body's share to ``W[0, q]`` / ``V[0, q]`` from its own
        slab and to ``W[1, q]`` / ``V[1, q]`` from the slab before."""
        first_next = slab_first[x + 1]
        u = 0.0
        for qa in range(slab_first[x], first_next):
            xa, ya, za = sp_[qa, 0], sp_[qa, 1], sp_[qa, 2]
            acc = opened(W, V, qa)
            for k in range(start[qa], start[qa + 1]):
                qb = nbr[k]
                h = 1 if qb >= first_next else 0
                acc = add_pair(acc, g, central, qa, qb, h, sp_, sn_, body, W, V, cut, B, cut2,
                               xa, ya, za)
            u += closed(W, V, qa, acc)
        return u

    def walk_py(order, first, us, g, central, slab_first, start, nbr, sp_, sn_, body, W, V,
                cut, B, cut2):
        """The slabs of part ``p``, ``order[first[p]:first[p + 1]]``, for every part (parts on
        numba's threads in a parallel caller): slab ``x``'s energy to ``us[x]``."""
        for p in numba.prange(first.shape[0] - 1):
            for k in range(first[p], first[p + 1]):
                x = order[k]
                us[x] = slab_walk(x, g, central, slab_first, start, nbr, sp_, sn_, body, W, V,
                                  cut, B, cut2)

    # one walk, two compilations, as the cell loop's (celllists.cell_loops): inlined into the
    # parallel loop, and without reference counts for the serial one (it allocates nothing)
    walk_par = jit(inline="always")(walk_py)
    walk_serial = jit(_nrt=False)(walk_py)

    def make(build: Dispatcher, parts: Dispatcher, walk: Dispatcher) -> Callable:
        """The loop around the list builder ``build``, the slab partition ``parts`` and the
        walk ``walk`` (compiled serial and parallel)."""

        def listed_py(g, central, members, pos, nu, F, T, cutoff, B, cut, state, s):
            n = members.shape[0]
            if n < 2:
                return 0.0
            ints, nbrs, refs, skin = state
            sp_ = np.empty((n, 3))
            sn_ = np.empty((n, 3))
            # a body's shares from its own slab and from the slab before in two separate halves:
            # threads on neighbouring slabs write different halves of the same body, which
            # side by side would share cache lines
            W = np.empty((2, n, 3))
            V = np.empty((2, n, 3))
            fresh = refs[s].shape[0] != n
            if fresh:
                body, start, nbr, slab_first, ref = build(members, pos, cutoff + skin)
            else:
                body = ints[3 * s]
                start = ints[3 * s + 1]
                nbr = nbrs[s]
                slab_first = ints[3 * s + 2]
                ref = refs[s]
            # gather in slot order and measure how far each body moved since the build
            far = 0.0
            for q in numba.prange(n):
                b = body[q]
                d2 = 0.0
                for d in range(3):
                    v = pos[b, d]
                    sp_[q, d] = v
                    sn_[q, d] = nu[b, d]
                    d2 += (v - ref[q, d]) ** 2
                    W[0, q, d] = 0.0
                    W[1, q, d] = 0.0
                    V[0, q, d] = 0.0
                    V[1, q, d] = 0.0
                far = max(far, d2)
            if far > 0.25 * skin * skin * (1.0 - 1e-9):  # a body moved more than skin / 2: rebuild
                body, start, nbr, slab_first, ref = build(members, pos, cutoff + skin)
                fresh = True
                for q in numba.prange(n):
                    b = body[q]
                    for d in range(3):
                        sp_[q, d] = pos[b, d]
                        sn_[q, d] = nu[b, d]
            if fresh:
                ints[3 * s] = body
                ints[3 * s + 1] = start
                nbrs[s] = nbr
                ints[3 * s + 2] = slab_first
                refs[s] = ref
            ns = slab_first.shape[0] - 1
            us = np.empty(ns)
            cut2 = cutoff * cutoff
            order, first = parts(start, slab_first)
            walk(order, first, us, g, central, slab_first, start, nbr, sp_, sn_, body, W, V, cut,
                 B, cut2)
            for q in numba.prange(n):
                b = body[q]
                for d in range(3):
                    F[b, d] += W[1, q, d] + W[0, q, d]
                    T[b, d] += V[1, q, d] + V[0, q, d]
            u = 0.0
            for x in range(ns):
                u += us[x]
            return u

        return listed_py

    # one source, two compilations: numba.prange is range in the serial one
    serial = jit(make(verlet_build, in_order, walk_serial))
    if parallel:
        par = jit(parallel=True)(make(verlet_build_par, per_thread, walk_par))

        @jit
        def listed(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, state, s):
            """The listed pairs on numba's threads once there are ``min_n`` members (the
            thread count is numba's: see ``cell_loops``)."""
            if members.shape[0] >= min_n:
                return par(g, central, members, pos, nu, F, T, cutoff, B, cut, state, s)
            return serial(g, central, members, pos, nu, F, T, cutoff, B, cut, state, s)
    else:
        @jit(inline="always")
        def listed(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, state, s):
            return serial(g, central, members, pos, nu, F, T, cutoff, B, cut, state, s)

    return listed
