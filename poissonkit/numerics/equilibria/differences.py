"""Central finite differences of scalar and vector functions of a state.

The energy, Casimirs and momenta of a system are compiled (numba) or numpy functions without
derivatives, so the equilibrium solver and the stability analysis differentiate them here, in
one place. Steps are relative to the state's size (``step * max(|x_i|, ‖x‖_∞)``, or ``step`` for
the zero state), so SI and internal units are treated alike.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

#: Relative step of first derivatives (central differences: error ~ step² + eps/step).
FIRST_STEP = 1e-6
#: Relative step of second derivatives (error ~ step² + eps/step²).
SECOND_STEP = 1e-4

ScalarFunction = Callable[[np.ndarray], float]
VectorFunction = Callable[[np.ndarray], np.ndarray]


def steps(x: np.ndarray, step: float) -> np.ndarray:
    """Per-component step sizes ``step * max(|x_i|, ‖x‖_∞)`` (``step`` where ``x = 0``)."""
    size = float(np.max(np.abs(x))) if x.size else 0.0
    return step * np.maximum(np.abs(x), size if size > 0 else 1.0)


def gradient(f: ScalarFunction, x: np.ndarray, step: float = FIRST_STEP) -> np.ndarray:
    """``∇f(x)`` by central differences."""
    h = steps(x, step)
    g = np.empty(x.size)
    for i in range(x.size):
        e = np.zeros(x.size)
        e[i] = h[i]
        g[i] = (f(x + e) - f(x - e)) / (2.0 * h[i])
    return g


def jacobian(f: VectorFunction, x: np.ndarray, step: float = FIRST_STEP) -> np.ndarray:
    """``∂f/∂x`` (rows: components of ``f``) by central differences."""
    h = steps(x, step)
    cols = []
    for i in range(x.size):
        e = np.zeros(x.size)
        e[i] = h[i]
        cols.append((np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2.0 * h[i]))
    return np.column_stack(cols) if cols else np.zeros((0, 0))


def hessian(f: ScalarFunction, x: np.ndarray, step: float = SECOND_STEP) -> np.ndarray:
    """Symmetric Hessian of ``f`` at ``x`` by the four-point central formula."""
    n = x.size
    h = steps(x, step)
    out = np.empty((n, n))
    f0 = f(x)
    for i in range(n):
        ei = np.zeros(n)
        ei[i] = h[i]
        out[i, i] = (f(x + ei) - 2.0 * f0 + f(x - ei)) / h[i] ** 2
        for j in range(i):
            ej = np.zeros(n)
            ej[j] = h[j]
            v = (f(x + ei + ej) - f(x + ei - ej) - f(x - ei + ej) + f(x - ei - ej))
            out[i, j] = out[j, i] = v / (4.0 * h[i] * h[j])
    return out


__all__ = ["FIRST_STEP", "SECOND_STEP", "gradient", "hessian", "jacobian", "steps"]
