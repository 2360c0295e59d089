"""System-specific claims of the survey beyond ``[P,P] = 0``, Casimirs, integrals and measure.

Each claim is a function ``claim(system) -> (ok, detail, method)`` whose docstring's first line
names the claim; :data:`CLAIMS` maps a system name to its claims. They are run by
:func:`poissonkit_nonholonomic.verify.verify_system`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import sympy as sp

from poissonkit.structure.jacobi import is_zero_expression
from poissonkit_nonholonomic.algebra import Radicals, extract_radicals, vanishes

Claim = Callable[[Any], tuple[bool, str, str]]


def _zero_vector(exprs) -> tuple[bool, str]:
    """Exact symbolic zero test of several expressions by the core
    (:func:`poissonkit.structure.jacobi.is_zero_expression`: square roots rationalised)."""
    for i, e in enumerate(exprs):
        e = sp.sympify(e)
        if not is_zero_expression(e):
            return False, f"component {i} nonzero: {str(e)[:200]}"
    return True, ""


def bmf_decomposition(system) -> tuple[bool, str, str]:
    """BMF (55): X = g1^-1 P_b dH1 + g2^-1 P_b dH2 (and Prop. 3) at random rational points"""
    # kept on the plugin's random-point zero test (exact square roots at a point): the core's
    # symbolic proof of (55) for the BMF bivector is far too slow (see verify.AUTO_EXACT_OPS)
    from poissonkit_nonholonomic.algebra import PointSampler
    from poissonkit_nonholonomic.ball import bmf_parts

    p = {k: system.params[k] for k in ("I1", "I2", "I3", "d")}
    parts = bmf_parts(**p)
    gam, M = parts["gamma"], parts["M"]
    coords = gam + M
    gg = sum(x**2 for x in gam)
    d, g, s = parts["d"], parts["g"], parts["s"]
    g1 = g * s / ((2 * d * gg - parts["trB"]) * d)
    g2 = g * s / (2 * d)
    P = parts["P"]
    exprs = list(P) + [sp.diff(parts["H1"], x) for x in coords] \
        + [sp.diff(parts["H2"], x) for x in coords] + [1 / g1, 1 / g2] \
        + [system.original[x] for x in coords]
    conv, rad = extract_radicals(exprs)
    sampler = PointSampler(coords, seed=7)
    for _ in range(3):
        pt = sampler.draw()
        vals = [e.subs(pt) for e in conv]
        Pv = sp.Matrix(6, 6, vals[:36])
        dH1 = sp.Matrix(vals[36:42])
        dH2 = sp.Matrix(vals[42:48])
        X = vals[48] * Pv * dH1 + vals[49] * Pv * dH2
        local = Radicals({k: sp.sympify(Q).subs(pt) for k, Q in rad.roots.items()})
        for i in range(6):
            if not vanishes(X[i] - vals[50 + i], local):
                return False, f"component {i} differs at {pt}", "exact arithmetic, random points"
    return True, "", "exact arithmetic at 3 random rational points"


def _canonical_radicals(expr: sp.Expr) -> sp.Expr:
    """Rewrite every ``sqrt(Q)`` as ``sqrt(cancel(Q))`` so equal radicands share one symbol."""
    return expr.replace(lambda e: e.is_Pow and e.exp.is_Rational and e.exp.q == 2,
                        lambda e: sp.Pow(sp.cancel(e.base), e.exp))


def veselova_chaplygin_equivalence(system) -> tuple[bool, str, str]:
    """Prop. 4/(68): with a_i^Ves = 1 - d a_i^Chap and K = M, on (gamma,gamma) = 1: g_Ves = g_Chap, P_v = P_g, H1^Ves = H2^Chap - d H1^Chap"""
    from poissonkit_nonholonomic.ball import chaplygin_ball
    from poissonkit_nonholonomic.veselova import veselova

    a = [sp.sympify(system.params[k]) for k in ("a1", "a2", "a3")]
    d = sp.Integer(1)
    note = ""
    if not all(x < 1 for x in a):  # a^Chap = (1 - a^Ves)/d must be a positive 1/(I + d)
        a = [sp.Rational(1, 2), sp.Rational(2, 3), sp.Rational(3, 4)]
        note = " (system's a_i >= 1 has no Chaplygin partner; used a^Ves = (1/2, 2/3, 3/4))"
    I = [1 / ((1 - x) / d) - d for x in a]
    ves = veselova(*a)
    ch = chaplygin_ball(*I, d)
    gam = ves.coords[:3]
    sub = dict(zip(ch.coords, ves.coords))
    Pg = ch.structure.matrix.xreplace(sub)
    Pv = ves.structure.matrix
    gv = sp.sqrt(sum(a[i] * gam[i] ** 2 for i in range(3)))
    gc = sp.sqrt(1 - d * sum((1 - a[i]) / d * gam[i] ** 2 for i in range(3)))
    H1v = ves.integrals["H1=(K,A_g K)"]
    H1c = ch.integrals["H1=(M,omega)"].xreplace(sub)
    H2c = ch.integrals["H2=(M,M)"].xreplace(sub)
    exprs = [gv - gc] + list(Pv - Pg) + [H1v - (H2c - d * H1c)]
    u, v = sp.symbols("_u _v", real=True)
    n = 1 + u**2 + v**2
    shell = dict(zip(gam, (2 * u / n, 2 * v / n, (1 - u**2 - v**2) / n)))
    exprs = [_canonical_radicals(sp.sympify(e).xreplace(shell)) for e in exprs]
    ok, detail = _zero_vector(exprs)
    return ok, detail + note, "exact (symbolic) on the unit sphere, rational parametrisation"


def veselova_pushforward(system) -> tuple[bool, str, str]:
    """(62) is the push-forward of the original Veselova equations (58) under K(gamma, M) of (61)"""
    from poissonkit_nonholonomic.algebra import PointSampler
    from poissonkit_nonholonomic.veselova import veselova_original_field

    a = [system.params[k] for k in ("a1", "a2", "a3")]
    orig = veselova_original_field(*a)
    coords = orig["coords"]
    K = orig["K"]
    gam = coords[:3]
    Kd = [sum(sp.diff(Ki, x) * f for x, f in zip(coords, orig["field"])) for Ki in K]
    target = system.original  # (62) in (gamma, K)
    ksub = dict(zip(system.coords, list(gam) + K))
    sampler = PointSampler(coords, seed=11)
    for _ in range(3):
        pt = sampler.draw()
        lhs = [sp.sympify(e).xreplace(pt) for e in list(orig["field"][:3]) + Kd]
        rhs = [sp.sympify(target[x]).xreplace(ksub).xreplace(pt) for x in system.coords]
        for i in range(6):
            if not is_zero_expression(lhs[i] - rhs[i]):
                return False, f"component {i} differs at {pt}", "exact arithmetic, random points"
    return True, "", "exact arithmetic at 3 random rational points"


def chaplygin_remark6(system) -> tuple[bool, str, str]:
    """Remark 6: on (gamma,M) = 0 the map L = M/g takes P_g to e(3) (not verified in FORMULAS.md §13)"""
    gam, M = system.coords[:3], system.coords[3:]
    P = system.structure.matrix
    d_, A = system.params["d"], [1 / (system.params[k] + system.params["d"]) for k in ("I1", "I2", "I3")]
    g = sp.sqrt(1 - d_ * sum(A[i] * gam[i] ** 2 for i in range(3)))
    L = [m / g for m in M]

    def br(F, G):
        dF = sp.Matrix([sp.diff(F, x) for x in system.coords])
        dG = sp.Matrix([sp.diff(G, x) for x in system.coords])
        return (dF.T * P * dG)[0, 0]

    # e(3) in the [v]_eps form: {L_i, L_j} = eps_ijk L_k, {L_i, gamma_j} = eps_ijk gamma_k
    exprs = []
    for i in range(3):
        for j in range(3):
            k = 3 - i - j
            e = sp.LeviCivita(i, j, k) if i != j else 0
            exprs.append(br(L[i], L[j]) - (e * L[k] if i != j else 0))
            exprs.append(br(L[i], gam[j]) - (e * gam[k] if i != j else 0))
    # restrict to (gamma, M) = 0 by solving for M_z
    sol = sp.solve(sum(gam[i] * M[i] for i in range(3)), M[2])[0]
    exprs = [sp.sympify(e).subs(M[2], sol) for e in exprs]
    ok, detail = _zero_vector(exprs)
    return ok, detail, "exact (symbolic) on (gamma, M) = 0"


CLAIMS: dict[str, tuple[Claim, ...]] = {
    "nh.chaplygin_ball_sphere_bmf": (bmf_decomposition,),
    "nh.veselova": (veselova_chaplygin_equivalence, veselova_pushforward),
    "nh.chaplygin_ball": (chaplygin_remark6,),
}
