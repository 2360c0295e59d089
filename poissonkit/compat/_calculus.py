"""Compat-only calculus that poissonkit's core does not need: curl of multivectors with a density,
the bracket of 1-forms, gauge transformations, Flaschka–Ratiu bivectors and the linear normal
forms on R^3. Everything works on sympy objects; parsing and output formats live elsewhere.

Sign convention of this module is PoissonGeometry's wherever it differs from
:mod:`poissonkit.conventions`: ``sharp(alpha) = -P alpha`` so that ``X_h = sharp(dh) = {h, .}``.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from poissonkit.compat._inputs import Key, is_zero


def sharp(P_matrix: sp.MatrixBase, alpha: sp.MatrixBase) -> sp.Matrix:
    """PoissonGeometry's ``P#(alpha) = -P alpha`` (column vector)."""
    return -(P_matrix * alpha)


def curl(components: dict[Key, sp.Expr], coords: Sequence[sp.Symbol], density: sp.Expr
         ) -> dict[Key, sp.Expr]:
    """Divergence (curl operator) of a multivector relative to the volume ``density * dx1^..^dxn``.

    For ``A = sum_J A^J d_J`` (0-based sorted keys ``J``)::

        D(A) = sum_J sum_{p, i = J[p]} (-1)^p (d_i A^J + A^J d_i log(density)) d_{J without i}

    i.e. ``D_{f Omega}(A) = D_Omega(A) + i_{d log f} A``. PoissonGeometry 1.1.1 differentiates the
    density by ``x_{p+1}`` (the *position* ``p`` of ``i`` in ``J``) instead of by ``x_i``; that is
    the bug this function does not have (docs/compat.md).
    """
    dlog = [sp.diff(density, x) / density for x in coords]
    out: dict[Key, sp.Expr] = {}
    for key, value in components.items():
        for p, i in enumerate(key):
            rest = key[:p] + key[p + 1:]
            term = sp.diff(value, coords[i]) + value * dlog[i]
            out[rest] = out.get(rest, 0) + (-1) ** p * term
    return out


def exterior_derivative_matrix(alpha: sp.MatrixBase, coords: Sequence[sp.Symbol]) -> sp.Matrix:
    """``J^T - J`` with ``J = d alpha_i / d x_j``: the matrix of ``d alpha`` as PoissonGeometry uses it."""
    J = alpha.jacobian(list(coords))
    return J.T - J


def one_forms_bracket(P_matrix: sp.MatrixBase, alpha: sp.MatrixBase, beta: sp.MatrixBase,
                      coords: Sequence[sp.Symbol]) -> sp.Matrix:
    """``{alpha, beta}_P = i_{P#alpha} d beta - i_{P#beta} d alpha + d P(alpha, beta)``.

    With PoissonGeometry's ``P# = -P`` this gives ``{df, dg}_P = d{f, g}``.
    """
    s1, s2 = sharp(P_matrix, alpha), sharp(P_matrix, beta)
    pairing = (beta.T * s1)[0, 0]
    grad = sp.Matrix([sp.diff(pairing, x) for x in coords])
    return (-exterior_derivative_matrix(beta, coords) * s1
            + exterior_derivative_matrix(alpha, coords) * s2 + grad)


def gauge(P_matrix: sp.MatrixBase, B_matrix: sp.MatrixBase) -> tuple[sp.Matrix | None, sp.Expr]:
    """Gauge transformation ``P (I - B P)^{-1}`` and ``det(I - B P)``; matrix ``None`` if singular."""
    n = P_matrix.shape[0]
    M = sp.eye(n) - B_matrix * P_matrix
    det = sp.factor(M.det(method="berkowitz"))
    if is_zero(det):
        return None, sp.Integer(0)
    return (P_matrix * M.adjugate(method="berkowitz") / det), det


def flaschka_ratiu(casimirs: Sequence[sp.Expr], coords: Sequence[sp.Symbol]) -> dict[Key, sp.Expr]:
    """Flaschka–Ratiu bivector ``P^{ij} = (-1)^{i+j} det(dK with columns i, j removed)`` (all i<j).

    Its Casimirs are ``K_1 .. K_{n-2}``; the sign is PoissonGeometry's.
    """
    n = len(coords)
    grads = sp.Matrix([[sp.diff(k, x) for x in coords] for k in casimirs])
    out: dict[Key, sp.Expr] = {}
    for i in range(n):
        for j in range(i + 1, n):
            keep = [c for c in range(n) if c not in (i, j)]
            minor = grads[:, keep]
            out[(i, j)] = (-1) ** (i + j) * minor.det(method="berkowitz")
    return out


def inertia(H: sp.MatrixBase) -> tuple[int, int]:
    """``(#positive, #negative)`` eigenvalues of a real symmetric matrix, exactly.

    Descartes' rule of signs is exact for a polynomial with only real roots, which the
    characteristic polynomial of a symmetric matrix has.
    """
    coeffs = H.charpoly().all_coeffs()

    def changes(cs: Sequence[sp.Expr]) -> int:
        signs = [sp.sign(c) for c in cs if c != 0]
        return sum(1 for a, b in zip(signs, signs[1:]) if a != b)

    deg = len(coeffs) - 1
    negated = [c * (-1) ** (deg - k) for k, c in enumerate(coeffs)]
    return changes(coeffs), changes(negated)
