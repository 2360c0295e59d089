"""Central finite differences of scalar and vector functions of a state.

The energy, Casimirs and momenta of a system are compiled (numba) or numpy functions without
derivatives, so the equilibrium solver and the stability analysis differentiate them here, in
one place. Component ``i`` moves by ``step * scale[i]``, with ``scale`` the typical size of each
component (:func:`typical_scales`), so SI states whose components differ by orders of magnitude
(positions of centimetres, angular momenta of 1e-4 kg m²/s) are differentiated alike.
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


def typical_scales(x: np.ndarray, layout: tuple[str, ...] | None = None) -> np.ndarray:
    """Typical size of each component of ``x``: the largest ``|x_j|`` over the components of
    the same vector (names that differ only in a trailing ``_x``/``_y``/``_z``), or, for a
    vector that is zero (below ``1e-6`` of the largest ``|x_j|``: the round-off of a solve),
    the largest ``|x_j|`` of the state (1 for the zero state)."""
    size = float(np.max(np.abs(x))) if x.size else 0.0
    fallback = size if size > 0 else 1.0
    if layout is None or len(layout) != x.size:
        return np.full(x.size, fallback)
    groups: dict[str, list[int]] = {}
    for i, name in enumerate(layout):
        stem, _, tail = name.rpartition("_")
        groups.setdefault(stem if stem and tail in ("x", "y", "z") else name, []).append(i)
    out = np.empty(x.size)
    for idx in groups.values():
        g = float(np.max(np.abs(x[idx])))
        out[idx] = g if g > 1e-6 * fallback else fallback
    return out


def gradient(f: ScalarFunction, x: np.ndarray, scale: np.ndarray,
             step: float = FIRST_STEP) -> np.ndarray:
    """``∇f(x)`` by central differences."""
    h = step * scale
    g = np.empty(x.size)
    for i in range(x.size):
        e = np.zeros(x.size)
        e[i] = h[i]
        g[i] = (f(x + e) - f(x - e)) / (2.0 * h[i])
    return g


def jacobian(f: VectorFunction, x: np.ndarray, scale: np.ndarray,
             step: float = FIRST_STEP) -> np.ndarray:
    """``∂f/∂x`` (rows: components of ``f``) by central differences."""
    h = step * scale
    cols = []
    for i in range(x.size):
        e = np.zeros(x.size)
        e[i] = h[i]
        cols.append((np.asarray(f(x + e)) - np.asarray(f(x - e))) / (2.0 * h[i]))
    return np.column_stack(cols) if cols else np.zeros((0, 0))


def hessian(f: ScalarFunction, x: np.ndarray, scale: np.ndarray,
            step: float = SECOND_STEP) -> np.ndarray:
    """Symmetric Hessian of ``f`` at ``x`` by the four-point central formula."""
    n = x.size
    h = step * scale
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


__all__ = ["FIRST_STEP", "SECOND_STEP", "gradient", "hessian", "jacobian", "typical_scales"]
