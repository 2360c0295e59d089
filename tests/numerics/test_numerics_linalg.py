"""The compiled LU solver of the implicit integrators, against numpy's LAPACK solve."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.numerics.linalg import gauss_solve, lu_factor, lu_solve


@pytest.mark.parametrize("n", [1, 2, 5, 9])
def test_lu_matches_lapack(n: int) -> None:
    rng = np.random.default_rng(n)
    A = rng.standard_normal((n, n)) + n * np.eye(n) * rng.choice([-1, 1])
    b = rng.standard_normal(n)
    truth = np.linalg.solve(A, b)
    F, piv, x = A.copy(), np.empty(n, dtype=np.int64), np.empty(n)
    assert lu_factor(F, piv)
    lu_solve(F, piv, b.copy(), x)
    assert np.allclose(x, truth, rtol=1e-12, atol=1e-12)
    # one factorisation serves several right-hand sides
    b2 = rng.standard_normal(n)
    lu_solve(F, piv, b2.copy(), x)
    assert np.allclose(x, np.linalg.solve(A, b2), rtol=1e-12, atol=1e-12)
    y = np.empty(n)
    assert gauss_solve(A.copy(), b.copy(), y)
    assert np.allclose(y, truth, rtol=1e-12, atol=1e-12)


def test_pivoting_needed() -> None:
    """A zero leading entry: only a row swap makes the elimination possible."""
    A = np.array([[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]])
    b = np.array([1.0, 2.0, 3.0])
    x = np.empty(3)
    assert gauss_solve(A.copy(), b.copy(), x)
    assert np.allclose(A @ x, b, rtol=0, atol=1e-14)


def test_singular_is_reported() -> None:
    A = np.array([[1.0, 2.0], [2.0, 4.0]])
    assert not lu_factor(A.copy(), np.empty(2, dtype=np.int64))
    assert not gauss_solve(np.zeros((3, 3)), np.ones(3), np.empty(3))
