"""The compiled terms of one pair: energy, force and torques of bodies ``i`` and ``j``.

Each pair ``(i, j)``, ``r = r_j − r_i``, ``e = r/|r|``, contributes (seed 000 eq. 20
generalised)::

    F   = −[U_r e + U_c1 (ν_i − c1 e)/r + U_c2 (ν_j − c2 e)/r]     ṗ_j += F,  ṗ_i −= F
    ṁ_i += U_c1 e × ν_i − U_c3 ν_i × ν_j,      ṁ_j += U_c2 e × ν_j + U_c3 ν_i × ν_j

The terms are compiled around a system's potential dispatchers (``kern_any``, ``kern_r`` from
:func:`~poissonkit.numerics.nbody.pairkernels._dispatcher`), so they are closures built by
:func:`pair_terms`; every pair loop (list, all pairs, serial and parallel cell lists) evaluates a
pair through them, which is what makes their numbers agree bit for bit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import pair_forces


@jit(inline="always")
def third_law(F, i, j, f0, f1, f2):
    """Newton's third law for one pair: ``f`` added to body ``j``'s force, taken from ``i``'s."""
    F[j, 0] += f0
    F[j, 1] += f1
    F[j, 2] += f2
    F[i, 0] -= f0
    F[i, 1] -= f1
    F[i, 2] -= f2


@jit(inline="always")
def switch(r, cut):
    """``(S, S')`` of the C² switching function, 1 below ``r_s``, 0 at the cutoff."""
    x = (r - cut[2]) * cut[3]
    return (1.0 - x * x * x * (10.0 - 15.0 * x + 6.0 * x * x),
            -30.0 * x * x * (1.0 - x) * (1.0 - x) * cut[3])


class PairTerms(NamedTuple):
    """The compiled pair terms of one pair of potential dispatchers (see :func:`pair_terms`)."""

    #: ``pair_one(g, i, j, pos, nu, cut, B, bi, bj) -> (U, f, τ_i, τ_j)`` (10 floats)
    one: Dispatcher
    #: ``pair_term(g, i, j, pos, nu, F, T, cut, B, bi, bj) -> U``, adds to ``F`` and ``T``
    term: Dispatcher
    #: ``pair_r_one(g, i, j, pos, cut, B, bi, bj) -> (U, (U_r/r) d)`` (orientation-free)
    radial_one: Dispatcher
    #: ``pair_r(g, i, j, pos, F, cut, B, bi, bj) -> U``, adds to ``F`` (orientation-free)
    radial: Dispatcher
    #: ``all_pairs_r(g, members, lo, hi, pos, F, B) -> U``: every pair of a set, no cutoff
    all_radial: Dispatcher


def pair_terms(kern_any: Dispatcher, kern_r: Dispatcher) -> PairTerms:
    """Compile the pair terms around the dispatchers ``kern_any`` and ``kern_r``.

    ``cut`` is ``(cutoff², switch start², switch start, 1 / switch width)`` (no switch: the
    start is ``inf``); ``B`` is the table of per-body attributes, read at rows ``bi``, ``bj``.
    """

    @jit(inline="always")
    def pair_one(g, i, j, pos, nu, cut, B, bi, bj):
        """``(U, f, τ_i, τ_j)`` of pair (i, j): ``f`` is the force on j (−f on i).

        The serial and the parallel loop both evaluate a pair through this one function with
        the lower slot as ``i``, so a pair's numbers are bit-for-bit the same in both.
        """
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        r2 = dx * dx + dy * dy + dz * dz
        if r2 > cut[0]:
            return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        r = math.sqrt(r2)
        inv = 1.0 / r
        ex = dx * inv
        ey = dy * inv
        ez = dz * inv
        a0 = nu[i, 0]
        a1 = nu[i, 1]
        a2 = nu[i, 2]
        b0 = nu[j, 0]
        b1 = nu[j, 1]
        b2 = nu[j, 2]
        c1 = ex * a0 + ey * a1 + ez * a2
        c2 = ex * b0 + ey * b1 + ez * b2
        c3 = a0 * b0 + a1 * b1 + a2 * b2
        u, ur, u1, u2, u3 = kern_any(g, r, c1, c2, c3, B, bi, bj)
        if r2 > cut[1]:  # smooth cutoff: U S(r), S' adds to the radial partial only
            sw, dsw = switch(r, cut)
            ur = sw * ur + dsw * u
            u *= sw
            u1 *= sw
            u2 *= sw
            u3 *= sw
        return pair_forces(u, ur, u1, u2, u3, ex, ey, ez, inv, c1, c2, a0, a1, a2, b0, b1, b2)

    # compiled once, called per pair: without reference counts (it allocates nothing), which
    # numba could not prune across the call of a potential (see nbody/assemble.py)
    @jit(_nrt=False)
    def pair_term(g, i, j, pos, nu, F, T, cut, B, bi, bj):
        u, f0, f1, f2, ti0, ti1, ti2, tj0, tj1, tj2 = pair_one(g, i, j, pos, nu, cut, B, bi, bj)
        third_law(F, i, j, f0, f1, f2)
        T[i, 0] += ti0
        T[i, 1] += ti1
        T[i, 2] += ti2
        T[j, 0] += tj0
        T[j, 1] += tj1
        T[j, 2] += tj2
        return u

    @jit(inline="always")
    def pair_r_one(g, i, j, pos, cut, B, bi, bj):
        """``(U, (U_r/r) d)`` of an orientation-free pair, ``d = r_j − r_i`` (the fast path):
        the force on j is minus the vector part, on i plus it."""
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        r2 = dx * dx + dy * dy + dz * dz
        if r2 > cut[0]:
            return 0.0, 0.0, 0.0, 0.0
        q = 1.0 / math.sqrt(r2)
        u, s = kern_r(g, q, B, bi, bj)
        if r2 > cut[1]:  # smooth cutoff: (U S)_r / r = S U_r/r + S' U / r
            sw, dsw = switch(r2 * q, cut)
            s = sw * s + dsw * u * q
            u *= sw
        return u, s * dx, s * dy, s * dz

    @jit(inline="always")
    def pair_r(g, i, j, pos, F, cut, B, bi, bj):
        """Orientation-free pair: no axes, no c1, c2, c3, no torques (the fast path)."""
        u, g0, g1, g2 = pair_r_one(g, i, j, pos, cut, B, bi, bj)
        # a - b is a + (-b) in IEEE arithmetic: the same bits as subtracting g from F[j]
        third_law(F, i, j, -g0, -g1, -g2)
        return u

    @jit(inline="always")
    def all_pairs_r(g, members, lo, hi, pos, F, B):
        """Every pair of ``members[lo:hi]`` with an orientation-free potential, no cutoff."""
        u = 0.0
        for a in range(lo, hi):
            ia = members[a]
            xa = pos[ia, 0]
            ya = pos[ia, 1]
            za = pos[ia, 2]
            fx = 0.0
            fy = 0.0
            fz = 0.0
            for b in range(a + 1, hi):
                ib = members[b]
                dx = pos[ib, 0] - xa
                dy = pos[ib, 1] - ya
                dz = pos[ib, 2] - za
                uu, s = kern_r(g, 1.0 / math.sqrt(dx * dx + dy * dy + dz * dz), B, ia, ib)
                u += uu
                F[ib, 0] -= s * dx
                F[ib, 1] -= s * dy
                F[ib, 2] -= s * dz
                fx += s * dx
                fy += s * dy
                fz += s * dz
            F[ia, 0] += fx
            F[ia, 1] += fy
            F[ia, 2] += fz
        return u

    return PairTerms(one=pair_one, term=pair_term, radial_one=pair_r_one, radial=pair_r,
                     all_radial=all_pairs_r)
