"""Run-time parameters of a pair potential: the parameter kernel the N-body systems compile
once equals the constant kernel, and changing a run-time parameter compiles nothing new
(``docs/performance.md``, "Parameters as data")."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from poissonkit.testing.geometry import configurations
from poissonkit.testing.potential_setup import Options, Setup
from poissonkit.testing.report import Findings


def _call(rk: Any, inv: tuple[float, float, float, float], body: tuple[float, ...] = ()
          ) -> np.ndarray:
    """Evaluate a :class:`~poissonkit.numerics.potentials.RuntimeKernel` at ``inv``."""
    if rk.array:
        return np.array(rk.kernel(*inv, tuple(rk.values)), float)
    return np.array(rk.kernel(*inv, *body, *rk.values), float)


def _worst(a: list[np.ndarray], b: list[np.ndarray]) -> float:
    out = 0.0
    for x, y in zip(a, b):
        scale = max(float(np.max(np.abs(y))), 1e-300)
        out = max(out, float(np.max(np.abs(x - y))) / scale)
    return out


def _bound(s: Setup) -> tuple[dict[str, Any], dict[str, tuple[str, int]], dict[tuple[str, int],
                                                                                 float]]:
    """Parameters without the body-bound ones, the binding, and each slot's value."""
    bound = {n: (a, w) for n, a, w in s.entry.body_params if n in s.params}
    given = {k: v for k, v in s.params.items() if k not in bound}
    slot_values = {slot: float(s.params[n]) for n, slot in bound.items()}
    return given, bound, slot_values


def _runtime_float_params(s: Setup) -> list[str]:
    """Float parameters a change of which should compile nothing: every float parameter but
    the declared ``constant_params`` (for an ``expr``), or any (for a ``param_kernel``)."""
    return [p.name for p in s.entry.params if p.type == "float" and p.name in s.params
            and p.name not in s.entry.constant_params]


def check_runtime_params(s: Setup, out: Findings, opt: Options) -> None:
    """The parameter kernel equals the constant kernel (also with body-bound parameters);
    no recompilation when a run-time parameter changes (same dispatcher, no new signature)."""
    from poissonkit.numerics.potentials import runtime_potential

    e = s.entry
    inv = [c.invariants() for c in configurations(opt.samples, s.distances, opt.seed + 4)]
    const = s.kernel()
    truth = [np.array(const(*x), float) for x in inv]
    rk = runtime_potential(e, s.params)
    err = _worst([_call(rk, x) for x in inv], truth)
    if err > opt.exact:
        out.add("runtime_params", f"the parameter kernel differs from the constant kernel by "
                                  f"{err:.3g} relative (tolerance {opt.exact:g})")
    given, bound, slots = _bound(s)
    if bound and e.expr is not None:
        bk = runtime_potential(e, given, bound)
        body = tuple(slots[slot] for slot in bk.slots)
        err = _worst([_call(bk, x, body) for x in inv], truth)
        if err > opt.exact:
            out.add("runtime_params", f"the kernel reading {', '.join(sorted(bound))} from the "
                                      f"bodies differs from the constant kernel by {err:.3g} "
                                      f"relative (tolerance {opt.exact:g})")
    if e.expr is None and e.param_kernel is None:
        out.advise("has only a constant kernel: every new parameter value compiles again "
                   "(give param_kernel and param_values)")
        return
    _check_no_recompilation(s, out, rk, inv[0])


def _check_no_recompilation(s: Setup, out: Findings, rk: Any,
                            inv: tuple[float, float, float, float]) -> None:
    from poissonkit.numerics.potentials import runtime_potential

    before = len(rk.kernel.signatures)
    culprits = _shaping_params(s)
    for name in culprits:
        out.add("runtime_params", f"the expr needs the value of the run-time parameter {name!r} "
                                  "(it fails with a symbol in its place), so every value of "
                                  "every parameter compiles a new kernel; declare it in "
                                  "constant_params or keep the expression free of branches")
    if culprits:
        return
    for name in _runtime_float_params(s):
        changed: Mapping[str, Any] = dict(s.params, **{name: float(s.params[name]) * 1.1})
        other = runtime_potential(s.entry, changed)
        if other.kernel is not rk.kernel:
            out.add("runtime_params", f"changing the run-time parameter {name!r} by 10 % "
                                      "compiles a new kernel (it shapes the compiled code: "
                                      "pass it at run time, or declare it in constant_params)")
            continue
        _call(other, inv)
        if len(other.kernel.signatures) != before:
            out.add("runtime_params", f"changing {name!r} adds a numba signature "
                                      f"({before} → {len(other.kernel.signatures)}): the "
                                      "values' types change with the value")


def _shaping_params(s: Setup) -> list[str]:
    """Float parameters of an ``expr`` that cannot be a symbol (it branches on their value)."""
    import sympy as sp

    if s.entry.expr is None or s.entry.param_kernel is not None:
        return []
    bad = []
    for name in _runtime_float_params(s):
        trial = dict(s.params, **{name: sp.Symbol(f"_kit_{name}", real=True)})
        try:
            s.entry.expr(trial)
        except Exception:  # noqa: BLE001 - any failure: the value shapes the expression
            bad.append(name)
    return bad
