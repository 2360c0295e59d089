"""External fields of an N-body system as a force term: the one-body energies, forces and
torques that :mod:`~poissonkit.numerics.nbody.assemble` adds to the pair term.

The kick keeps ``r`` and ``ν`` fixed, so the pair kick followed by the field kick is exactly
the kick of their sum; the right-hand side, the energy and the forces add the field term to
the pair term. The field data is ``data.fields``, a
:class:`~poissonkit.numerics.nbody.data.FieldData`.

Fixed bodies are skipped (their field energy is a constant).
"""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np
from numba.core.dispatcher import Dispatcher

from poissonkit.contracts import CompiledFunction
from poissonkit.errors import InputError
from poissonkit.numerics.fields.base import CompiledField
from poissonkit.numerics.jit import jit
from poissonkit.numerics.nbody.assemble import Term
from poissonkit.numerics.nbody.bodies import Body
from poissonkit.numerics.nbody.data import FieldData
from poissonkit.numerics.nbody.pairkernels import compile_counted_if_needed

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
        chunk = np.asarray(fld.data, dtype=float).ravel()
        if fld.capacity > chunk.size:  # room for a regrown table (numerics/fields/growth)
            chunk = np.concatenate([chunk, np.zeros(fld.capacity - chunk.size)])
        chunks.append(chunk)
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

_F = numba.types.float64
#: The argument types the field term calls ``field_any`` with: ``g``, the position, the axis,
#: the coupling and the field's slice ``P`` of the parameter array.
FIELD_ANY_ARGS = (numba.types.int64, _F, _F, _F, _F, _F, _F, _F, _F[::1])


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
    # without reference counts when no field kernel allocates, with them otherwise (a
    # plugin's field kernel may allocate): decided by compiling it (nbody/pairkernels)
    fn = compile_counted_if_needed("\n".join(lines), "field_any",
                                   {f"f{g}": k for g, k in enumerate(kerns)}, FIELD_ANY_ARGS)
    _dispatch_cache[key] = (fn, tuple(kerns))  # keep the kernels (and their ids) alive
    return fn


def _field_loop(dispatch: Dispatcher) -> Term:
    """The field term ``field_forces(data, work) -> U``: adds every field's forces and torques
    to ``work.F``, ``work.T`` (internal units) and returns the field energy."""

    def field_forces(data, work):
        pos, nu, F, T = work.pos, work.nu, work.F, work.T
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

    # allocates nothing (``P[...]`` is a view): no reference counts needed (nbody/assemble)
    return Term(plain=jit(field_forces), inline=jit(inline="always")(field_forces),
                allocates=False)


_term_cache: dict[int, Term] = {}


def field_term(kerns: Sequence[CompiledFunction]) -> Term:
    """The force term of the fields with kernels ``kerns`` (cached per field kernels), for
    :func:`~poissonkit.numerics.nbody.assemble.assemble` to add to the pair term.

    The kick keeps ``r`` and ``ν`` fixed, so the pair kick followed by the field kick (what
    the generator does with two terms) is exactly the kick of their sum.
    """
    dispatch = field_dispatcher(kerns)
    hit = _term_cache.get(id(dispatch))
    if hit is None:
        hit = _term_cache[id(dispatch)] = _field_loop(dispatch)
    return hit
