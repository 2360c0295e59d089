"""Rank-4 Poisson bivectors of SO(2)-symmetric rolling systems, pulled back from e(3).

Survey §5.2–§5.3 ((85)–(94)): a body of revolution rolling on a plane (and, §6, a ball on a
surface of revolution) has two integrals linear in the momenta, ``J_k = (v^(k)(gamma), M)``, and
the symmetry field ``X_S`` (74) of rotations about the symmetry axis. The survey builds rank-4
bivectors ``P^(k)`` with the Casimirs ``(gamma, gamma)`` and ``J_k`` and maps them to e(3) by the
Poisson maps ``phi_k`` of (91). The OCR of (85)–(92) is too garbled to copy, so
here the construction runs the other way round, which needs no unknown function:

* choose the map first. ``L = A(gamma) M`` is fixed by three linear conditions

  - ``(gamma, L) = (c(gamma), M)`` — the Casimir integral ``J_k`` becomes the Casimir
    ``(gamma, L)``;
  - ``(e3 x gamma, L) = (e3 x gamma, M)`` — the momentum conjugate to the latitude is kept;
  - ``L3 = (p(gamma), M)`` — the other linear integral becomes ``L3``, the generator of ``X_S``;

* the bivector is the pull-back ``P = (D phi)^{-1} Lambda_e(3) (D phi)^{-T}``. It is Poisson by
  construction (``phi`` is a local diffeomorphism off the poles ``gamma1 = gamma2 = 0``, where
  ``det`` of the conditions is ``gamma1^2 + gamma2^2``: the survey's singular points ``e±``),
  ``phi`` is a Poisson map onto e(3), and ``(gamma, gamma)`` and ``J_k`` are its Casimirs.

Whether the dynamics is ``X = N P dH + mu X_S`` (Proposition 5) is not built in: it is a claim,
checked by the core (it holds for the Routh sphere, see :mod:`poissonkit_nonholonomic.routh`).
Every check of the resulting bivector (Jacobi, Casimirs, the Poisson map) is run independently
by the core in the plugin's verification.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from poissonkit.errors import InputError
from poissonkit_nonholonomic.common import claim_outcome

_EPS = sp.LeviCivita


def e3_frame_map(gamma: Sequence[sp.Symbol], casimir_row: Sequence[sp.Expr],
                 axial_row: Sequence[sp.Expr]) -> tuple[sp.Matrix, sp.Matrix]:
    """The fibrewise-linear map ``L = A(gamma) M`` of the module docstring and its inverse.

    Parameters
    ----------
    gamma
        The three symbols of the unit normal.
    casimir_row
        ``c(gamma)``: ``(gamma, L) = (c, M)``.
    axial_row
        ``p(gamma)``: ``L3 = (p, M)``.

    Returns
    -------
    (A, B)
        ``L = A M`` and ``M = B L`` (rational in ``gamma`` and in any radical symbol used in the
        rows; denominators vanish at the poles ``gamma1 = gamma2 = 0``).
    """
    if len(gamma) != 3 or len(casimir_row) != 3 or len(axial_row) != 3:
        raise InputError("e3_frame_map needs three gamma symbols and two 3-vectors")
    e = [-gamma[1], gamma[0], sp.Integer(0)]  # e3 x gamma
    W = sp.Matrix([list(gamma), e, [0, 0, 1]])
    V = sp.Matrix([list(casimir_row), e, list(axial_row)])
    A = W.LUsolve(V).applyfunc(sp.cancel)
    B = V.LUsolve(W).applyfunc(sp.cancel)
    return A, B


def e3_pullback(gamma: Sequence[sp.Symbol], M: Sequence[sp.Symbol], A: sp.Matrix, B: sp.Matrix,
                radical: tuple[sp.Symbol, sp.Expr] | None = None) -> sp.Matrix:
    """Pull the e(3) bracket back through ``(gamma, M) -> (gamma, L = A M)``.

    Parameters
    ----------
    gamma, M
        Coordinates, in the order ``(gamma, M)`` of the returned 6x6 matrix.
    A, B
        ``L = A M`` and ``M = B L`` (``B = A^{-1}``), from :func:`e3_frame_map`.
    radical
        ``(G, G2)``: a symbol ``G`` standing for ``sqrt(G2(gamma))`` inside ``A``, ``B``; it is
        differentiated by the chain rule and substituted at the end. Keeping it a symbol keeps
        the rational simplification cheap.

    Notes
    -----
    With ``M = B(gamma) L`` and the e(3) bracket of :mod:`poissonkit.conventions`
    (``{L_k, L_l} = eps_klq L_q``, ``{L_k, gamma_n} = eps_knq gamma_q``)::

        {gamma_i, M_j} = sum_k B_jk {gamma_i, L_k}
        {M_i, M_j}     = (B Lambda_LL B^T)_ij + T_ij - T_ji,
        T_ij           = sum_{k,n} B_ik (d_n B L)_j {L_k, gamma_n},   L = A M.
    """
    gamma, M = list(gamma), list(M)
    G, G2 = radical if radical is not None else (None, None)
    syms = sorted(set(gamma) | set(M) | set().union(*(e.free_symbols for e in list(A) + list(B)))
                  | ({G} | G2.free_symbols if G is not None else set()), key=str)
    # sympy's sparse rational-function field cancels as it goes: far faster than sp.cancel on
    # the assembled sums
    F, *_ = sp.polys.fields.field(syms, sp.QQ)
    gs = [F.from_expr(v) for v in gamma]
    Ms = [F.from_expr(v) for v in M]
    As = [[F.from_expr(A[i, j]) for j in range(3)] for i in range(3)]
    Bs = [[F.from_expr(B[i, j]) for j in range(3)] for i in range(3)]
    gi = [syms.index(v) for v in gamma]
    if G is not None:
        Gi = syms.index(G)
        Gs = F.from_expr(G)
        dG = [F.from_expr(sp.diff(G2, v)) / (2 * Gs) for v in gamma]

    def d(f, n: int):
        out = f.diff(F.gens[gi[n]])
        return out + f.diff(F.gens[Gi]) * dG[n] if G is not None else out

    Ls = [sum((As[i][j] * Ms[j] for j in range(3)), F.zero) for i in range(3)]
    eps = [[[int(_EPS(i, j, k)) for k in range(3)] for j in range(3)] for i in range(3)]
    # {L_k, gamma_n} = eps_knq gamma_q ; {L_k, L_l} = eps_klq L_q
    lam_Lg = [[sum((eps[k][n][q] * gs[q] for q in range(3)), F.zero) for n in range(3)]
              for k in range(3)]
    lam_LL = [[sum((eps[k][l][q] * Ls[q] for q in range(3)), F.zero) for l in range(3)]
              for k in range(3)]
    dBL = [[sum((d(Bs[j][l], n) * Ls[l] for l in range(3)), F.zero) for j in range(3)]
           for n in range(3)]
    T = [[sum((Bs[i][k] * dBL[n][j] * lam_Lg[k][n] for k in range(3) for n in range(3)), F.zero)
          for j in range(3)] for i in range(3)]
    P = sp.zeros(6, 6)
    for i in range(3):
        for j in range(3):
            P[i, 3 + j] = (-sum((Bs[j][k] * lam_Lg[k][i] for k in range(3)), F.zero)).as_expr()
            P[3 + j, i] = -P[i, 3 + j]
        for j in range(i + 1, 3):
            mm = sum((Bs[i][k] * Bs[j][l] * lam_LL[k][l] for k in range(3) for l in range(3)),
                     F.zero) + T[i][j] - T[j][i]
            P[3 + i, 3 + j] = mm.as_expr()
            P[3 + j, 3 + i] = -P[3 + i, 3 + j]
    if G is not None:
        P = P.xreplace({G: sp.sqrt(G2)})
    return P


def symmetry_field(gamma: Sequence[sp.Symbol], M: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """``X_S`` of (74): rotation of ``gamma`` and ``M`` about the symmetry axis ``e3``.

    Components ``(gamma2, -gamma1, 0, M2, -M1, 0)``, i.e. ``gamma_dot = gamma x e3``,
    ``M_dot = M x e3``; in poissonkit's e(3) convention (``xdot = {x, H}``) this is
    ``X_S = -P_e(3) d L3``.
    """
    return [gamma[1], -gamma[0], sp.Integer(0), M[1], -M[0], sp.Integer(0)]


def symmetry_decomposition(field: Sequence[sp.Expr], P: sp.Matrix, H: sp.Expr, N: sp.Expr,
                           gamma: Sequence[sp.Symbol], M: Sequence[sp.Symbol],
                           seed: int = 5) -> tuple[bool, str, str]:
    """Check ``X = N P dH + mu X_S`` with ``mu`` linear in ``M`` on ``(gamma, gamma) = 1``.

    The survey's Propositions 5 and 7. ``mu`` is taken as the ``X_S``-component of
    ``X - N P dH`` in the ``M1, M2`` plane; the check is that the remainder vanishes in every
    component and that ``mu`` is additive in ``M`` (with the quotient form this means linear;
    cheaper at a point than second derivatives). Exact arithmetic at random rational points.

    Returns
    -------
    (holds, detail, method)
        In the form of the plugin's claims.
    """
    from poissonkit.structure.checks import check_vanishing

    coords = list(gamma) + list(M)
    dH = sp.Matrix([sp.diff(H, x) for x in coords])
    Y = sp.Matrix(list(field)) - N * (P * dH)
    XS = symmetry_field(gamma, M)
    mu = (Y[3] * XS[3] + Y[4] * XS[4]) / (XS[3] ** 2 + XS[4] ** 2)
    exprs = {f"(X - N P dH - mu X_S)_{x}": Y[i] - mu * XS[i] for i, x in enumerate(coords)}
    Ma, Mb = sp.symbols("_Ma:3", real=True), sp.symbols("_Mb:3", real=True)
    exprs["mu(M' + M'') - mu(M') - mu(M'')"] = (
        mu.xreplace({x: y + z for x, y, z in zip(M, Ma, Mb)}) - mu.xreplace(dict(zip(M, Ma)))
        - mu.xreplace(dict(zip(M, Mb))))
    sphere = sum(g**2 for g in gamma) - 1
    res = check_vanishing(exprs, (sphere,), coords=coords + list(Ma) + list(Mb),
                          method="random", seed=seed)
    return claim_outcome(res, "exact arithmetic at random rational points on (gamma, gamma) = 1 "
                              f"(false-positive bound {res.false_positive_bound:.1e})")
