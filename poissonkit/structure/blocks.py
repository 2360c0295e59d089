"""Standard Poisson blocks: canonical, Lie–Poisson (any structure constants), so(3), e(3)."""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from poissonkit.errors import DimensionError, InputError
from poissonkit.structure.bivector import Bivector, _as_symbols

_AXES = ("x", "y", "z")


def eps_matrix(v: Sequence) -> sp.Matrix:
    """``[v]_eps`` with entries ``eps_ijk v_k`` (so ``[v]_eps w = w x v``)."""
    v = list(v)
    if len(v) != 3:
        raise DimensionError(f"eps_matrix needs a 3-vector, got length {len(v)}")
    return sp.Matrix([[0, v[2], -v[1]], [-v[2], 0, v[0]], [v[1], -v[0], 0]])


def canonical(n: int, q: str = "q", p: str = "p") -> Bivector:
    """Canonical bracket ``{q_i, p_j} = delta_ij`` on ``(q_1..q_n, p_1..p_n)``.

    For ``n = 3`` the coordinates are named ``q_x, q_y, q_z, p_x, p_y, p_z``; otherwise
    ``q_1 .. q_n, p_1 .. p_n``.
    """
    if not isinstance(n, int) or n < 1:
        raise InputError(f"canonical: number of degrees of freedom must be a positive int, got {n!r}")
    suffix = _AXES if n == 3 else tuple(str(i + 1) for i in range(n))
    coords = [f"{q}_{s}" for s in suffix] + [f"{p}_{s}" for s in suffix]
    mat = sp.zeros(2 * n, 2 * n)
    for i in range(n):
        mat[i, n + i] = 1
        mat[n + i, i] = -1
    return Bivector.from_matrix(mat, coords)


def lie_poisson(structure_constants, coords: Sequence[sp.Symbol | str] | None = None) -> Bivector:
    """Lie–Poisson bivector ``{x_i, x_j} = sum_k C[i][j][k] x_k``, or of a classical algebra by name.

    Parameters
    ----------
    structure_constants
        Nested sequence ``C[i][j][k]`` of shape ``(n, n, n)``, antisymmetric in ``i, j``.
        The Jacobi identity of the Lie algebra is *not* assumed; check it with
        :func:`poissonkit.structure.check_jacobi`. Or the name of a classical algebra,
        ``"so(5)"``, ``"sl(4)"``, ``"so(3,1)"``, ... (see
        :func:`poissonkit.structure.lie_algebras.lie_algebra` for the names, bases and
        coordinates; ``"so(3)"``, ``"e(3)"``, ``"se(3)"`` give :func:`so3`, :func:`e3`,
        :func:`se3`).
    coords
        Coordinate names (default ``x_1 .. x_n``, or the algebra's own names).

    Examples
    --------
    >>> lie_poisson("so(3)") == so3()
    True
    """
    if isinstance(structure_constants, str):
        from poissonkit.structure.lie_algebras import lie_algebra

        return lie_algebra(structure_constants, coords).bivector
    try:
        # strict: strings are refused, never evaluated
        C = [[[sp.sympify(c, strict=True) for c in row] for row in mat] for mat in structure_constants]
    except (TypeError, sp.SympifyError):
        raise InputError("structure constants must be a nested (n, n, n) sequence of numbers or "
                         "sympy expressions (strings are not accepted)") from None
    n = len(C)
    if any(len(row) != n or any(len(c) != n for c in row) for row in C):
        raise DimensionError("structure constants must have shape (n, n, n)")
    syms = _as_symbols(coords if coords is not None else [f"x_{i + 1}" for i in range(n)])
    if len(syms) != n:
        raise DimensionError(f"{len(syms)} coordinates for {n}-dimensional structure constants")
    mat = sp.zeros(n, n)
    for i in range(n):
        for j in range(n):
            mat[i, j] = sum(C[i][j][k] * syms[k] for k in range(n))
    return Bivector.from_matrix(mat, syms)


def so3(name: str = "m") -> Bivector:
    """so(3): ``{m_i, m_j} = eps_ijk m_k`` on ``(m_x, m_y, m_z)``; Casimir ``|m|^2``."""
    m = sp.symbols(f"{name}_x {name}_y {name}_z", real=True)
    return Bivector.from_matrix(eps_matrix(m), m)


def e3(order: str = "nu_m", names: tuple[str, str] | None = None) -> Bivector:
    """e(3) Lie–Poisson bracket, in either ordering the seeds use.

    ``{m_i, m_j} = eps_ijk m_k``, ``{m_i, nu_j} = eps_ijk nu_k``, ``{nu_i, nu_j} = 0``.

    Parameters
    ----------
    order
        ``"nu_m"`` (seed 000: ``(nu, m)``) or ``"gamma_M"`` (seed 001: ``(gamma, M)``). Both put
        the "position" vector first; the bracket is the same.
    names
        Override the two vector names, e.g. ``("gamma", "L")``.
    """
    if order not in ("nu_m", "gamma_M"):
        raise InputError(f"e3: order must be 'nu_m' or 'gamma_M', got {order!r}")
    a, b = names or (("nu", "m") if order == "nu_m" else ("gamma", "M"))
    g = sp.symbols(f"{a}_x {a}_y {a}_z", real=True)
    L = sp.symbols(f"{b}_x {b}_y {b}_z", real=True)
    G = eps_matrix(g)
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = G
    mat[3:6, 0:3] = G
    mat[3:6, 3:6] = eps_matrix(L)
    return Bivector.from_matrix(mat, g + L)


def se3(names: tuple[str, str] = ("L", "P")) -> Bivector:
    """se(3)* Lie–Poisson bracket built from the 4x4 matrix Lie algebra of rigid motions.

    The structure constants are computed from matrix commutators ``[E_a, E_b] = C_ab^c E_c`` of
    the rotation generators ``J_a`` (``(J_a)_bc = -eps_abc``) and translations ``T_a``, so
    ``{L_i, L_j} = eps_ijk L_k``, ``{L_i, P_j} = eps_ijk P_k``, ``{P_i, P_j} = 0`` (Kirchhoff's
    order: angular momentum first). Isomorphic to :func:`e3` with the blocks swapped; built
    independently, it is a positive control for Jacobi checks.
    """
    basis = []
    for a in range(3):
        J = sp.zeros(4, 4)
        for b in range(3):
            for c in range(3):
                J[b, c] = -sp.LeviCivita(a, b, c)
        basis.append(J)
    for a in range(3):
        T = sp.zeros(4, 4)
        T[a, 3] = 1
        basis.append(T)
    # coordinates of a matrix in the basis: rotation part from the antisymmetric block
    def coords_of(X: sp.Matrix) -> list:
        return [-X[1, 2], -X[2, 0], -X[0, 1], X[0, 3], X[1, 3], X[2, 3]]

    C = [[coords_of(basis[i] * basis[j] - basis[j] * basis[i]) for j in range(6)] for i in range(6)]
    a, b = names
    coords = [f"{a}_{s}" for s in _AXES] + [f"{b}_{s}" for s in _AXES]
    return lie_poisson(C, coords)


def symmetric_top() -> Bivector:
    """Phase space of one symmetric top, ``(nu, m)`` with the e(3) bracket (seed 000 eq. (11)).

    Its Casimirs are ``|nu|^2`` and ``(nu, m)``; the kinetic energy is ``alpha |m|^2 / 2``.
    """
    return e3("nu_m")
