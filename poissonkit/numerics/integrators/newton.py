"""The one Newton solve of the implicit integrators (midpoint, discrete gradient), compiled.

Each step solves ``G(Z) = 0`` for an unknown ``Z`` (the new state, or the step's increment)
with the matrix ``I − (h/2) J(x̄)``, ``J`` the field's Jacobian at the midpoint ``x̄`` the
residual leaves in ``mid``: full Newton (a fresh factorisation per iteration) or simplified
Newton (one per step), or fixed-point iteration without a Jacobian. The factorisation and the
solves are :mod:`poissonkit.numerics.linalg`'s LU.
"""

from __future__ import annotations

import math

import numpy as np

from poissonkit.contracts import CompiledFunction
from poissonkit.numerics.jit import jit
from poissonkit.numerics.kernels import copy_into
from poissonkit.numerics.linalg import lu_factor, lu_solve

#: outcomes of :func:`newton_solver`'s solve
CONVERGED, NOT_CONVERGED, SINGULAR = range(3)


@jit
def no_jacobian(y, data, work, out):
    """Placeholder Jacobian of a system without one (never called: fixed-point iteration)."""
    return


@jit(inline="always")
def near_state(dn, prev, zn, yn, tol):
    """Converged for an unknown that is the new state ``Z = x'``: ``max|ΔZ| <= tol (1 + max|Z|)``,
    or the correction stopped shrinking while already within 1000 times that."""
    if dn <= tol * (1.0 + zn):
        return True
    # round-off floor: the correction stopped shrinking while already tiny
    return dn >= prev and dn <= 1e3 * tol * (1.0 + zn)


@jit(inline="always")
def near_increment(dn, prev, zn, yn, tol):
    """Converged for an unknown that is the increment ``Z = x' − x``: ``max|ΔZ| <= tol max|Z|``,
    or stagnation within ``1000 tol (max|Z| + 0.01 (1 + max|x|))`` (Gonzalez's correction
    divides the rounding of ``H`` by ``|Z|``: its floor is of order ``eps (1 + |x|)``)."""
    if dn <= tol * zn:
        return True
    return dn >= prev and dn <= 1e3 * tol * (zn + 1e-2 * (1.0 + yn))


_solvers: dict[tuple[int, int, int, bool], tuple[CompiledFunction, tuple[object, ...]]] = {}


def newton_solver(residual: CompiledFunction, jac: CompiledFunction, converged: CompiledFunction,
                  simplified: bool) -> CompiledFunction:
    """The compiled Newton solve around one residual (cached, inlined into the time loops).

    ``residual(Z, y, h, mid, G, data, work, args)`` writes ``G(Z)`` into ``G`` and the point
    the matrix is taken at into ``mid``; ``jac(mid, data, work, J)`` the Jacobian;
    ``converged(dn, prev, zn, yn, tol)`` the stopping test (:func:`near_state`,
    :func:`near_increment`); ``simplified``: factorise once, at the first iteration.

    ``solve(Z, y, h, tol, maxiter, newton, yn, data, work, args, mid, G, J, A, piv, delta)
    -> (outcome, evaluations)`` improves ``Z`` in place (``yn = max|y|``, ``newton``: use the
    Jacobian, else fixed-point iteration); the outcome is :data:`CONVERGED`,
    :data:`NOT_CONVERGED` (limit reached or not finite) or :data:`SINGULAR` (``Z`` unchanged
    by that iteration).
    """
    key = (id(residual), id(jac), id(converged), bool(simplified))
    hit = _solvers.get(key)
    if hit is not None:
        return hit[0]
    simple = bool(simplified)  # a compile-time constant of the closure

    @jit(inline="always")
    def solve(Z, y, h, tol, maxiter, newton, yn, data, work, args, mid, G, J, A, piv, delta):
        n = Z.shape[0]
        nfev = 0
        prev = np.inf
        for it in range(maxiter):
            residual(Z, y, h, mid, G, data, work, args)
            nfev += 1
            if newton:
                if it == 0 or not simple:
                    jac(mid, data, work, J)
                    for i in range(n):
                        for j in range(n):
                            A[i, j] = -0.5 * h * J[i, j]
                        A[i, i] += 1.0
                    if not lu_factor(A, piv):
                        return SINGULAR, nfev
                lu_solve(A, piv, G, delta)
            else:
                copy_into(G, delta)
            dn = 0.0
            zn = 0.0
            for i in range(n):
                Z[i] -= delta[i]
                dn = max(dn, abs(delta[i]))
                zn = max(zn, abs(Z[i]))
            if not math.isfinite(dn):
                return NOT_CONVERGED, nfev
            if converged(dn, prev, zn, yn, tol):
                return CONVERGED, nfev
            prev = dn
        return NOT_CONVERGED, nfev

    _solvers[key] = (solve, (residual, jac, converged))  # keep the callees (and ids) alive
    return solve
