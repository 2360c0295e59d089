"""Small dense linear-algebra helpers: numerical rank, null spaces, complements."""

from __future__ import annotations

import numpy as np

#: Singular values below ``RANK_TOL`` times the largest count as zero.
RANK_TOL = 1e-8


def rank(a: np.ndarray, tol: float = RANK_TOL) -> int:
    """Numerical rank of ``a`` (relative to its largest singular value)."""
    if a.size == 0:
        return 0
    s = np.linalg.svd(a, compute_uv=False)
    return int(np.sum(s > tol * s[0])) if s.size and s[0] > 0 else 0


def null_space(a: np.ndarray, n: int, tol: float = RANK_TOL) -> np.ndarray:
    """Orthonormal basis (columns) of ``{v ∈ Rⁿ : a v = 0}`` (``a`` has ``n`` columns)."""
    if a.size == 0:
        return np.eye(n)
    _, s, vt = np.linalg.svd(a)
    r = int(np.sum(s > tol * s[0])) if s.size and s[0] > 0 else 0
    return vt[r:].T.copy()


def complement(basis: np.ndarray, vectors: np.ndarray, tol: float = RANK_TOL) -> np.ndarray:
    """Orthonormal basis of the orthogonal complement of ``span(vectors)`` inside
    ``span(basis)`` (``basis`` orthonormal columns; ``vectors`` columns, any number)."""
    if vectors.size == 0 or basis.shape[1] == 0:
        return basis
    coeffs = basis.T @ vectors  # components inside the subspace
    scale = max(float(np.linalg.norm(vectors)), 1e-300)
    if float(np.linalg.norm(coeffs)) <= tol * scale:
        return basis
    q = null_space(coeffs.T, basis.shape[1], tol)
    return basis @ q


__all__ = ["RANK_TOL", "complement", "null_space", "rank"]
