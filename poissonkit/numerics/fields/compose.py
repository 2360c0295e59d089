"""The kernels of an N-body system with external fields: the pair kernels plus the one-body
terms, added in the same sub-flows.

The kick keeps ``r`` and ``ν`` fixed, so the pair kick followed by the field kick is exactly
the kick of their sum; the right-hand side, the energy and the forces add the field terms to
the pair terms. The field data is ``data.fields``, a
:class:`~poissonkit.numerics.nbody.data.FieldData`.

Fixed bodies are skipped (their field energy is a constant).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.contracts import CompiledFunction
from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField
from poissonkit.numerics.jit import compile_generated, jit
from poissonkit.numerics.kernels import Kernels, kahan_add, zero2
from poissonkit.numerics.nbody.bodies import Body
from poissonkit.numerics.nbody.data import FieldData
from poissonkit.numerics.nbody.state import apply_forces, gather, gather_inl

def field_data(fields: Sequence[CompiledField], bodies: Sequence[Body], length: float,
               energy: float) -> tuple[FieldData, tuple[CompiledFunction, ...]]:
    """The field data (module docstring) and the distinct kernels it indexes.

    Raises
    ------
    InputError
        If a field that depends on the axis acts on a moving point mass.
    """
    kerns: list[CompiledFunction] = []
    gid = []
    offs = [0]
    chunks = []
    coup = np.zeros((len(bodies), len(fields)))
    for f, fld in enumerate(fields):
        if fld.kernel not in kerns:
            kerns.append(fld.kernel)
        gid.append(kerns.index(fld.kernel))
        chunks.append(np.asarray(fld.data, dtype=float).ravel())
        offs.append(offs[-1] + chunks[-1].size)
        for k, b in enumerate(bodies):
            value = dict(b.attributes).get(fld.reads) if fld.reads != "mass" else b.mass
            if value is None or b.fixed:
                continue
            if fld.orientation and b.alpha is None and value != 0:
                raise InputError(f"field {fld.name!r} acts on the axis of body {b.name!r}, "
                                 "which is a point mass; give it alpha or inertia")
            coup[k, f] = float(value)
    P = np.concatenate(chunks) if chunks else np.zeros(0)
    data = FieldData(kernel=np.array(gid, dtype=np.int64), offsets=np.array(offs, dtype=np.int64),
                     params=np.ascontiguousarray(P), coupling=coup,
                     units=np.array([length, 1.0 / energy]))
    return data, tuple(kerns)


_dispatch_cache: dict[tuple[int, ...], tuple[Dispatcher, tuple[CompiledFunction, ...]]] = {}


def field_dispatcher(kerns: Sequence[CompiledFunction]) -> Dispatcher:
    """``f(g, x, y, z, ν_x, ν_y, ν_z, c, P)`` calling field kernel number ``g`` (cached)."""
    key = tuple(id(k) for k in kerns)
    hit = _dispatch_cache.get(key)
    if hit is not None:
        return hit[0]
    lines = ["def field_any(g, x, y, z, n0, n1, n2, c, P):"]
    for g in range(len(kerns) - 1):
        lines.append(f"    if g == {g}:\n        return f{g}(x, y, z, n0, n1, n2, c, P)")
    lines.append(f"    return f{len(kerns) - 1}(x, y, z, n0, n1, n2, c, P)")
    fn = compile_generated("\n".join(lines), "field_any",
                           {f"f{g}": k for g, k in enumerate(kerns)})
    _dispatch_cache[key] = (fn, tuple(kerns))  # keep the kernels (and their ids) alive
    return fn


def _field_loop(dispatch: Dispatcher) -> tuple[Dispatcher, Dispatcher]:
    """``field_forces(pos, nu, data, F, T) -> U``: adds every field's forces and torques to
    ``F``, ``T`` (internal units) and returns the field energy."""

    def field_forces(pos, nu, data, F, T):
        fd = data.fields
        gid = fd.kernel
        off = fd.offsets
        P = fd.params
        coup = fd.coupling
        lu = fd.units[0]
        ie = fd.units[1]
        bslot = data.body_slot
        tslot = data.top_slot
        u = 0.0
        for b in range(bslot.shape[0]):
            if bslot[b] < 0:
                continue
            top = tslot[b] >= 0
            n0 = 0.0
            n1 = 0.0
            n2 = 0.0
            if top:
                n0 = nu[b, 0]
                n1 = nu[b, 1]
                n2 = nu[b, 2]
            for f in range(gid.shape[0]):
                c = coup[b, f]
                if c == 0.0:
                    continue
                e, gx, gy, gz, h0, h1, h2 = dispatch(
                    gid[f], pos[b, 0] * lu, pos[b, 1] * lu, pos[b, 2] * lu, n0, n1, n2, c,
                    P[off[f]:off[f + 1]])
                u += e * ie
                s = lu * ie
                F[b, 0] -= gx * s
                F[b, 1] -= gy * s
                F[b, 2] -= gz * s
                if top:  # ṁ = ∂U/∂ν × ν
                    T[b, 0] += (h1 * n2 - h2 * n1) * ie
                    T[b, 1] += (h2 * n0 - h0 * n2) * ie
                    T[b, 2] += (h0 * n1 - h1 * n0) * ie
        return u

    return jit(field_forces), jit(inline="always")(field_forces)


_kernel_cache: dict[tuple[int, int], Kernels] = {}


def field_kernels(pair: Kernels, kerns: Sequence[CompiledFunction]) -> Kernels:
    """The kernels of ``pair`` with the field terms added (cached per pair kernels and field
    kernels)."""
    dispatch = field_dispatcher(kerns)
    key = (id(pair.rhs), id(dispatch))
    hit = _kernel_cache.get(key)
    if hit is not None:
        return hit
    ff, ff_inl = _field_loop(dispatch)
    pair_rhs = pair.rhs
    pair_kick = pair.kick
    pair_kick_c = pair.kick_compensated
    pair_energy = pair.energy
    pair_forces = pair.forces

    @jit
    def rhs(y, data, work, out):
        pair_rhs(y, data, work, out)  # leaves pos, nu gathered
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        zero2(F)
        zero2(T)
        ff(pos, nu, data, F, T)
        nm = data.mass.shape[0]
        bslot = data.body_slot
        tslot = data.top_slot
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    out[6 * s + 3 + d] += F[b, d]
            t = tslot[b]
            if t >= 0:
                for d in range(3):
                    out[6 * nm + 6 * t + 3 + d] += T[b, d]

    @jit
    def kick(y, h, data, work):
        # r and ν are fixed in a kick: the pair kick then the field kick is the kick of the sum
        pair_kick(y, h, data, work)
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        gather_inl(y, data, pos, nu)
        zero2(F)
        zero2(T)
        ff_inl(pos, nu, data, F, T)
        apply_forces(y, h, data, work)

    @jit
    def kick_compensated(y, c, h, data, work):
        pair_kick_c(y, c, h, data, work)
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        gather_inl(y, data, pos, nu)
        zero2(F)
        zero2(T)
        ff_inl(pos, nu, data, F, T)
        nm = data.mass.shape[0]
        bslot = data.body_slot
        tslot = data.top_slot
        for b in range(bslot.shape[0]):
            s = bslot[b]
            if s >= 0:
                for d in range(3):
                    kahan_add(y, c, 6 * s + 3 + d, h * F[b, d])
            t = tslot[b]
            if t >= 0:
                for d in range(3):
                    kahan_add(y, c, 6 * nm + 6 * t + 3 + d, h * T[b, d])

    @jit
    def energy(y, data, work):
        e = pair_energy(y, data, work)
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        gather(y, data, pos, nu)
        zero2(F)
        zero2(T)
        return e + ff(pos, nu, data, F, T)

    @jit(inline="always")
    def forces_of(y, data, work):
        """Pair and field forces and torques into ``work.F``, ``work.T``; returns U."""
        u = pair_forces(y, data, work)
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
        return u + ff_inl(pos, nu, data, F, T)

    out = pair._replace(rhs=rhs, kick=kick, energy=energy, forces=forces_of,
                        kick_compensated=kick_compensated if pair_kick_c is not None else None)
    _kernel_cache[key] = out
    return out
