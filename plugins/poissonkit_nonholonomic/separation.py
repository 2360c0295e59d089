"""Survey Remark 9, (48): the Chaplygin ball's integrals in sphero-conical coordinates and the
separated variables ``s_{1,2}``.

On the leaf ``c = (gamma, L) = 0`` of e(3) (``T*S^2``) the survey writes the integrals (47) in
sphero-conical coordinates ``u_{1,2}`` of the Poisson sphere as

    ``H1 = a p1^2 + 2 b p1 p2 + c p2^2 + d p1 + e p2 + f``,
    ``H2 = A p1^2 + 2 B p1 p2 + C p2^2 + D p1 + E p2 + F``     (48)

(``p_k`` conjugate to ``u_k``) and states that the separated variables are the roots ``s`` of
``(B - b s)^2 - (A - a s)(C - c s) = 0``, "which in our case are ``s_{1,2} = d(1 + u_{1,2})
u_{1,2}^{-1}``". That equation only involves the parts of ``H1, H2`` quadratic in the momenta,
and these do not depend on ``b = (gamma, M)``: the map (46) is ``M = g L + (terms free of L)``,
so the quadratic parts are those of ``H_k(M = g L)``, the map of Remark 6 on ``b = 0``.

Reconstruction (the OCR of (48) and of the roots is garbled, and the sphero-conical parameters
are not stated):

* ``u_{1,2}`` are the roots of ``sum_i gamma_i^2 / (a_i - u) = 0`` with ``a_i = 1 / I_i``
  (inverse principal moments about the centre), so ``gamma_i^2 = (a_i - u1)(a_i - u2) /
  prod_{j != i} (a_i - a_j)`` and ``d gamma / d u_k = -gamma / (2 (a - u_k))``;
* the roots are read as ``s_k = (1 + d u_k) / u_k`` (``d = m b^2``). The reading
  ``d (1 + u_k) / u_k`` agrees only when ``d = 1`` and fails the check otherwise (tested).

The check :func:`chaplygin_separation_48` derives the coefficients ``a, b, c, A, B, C`` from the
registered system's own ``H1 = (M, omega)`` and ``H2 = (M, M)`` (Hessians in ``M``), never from
the formula being checked, and proves symbolically that ``(B - b s)^2 - (A - a s)(C - c s)``
vanishes at ``s = s_1`` and at ``s = s_2`` identically in ``u_1, u_2`` (so these are its two
roots, and each depends on one coordinate only: separation).
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from poissonkit.errors import InputError


def sphero_conical(a: Sequence[sp.Expr], u: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """``gamma_i^2`` as functions of the sphero-conical coordinates ``u = (u1, u2)``.

    Parameters
    ----------
    a
        The three distinct parameters ``a_i``.
    u
        The two coordinate symbols.

    Returns
    -------
    list of sympy.Expr
        ``(a_i - u1)(a_i - u2) / prod_{j != i} (a_i - a_j)``; they sum to 1.
    """
    if len(set(a)) != 3:
        raise InputError("sphero-conical coordinates need three distinct parameters")
    out = []
    for i in range(3):
        j, k = (x for x in range(3) if x != i)
        out.append((a[i] - u[0]) * (a[i] - u[1]) / ((a[i] - a[j]) * (a[i] - a[k])))
    return out


def _even_substitute(expr: sp.Expr, gamma: Sequence[sp.Symbol], squares: Sequence[sp.Expr]
                     ) -> sp.Expr:
    """Replace ``gamma_i^2`` by ``squares[i]`` in a rational function even in each ``gamma_i``."""
    num, den = sp.fraction(sp.cancel(sp.together(expr)))

    def sub(e: sp.Expr) -> sp.Expr:
        out = sp.Integer(0)
        for mon, c in sp.Poly(sp.expand(e), *gamma).terms():
            if any(x % 2 for x in mon):
                raise InputError("expression is not even in gamma")  # cannot happen: reflections
            out += c * sp.Mul(*[squares[i] ** (mon[i] // 2) for i in range(3)])
        return out

    return sp.factor(sub(num) / sub(den))


def momentum_forms(H1: sp.Expr, H2: sp.Expr, gamma: Sequence[sp.Symbol],
                   M: Sequence[sp.Symbol], g2: sp.Expr, a: Sequence[sp.Expr],
                   u: Sequence[sp.Symbol]) -> tuple[sp.Matrix, sp.Matrix]:
    """The quadratic parts of ``H1, H2`` in the momenta ``p_{u1}, p_{u2}`` of (48).

    ``M = g L``, ``L = gamma x p`` with ``p = p_{u1} f_1 + p_{u2} f_2`` tangent to the sphere
    (``f_k = e_k / |e_k|^2`` dual to ``e_k = d gamma / d u_k``; sphero-conical coordinates are
    orthogonal). Returns the symmetric matrices ``[[a, b], [b, c]]`` and ``[[A, B], [B, C]]``.
    """
    sq = sphero_conical(a, u)
    E = sp.Matrix([[-gamma[i] / (2 * (a[i] - uk)) for uk in u] for i in range(3)])
    Gx = sp.Matrix([[0, -gamma[2], gamma[1]], [gamma[2], 0, -gamma[0]],
                    [-gamma[1], gamma[0], 0]])
    EE = E.T * E
    norms = [_even_substitute(EE[k, k], gamma, sq) for k in range(2)]
    if _even_substitute(EE[0, 1], gamma, sq) != 0:
        raise InputError("the sphero-conical frame is not orthogonal")  # a wrong parametrisation
    out = []
    for H in (H1, H2):
        S = sp.hessian(H, M) / 2
        if any(s.free_symbols & set(M) for s in S):
            raise InputError("H is not quadratic in M")
        W = (Gx * E).T * S * (Gx * E) * g2
        out.append(sp.Matrix(2, 2, lambda i, j: _even_substitute(W[i, j], gamma, sq)
                             / (norms[i] * norms[j])))
    return out[0], out[1]


def chaplygin_separation_48(system) -> tuple[bool, str, str]:
    """Remark 9 (48): in sphero-conical u_k (parameters 1/I_i), (B - b s)^2 - (A - a s)(C - c s) = 0 at s_k = (1 + d u_k)/u_k (separated variables)"""
    q = system.params
    I = [sp.sympify(q[k]) for k in ("I1", "I2", "I3")]
    d = sp.sympify(q["d"])
    note = ""
    if len(set(I)) != 3:  # sphero-conical coordinates need distinct parameters
        from poissonkit_nonholonomic.ball import chaplygin_ball

        system = chaplygin_ball(1, 2, 3, d)
        I = [sp.Integer(1), sp.Integer(2), sp.Integer(3)]
        note = " (system's I_i not distinct; used I = (1, 2, 3))"
    gam, M = system.coords[:3], system.coords[3:]
    H1 = system.integrals["H1=(M,omega)"]
    H2 = system.integrals["H2=(M,M)"]
    g2 = 1 - d * sum(gam[i] ** 2 / (I[i] + d) for i in range(3))  # g^2 of (37)
    u = sp.symbols("_u1 _u2", positive=True)
    K1, K2 = momentum_forms(H1, H2, gam, M, g2, [1 / x for x in I], u)
    s = sp.Symbol("_s")
    (a_, b_), (_, c_) = K1.tolist()
    (A_, B_), (_, C_) = K2.tolist()
    pencil = (B_ - b_ * s) ** 2 - (A_ - a_ * s) * (C_ - c_ * s)
    for k, uk in enumerate(u):
        r = sp.factor(sp.cancel(pencil.subs(s, (1 + d * uk) / uk)))
        if r != 0:
            return False, f"at s_{k + 1} = (1 + d u_{k + 1})/u_{k + 1}: {str(r)[:200]}" + note, \
                "exact (symbolic) in u1, u2"
    return True, note.strip(), "exact (symbolic) in u1, u2"


SEPARATION_CLAIMS = (chaplygin_separation_48,)


def chaplygin_spheroconical(I1=1, I2=2, I3=3, d=1):
    """Chaplygin ball on (gamma,M) = 0 in sphero-conical coordinates, survey Remark 9 (48).

    ``T*S^2`` with the canonical bracket on ``(u_1, u_2, p_1, p_2)``; ``H = H1/2`` and the
    integral ``H2`` of (47)–(48) at ``b = c = 0``, their coefficients derived from the ball's
    ``(M, omega)`` and ``(M, M)`` by :func:`momentum_forms` (sphero-conical parameters
    ``1/I_i``, distinct). ``verify`` then proves ``{H1, H2} = 0`` for the canonical bracket (the
    survey's "integrable system ... in involution with respect to the canonical bracket") and
    the separated variables of :func:`chaplygin_separation_48`.

    Parameters
    ----------
    I1, I2, I3
        Distinct principal moments about the centre (numbers).
    d
        ``m b^2``.
    """
    from poissonkit.structure.blocks import canonical
    from poissonkit.structure.system import HamiltonianSystem
    from poissonkit_nonholonomic.ball import chaplygin_ball
    from poissonkit_nonholonomic.common import positive

    I = [positive(x, n) for x, n in ((I1, "I1"), (I2, "I2"), (I3, "I3"))]
    d = positive(d, "d")
    if len(set(I)) != 3:
        raise InputError("sphero-conical coordinates need distinct I1, I2, I3")
    ball = chaplygin_ball(*I, d)
    gam, M = ball.coords[:3], ball.coords[3:]
    g2 = 1 - d * sum(gam[i] ** 2 / (I[i] + d) for i in range(3))
    P = canonical(2, q="u", p="p")
    u, p = P.coords[:2], P.coords[2:]
    uu = sp.symbols("_u1 _u2", positive=True)
    K1, K2 = momentum_forms(ball.integrals["H1=(M,omega)"], ball.integrals["H2=(M,M)"], gam, M,
                            g2, [1 / x for x in I], uu)
    back = dict(zip(uu, u))
    pv = sp.Matrix(p)
    H1 = sp.factor((pv.T * K1 * pv)[0, 0].xreplace(back))
    H2 = sp.factor((pv.T * K2 * pv)[0, 0].xreplace(back))
    return HamiltonianSystem(
        structure=P, hamiltonian=H1 / 2, multiplier=sp.Integer(1),
        integrals={"H2=(M,M)": H2},
        params={"I1": I[0], "I2": I[1], "I3": I[2], "d": d},
        name="nh.chaplygin_spheroconical",
        doc="Chaplygin ball on (gamma,M) = 0 in sphero-conical coordinates, survey (48).")


def separated_variables_48(system) -> tuple[bool, str, str]:
    """Remark 9 (48): the roots of (B - b s)^2 - (A - a s)(C - c s) are s_k = (1 + d u_k)/u_k"""
    u, p = system.coords[:2], system.coords[2:]
    d = sp.sympify(system.params["d"])
    forms = []
    for H in (system.hamiltonian * 2, system.integrals["H2=(M,M)"]):
        forms.append([sp.diff(H, p[0], 2) / 2, sp.diff(H, p[0], p[1]) / 2, sp.diff(H, p[1], 2) / 2])
    (a_, b_, c_), (A_, B_, C_) = forms
    s = sp.Symbol("_s")
    pencil = (B_ - b_ * s) ** 2 - (A_ - a_ * s) * (C_ - c_ * s)
    for k, uk in enumerate(u):
        r = sp.factor(sp.cancel(pencil.subs(s, (1 + d * uk) / uk)))
        if r != 0:
            return False, f"at s_{k + 1}: {str(r)[:200]}", "exact (symbolic)"
    return True, "", "exact (symbolic)"


SPHEROCONICAL_CLAIMS = (separated_variables_48,)
