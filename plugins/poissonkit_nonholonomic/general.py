"""The survey's general classes: generalised Chaplygin systems (Theorem 1, survey (14)–(18)) and
the family ``P_{g,f}`` with Theorem 2 (survey (19)–(23)). Everything here is symbolic: the
free functions are sympy undefined functions, so the checks are proofs for all of them.
"""

from __future__ import annotations

import sympy as sp

from poissonkit.structure.bivector import Bivector
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import block, cross, dot, eps_matrix, gamma_M


def generalized_chaplygin() -> HamiltonianSystem:
    """Theorem 1: ``{q_i, p_j} = delta_ij``, ``{p1, p2} = N(q) B(q)``, ``X = N P dH~``.

    Original system (16) in ``(q, P)`` with ``S = A1 P1 + A2 P2 + B``, ``A2 = d1 ln N``,
    ``A1 = -d2 ln N`` (the measure condition (18)), ``H = sum a_ij(q) P_i P_j / 2 + V(q)``;
    ``p = N P`` and ``H~(q, p) = H(q, p / N)``. The original field is pushed forward to ``(q, p)``.
    Invariant measure in ``(q, p)``: ``1/N`` (``= N dP dq``).
    """
    q1, q2, p1, p2 = sp.symbols("q1 q2 p1 p2", real=True)
    P1, P2 = sp.symbols("P1 P2", real=True)
    N = sp.Function("N")(q1, q2)
    Bf = sp.Function("B")(q1, q2)
    a11, a12, a22, V = (sp.Function(n)(q1, q2) for n in ("a11", "a12", "a22", "V"))
    Hq = (a11 * P1**2 + 2 * a12 * P1 * P2 + a22 * P2**2) / 2 + V
    A2 = sp.diff(N, q1) / N
    A1 = -sp.diff(N, q2) / N
    S = A1 * P1 + A2 * P2 + Bf
    qd1, qd2 = sp.diff(Hq, P1), sp.diff(Hq, P2)
    Pd1 = -sp.diff(Hq, q1) + qd2 * S
    Pd2 = -sp.diff(Hq, q2) - qd1 * S
    Nd = sp.diff(N, q1) * qd1 + sp.diff(N, q2) * qd2
    back = {P1: p1 / N, P2: p2 / N}
    field = [qd1, qd2, Nd * P1 + N * Pd1, Nd * P2 + N * Pd2]
    field = [sp.sympify(f).subs(back, simultaneous=True) for f in field]
    Ht = Hq.subs(back, simultaneous=True)
    mat = sp.Matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-1, 0, 0, N * Bf], [0, -1, -N * Bf, 0]])
    coords = (q1, q2, p1, p2)
    return HamiltonianSystem(
        structure=Bivector.from_matrix(mat, coords),
        hamiltonian=Ht,
        multiplier=N,
        integrals={"H~": Ht},
        measure=1 / N,
        name="nh.generalized_chaplygin",
        doc="Generalised Chaplygin system, survey Theorem 1 (14)-(18): X = N {x, H~} with "
            "{p1,p2} = N B (survey (14)–(18)); N, B, a_ij, V arbitrary functions.",
        original=dict(zip(coords, field)),
    )


def _function_or(expr, name, gam):
    """An undefined function of gamma, or the given expression (string parsed safely)."""
    from poissonkit.structure.parsing import parse_expression

    if expr is None:
        return sp.Function(name)(*gam)
    return parse_expression(expr, gam) if isinstance(expr, str) else sp.sympify(expr)


def p_gf_system(with_phi: bool = False, g=None, f=None, phi=None) -> HamiltonianSystem:
    """The family ``P_{g,f}`` (22)/(23) with Theorem 2: ``X = -g^{-1} P_{g,f} dH``.

    ``g(gamma) > 0``, ``f(gamma)``, ``U(gamma)`` arbitrary; ``H = (M, A M)/2 + U`` with symbolic
    ``A = diag(a1, a2, a3)``. The original system is (19) in the ``[v]_eps`` sign
    (``Mdot = (M - S gamma) x dH/dM + gamma x dH/dgamma``) with ``S = (K, M)``,
    ``K = f gamma + grad(rho)/rho`` and ``rho = 1/g`` (Theorem 2; survey (19)–(23)).

    Parameters
    ----------
    with_phi
        Add Remark 5's term ``phi(gamma) [[0, 0], [0, Gamma]]`` (then only Jacobi and the
        Casimirs are claimed, not (19)).
    g, f, phi
        Optional concrete functions of ``gamma_x, gamma_y, gamma_z`` (strings or sympy
        expressions); ``None`` keeps an arbitrary (undefined) function. Giving ``phi`` implies
        ``with_phi``.
    """
    gam, M = gamma_M("M")
    with_phi = with_phi or phi is not None
    g = _function_or(g, "g", gam)
    f = _function_or(f, "f", gam)
    U = sp.Function("U")(*gam)
    a = sp.symbols("a1 a2 a3", positive=True)
    G = eps_matrix(gam)
    grad_g = [sp.diff(g, x) for x in gam]
    lower = g * eps_matrix(M) + (dot(grad_g, M) - g * f * dot(gam, M)) * G
    if with_phi:
        lower = lower + _function_or(phi, "phi", gam) * G
    P = block(sp.zeros(3), g * G, g * G, lower)
    H = dot(M, [a[i] * M[i] for i in range(3)]) / 2 + U
    dHM = [sp.diff(H, x) for x in M]
    dHg = [sp.diff(H, x) for x in gam]
    K = [f * gam[i] - grad_g[i] / g for i in range(3)]
    S = dot(K, M)
    MS = [M[i] - S * gam[i] for i in range(3)]
    original = None if with_phi else dict(zip(gam + M, cross(gam, dHM)
                                                  + [x + y for x, y in zip(cross(MS, dHM),
                                                                           cross(gam, dHg))]))
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, gam + M),
        hamiltonian=H,
        multiplier=-1 / g,
        casimirs={"(gamma,gamma)": dot(gam, gam), "(gamma,M)": dot(gam, M)},
        measure=1 / g,
        name="nh.p_gf_phi" if with_phi else "nh.p_gf",
        doc="The family P_{g,f}" + (" + phi (Remark 5)" if with_phi else "")
            + ", survey (22)/(23) and Theorem 2; g, f, U arbitrary.",
        original=original,
    )
