"""System-specific claims of the survey beyond ``[P,P] = 0``, Casimirs, integrals and measure.

Each claim is a function ``claim(system) -> (ok, detail, method)`` whose docstring's first line
names the claim; :data:`CLAIMS` maps a system name to its claims. They are run by
:func:`poissonkit_nonholonomic.verify.verify_system`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import sympy as sp

from poissonkit.structure.checks import CheckResult, check_vanishing
from poissonkit.structure.jacobi import is_zero_expression
from poissonkit.structure.randompoints import RandomPoints
from poissonkit_nonholonomic.common import claim_outcome
from poissonkit_nonholonomic.paraboloid import proposition7
from poissonkit_nonholonomic.reduction import CHAPLYGIN_REDUCTION_CLAIMS, VESELOVA_REDUCTION_CLAIMS
from poissonkit_nonholonomic.routh import RANK4_CLAIMS as ROUTH_RANK4_CLAIMS
from poissonkit_nonholonomic.routh_gyrostat import GYROSTAT_RANK4_CLAIMS
from poissonkit_nonholonomic.routh_horizontal import HORIZONTAL_CLAIMS as ROUTH_HORIZONTAL_CLAIMS
from poissonkit_nonholonomic.separation import SEPARATION_CLAIMS, SPHEROCONICAL_CLAIMS
from poissonkit_nonholonomic.suslov import suslov_prop9, suslov_rank4_casimirs, suslov_rank4_jacobi

Claim = Callable[[Any], tuple[bool, str, str]]


def _zero_vector(exprs) -> tuple[bool, str]:
    """Exact symbolic zero test of several expressions by the core
    (:func:`poissonkit.structure.jacobi.is_zero_expression`: square roots rationalised)."""
    for i, e in enumerate(exprs):
        e = sp.sympify(e)
        if not is_zero_expression(e):
            return False, f"component {i} nonzero: {str(e)[:200]}"
    return True, ""


def _random_outcome(res: CheckResult) -> tuple[bool, str, str]:
    """``(ok, detail, method)`` of a claim tested by the core's ``check_vanishing`` at random
    points: a failure names the component, its exact value and the point."""
    return claim_outcome(res, f"exact arithmetic at {res.trials} random rational points "
                              f"(poissonkit.structure.check_vanishing; false-positive bound "
                              f"{res.false_positive_bound:.1e})")


def bmf_decomposition(system) -> tuple[bool, str, str]:
    """BMF (55): X = g1^-1 P_b dH1 + g2^-1 P_b dH2 (and Prop. 3) at random rational points"""
    # at random points (exact square roots): the core's symbolic proof of (55) for the BMF
    # bivector is far too slow (see verify.AUTO_EXACT_OPS)
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
    pts = RandomPoints(coords, trials=3, seed=7)
    dH1 = [pts.derivative(parts["H1"], x) for x in coords]
    dH2 = [pts.derivative(parts["H2"], x) for x in coords]
    comps = {}
    for i, x in enumerate(coords):
        row = [(P[i, j], j) for j in range(6) if P[i, j] != 0]
        field = (sp.Add(*[e * dH1[j] for e, j in row]) / g1
                 + sp.Add(*[e * dH2[j] for e, j in row]) / g2)
        comps[f"{x}dot"] = field - system.original[x]
    return _random_outcome(check_vanishing(comps, method="random", points=pts))


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
    from poissonkit_nonholonomic.veselova import veselova_original_field

    a = [system.params[k] for k in ("a1", "a2", "a3")]
    orig = veselova_original_field(*a)
    coords = orig["coords"]
    K = orig["K"]
    gam = coords[:3]
    Kd = [sum(sp.diff(Ki, x) * f for x, f in zip(coords, orig["field"])) for Ki in K]
    target = system.original  # (62) in (gamma, K)
    ksub = dict(zip(system.coords, list(gam) + K))
    lhs = list(orig["field"][:3]) + Kd
    comps = {f"{x}dot": lhs[i] - sp.sympify(target[x]).xreplace(ksub)
             for i, x in enumerate(system.coords)}
    return _random_outcome(check_vanishing(comps, method="random", coords=coords, trials=3,
                                           seed=11))


def chaplygin_remark6(system) -> tuple[bool, str, str]:
    """Remark 6: on (gamma,M) = 0 the map L = M/g takes P_g to e(3) (stated, not checked, in the survey)"""
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
    "nh.veselova": (veselova_chaplygin_equivalence, veselova_pushforward)
    + VESELOVA_REDUCTION_CLAIMS,
    "nh.chaplygin_ball": (chaplygin_remark6,) + CHAPLYGIN_REDUCTION_CLAIMS + SEPARATION_CLAIMS,
    "nh.chaplygin_spheroconical": SPHEROCONICAL_CLAIMS,
    "nh.routh_sphere_rank4": ROUTH_RANK4_CLAIMS + ROUTH_HORIZONTAL_CLAIMS,
    "nh.routh_gyrostat_rank4": GYROSTAT_RANK4_CLAIMS,
    "nh.ball_on_paraboloid_rank4": (proposition7,),
    "nh.suslov_rank4": (suslov_rank4_jacobi, suslov_rank4_casimirs, suslov_prop9),
}
