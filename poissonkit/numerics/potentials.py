"""Compiled pair-potential kernels ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)``.

A :class:`~poissonkit.plugin.PairPotential` gives either a ready numba kernel or a sympy
expression ``U(r, c1, c2, c3)``. Expressions are differentiated once, common subexpressions are
eliminated, and the result is compiled with numba; kernels are cached per (entry, params), so
sympy never runs inside a time loop. Geometry conventions: :mod:`poissonkit.conventions`.

Two forms: :func:`compile_potential` bakes every parameter in as a constant (one compilation
per parameter set); :func:`runtime_potential`, what the N-body systems use, compiles the
parameter-free kernel once and returns the float parameters as run-time values, so sweeping a
parameter compiles nothing new (see "Parameters as data" in docs/performance.md).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from typing import NamedTuple, Union

import numba
import sympy as sp

from poissonkit.contracts import CompiledFunction
from poissonkit.errors import InputError
from poissonkit.numerics.codegen import check_free_symbols, compile_source, scalar_source
from poissonkit.numerics.jit import jit, load_sources, source_key, store_sources
from poissonkit.plugin.contributions import PairPotential

#: The four invariants as the real sympy symbols potentials must use.
R, C1, C2, C3 = sp.symbols("r c1 c2 c3", real=True)

#: compiled kernels by (entry, parameters) and wrappers by (kind, id of the kernel wrapped), the
#: latter with the wrapped kernel kept alive so its id stays unique
_cache: dict[tuple[object, ...],
             Union[CompiledFunction, tuple[CompiledFunction, CompiledFunction]]] = {}
_lock = threading.Lock()


def _freeze(value: object) -> object:
    if isinstance(value, Mapping):
        return tuple(sorted((k, _freeze(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return tuple(_freeze(v) for v in value)
    return value


def _invariant_symbols(expr: sp.Expr) -> dict[sp.Symbol, sp.Symbol]:
    """Map symbols named r, c1, c2, c3 (whatever their assumptions) to the canonical ones."""
    canon = {"r": R, "c1": C1, "c2": C2, "c3": C3}
    return {s: canon[s.name] for s in expr.free_symbols if s.name in canon and s != canon[s.name]}


def kernel_from_expr(expr: sp.Expr, name: str = "pair",
                     extra: tuple[sp.Symbol, ...] = ()) -> CompiledFunction:
    """Differentiate ``U(r, c1, c2, c3)`` once and compile ``(U, U_r, U_c1, U_c2, U_c3)``.

    Parameters
    ----------
    expr
        Sympy expression in symbols named ``r, c1, c2, c3`` (and ``extra``) and numbers only.
    name
        Used in error messages and the generated function's name.
    extra
        Further scalar arguments appended after ``c3`` (per-body parameters bound to body
        attributes, see :func:`compile_bound_potential`); never differentiated.

    Returns
    -------
    numba dispatcher
        ``f(r, c1, c2, c3, *extra) -> (U, U_r, U_c1, U_c2, U_c3)`` (floats).
    """
    try:
        expr = sp.sympify(expr)
    except (sp.SympifyError, TypeError) as exc:
        raise InputError(f"potential {name!r}: expression is not a sympy expression: {exc}") from None
    expr = expr.xreplace(_invariant_symbols(expr))
    extra = tuple(extra)
    key = ("expr", sp.srepr(expr), tuple(sp.srepr(e) for e in extra))
    with _lock:
        hit = _cache.get(key)
    if hit is not None:
        return hit
    check_free_symbols([expr], (R, C1, C2, C3) + extra, f"potential {name!r}")
    fname = "pair_" + "".join(ch if ch.isalnum() else "_" for ch in name)
    args = ("r", "c1", "c2", "c3") + _extra_names(extra)

    def generate() -> str:
        outs = [expr] + [sp.diff(expr, s) for s in (R, C1, C2, C3)]
        return scalar_source(fname, args, (R, C1, C2, C3) + extra, outs)

    kern = compile_source(_stored_source(generate, "pair", fname, key[1], *key[2]), fname)
    with _lock:
        _cache[key] = kern
        _sources[id(kern)] = (expr, name, extra, kern)
    return kern


def _extra_names(extra: tuple[sp.Symbol, ...]) -> tuple[str, ...]:
    """Argument names of the extra symbols: ``_a<k>`` for run-time parameters (symbols named
    ``_param_*``), ``_b<k>`` for body values. The names order the factors of the printed
    products: a parameter sorts first, where its number stood when it was a constant, so a
    product like ``-G m1 m2 / r`` is evaluated in the same order (same bits) either way."""
    return tuple(f"_a{k}" if s.name.startswith("_param_") else f"_b{k}"
                 for k, s in enumerate(extra))


#: expression behind each kernel compiled from one (kept with the kernel, so ids stay unique)
_sources: dict[int, tuple[sp.Expr, str, tuple[sp.Symbol, ...], CompiledFunction]] = {}
Q = sp.Symbol("q", positive=True)


def radial_kernel(kern: CompiledFunction) -> CompiledFunction:
    """Fast form of an orientation-free kernel: ``g(q, *extra) -> (U, U_r / r)`` with ``q = 1/r``.

    Written in ``q`` the usual central potentials (``1/r``, ``1/r^6``, …) need no division, and
    ``U_r / r`` is exactly the factor of the pair force ``−(U_r/r) d``. Kernels compiled from an
    expression are regenerated in ``q``; other kernels (numba functions given directly) are
    wrapped, calling them at ``r = 1/q``.
    """
    key = ("radial", id(kern))
    with _lock:
        hit = _cache.get(key)
        src = _sources.get(id(kern))
    if hit is not None:
        return hit[0]
    if src is not None and not (src[0].free_symbols & {C1, C2, C3}):
        expr, name, extra, _ = src
        fname = "radial_" + "".join(ch if ch.isalnum() else "_" for ch in name)
        args = ("q",) + _extra_names(extra)

        def generate() -> str:
            outs = [expr.subs(R, 1 / Q), (sp.diff(expr, R) / R).subs(R, 1 / Q)]
            return scalar_source(fname, args, (Q,) + extra, outs)

        fast = compile_source(_stored_source(generate, "radial", fname, sp.srepr(expr),
                                             *(sp.srepr(e) for e in extra)), fname)
    else:
        n_extra = len(src[2]) if src is not None else _arity(kern) - 4
        extra_args = "".join(f", _b{k}" for k in range(n_extra))
        source = (f"def radial_wrap(q{extra_args}):\n"
                  "    r = 1.0 / q\n"
                  f"    u, ur, u1, u2, u3 = base(r, 0.0, 0.0, 0.0{extra_args})\n"
                  "    return (u, ur * q)")
        fast = compile_source(source, "radial_wrap", {"base": kern})
    with _lock:
        _cache[key] = (fast, kern)  # keep kern alive so its id stays unique
    return fast


def _stored_source(generate: Callable[[], str], *key: str) -> str:
    """Generated kernel source, from the disk cache when an earlier process made it (the
    symbolic differentiation and CSE are the slow part of a new potential)."""
    k = source_key(*key)
    stored = load_sources(k)
    if stored is not None and "source" in stored:
        return stored["source"]
    src = generate()
    store_sources(k, {"source": src})
    return src


def _arity(kern: CompiledFunction) -> int:
    import inspect

    return len(inspect.signature(kern.py_func).parameters)


def compile_potential(entry: PairPotential, params: Mapping[str, object] | None = None
                      ) -> CompiledFunction:
    """Compiled scalar kernel of a pair potential, cached per ``(entry, params)``.

    Parameters
    ----------
    entry
        The registry entry. Its ``kernel(params)`` is used if given, else ``expr(params)`` is
        differentiated and compiled (see :func:`kernel_from_expr`).
    params
        User parameters; validated with ``entry.resolve_params``.

    Returns
    -------
    numba dispatcher
        ``f(r, c1, c2, c3) -> (U, U_r, U_c1, U_c2, U_c3)`` in the entry's units (SI).

    Raises
    ------
    InputError
        If the entry provides neither a kernel nor an expression, or its expression has
        unresolved symbols.
    """
    if not isinstance(entry, PairPotential):
        raise InputError(f"compile_potential needs a PairPotential, got {type(entry).__name__}")
    resolved = entry.resolve_params(dict(params or {}))
    key = (entry.name, id(entry), _freeze(resolved))
    with _lock:
        hit = _cache.get(key)
    if hit is not None:
        return hit
    if entry.kernel is not None:
        kern = entry.kernel(resolved)
        if not isinstance(kern, numba.core.registry.CPUDispatcher):
            raise InputError(f"potential {entry.name!r}: kernel(params) must return a numba "
                             f"njit function, got {type(kern).__name__}")
    elif entry.expr is not None:
        kern = kernel_from_expr(entry.expr(resolved), entry.name)
    else:
        raise InputError(f"potential {entry.name!r} provides neither expr nor kernel")
    with _lock:
        _cache[key] = kern
    return kern


def compile_bound_potential(entry: PairPotential, params: Mapping[str, object] | None,
                            bound: Mapping[str, tuple[str, int]]
                            ) -> tuple[CompiledFunction, tuple[tuple[str, int], ...]]:
    """Compiled kernel of a potential some of whose parameters come from the two bodies.

    Parameters
    ----------
    entry
        A registry entry with an ``expr`` (kernel-only entries cannot bind parameters).
    params
        The parameters given by the user (SI); these are fixed for every pair.
    bound
        ``{parameter: (body attribute, 1 or 2)}`` for the parameters taken from the first or
        second body of each pair (``entry.body_params`` minus those given in ``params``).

    Returns
    -------
    kernel, slots
        ``f(r, c1, c2, c3, b_0, …, b_{k-1}) -> (U, U_r, U_c1, U_c2, U_c3)`` (SI) and the
        ``(attribute, which body)`` of each extra argument ``b_k``, in order.
    """
    if entry.expr is None:
        raise InputError(f"potential {entry.name!r} has no closed-form expr, so its parameters "
                         f"{sorted(bound)} cannot come from the bodies; give them explicitly")
    given = dict(params or {})
    # validate the fixed parameters with placeholders for the bound ones (then replaced)
    placeholders = {k: 1.0 for k in bound}
    resolved = entry.resolve_params({**given, **placeholders})
    slots = tuple(sorted(set(bound.values())))
    symbols = tuple(sp.Symbol(f"_body{w}_{a}", real=True) for a, w in slots)
    by_slot = dict(zip(slots, symbols))
    for k, slot in bound.items():
        resolved[k] = by_slot[slot]
    key = (entry.name, id(entry), _freeze({k: v for k, v in resolved.items() if k not in bound}),
           tuple(sorted(bound.items())))
    with _lock:
        hit = _cache.get(key)
    if hit is not None:
        return hit, slots
    kern = kernel_from_expr(entry.expr(resolved), entry.name, symbols)
    with _lock:
        _cache[key] = kern
    return kern, slots


def scaled_kernel(kern: CompiledFunction, length: float, energy: float) -> CompiledFunction:
    """Nondimensional version of an SI kernel: ``U/E`` as a function of ``r/L``.

    ``U_r`` picks up a factor ``L/E``; the angular partials ``1/E``.
    """
    L = float(length)
    inv_e = 1.0 / float(energy)
    key = ("scaled", id(kern), L, inv_e)
    with _lock:
        hit = _cache.get(key)
    if hit is not None:
        return hit[0]

    @jit
    def scaled(r, c1, c2, c3):
        u, ur, u1, u2, u3 = kern(r * L, c1, c2, c3)
        return u * inv_e, ur * (L * inv_e), u1 * inv_e, u2 * inv_e, u3 * inv_e

    with _lock:
        _cache[key] = (scaled, kern)  # keep kern alive so its id stays unique
    return scaled


class RuntimeKernel(NamedTuple):
    """An SI kernel whose parameters arrive at run time (see :func:`runtime_potential`).

    Attributes
    ----------
    kernel
        ``f(r, c1, c2, c3, *body values, *params) -> (U, U_r, U_c1, U_c2, U_c3)`` when
        ``array`` is false (one float argument per value of ``values``, after one per body
        slot), else ``f(r, c1, c2, c3, P)`` with ``P`` the tuple of ``values``.
    slots
        ``(body attribute, 1 or 2)`` of each body-bound argument (empty for ``array``).
    values
        The run-time parameter values, in argument order (empty: everything is constant).
    array
        Whether the values go in as one array (a plugin's ``param_kernel``, see
        :class:`~poissonkit.plugin.PairPotential`) or as scalars (kernels generated from an
        ``expr``).
    """

    kernel: CompiledFunction
    slots: tuple[tuple[str, int], ...]
    values: tuple[float, ...]
    array: bool


#: the parameter-free kernel of (entry, constant params, run-time names, bound slots)
_runtime_cache: dict[tuple[object, ...], tuple[CompiledFunction, tuple[tuple[str, int], ...],
                                                PairPotential]] = {}
#: keys whose expr failed with symbolic parameters (they use constants), with the entry kept
#: alive so its id stays unique
_symbolic_failed: dict[tuple[object, ...], PairPotential] = {}


def runtime_names(entry: PairPotential, resolved: Mapping[str, object],
                  exclude: frozenset[str] | set[str] = frozenset()) -> tuple[str, ...]:
    """The parameters of ``entry`` passed at run time: its float parameters present in
    ``resolved``, in declaration order, but those in ``exclude`` (bound to bodies) and in
    ``entry.constant_params``. Integers, strings, booleans and vectors shape the generated
    code (loop counts, branches) and stay constants."""
    return tuple(p.name for p in entry.params
                 if p.type == "float" and p.name in resolved and p.name not in exclude
                 and p.name not in entry.constant_params)


def runtime_potential(entry: PairPotential, params: Mapping[str, object] | None = None,
                      bound: Mapping[str, tuple[str, int]] | None = None) -> RuntimeKernel:
    """The kernel of a pair potential with its parameters as run-time arguments.

    Parameters
    ----------
    entry
        The registry entry. Its ``param_kernel`` is used
        first (values from ``param_values``); an ``expr`` is compiled once with symbols for its
        float parameters; a plain ``kernel`` (or an ``expr`` that cannot take symbols) has
        every parameter compiled in as a constant (:func:`compile_potential`).
    params
        The user's parameters (SI), validated with ``entry.resolve_params``.
    bound
        ``{parameter: (body attribute, 1 or 2)}`` read per pair from the bodies (see
        :func:`compile_bound_potential`); needs an ``expr``.

    Returns
    -------
    RuntimeKernel
        The kernel is the same object for every value of the run-time parameters.

    Raises
    ------
    InputError
        As :func:`compile_potential` and :func:`compile_bound_potential`.
    """
    if not isinstance(entry, PairPotential):
        raise InputError(f"runtime_potential needs a PairPotential, got {type(entry).__name__}")
    given = dict(params or {})
    bound = dict(bound or {})
    if bound and entry.expr is None:
        compile_bound_potential(entry, given, bound)  # raises the typed error
    if not bound and entry.param_kernel is not None:
        return _array_kernel(entry, entry.resolve_params(given))
    if not bound and (entry.kernel is not None or entry.expr is None):
        return RuntimeKernel(compile_potential(entry, given), (), (), False)
    resolved = entry.resolve_params({**given, **{k: 1.0 for k in bound}})
    names = runtime_names(entry, resolved, set(bound))
    constants = _freeze({k: v for k, v in resolved.items() if k not in bound and k not in names})
    key = (id(entry), constants, names, tuple(sorted(bound.items())))
    if key in _symbolic_failed or not names:
        kern, slots = (compile_bound_potential(entry, given, bound) if bound
                       else (compile_potential(entry, given), ()))
        return RuntimeKernel(kern, slots, (), False)
    with _lock:
        hit = _runtime_cache.get(key)
    if hit is None:
        try:
            hit = _symbolic_kernel(entry, resolved, names, bound)
        except InputError:
            raise
        except Exception:  # noqa: BLE001 - an expr that needs numbers: compile constants
            with _lock:
                _symbolic_failed[key] = entry
            return runtime_potential(entry, given, bound)
        with _lock:
            _runtime_cache[key] = hit
    kern, slots, _ = hit
    return RuntimeKernel(kern, slots, tuple(float(resolved[n]) for n in names), False)


def _symbolic_kernel(entry: PairPotential, resolved: Mapping[str, object],
                     names: tuple[str, ...], bound: Mapping[str, tuple[str, int]]
                     ) -> tuple[CompiledFunction, tuple[tuple[str, int], ...], PairPotential]:
    """Compile ``entry.expr`` with symbols for the bound and the run-time parameters."""
    assert entry.expr is not None
    positive = {p.name for p in entry.params if p.positive}
    slots = tuple(sorted(set(bound.values())))
    body = tuple(sp.Symbol(f"_body{w}_{a}", real=True) for a, w in slots)
    by_slot = dict(zip(slots, body))
    run = tuple(sp.Symbol(f"_param_{n}", real=True, positive=(True if n in positive else None))
                for n in names)
    symbolic = dict(resolved)
    symbolic.update({k: by_slot[slot] for k, slot in bound.items()})
    symbolic.update(dict(zip(names, run)))
    kern = kernel_from_expr(entry.expr(symbolic), entry.name, body + run)
    return kern, slots, entry  # the entry kept alive: its id is part of the key


def _array_kernel(entry: PairPotential, resolved: Mapping[str, object]) -> RuntimeKernel:
    """A plugin's :attr:`~poissonkit.plugin.PairPotential.param_kernel` and its values."""
    assert entry.param_kernel is not None
    if entry.param_values is None:
        raise InputError(f"potential {entry.name!r}: param_kernel needs param_values")
    kern = entry.param_kernel(resolved)
    if not isinstance(kern, numba.core.registry.CPUDispatcher):
        raise InputError(f"potential {entry.name!r}: param_kernel(params) must return a numba "
                         f"njit function, got {type(kern).__name__}")
    try:
        values = tuple(float(v) for v in entry.param_values(resolved))
    except (TypeError, ValueError):
        raise InputError(f"potential {entry.name!r}: param_values(params) must give "
                         "numbers") from None
    if not values:
        raise InputError(f"potential {entry.name!r}: param_values(params) is empty; give a "
                         "plain kernel instead")
    return RuntimeKernel(kern, (), values, True)
