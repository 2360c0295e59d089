"""The pair-force term of an N-body system and the kernels built on it.

:func:`pair_force_term` composes, around one pair of potential dispatchers, the pair terms
(:mod:`~poissonkit.numerics.nbody.pairterms`) and the cell-list or neighbour-list loop
(:mod:`~poissonkit.numerics.nbody.celllists`, :mod:`~poissonkit.numerics.nbody.verlet`) into
one force term; :func:`_build_kernels` hands it, with any further terms (external fields), to
the generator of :mod:`~poissonkit.numerics.nbody.assemble` on the layout of
:mod:`~poissonkit.numerics.nbody.state`. Terms and kernels are cached per dispatcher, so
systems with the same potentials share one compilation.

``data`` is the system's :class:`~poissonkit.numerics.nbody.data.SystemData` and ``work`` its
:class:`~poissonkit.numerics.nbody.data.Work` (``pos, nu, F, T`` and, for a system with a skin,
its neighbour lists, :mod:`~poissonkit.numerics.nbody.verlet`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import Kernels
from poissonkit.numerics.nbody.assemble import Term, assemble
from poissonkit.numerics.nbody.celllists import cell_loops
from poissonkit.numerics.nbody.pairterms import pair_terms
from poissonkit.numerics.nbody.state import GENERAL
from poissonkit.numerics.nbody.verlet import verlet_loops


def force_loops(pair_term: Dispatcher, pair_r: Dispatcher, all_pairs_r: Dispatcher,
                set_pairs: Dispatcher, allocates: bool = True) -> Term:
    """The pair-force term ``forces(data, work) -> U``: every pair of the system, forces added
    to ``work.F`` and torques to ``work.T`` (rows: all bodies; ``T`` untouched for point masses
    only).

    ``set_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, lists, s)`` is the
    pair loop of all-pairs set ``s`` with a cutoff: the cell loop (``lists`` is ``None``) or
    the neighbour-list loop (``lists``: the system's Verlet state, ``work.lists``);
    ``allocates``: whether ``set_pairs`` may allocate arrays (:attr:`Term.allocates`).
    """

    def forces_py(data, work):
        pos, nu, F, T, lists = work.pos, work.nu, work.F, work.T, work.lists
        pairs = data.pairs
        cmembers = data.set_members
        coffs = data.set_offsets
        cgid = data.set_kernel
        cutoff = data.cutoff
        B = data.table
        rpairs = data.radial_pairs
        ccentral = data.set_central
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
    return Term(plain=jit(forces_py), inline=jit(inline="always")(forces_py),
                allocates=allocates)


#: (id of kern_any, parallel, verlet, cells) -> the pair-force term
_term_cache: dict[tuple[int, bool, bool, bool], Term] = {}


@jit(inline="always")
def _no_cell_loop(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, lists, s):
    # the all-pairs loop of a system without cutoff never takes the cutoff branch: this stands
    # in for the cell-list loop, which then is not compiled (seconds of every first run)
    if np.isfinite(cutoff):
        raise ValueError("pair kernels compiled without a cutoff were given one")
    return 0.0


def pair_force_term(kern_any: Dispatcher, kern_r: Dispatcher, parallel: bool = False,
                    verlet: bool = False, cells: bool = True) -> Term:
    """The pair-force term around one pair of potential dispatchers (cached).

    ``parallel`` adds the multi-threaded pair loop (chosen at run time by the number of
    members, ``data.parallel_min``); without it only the serial loop exists. ``verlet`` walks
    neighbour lists kept in ``work.lists`` (:mod:`~poissonkit.numerics.nbody.verlet`) instead of
    building a cell list at every evaluation. ``cells=False`` (a system without cutoff, whose
    data never has one) leaves the cell-list loop out.
    """
    key = (id(kern_any), parallel, verlet, cells)
    hit = _term_cache.get(key)
    if hit is not None:
        return hit
    terms = pair_terms(kern_any, kern_r)
    if verlet:
        set_pairs = verlet_loops(terms.one, terms.radial_one, parallel)
    elif not cells:
        set_pairs = _no_cell_loop
    else:
        cell_pairs = cell_loops(terms.one, terms.radial_one, parallel)

        @jit(inline="always")
        def set_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n, lists, s):
            return cell_pairs(g, central, members, pos, nu, F, T, cutoff, B, cut, min_n)
    # the cell and neighbour lists allocate; the loops over listed pairs and over all pairs do
    # not, and their kernels then go without reference counts (assemble's module docstring).
    # With lists, the kernels keep the counts but the walk over the pairs does not: it is a
    # function of its own, compiled without them (celllists.cell_loops, verlet.verlet_loops)
    out = force_loops(terms.term, terms.radial, terms.all_radial, set_pairs,
                      allocates=verlet or cells)
    _term_cache[key] = out
    return out


def _build_kernels(kern_any: Dispatcher, kern_r: Dispatcher, parallel: bool = False,
                   verlet: bool = False, extra: Sequence[Term] = (),
                   cells: bool = True, counted: bool | None = None) -> Kernels:
    """The N-body kernels of the pair-force term (:func:`pair_force_term`) plus the terms
    ``extra`` (external fields), assembled on the general layout (cached; ``counted`` as in
    :func:`~poissonkit.numerics.nbody.assemble.assemble`)."""
    return assemble(GENERAL, (pair_force_term(kern_any, kern_r, parallel, verlet, cells),
                              *extra), counted)
