"""Cell lists: the pairs of a set of bodies closer than a cutoff in O(n), serial and parallel.

:func:`cell_list` bins the bodies into cubic cells of side at least the cutoff, so every pair
within the cutoff lies in one cell or in two adjacent ones. The pair loop runs over x-slabs of
cells (:func:`cell_loops`); each pair is evaluated once, and the sums are arranged so that the
slabs can run on any threads in any order and still give the same numbers bit for bit.
"""

from __future__ import annotations

import os
from typing import NamedTuple

import numba
import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import jit

try:
    # numba.get_num_threads() in compiled code holds a ctypes pointer, which keeps the kernel
    # (and every kernel inlining it) out of the disk cache; the intrinsic behind it reads the
    # same count through a named symbol and caches
    from numba.np.ufunc.parallel import _iget_num_threads as threads_now
except ImportError:  # pragma: no cover - a numba without it: one part per slab, as before
    @numba.njit(cache=True)
    def threads_now():
        return 0


def _cell_list_py(members, pos, nu, cutoff):
    """Bin ``members`` into cubic cells of side ≥ ``cutoff``.

    Returns ``(nc, start, cell, p, n, body)``: cells per axis, slot offsets of each cell
    (``start[c]:start[c + 1]``, cells numbered row-major ``(cx·nc_y + cy)·nc_z + cz``), the
    cell of each slot, positions and axes copied in slot order (neighbours sit next to each
    other in memory) and the original body index of each slot. The O(n) passes that do not
    decide the order run on numba's threads in the parallel compilation (the same result).
    """
    n = members.shape[0]
    lo0 = np.inf
    lo1 = np.inf
    lo2 = np.inf
    hi0 = -np.inf
    hi1 = -np.inf
    hi2 = -np.inf
    for a in numba.prange(n):  # min / max: exact, in any order
        b = members[a]
        lo0 = min(lo0, pos[b, 0])
        lo1 = min(lo1, pos[b, 1])
        lo2 = min(lo2, pos[b, 2])
        hi0 = max(hi0, pos[b, 0])
        hi1 = max(hi1, pos[b, 1])
        hi2 = max(hi2, pos[b, 2])
    lo = np.array([lo0, lo1, lo2])
    hi = np.array([hi0, hi1, hi2])
    side = cutoff
    nc = np.empty(3, dtype=np.int64)
    while True:
        total = 1
        for d in range(3):
            nc[d] = int((hi[d] - lo[d]) / side) + 1
            total *= nc[d]
        if total <= 4 * n + 64:  # sparse, far-flung bodies: coarser cells, same result
            break
        side *= 1.5
    ncell = nc[0] * nc[1] * nc[2]
    cell_of = np.empty(n, dtype=np.int64)
    count = np.zeros(ncell + 1, dtype=np.int64)
    for a in numba.prange(n):
        b = members[a]
        cx = min(int((pos[b, 0] - lo[0]) / side), nc[0] - 1)
        cy = min(int((pos[b, 1] - lo[1]) / side), nc[1] - 1)
        cz = min(int((pos[b, 2] - lo[2]) / side), nc[2] - 1)
        cell_of[a] = (cx * nc[1] + cy) * nc[2] + cz
    for a in range(n):
        count[cell_of[a] + 1] += 1
    for c in range(ncell):
        count[c + 1] += count[c]
    start = count.copy()
    order = np.empty(n, dtype=np.int64)
    for a in range(n):
        c = cell_of[a]
        order[start[c]] = a
        start[c] += 1
    sp_ = np.empty((n, 3))
    sn_ = np.empty((n, 3))
    body = np.empty(n, dtype=np.int64)
    cell = np.empty(n, dtype=np.int64)
    for q in numba.prange(n):
        b = members[order[q]]
        body[q] = b
        cell[q] = cell_of[order[q]]
        for d in range(3):
            sp_[q, d] = pos[b, d]
            sn_[q, d] = nu[b, d]
    return nc, count, cell, sp_, sn_, body


#: the cell list, one thread (numba.prange is range here)
cell_list = jit(_cell_list_py)
#: the cell list with its order-free passes on numba's threads; the same result
cell_list_par = jit(parallel=True)(_cell_list_py)


#: the row of a part's forward cells (13 used): 256 bytes, so that the rows two threads write
#: never share a cache line
FWD_ROW = 32


@numba.njit(cache=True, error_model="numpy")
def forward_cells(c, nc, out):
    """The "forward" neighbours of cell ``c`` (higher index, up to 13) into ``out``, in
    increasing index; returns how many. Each pair of adjacent cells is one cell's forward pair."""
    cx = c // (nc[1] * nc[2])
    cy = (c // nc[2]) % nc[1]
    cz = c % nc[2]
    k = 0
    for ddx in range(2):
        nx = cx + ddx
        if nx >= nc[0]:
            continue
        for ddy in range(-1, 2):
            if ddx == 0 and ddy < 0:
                continue
            ny = cy + ddy
            if ny < 0 or ny >= nc[1]:
                continue
            for ddz in range(-1, 2):
                if ddx == 0 and ddy == 0 and ddz <= 0:
                    continue
                nz = cz + ddz
                if nz < 0 or nz >= nc[2]:
                    continue
                out[k] = (nx * nc[1] + ny) * nc[2] + nz
                k += 1
    return k


@numba.njit(cache=True)
def _lightest(load):
    k = 0
    for p in range(1, load.shape[0]):
        if load[p] < load[k]:
            k = p
    return k


@numba.njit(cache=True)
def _rebalanced(w, owner, load):
    """One move or swap of slabs between the heaviest and the lightest part that lowers the
    heavier of the two the most; False when none does."""
    hi = 0
    for p in range(1, load.shape[0]):
        if load[p] > load[hi]:
            hi = p
    lo = _lightest(load)
    best = load[hi]
    a_best = -1
    b_best = -1
    for a in range(w.shape[0]):
        if owner[a] != hi:
            continue
        for b in range(-1, w.shape[0]):
            if b >= 0 and owner[b] != lo:
                continue
            d = w[a] - (w[b] if b >= 0 else 0)
            worse = max(load[hi] - d, load[lo] + d)
            if d > 0 and worse < best:
                best = worse
                a_best = a
                b_best = b
    if a_best < 0:
        return False
    d = w[a_best] - (w[b_best] if b_best >= 0 else 0)
    owner[a_best] = lo
    if b_best >= 0:
        owner[b_best] = hi
    load[hi] -= d
    load[lo] += d
    return True


@numba.njit(cache=True)
def slab_parts(w, nt):
    """The slabs of work ``w`` shared out between ``nt`` threads, as even as slabs allow.

    Returns ``(order, first)``: part ``p`` runs slabs ``order[first[p]:first[p + 1]]`` (in
    increasing index), one part per thread (``prange(nt)`` gives each thread one iteration).
    Heaviest slab first to the lightest part, then moves and swaps between the heaviest and the
    lightest part while they lower it. Any partition gives the same numbers (no two slabs write
    the same sum); this one only decides how long the threads wait for each other. With
    ``nt <= 0`` (the thread count unknown) every slab is its own part, even slabs first.
    """
    ns = w.shape[0]
    owner = np.empty(ns, dtype=np.int64)
    if nt <= 0:
        half = (ns + 1) // 2
        for x in range(ns):
            owner[x] = x // 2 if x % 2 == 0 else half + x // 2
        nt = ns
    else:
        load = np.zeros(nt, dtype=np.int64)
        for x in np.argsort(-w, kind="mergesort"):
            p = _lightest(load)
            owner[x] = p
            load[p] += w[x]
        if nt > 1 and ns <= 512:  # many small slabs: the greedy pass is as good
            for _ in range(4 * nt):
                if not _rebalanced(w, owner, load):
                    break
    first = np.zeros(nt + 1, dtype=np.int64)
    for x in range(ns):
        first[owner[x] + 1] += 1
    for p in range(nt):
        first[p + 1] += first[p]
    fill = first[:-1].copy()
    order = np.empty(ns, dtype=np.int64)
    for x in range(ns):
        order[fill[owner[x]]] = x
        fill[owner[x]] += 1
    return order, first


@jit(inline="always")
def cell_setup(members, pos, nu, cutoff):
    """The cell list of ``members`` and zeroed accumulators ``(2, n, 3)`` (see ``slab_pairs``:
    a body's shares from its own slab and from the slab before in separate halves, so that
    threads on neighbouring slabs do not write the same cache lines)."""
    n = members.shape[0]
    nc, count, cell_of, sp_, sn_, body = cell_list(members, pos, nu, cutoff)
    return (nc, count, sp_, sn_, body, np.zeros((2, n, 3)), np.zeros((2, n, 3)),
            np.empty(nc[0]))


@jit(inline="always")
def cell_setup_par(members, pos, nu, cutoff):
    """:func:`cell_setup` with the cell list's O(n) passes and the zeroing on threads."""
    n = members.shape[0]
    nc, count, cell_of, sp_, sn_, body = cell_list_par(members, pos, nu, cutoff)
    W = np.empty((2, n, 3))
    V = np.empty((2, n, 3))
    for q in numba.prange(n):
        for d in range(3):
            W[0, q, d] = 0.0
            W[1, q, d] = 0.0
            V[0, q, d] = 0.0
            V[1, q, d] = 0.0
    return nc, count, sp_, sn_, body, W, V, np.empty(nc[0])


@jit(inline="always")
def cell_gather(n, body, W, V, us, F, T):
    """Add the slot sums to the bodies' rows; total energy, summed slab by slab."""
    for q in range(n):
        b = body[q]
        for d in range(3):
            F[b, d] += W[1, q, d] + W[0, q, d]
            T[b, d] += V[1, q, d] + V[0, q, d]
    u = 0.0
    for x in range(us.shape[0]):
        u += us[x]
    return u


class SlotSums(NamedTuple):
    """One slot's pair sums, shared by both pair loops (:func:`cell_loops`, the Verlet walk).

    ``acc = opened(W, V, qa)`` starts slot ``qa``'s sums in registers (its force and torque so
    far, energy 0); ``acc = add_pair(acc, g, central, qa, qb, h, sp_, sn_, body, W, V, cut, B,
    cut2, xa, ya, za)`` adds the pair ``qa < qb`` when it lies within ``cut2`` of ``(xa, ya,
    za)``, slot ``qb``'s force and torque going to ``W[h, qb]``, ``V[h, qb]``; ``closed(W, V, qa,
    acc)`` stores the slot's sums and returns its energy. No later slot of a loop writes
    ``W[0, qa]`` (every ``qb > qa``), so the sums are the same with fewer loads and stores.
    """

    opened: Dispatcher
    add_pair: Dispatcher
    closed: Dispatcher


def slot_sums(pair_one: Dispatcher, pair_r_one: Dispatcher) -> SlotSums:
    """The :class:`SlotSums` of the pair terms ``pair_one`` (with orientations) and
    ``pair_r_one`` (orientation-free, used when ``central``)."""

    @jit(inline="always")
    def shares(g, central, qa, qb, h, sp_, sn_, body, W, V, cut, B):
        # a - b is a + (-b) in IEEE arithmetic: returning -f keeps every sum's bits
        if central:
            uu, d0, d1, d2 = pair_r_one(g, qa, qb, sp_, cut, B, body[qa], body[qb])
            t0 = 0.0  # a central set writes no torque: qa's stays +0.0, as without the add
            t1 = 0.0
            t2 = 0.0
        else:
            (uu, f0, f1, f2, t0, t1, t2,
             tj0, tj1, tj2) = pair_one(g, qa, qb, sp_, sn_, cut, B, body[qa], body[qb])
            d0 = -f0
            d1 = -f1
            d2 = -f2
            V[h, qb, 0] += tj0
            V[h, qb, 1] += tj1
            V[h, qb, 2] += tj2
        W[h, qb, 0] -= d0
        W[h, qb, 1] -= d1
        W[h, qb, 2] -= d2
        return uu, d0, d1, d2, t0, t1, t2

    @jit(inline="always")
    def opened(W, V, qa):
        return (W[0, qa, 0], W[0, qa, 1], W[0, qa, 2], V[0, qa, 0], V[0, qa, 1], V[0, qa, 2],
                0.0)

    @jit(inline="always")
    def add_pair(acc, g, central, qa, qb, h, sp_, sn_, body, W, V, cut, B, cut2, xa, ya, za):
        # cheap distance test before the pair term
        dx = sp_[qb, 0] - xa
        dy = sp_[qb, 1] - ya
        dz = sp_[qb, 2] - za
        if dx * dx + dy * dy + dz * dz > cut2:
            return acc
        uu, d0, d1, d2, t0, t1, t2 = shares(g, central, qa, qb, h, sp_, sn_, body, W, V, cut, B)
        return (acc[0] + d0, acc[1] + d1, acc[2] + d2, acc[3] + t0, acc[4] + t1, acc[5] + t2,
                acc[6] + uu)

    @jit(inline="always")
    def closed(W, V, qa, acc):
        W[0, qa, 0] = acc[0]
        W[0, qa, 1] = acc[1]
        W[0, qa, 2] = acc[2]
        V[0, qa, 0] = acc[3]
        V[0, qa, 1] = acc[4]
        V[0, qa, 2] = acc[5]
        return acc[6]

    return SlotSums(opened, add_pair, closed)


def cell_loops(pair_one: Dispatcher, pair_r_one: Dispatcher, parallel: bool) -> Dispatcher:
    """The cell-list pair loop around the pair terms ``pair_one`` and ``pair_r_one``.

    Returns ``cells(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n) -> U``: every
    pair of ``members`` closer than ``cutoff`` through potential ``g`` (the orientation-free
    term if ``central``), forces and torques added to ``F`` and ``T``. With ``parallel`` the loop
    runs on numba's threads once there are ``min_n`` members; without it only the serial loop
    is compiled.
    """
    if parallel:
        # OpenMP's default active wait spins at every barrier: when another process holds
        # the other core, a force evaluation of 10⁴ tops took 4× the serial time instead of
        # the same (benchmarks/bench_nbody_parallel.py). Read once, at the first parallel
        # launch; a value the user set wins.
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    opened, add_pair, closed = slot_sums(pair_one, pair_r_one)

    @jit(inline="always")
    def slab_pairs(x, g, central, nc, count, sp_, sn_, body, W, V, cut, B, cut2, fwd):
        """Pairs of the cell list whose first cell lies in x-slab ``x`` (cells of one ``cx``).

        Newton's third law: each pair is evaluated once and added to both bodies, the lower
        slot as ``i``. Slots are visited in cell order; for each slot its own cell's later
        slots, then the 13 "forward" neighbour cells in increasing index. A body's share goes
        to ``W[0, q]`` (forces) / ``V[0, q]`` (torques) when the pair's first cell is in the
        body's own slab and to ``W[1, q]`` / ``V[1, q]`` when it is in the slab before, so
        two slabs never write the same numbers: the slabs can run on any threads, in any
        order, and every sum is still formed in one fixed order. ``fwd``: room for 13 cell
        indices (the caller's, so that the walk allocates nothing).
        """
        per_slab = nc[1] * nc[2]
        first_next = (x + 1) * per_slab
        u = 0.0
        for c in range(x * per_slab, first_next):
            if count[c] == count[c + 1]:
                continue
            nf = forward_cells(c, nc, fwd)
            for qa in range(count[c], count[c + 1]):
                xa, ya, za = sp_[qa, 0], sp_[qa, 1], sp_[qa, 2]
                acc = opened(W, V, qa)
                for k in range(-1, nf):
                    c2 = c if k < 0 else fwd[k]
                    h = 1 if c2 >= first_next else 0  # j's cell in the next slab
                    for qb in range(qa + 1 if k < 0 else count[c2], count[c2 + 1]):
                        acc = add_pair(acc, g, central, qa, qb, h, sp_, sn_, body, W, V, cut,
                                       B, cut2, xa, ya, za)
                u += closed(W, V, qa, acc)
        return u

    def walk_py(order, first, us, fwd, g, central, nc, count, sp_, sn_, body, W, V, cut, B,
                cut2):
        """The slabs of part ``p``, ``order[first[p]:first[p + 1]]``, for every part (parts on
        numba's threads in a parallel caller): slab ``x``'s energy to ``us[x]``, forces and
        torques to ``W``, ``V``; ``fwd[p]``: part ``p``'s room for the forward cells."""
        for p in numba.prange(first.shape[0] - 1):
            for k in range(first[p], first[p + 1]):
                x = order[k]
                us[x] = slab_pairs(x, g, central, nc, count, sp_, sn_, body, W, V, cut, B,
                                   cut2, fwd[p])

    # one walk, two compilations: inlined into the parallel loop (its body, a gufunc, gets
    # raw array pointers), and for the serial loop a separate function without reference
    # counts: it allocates nothing, and with counts numba kept an atomic increment and
    # decrement of the arrays around every pair term that calls a potential that may raise
    # (assemble's module docstring) -- 2.6x the parallel loop's time on one thread
    walk_par = jit(inline="always")(walk_py)
    walk_serial = jit(_nrt=False)(walk_py)

    @jit
    def cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut):
        """All pairs of ``members`` closer than ``cutoff``, via a cell list (O(n)), one thread."""
        if members.shape[0] < 2:
            return 0.0
        nc, count, sp_, sn_, body, W, V, us = cell_setup(members, pos, nu, cutoff)
        fwd = np.empty((1, FWD_ROW), np.int64)
        walk_serial(np.arange(nc[0]), np.array([0, nc[0]]), us, fwd, g, central, nc, count, sp_, sn_, body, W, V, cut, B, cutoff * cutoff)
        return cell_gather(members.shape[0], body, W, V, us, F, T)

    @jit(parallel=True)
    def cell_pairs_par(g, central, members, pos, nu, F, T, cutoff, B, cut):
        """:func:`cell_pairs` with the x-slabs shared out between threads, one part per
        thread (:func:`slab_parts`); the same numbers bit for bit on any number of threads (see
        ``slab_pairs``: no two slabs write the same sum, no atomics, no reduction whose order
        depends on the threads)."""
        if members.shape[0] < 2:
            return 0.0
        nc, count, sp_, sn_, body, W, V, us = cell_setup_par(members, pos, nu, cutoff)
        # a slab's work: its candidate pairs, ~ n_x (n_x + 2 n_(x+1)) at even density in y, z
        # (n_x bodies in slab x), plus one per body
        per = nc[1] * nc[2]
        w = np.empty(nc[0], dtype=np.int64)
        for x in range(nc[0]):
            n_x = count[(x + 1) * per] - count[x * per]
            n_next = count[(x + 2) * per] - count[(x + 1) * per] if x + 1 < nc[0] else 0
            w[x] = n_x * (n_x + 2 * n_next + 1)
        nt = threads_now()
        order, first = slab_parts(w, nt)
        fwd = np.empty((first.shape[0] - 1, FWD_ROW), np.int64)
        walk_par(order, first, us, fwd, g, central, nc, count, sp_, sn_, body, W, V, cut, B,
                 cutoff * cutoff)
        for q in numba.prange(members.shape[0]):  # cell_gather's sums, slots on threads
            b = body[q]
            for d in range(3):
                F[b, d] += W[1, q, d] + W[0, q, d]
                T[b, d] += V[1, q, d] + V[0, q, d]
        u = 0.0
        for x in range(nc[0]):
            u += us[x]
        return u

    if parallel:
        @jit
        def cells(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n):
            """The cell-list pairs on numba's threads once there are ``min_n`` members.

            The thread count is numba's (``numba.set_num_threads``), read by the parallel
            loop to share the slabs out (:func:`slab_parts`); on one thread the parallel loop
            does the serial loop's work.
            """
            if members.shape[0] >= min_n:
                return cell_pairs_par(g, central, members, pos, nu, F, T, cutoff, B, cut)
            return cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut)
    else:
        # no parallel loop compiled at all: compiling it costs seconds that small systems
        # (and systems told to stay serial) never get back
        @jit(inline="always")
        def cells(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n):
            return cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut)

    return cells
