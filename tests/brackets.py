"""Brackets the structure tests write out themselves from their printed formulas (never from
poissonkit's own builders), shared so that each formula is typed once.

Import as ``from brackets import ...`` (``tests/`` is on ``sys.path``).
"""

from __future__ import annotations

import sympy as sp

from poissonkit.structure import Bivector, eps_matrix


def bivector_of(coords, entries) -> Bivector:
    """The bivector on ``coords`` with ``{u, v} = value`` for each ``(u, v): value`` of
    ``entries`` (and ``{v, u} = -value``)."""
    M = sp.zeros(len(coords))
    for (u, v), val in entries.items():
        i, j = coords.index(u), coords.index(v)
        M[i, j] += val
        M[j, i] -= val
    return Bivector(coords, sp.ImmutableMatrix(M))


def p_g(gam, M, g, c) -> Bivector:
    """The bracket on ``(γ, M)`` of FORMULAS §5: ``{γ_i, M_j} = g ε_ijk γ_k`` and
    ``{M_i, M_j} = (g ε(M) + c ε(γ))_ij``; ``c = (∇g, M)`` gives ``P_{g,0}`` (44), and the
    Chaplygin ball (38) is ``g = sqrt(1 - d (γ, Aγ))``, ``c = -d (M, Aγ)/g``."""
    G = eps_matrix(gam)
    mat = sp.zeros(6, 6)
    mat[0:3, 3:6] = g * G
    mat[3:6, 0:3] = g * G
    mat[3:6, 3:6] = g * eps_matrix(M) + c * G
    return Bivector.from_matrix(mat, (*gam, *M))
