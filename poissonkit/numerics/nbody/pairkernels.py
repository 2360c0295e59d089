"""From a pair potential as given to the compiled kernels the force loops call.

Three steps, each cached: resolve what the user gave (registry entry or name, sympy
expression, numba kernel) to an SI kernel ``f(r, c1, c2, c3[, body values][, parameters]) ->
(U, U_r, U_c1, U_c2, U_c3)``; wrap it in internal units with its per-body parameters read from
the attribute table ``B``; and generate one dispatcher that calls kernel number ``g`` of a
system, so the compiled loops take the potential as an integer.

Parameters as data: the float parameters of a registry potential are not compiled in. They sit
in the last row of ``B`` (one column each, after the body attributes), and the wrapper reads
them there, so a system with other parameter values reuses every compiled kernel and loop
(:func:`~poissonkit.numerics.potentials.runtime_potential`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Union

import numba
import sympy as sp
from numba.core import event
from numba.core.dispatcher import Dispatcher
from numba.core.errors import NumbaError

from poissonkit.contracts import CompiledFunction
from poissonkit.errors import InputError
from poissonkit.numerics.jit import compile_generated
from poissonkit.numerics.nbody.bodies import PotentialLike
from poissonkit.numerics.potentials import (RuntimeKernel, compile_bound_potential,
                                            compile_potential, kernel_from_expr, radial_kernel,
                                            runtime_potential)
from poissonkit.plugin.contributions import PairPotential

#: ``(column of the attribute table B, 1 or 2)`` per extra argument of a kernel: the first or
#: the second body of the pair.
SlotSpec = tuple[tuple[int, int], ...]


def resolve_kernel(potential: PotentialLike, params: Mapping[str, object]
                   ) -> tuple[Dispatcher, str]:
    """The SI kernel of a pair potential as given, and its orientation.

    Parameters
    ----------
    potential
        A :class:`~poissonkit.plugin.PairPotential`, its registry name, a sympy expression in
        ``r, c1, c2, c3`` or a numba kernel ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``.
    params
        Values of the potential's parameters (SI).

    Returns
    -------
    tuple
        ``(kernel, orientation)``: the compiled kernel ``f(r, c1, c2, c3)`` in SI and which
        axes it reads (``"both"``, ``"first"``, ``"second"`` or ``"none"``).

    Raises
    ------
    InputError
        If ``potential`` is none of these.
    """
    if isinstance(potential, str):
        from poissonkit.plugin import potential as lookup

        potential = lookup(potential)
    if isinstance(potential, PairPotential):
        return compile_potential(potential, params), potential.orientation
    if isinstance(potential, numba.core.registry.CPUDispatcher):
        return potential, "both"
    if isinstance(potential, sp.Basic):
        names = {s.name for s in potential.free_symbols}
        has1, has2 = bool(names & {"c1", "c3"}), bool(names & {"c2", "c3"})
        orient = {(True, True): "both", (True, False): "first", (False, True): "second",
                  (False, False): "none"}[(has1, has2)]
        return kernel_from_expr(potential, "expr"), orient
    raise InputError(f"cannot use {type(potential).__name__} as a pair potential; give a "
                     "PairPotential, a registry name, a sympy expression or a numba kernel")


def _resolve_bound(potential: PotentialLike, params: Mapping[str, object]
                   ) -> tuple[Dispatcher, tuple[tuple[str, int], ...], str]:
    """(SI kernel, bound slots, orientation) of one interaction's potential.

    Parameters of a :class:`PairPotential` listed in its ``body_params`` and not given in
    ``params`` are taken from the two bodies of each pair: the kernel then has one extra
    argument per ``(attribute, which body)`` slot.
    """
    if isinstance(potential, str):
        from poissonkit.plugin import potential as lookup

        potential = lookup(potential)
    if isinstance(potential, PairPotential) and potential.body_params:
        bound = {p: (attr, int(w)) for p, attr, w in potential.body_params if p not in params}
        if bound:
            kern, slots = compile_bound_potential(potential, params, bound)
            return kern, slots, potential.orientation
    kern, orient = resolve_kernel(potential, params)
    return kern, (), orient


#: ``(first column of B's last row, count, as one array)`` of a kernel's run-time parameters;
#: ``None`` when it has none.
ParamSpec = Union[tuple[int, int, bool], None]


def resolve_runtime(potential: PotentialLike, params: Mapping[str, object]
                    ) -> tuple[RuntimeKernel, str]:
    """The SI kernel of one interaction's potential with its parameters as run-time data.

    As :func:`_resolve_bound`, but the float parameters of a registry potential are left out
    of the compiled code (:func:`~poissonkit.numerics.potentials.runtime_potential`): the
    kernel is the same for every value, and the values come back with it. Sympy expressions
    and numba kernels given directly have no parameters and are returned as they are.
    """
    entry = _registry_entry(potential)
    if entry is None:
        kern, slots, orient = _resolve_bound(potential, params)
        return RuntimeKernel(kern, slots, (), False), orient
    bound = {p: (attr, int(w)) for p, attr, w in entry.body_params if p not in params}
    return runtime_potential(entry, params, bound), entry.orientation


#: The former private name of :func:`resolve_kernel`.
_resolve_kernel = resolve_kernel


def _registry_entry(potential: PotentialLike) -> PairPotential | None:
    """The :class:`PairPotential` behind a registry name or entry (``None`` otherwise)."""
    if isinstance(potential, str):
        from poissonkit.plugin import potential as lookup

        return lookup(potential)
    return potential if isinstance(potential, PairPotential) else None


#: (kind, kernel id, slots, L, 1/E) -> (wrapper, kernel kept alive so its id stays unique)
_wrap_cache: dict[tuple[object, ...], tuple[Dispatcher, Dispatcher]] = {}


#: id of a compiled wrapper -> (its source, name, namespace, itself kept alive): to compile
#: its twin without reference counts (:func:`_uncounted_twin`)
_generated: dict[int, tuple[str, str, dict[str, Dispatcher], Dispatcher]] = {}

#: id of a compiled wrapper -> (its twin without reference counts, the wrapper kept alive)
_twins: dict[int, tuple[Dispatcher, Dispatcher]] = {}


def _compile_wrapper(source: str, name: str, namespace: dict[str, Dispatcher],
                     **options: object) -> Dispatcher:
    """Execute generated ``source`` (a small kernel wrapper) and compile it with numba."""
    fn = compile_generated(source, name, namespace, **options)
    _generated[id(fn)] = (source, name, namespace, fn)
    return fn


def _uncounted_twin(fn: Dispatcher) -> Dispatcher:
    """A wrapper compiled from the same source without reference counts, said explicitly: a
    callee already compiled (or loaded from the disk cache) with counts for the same types
    would keep them under an uncounted caller. A kernel not made here is returned as it is."""
    hit = _twins.get(id(fn))
    if hit is None:
        made = _generated.get(id(fn))
        if made is None:
            return fn
        twin = compile_generated(made[0], made[1], made[2], _nrt=False)
        hit = _twins[id(fn)] = (twin, fn)
    return hit[0]


def _extra_args(spec: SlotSpec, pspec: ParamSpec) -> str:
    """Source of the extra arguments of a kernel: body slots from rows ``i``/``j`` of ``B``,
    run-time parameters from its last row (scalars, or one tuple of floats ``P``)."""
    extra = "".join(f", B[{'i' if w == 1 else 'j'}, {c}]" for c, w in spec)
    if pspec is not None:
        first, count, array = pspec
        if array:  # a tuple, not a view of B: a view costs two atomic reference counts
            extra += ", (" + "".join(f"B[-1, {first + k}], " for k in range(count)) + ")"
        else:
            extra += "".join(f", B[-1, {first + k}]" for k in range(count))
    return extra


def unit_values(L: float, inv_e: float) -> tuple[float, float, float, float, float]:
    """The factors the wrappers multiply by, ``(L, 1/E, L/E, 1/L, L²/E)``, each rounded once
    exactly as when they were compiled-in constants (so the numbers are the same bits)."""
    return (L, inv_e, L * inv_e, 1.0 / L, L * L * inv_e)


def _wrapped(kern: CompiledFunction, spec: SlotSpec, L: float, inv_e: float,
             pspec: ParamSpec = None, ucol: int | None = None) -> Dispatcher:
    """``w(r, c1, c2, c3, B, i, j)``: the SI kernel in internal units, bound slots read from ``B``.

    ``spec`` lists ``(column of B, 1 or 2)`` per extra argument of ``kern``: row ``i`` (first
    body) or ``j`` (second body); ``pspec`` places the run-time parameters in the last row of
    ``B`` (:data:`ParamSpec`). ``U/E`` as a function of ``r/L``: ``U_r`` gains ``L/E``, the
    angular partials ``1/E``. With ``ucol`` the factors :func:`unit_values` are read from the
    last row of ``B`` from that column on (``L``, ``inv_e`` are then ignored), so systems in
    other units share the wrapper.
    """
    key = (id(kern), spec, L, inv_e, pspec, ucol)
    hit = _wrap_cache.get(key)
    if hit is not None:
        return hit[0]
    extra = _extra_args(spec, pspec)
    if ucol is not None:
        u = [f"B[-1, {ucol + k}]" for k in range(5)]
        src = ("def wrapped(r, c1, c2, c3, B, i, j):\n"
               f"    u, ur, u1, u2, u3 = base(r * {u[0]}, c1, c2, c3{extra})\n"
               f"    return (u * {u[1]}, ur * {u[2]}, u1 * {u[1]}, u2 * {u[1]}, u3 * {u[1]})")
    elif L == 1.0 and inv_e == 1.0:
        src = ("def wrapped(r, c1, c2, c3, B, i, j):\n"
               f"    return base(r, c1, c2, c3{extra})")
    else:
        src = ("def wrapped(r, c1, c2, c3, B, i, j):\n"
               f"    u, ur, u1, u2, u3 = base(r * {L!r}, c1, c2, c3{extra})\n"
               f"    return (u * {inv_e!r}, ur * {L * inv_e!r}, u1 * {inv_e!r}, u2 * {inv_e!r}, "
               f"u3 * {inv_e!r})")
    fn = _compile_wrapper(src, "wrapped", {"base": kern})
    _wrap_cache[key] = (fn, kern)  # keep kern alive so its id stays unique
    return fn


def _wrapped_radial(kern: CompiledFunction, spec: SlotSpec, L: float, inv_e: float,
                    pspec: ParamSpec = None, ucol: int | None = None) -> Dispatcher:
    """``w(q, B, i, j) -> (U, U_r/r)`` in internal units, ``q = 1/r``: the fast-path kernel.

    With ``r = r_int L``: ``q_SI = q / L``, ``U_int = U/E``, ``(U_r/r)_int = (U_r/r) L²/E``;
    ``ucol`` as in :func:`_wrapped`.
    """
    key = ("radial", id(kern), spec, L, inv_e, pspec, ucol)
    hit = _wrap_cache.get(key)
    if hit is not None:
        return hit[0]
    base = radial_kernel(kern)
    extra = _extra_args(spec, pspec)
    if ucol is not None:
        src = ("def wrapped_r(q, B, i, j):\n"
               f"    u, f = base(q * B[-1, {ucol + 3}]{extra})\n"
               f"    return (u * B[-1, {ucol + 1}], f * B[-1, {ucol + 4}])")
    elif L == 1.0 and inv_e == 1.0:
        src = f"def wrapped_r(q, B, i, j):\n    return base(q{extra})"
    else:
        src = ("def wrapped_r(q, B, i, j):\n"
               f"    u, f = base(q * {1.0 / L!r}{extra})\n"
               f"    return (u * {inv_e!r}, f * {L * L * inv_e!r})")
    fn = _compile_wrapper(src, "wrapped_r", {"base": base})
    _wrap_cache[key] = (fn, kern)
    return fn


#: The argument types the pair loops call the dispatchers with (``B`` is the C-ordered table
#: of :mod:`~poissonkit.numerics.nbody.table`): ``kern_any(g, r, c1, c2, c3, B, i, j)`` and
#: ``kern_r(g, q, B, i, j)``.
_TABLE = numba.types.float64[:, ::1]
_I, _F = numba.types.int64, numba.types.float64
KERN_ANY_ARGS = (_I, _F, _F, _F, _F, _TABLE, _I, _I)
KERN_R_ARGS = (_I, _F, _TABLE, _I, _I)


class _Compilations(event.Listener):
    """Records every compilation numba starts (dispatcher, argument types, return type)."""

    def __init__(self) -> None:
        self.started: list[tuple[Dispatcher, tuple[object, ...], object]] = []

    def on_start(self, ev: event.Event) -> None:
        d = ev.data
        self.started.append((d["dispatcher"], tuple(d["args"]), d["return_type"]))

    def on_end(self, ev: event.Event) -> None:
        pass

    def forget_failures(self) -> None:
        """Drop the failures numba remembers from these compilations: it keeps one per
        dispatcher and argument types whatever the flags, and would repeat a failure of the
        uncounted attempt (say ``np.array`` without the runtime) to the counted compilation."""
        for disp, args, ret in self.started:
            disp._compiler._failed_cache.pop((args, ret), None)


def compile_counted_if_needed(source: str, name: str,
                              namespace: Mapping[str, CompiledFunction],
                              args: tuple[numba.types.Type, ...],
                              uncounted: Mapping[str, CompiledFunction] | None = None
                              ) -> Dispatcher:
    """A generated dispatcher compiled without numba's reference counts when every kernel it
    calls allocates nothing, with them otherwise (decided here, once per dispatcher).

    Without counts, each call saves the atomic increment and decrement of its array argument
    (``B``, ``P``) that numba cannot prune across the call. Whether a kernel allocates is what
    the compiler itself answers: the dispatcher is compiled for ``args`` (the types its callers
    pass) without counts, which fails in typing or lowering when any kernel it reaches
    allocates (numba needs its runtime for that); it is then compiled with counts, as before,
    after the failures of the attempt are forgotten (:meth:`_Compilations.forget_failures`).
    The kernels it calls are compiled with its setting (numba's flags are inherited by callees
    not compiled yet), so a kernel already compiled with counts keeps them, and the dispatcher
    then calls it without counts of its own, as the pair loops call a counted dispatcher
    (safe: a counted callee balances its own counts): the same numbers either way.
    ``uncounted`` replaces ``namespace`` in the uncounted attempt (callees compiled without
    counts explicitly). The uncounted variant is the one the loops call (the same types) and
    goes to the disk cache; a failed attempt is not cached, so a system whose kernel allocates
    pays it once per process.
    """
    seen = _Compilations()
    try:
        with event.install_listener("numba:compile", seen):
            fn = compile_generated(source, name,
                                   dict(namespace if uncounted is None else uncounted),
                                   _nrt=False)
            fn.compile(args)
        return fn
    except NumbaError:  # a kernel allocates (or cannot be typed so): keep the counts
        seen.forget_failures()
        # said explicitly: numba compiles a callee with its caller's setting unless told, and
        # the pair loops are compiled without counts (nbody/assemble.py)
        return compile_generated(source, name, dict(namespace), _nrt=True)


#: kernel ids -> (kern_any, kern_r, the kernels and radial kernels, kept alive)
_dispatch_cache: dict[tuple[int, ...], tuple[Dispatcher, Dispatcher, tuple[Dispatcher, ...],
                                             tuple[Dispatcher | None, ...]]] = {}


def _dispatcher(kerns: Sequence[Dispatcher], rkerns: Sequence[Dispatcher | None]
                ) -> tuple[Dispatcher, Dispatcher]:
    """``(kern_any, kern_r)`` calling wrapped kernel number ``g``; cached per kernel tuple.

    ``kern_any(g, r, c1, c2, c3, B, i, j) -> (U, U_r, U_c1, U_c2, U_c3)``;
    ``kern_r(g, q, B, i, j) -> (U, U_r/r)`` (``q = 1/r``) for the orientation-free fast path;
    ``rkerns[g]`` is ``None`` for a kernel that depends on orientation.
    """
    key = tuple(id(k) for k in kerns)
    hit = _dispatch_cache.get(key)
    if hit is not None:
        return hit[0], hit[1]
    ns: dict[str, Dispatcher] = {f"k{g}": k for g, k in enumerate(kerns)}
    ns.update({f"q{g}": k for g, k in enumerate(rkerns) if k is not None})
    radial = [g for g, k in enumerate(rkerns) if k is not None]
    if not kerns:
        src_any = ("def kern_any(g, r, c1, c2, c3, B, i, j):\n"
                   "    return (0.0, 0.0, 0.0, 0.0, 0.0)")
    else:
        la = ["def kern_any(g, r, c1, c2, c3, B, i, j):"]
        last = len(kerns) - 1
        for g in range(last):
            la.append(f"    if g == {g}:\n        return k{g}(r, c1, c2, c3, B, i, j)")
        la.append(f"    return k{last}(r, c1, c2, c3, B, i, j)")
        src_any = "\n".join(la)
    if not radial:
        src_r = "def kern_r(g, q, B, i, j):\n    return (0.0, 0.0)"
    else:
        lr = ["def kern_r(g, q, B, i, j):"]
        for g in radial[:-1]:
            lr.append(f"    if g == {g}:\n        return q{g}(q, B, i, j)")
        lr.append(f"    return q{radial[-1]}(q, B, i, j)")
        src_r = "\n".join(lr)
    twins = {k: _uncounted_twin(v) for k, v in ns.items()}
    fa = compile_counted_if_needed(src_any, "kern_any", ns, KERN_ANY_ARGS, twins)
    fr = compile_counted_if_needed(src_r, "kern_r", ns, KERN_R_ARGS, twins)
    _dispatch_cache[key] = (fa, fr, tuple(kerns), tuple(rkerns))  # keep kernels (and ids) alive
    return fa, fr
