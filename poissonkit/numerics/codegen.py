"""Sympy expressions → numba-compiled scalar code (common subexpressions eliminated once).

Used by :mod:`poissonkit.numerics.potentials` (pair kernels) and
:mod:`poissonkit.numerics.system` (right-hand sides and Jacobians of symbolic systems). The
generated source is our own (printed from sympy trees, never from user strings), executed in a
namespace that holds only :mod:`math`; sympy is never called at run time.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from poissonkit.errors import InputError


class _Printer(PythonCodePrinter):
    """Prints ``math.*`` calls that numba understands; floats at full precision."""

    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Rational(self, expr):
        return repr(float(expr))

    def _print_Half(self, expr):
        return "0.5"

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and abs(int(exp)) <= 8:
            n = int(exp)
            b = self.parenthesize(base, 100)
            if n == 0:
                return "1.0"
            body = "*".join([b] * abs(n))
            return f"({body})" if n > 0 else f"(1.0/({body}))"
        if exp == sp.Rational(1, 2):
            return f"math.sqrt({self._print(base)})"
        if exp == -sp.Rational(1, 2):
            return f"(1.0/math.sqrt({self._print(base)}))"
        return f"({self.parenthesize(base, 100)})**({self._print(sp.Float(exp) if exp.is_Rational else exp)})"


def check_free_symbols(exprs: Sequence[sp.Expr], allowed: Sequence[sp.Symbol], what: str) -> None:
    """Raise :class:`InputError` if ``exprs`` contain symbols outside ``allowed``."""
    allowed_set = set(allowed)
    free: set[sp.Symbol] = set()
    for e in exprs:
        free |= set(sp.sympify(e).free_symbols)
    extra = free - allowed_set
    if extra:
        names = ", ".join(sorted(map(str, extra)))
        raise InputError(f"{what}: unresolved symbols {names} (give them numerical values)")
    funcs = set()
    for e in exprs:
        funcs |= {type(f).__name__ for f in sp.sympify(e).atoms(sp.core.function.AppliedUndef)}
    if funcs:
        raise InputError(f"{what}: undefined functions {', '.join(sorted(funcs))} cannot be compiled")


def scalar_source(name: str, args: Sequence[str], inputs: Sequence[sp.Symbol],
                  outputs: Sequence[sp.Expr]) -> str:
    """Source of ``def name(*args): ... return (out_0, ..., out_k)`` with CSE.

    ``inputs`` are the symbols bound to ``args`` (same order).
    """
    printer = _Printer()
    subs = {s: sp.Symbol(a, real=True) for s, a in zip(inputs, args)}
    outs = [sp.sympify(o).xreplace(subs) for o in outputs]
    reps, reduced = sp.cse(outs, symbols=sp.numbered_symbols("_t"), optimizations="basic")
    lines = [f"def {name}({', '.join(args)}):"]
    for sym, val in reps:
        lines.append(f"    {sym} = {printer.doprint(val)}")
    lines.append("    return (" + ", ".join(f"float({printer.doprint(o)})" for o in reduced)
                 + ("," if len(reduced) == 1 else "") + ")")
    return "\n".join(lines)


#: Expression trees with more nodes than this (counted with repetition, see :func:`tree_size`)
#: skip sympy's "basic" CSE pre-optimisation (``opt_cse``), whose cost grows steeply with tree
#: size (minutes for the Routh sphere's ``P dH``), and get their Jacobian by differentiating the
#: generated straight-line program instead of the expression trees. Below it, code generation
#: is exactly as before.
LARGE_TREE = 6000


def tree_size(exprs: Sequence[sp.Expr]) -> int:
    """Number of nodes of the expression trees *with repetition* (shared subtrees counted each
    time they occur), computed on the DAG in linear time."""
    memo: dict[sp.Basic, int] = {}

    def size(e: sp.Basic) -> int:
        stack = [e]
        while stack:  # iterative post-order: deep trees must not hit the recursion limit
            top = stack[-1]
            pending = [a for a in top.args if a not in memo]
            if pending:
                stack.extend(pending)
                continue
            stack.pop()
            memo[top] = 1 + sum(memo[a] for a in top.args)
        return memo[e]

    return sum(size(sp.sympify(e)) for e in exprs)


def is_large(exprs: Sequence[sp.Expr]) -> bool:
    """Whether ``exprs`` take the large-expression code path (see :data:`LARGE_TREE`)."""
    return tree_size(exprs) > LARGE_TREE


def straight_line(inputs: Sequence[sp.Symbol], outputs: Sequence[sp.Expr],
                  large: bool | None = None
                  ) -> tuple[list[sp.Symbol], list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr]]:
    """Common-subexpression-eliminated program computing ``outputs`` from ``inputs``.

    Returns ``(args, temporaries, results)``: ``inputs`` renamed to the real symbols ``_y0,
    _y1, ...``, the ordered assignments ``(_t_k, expr)`` and the outputs in terms of both. No
    expression is expanded or simplified. ``large`` (default: :func:`is_large`) selects plain
    CSE without sympy's pre-optimisation and real temporaries (so that programs can be
    differentiated, :func:`jacobian_program`).
    """
    args = [sp.Symbol(f"_y{i}", real=True) for i in range(len(inputs))]
    subs = dict(zip(inputs, args))
    outs = [sp.sympify(o).xreplace(subs) for o in outputs]
    if large is None:
        large = is_large(outs)
    if large:
        reps, reduced = sp.cse(outs, symbols=sp.numbered_symbols("_t", real=True),
                               optimizations=None)
    else:
        reps, reduced = sp.cse(outs, symbols=sp.numbered_symbols("_t"), optimizations="basic")
    return args, list(reps), list(reduced)


def jacobian_program(args: Sequence[sp.Symbol], reps: Sequence[tuple[sp.Symbol, sp.Expr]],
                     results: Sequence[sp.Expr]
                     ) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr]]:
    """Forward-mode differentiation of a straight-line program (from :func:`straight_line`).

    Each temporary ``t = e(s_1, ..., s_m)`` gets tangents ``dt/dy_j = sum_k de/ds_k ds_k/dy_j``
    as new temporaries; only the small expressions ``e`` are differentiated by sympy, so the
    cost is linear in the program length (differentiating the expanded trees of a large field
    and re-running CSE on the result takes minutes). Returns ``(temporaries, jacobian)`` with the
    Jacobian row-major (``d result_i / d y_j`` at ``i * n + j``); the temporaries include the
    original ones, in dependency order.
    """
    n = len(args)
    zero = sp.Integer(0)
    tangent: dict[sp.Symbol, list[sp.Expr]] = {
        a: [sp.Integer(1) if j == i else zero for j in range(n)] for i, a in enumerate(args)}
    names = sp.numbered_symbols("_d", real=True)
    program: list[tuple[sp.Symbol, sp.Expr]] = []

    def named(e: sp.Expr) -> sp.Expr:
        if e.is_Atom or (e.is_Mul and len(e.args) == 2 and e.args[0].is_Number
                         and e.args[1].is_Atom):
            return e
        s = next(names)
        program.append((s, e))
        return s

    def tangents(e: sp.Expr) -> list[sp.Expr]:
        parts = []
        for s in sorted(e.free_symbols & tangent.keys(), key=str):
            ds = tangent[s]
            if all(d == 0 for d in ds):
                continue
            partial = sp.diff(e, s)
            if partial != 0:
                parts.append((named(partial), ds))
        return [sp.Add(*[p * ds[j] for p, ds in parts if ds[j] != 0]) for j in range(n)]

    for sym, val in reps:
        program.append((sym, val))
        tangent[sym] = [named(d) for d in tangents(val)]
    jac = [d for r in results for d in tangents(sp.sympify(r))]
    return program, jac


def program_source(name: str, args: Sequence[sp.Symbol],
                   reps: Sequence[tuple[sp.Symbol, sp.Expr]], results: Sequence[sp.Expr],
                   out_shape: tuple[int, ...]) -> str:
    """Source of ``def name(y, out)`` running the straight-line program and filling ``out``."""
    printer = _Printer()
    lines = [f"def {name}(y, out):"]
    for i, a in enumerate(args):
        lines.append(f"    {a} = y[{i}]")
    for sym, val in reps:
        lines.append(f"    {sym} = {printer.doprint(val)}")
    ncol = out_shape[1] if len(out_shape) == 2 else None
    for k, o in enumerate(results):
        idx = f"{k // ncol}, {k % ncol}" if ncol else f"{k}"
        lines.append(f"    out[{idx}] = {printer.doprint(o)}")
    lines.append("    return out")
    return "\n".join(lines)


def array_source(name: str, inputs: Sequence[sp.Symbol], outputs: Sequence[sp.Expr],
                 out_shape: tuple[int, ...], large: bool | None = None) -> str:
    """Source of ``def name(y, out)`` filling ``out`` (flat or 2-D, C order) from ``y``.

    ``large`` as in :func:`straight_line` (default: decided from the expression size).
    """
    args, reps, reduced = straight_line(inputs, outputs, large)
    return program_source(name, args, reps, reduced, out_shape)


def jacobian_source(name: str, inputs: Sequence[sp.Symbol], outputs: Sequence[sp.Expr],
                    large: bool | None = None) -> str:
    """Source of ``def name(y, out)`` filling ``out[i, j] = d outputs_i / d inputs_j``.

    Small outputs are differentiated symbolically and CSE'd (as before); large ones (or
    ``large=True``) through :func:`jacobian_program` on their CSE program.
    """
    n = len(inputs)
    if large is None:
        large = is_large(outputs)
    if not large:
        Jm = [sp.diff(o, x) for o in outputs for x in inputs]
        return array_source(name, inputs, Jm, (len(outputs), n), large=False)
    args, reps, reduced = straight_line(inputs, outputs, large=True)
    program, jac = jacobian_program(args, reps, reduced)
    return program_source(name, args, program, jac, (len(outputs), n))


def polynomial_degree(expr: sp.Expr, coords: Sequence[sp.Symbol]) -> int | None:
    """Total degree of ``expr`` as a polynomial in ``coords``, or ``None`` if it is not one
    (roots, quotients, transcendental functions of the coordinates)."""
    e = sp.sympify(expr)
    if not e.is_polynomial(*coords):
        return None
    return int(sp.Poly(e, *coords).total_degree()) if e.free_symbols & set(coords) else 0


def discrete_gradient_sources(coords: Sequence[sp.Symbol], hamiltonian: sp.Expr,
                              multiplier: sp.Expr, structure: sp.Matrix) -> dict[str, str]:
    """Sources of the kernels of a discrete-gradient method for ``ẋ = N P ∇H``.

    * ``dg_skew(y, out)`` fills ``out`` with the ``n(n-1)/2`` entries of ``S = N P`` above the
      diagonal, row by row (the caller mirrors them, so ``S`` is skew to the last bit);
    * ``dg_grad(y, out)`` fills ``out`` with ``∇H``;
    * ``dg_energy(y, out)`` fills ``out[0] = H`` (apart from ``dg_grad``: the average vector
      field never needs ``H``, Gonzalez's discrete gradient needs ``H`` and ``∇H`` at different
      points).

    ``"degree"`` is the total degree of ``H`` when it is a polynomial in ``coords``, else
    ``"-1"``.
    """
    n = len(coords)
    H = sp.sympify(hamiltonian)
    N = sp.sympify(multiplier)
    upper = [N * structure[i, j] if structure[i, j] != 0 else sp.Integer(0)
             for i in range(n) for j in range(i + 1, n)]
    grad = [sp.diff(H, x) for x in coords]
    degree = polynomial_degree(H, coords)
    return {
        "dg_skew": array_source("dg_skew", coords, upper or [sp.Integer(0)],
                                (max(len(upper), 1),)),
        "dg_grad": array_source("dg_grad", coords, grad, (n,)),
        "dg_energy": array_source("dg_energy", coords, [H], (1,)),
        "degree": str(-1 if degree is None else degree),
    }


def compile_source(source: str, name: str, namespace: dict | None = None):
    """Execute generated ``source`` and return the compiled function ``name`` (disk-cached,
    see :mod:`poissonkit.numerics.jit`)."""
    from poissonkit.numerics.jit import compile_generated

    return compile_generated(source, name, namespace)
