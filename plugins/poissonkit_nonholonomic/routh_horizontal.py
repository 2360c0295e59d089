"""Survey (87)–(90) for the Routh sphere: the horizontal and vertical rank-2 bivectors, the
decomposition of Proposition 5 and the choice of ``alpha``, ``beta`` of (89)–(90).

The OCR of (86)–(89) is garbled, so nothing is copied; every object is fixed by the properties
the survey states, and the claims below check them in exact arithmetic (square roots kept
exact) at seeded random rational points of the sphere ``(gamma, gamma) = 1``:

* vertical ``P_v^(k) = X_S ^ Y`` (86): rank 2, Casimirs ``C``, ``gamma3``,
  ``gamma1 M2 - gamma2 M1`` and ``J_k``, and ``P_v dM3 = X_S``. These properties fix it
  uniquely: ``Y = (0, 0, 0, t gamma1, t gamma2, 1)`` with ``Y(J_k) = 0``.
* horizontal ``Pbar`` (87): rank 2 with Casimirs ``C``, ``J1``, ``J2`` and ``gamma2/gamma1``
  (the OCR's "``d(gamma2/gamma1)``"), i.e. ``Pbar = h V1 ^ V2`` with ``V1``, ``V2`` spanning the
  common kernel of those four differentials; such a bivector is Poisson for every factor ``h``
  (its image is the tangent space of the common level sets, an integrable distribution).
  ``h`` is fixed here by Proposition 5: ``X - g^-1 Pbar dH`` is a multiple of ``X_S``.
* Proposition 5 (88): ``X = N (alpha P_v + beta Pbar) dH + mu X_S``. Because
  ``P_v dH = Y(H) X_S``, the field fixes ``N beta`` and ``mu + N alpha Y(H)``; for ``mu``
  proportional to ``J_k`` the three ``M``-coefficients give a linear system in
  ``(lambda, N alpha)``: ``mu' - lambda J_k - (N alpha) Y(H) = 0``, uniquely solvable.

Finding (checked, with a certificate): the solution ``lambda`` is a non-constant function of
``gamma3``, so no functions ``N``, ``alpha``, ``beta`` of ``gamma`` give the coefficient ``J_k``
(or any constant multiple of it) in (90). What holds is
``X = nu (P_v + beta Pbar) dH + lambda(gamma3) J_k X_S`` with ``alpha = 1``,
``nu = N alpha`` and ``beta = g^-1 / nu`` functions of ``gamma3`` alone.
"""

from __future__ import annotations

import random
from functools import lru_cache

import sympy as sp

from poissonkit.structure.jacobi import is_zero_expression
from poissonkit_nonholonomic.routh import routh_parts

#: Number of random points per claim and the seed of the point generator.
TRIALS, SEED = 3, 87


def _sphere_points(n: int, seed: int) -> list[list[sp.Rational]]:
    """Rational points of the unit sphere (inverse stereographic projection)."""
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        u, v = (sp.Rational(rng.randint(-9, 9), rng.randint(1, 9)) for _ in range(2))
        d = 1 + u**2 + v**2
        out.append([2 * u / d, 2 * v / d, (1 - u**2 - v**2) / d])
    return out


def _zero(e: sp.Expr) -> bool:
    return bool(is_zero_expression(sp.radsimp(sp.expand(e))))


@lru_cache(maxsize=4)
def _parts(params: tuple):
    R, a, m, I1, I3, u = params
    return routh_parts(R, a, m, I1, I3, u)


def _params(system) -> tuple:
    q = system.params
    return tuple(q[k] for k in ("R", "a", "m", "I1", "I3", "u"))


def point_data(p: dict, gpt, k: int) -> dict:
    """At a point ``gamma = gpt`` of the sphere (``M`` symbolic): ``X``, ``X_S``, ``dH``, the
    vertical ``Y``, the horizontal ``V1``, ``V2``, the factor ``b`` of ``X = b V1^V2 dH + mu' X_S``
    and ``mu'``, and the unique ``(lambda, nu)`` with ``mu' = lambda J_k + nu Y(H)``.

    Parameters
    ----------
    p
        :func:`poissonkit_nonholonomic.routh.routh_parts`.
    gpt
        Exact coordinates of a point with ``(gamma, gamma) = 1`` and ``gamma1 != 0``.
    k
        1 (Jellett ``J1``) or 2 (Routh ``J2``).
    """
    gam, M = p["gamma"], p["M"]
    coords = gam + M
    sub = dict(zip(gam, gpt))
    g1, g2, g3 = gpt
    at = lambda e: sp.sympify(e).xreplace(sub)  # noqa: E731
    J = {1: p["J1"], 2: p["J2"]}
    dJ = {j: [at(sp.diff(J[j], v)) for v in coords] for j in J}
    X = sp.Matrix([at(f) for f in p["field"]])
    XS = sp.Matrix([g2, -g1, 0, M[1], -M[0], 0])
    dH = sp.Matrix([at(sp.diff(p["H"], v)) for v in coords])
    # vertical: Y = (0, 0, 0, t g1, t g2, 1), Y(J_k) = 0 (dJ_k is M-independent: J_k linear in M)
    qk = dJ[k][3:]
    t = -qk[2] / (g1 * qk[0] + g2 * qk[1])
    Y = sp.Matrix([0, 0, 0, t * g1, t * g2, 1])
    # horizontal: V1 = (meridian, w), V2 = (0, q1 x q2), w from V1(J1) = V1(J2) = 0, w . (q1 x q2) = 0
    q1, q2 = sp.Matrix(dJ[1][3:]), sp.Matrix(dJ[2][3:])
    n = q1.cross(q2)
    vg = sp.Matrix([g1 * g3, g2 * g3, -(g1**2 + g2**2)])
    rhs = sp.Matrix([-sp.Matrix(dJ[1][:3]).dot(vg), -sp.Matrix(dJ[2][:3]).dot(vg), 0])
    w = sp.Matrix.vstack(q1.T, q2.T, n.T).LUsolve(rhs)
    V1, V2 = sp.Matrix.vstack(vg, w), sp.Matrix.vstack(sp.zeros(3, 1), n)
    PdH = V1 * V2.dot(dH) - V2 * V1.dot(dH)
    # gamma part: X_S and Pbar dH (a multiple of the meridian vg) are orthogonal there
    e = XS[:3, 0]
    mu1 = sp.radsimp(X[:3, 0].dot(e) / e.dot(e))
    b = sp.radsimp(X[:3, 0].dot(vg) / (vg.dot(vg) * V2.dot(dH)))
    YH = Y.dot(dH)
    Jk = sum(qk[i] * M[i] for i in range(3))
    lam, nu = sp.symbols("_lam _nu")
    e = sp.expand(mu1 - lam * Jk - nu * YH)
    eqs = [sp.radsimp(e.coeff(v)) for v in M]
    sol = sp.solve(eqs, [lam, nu], dict=True)  # [] if inconsistent
    lam_v, nu_v = (sol[0].get(lam, sp.nan), sol[0].get(nu, sp.nan)) if sol else (sp.nan, sp.nan)
    resid = sp.Matrix(eqs).xreplace({lam: lam_v, nu: nu_v})
    return dict(X=X, XS=XS, dH=dH, Y=Y, V1=V1, V2=V2, b=b, mu1=mu1, PbdH=PdH,
                lam=lam_v, nu=nu_v, resid=resid, Jk=Jk, dJ=dJ, M=M, g=at(p["g"]),
                gamma=list(gpt), k=k)


def _k(system) -> int:
    return 1 if system.params.get("casimir", "jellett") == "jellett" else 2


def _check(exprs: dict) -> tuple[bool, str]:
    for label, e in exprs.items():
        if not _zero(e):
            return False, f"{label} = {str(sp.radsimp(e))[:160]}"
    return True, ""


def _run(system, build) -> tuple[bool, str, str]:
    p = _parts(_params(system))
    k = _k(system)
    for gpt in _sphere_points(TRIALS, SEED):
        ok, detail = _check(build(point_data(p, gpt, k), p))
        if not ok:
            return False, f"{detail} at gamma = {tuple(gpt)}", _METHOD
    return True, "", _METHOD


_METHOD = (f"exact arithmetic (exact square roots) at {TRIALS} seeded random rational points of "
           "(gamma, gamma) = 1, M symbolic")


def _rot(gpt, c=sp.Rational(3, 5), s=sp.Rational(4, 5)):
    return [c * gpt[0] - s * gpt[1], s * gpt[0] + c * gpt[1], gpt[2]]


def horizontal_87(system) -> tuple[bool, str, str]:
    """(87): Pbar = h V1^V2 has rank 2, Casimirs C, J1, J2, gamma2/gamma1, and X - g^-1 Pbar dH = mu' X_S (h = g b, mu' linear in M)"""
    def build(d, p):
        g1, g2, g3 = d["gamma"]
        V1, V2 = d["V1"], d["V2"]
        dC = sp.Matrix([2 * g1, 2 * g2, 2 * g3, 0, 0, 0])
        dphi = sp.Matrix([-g2 / g1**2, 1 / g1, 0, 0, 0, 0])  # d(gamma2/gamma1)
        out = {}
        for name, df in (("C", dC), ("J1", sp.Matrix(d["dJ"][1])), ("J2", sp.Matrix(d["dJ"][2])),
                         ("gamma2/gamma1", dphi)):
            out[f"V1({name})"] = V1.dot(df)
            out[f"V2({name})"] = V2.dot(df)
        # rank 2: V1 has a non-zero gamma part (g1^2 + g2^2 != 0), V2 a non-zero M part
        out["rank 2 (V2 = 0)"] = sp.Integer(1) if _zero(V2.dot(V2)) else sp.Integer(0)
        rem = d["X"] - d["b"] * d["PbdH"] - d["mu1"] * d["XS"]
        out.update({f"(X - b Pbar dH - mu' X_S)_{i}": rem[i] for i in range(6)})
        # b (hence h = g b) does not depend on M; mu' is linear in M (no constant term)
        M = d["M"]
        out["db/dM"] = sum(sp.diff(d["b"], v) ** 2 for v in M)
        out["mu'(0)"] = d["mu1"].xreplace({v: 0 for v in M})
        return out
    return _run(system, build)


def vertical_86(system) -> tuple[bool, str, str]:
    """(86): P_v = X_S^Y has Casimirs C, gamma3, gamma1 M2 - gamma2 M1, J_k, P_v dM3 = X_S and P_v dH = Y(H) X_S"""
    def build(d, p):
        XS, Y, M = d["XS"], d["Y"], d["M"]
        g1, g2, _ = d["gamma"]
        k = d["k"]
        out = {}
        dK = sp.Matrix([M[1], -M[0], 0, -g2, g1, 0])
        dg3 = sp.Matrix([0, 0, 1, 0, 0, 0])
        for name, df in (("gamma3", dg3), ("gamma1 M2 - gamma2 M1", dK),
                         ("J_k", sp.Matrix(d["dJ"][k]))):
            out[f"X_S({name})"] = XS.dot(df)
            out[f"Y({name})"] = Y.dot(df)
        out["Y(C)"] = Y[0] * g1 + Y[1] * g2  # Y has no gamma part
        out["Y(M3) - 1"] = Y[5] - 1
        out["X_S(H)"] = XS.dot(d["dH"])
        return out
    return _run(system, build)


def survey90_obstruction(system) -> tuple[bool, str, str]:
    """(90) as read fails: X = N(alpha P_v + beta Pbar) dH + c J_k X_S has no solution with c constant (certificate: lambda(gamma3) takes two values)"""
    p = _parts(_params(system))
    k = _k(system)
    pts = [[sp.Rational(3, 5), 0, sp.Rational(4, 5)], [sp.Rational(4, 5), 0, sp.Rational(3, 5)]]
    lams = []
    for gpt in pts:
        d = point_data(p, gpt, k)
        if d["lam"] is sp.nan or d["nu"] is sp.nan or not all(_zero(r) for r in d["resid"]):
            return False, "the M-linear system for (lambda, nu) is inconsistent", _OBS_METHOD
        lams.append(sp.radsimp(d["lam"]))
    if _zero(lams[0] - lams[1]):
        return False, f"lambda equal at both points: {lams[0]}", _OBS_METHOD
    return True, (f"unique lambda(gamma3 = 4/5) = {lams[0]}, lambda(gamma3 = 3/5) = {lams[1]}: "
                  "no constant c (so not c = 1)"), _OBS_METHOD


_OBS_METHOD = ("exact: at each point the 3 M-coefficients of mu' - c J_k - (N alpha) Y(H) = 0 "
               "determine (c, N alpha) uniquely; two values of gamma3 give two different c")


def survey90_corrected(system) -> tuple[bool, str, str]:
    """(90) corrected: X = nu (P_v + beta Pbar) dH + lambda J_k X_S with lambda, nu, beta = g^-1 b / nu (b of (87), h = g b) functions of gamma3 only"""
    def build(d, p):
        lam, nu = d["lam"], d["nu"]
        beta = d["b"] / nu  # Pbar = V1^V2, so beta Pbar with multiplier nu gives b V1^V2
        Pv_dH = d["Y"].dot(d["dH"]) * d["XS"]
        rem = d["X"] - nu * (Pv_dH + beta * d["PbdH"]) - lam * d["Jk"] * d["XS"]
        out = {f"(X - nu (P_v + beta Pbar) dH - lambda J_k X_S)_{i}": rem[i] for i in range(6)}
        out.update({f"M-coefficient {i} of mu' - lambda J_k - nu Y(H)": r
                    for i, r in enumerate(d["resid"])})
        # functions of gamma3 only: same values after a rotation about e3
        e = point_data(p, _rot(d["gamma"]), d["k"])
        out["lambda(R gamma) - lambda(gamma)"] = e["lam"] - lam
        out["nu(R gamma) - nu(gamma)"] = e["nu"] - nu
        out["beta(R gamma) - beta(gamma)"] = e["b"] / e["nu"] - beta
        return out
    return _run(system, build)


HORIZONTAL_CLAIMS = (horizontal_87, vertical_86, survey90_obstruction, survey90_corrected)
