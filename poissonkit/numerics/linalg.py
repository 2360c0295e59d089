"""The one dense linear solver of the compiled code: LU with partial pivoting (numba).

The implicit integrators (:mod:`~poissonkit.numerics.integrators.newton`) factorise a small
Newton matrix ``I − (h/2) J`` and solve with it, once or several times per factorisation. The
matrices are tiny (the state's dimension), so a plain loop beats a LAPACK call from compiled code.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, error_model="numpy", inline="always")
def lu_factor(A, piv):
    """LU factorisation with partial pivoting, in place.

    Parameters
    ----------
    A
        ``(n, n)`` float array; on return its strict lower triangle holds the multipliers of
        ``L`` (unit diagonal) and its upper triangle ``U``.
    piv
        ``(n,)`` int64 array receiving the row swapped with row ``k`` at step ``k``.

    Returns
    -------
    bool
        False if ``A`` is singular to working precision (a zero pivot column).
    """
    n = A.shape[0]
    for k in range(n):
        p = k
        best = abs(A[k, k])
        for i in range(k + 1, n):
            if abs(A[i, k]) > best:
                best = abs(A[i, k])
                p = i
        if best == 0.0:
            return False
        piv[k] = p
        if p != k:
            for j in range(n):
                tmp = A[k, j]
                A[k, j] = A[p, j]
                A[p, j] = tmp
        for i in range(k + 1, n):
            A[i, k] /= A[k, k]
            f = A[i, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
    return True


@numba.njit(cache=True, error_model="numpy", inline="always")
def lu_solve(A, piv, b, x):
    """Solve ``A x = b`` with the factors of :func:`lu_factor` (``b`` is overwritten)."""
    n = b.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= A[i, j] * x[j]
        x[i] = acc
    for i in range(n - 1, -1, -1):
        acc = x[i]
        for j in range(i + 1, n):
            acc -= A[i, j] * x[j]
        x[i] = acc / A[i, i]


@numba.njit(cache=True, error_model="numpy")
def gauss_solve(A, b, x):
    """Solve ``A x = b`` (``A`` and ``b`` overwritten): :func:`lu_factor` then
    :func:`lu_solve`. Returns False if ``A`` is singular to working precision."""
    piv = np.empty(b.shape[0], dtype=np.int64)
    if not lu_factor(A, piv):
        return False
    lu_solve(A, piv, b, x)
    return True
