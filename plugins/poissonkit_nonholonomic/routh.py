"""The Routh sphere: a dynamically symmetric, unbalanced ball rolling on a plane (survey §5.5,
(30)–(33), (77), (97)–(98)).

``I = diag(I1, I1, I3)``, ``r(gamma) = (R gamma1, R gamma2, R gamma3 + a)`` (centre of mass to the
contact point), ``U = u gamma3`` (gravity). Integrals: energy, Jellett ``J1 = (M, r)``, Routh
``J2 = g omega3`` with ``g = sqrt(I1 I3 + m (r, I r))``; invariant measure ``g^{-1}``.

Two registered systems:

* ``nh.routh_sphere`` — the dynamics: the rank-2 bivector ``P = X ^ Z / Z(H)`` of
  :func:`poissonkit_nonholonomic.common.euler_bivector` reproduces ``X`` exactly (``X = P dH``);
  it is Poisson for ``u = 0`` and fails the Jacobi identity for ``u != 0`` (reported).
* ``nh.routh_sphere_rank4`` — the survey's §5.2–§5.3 structure: a rank-4 Poisson bivector
  ``P^(k)`` with the Casimirs ``(gamma, gamma)`` and ``J_k`` (Jellett ``k = 1`` or Routh ``k = 2``),
  pulled back from e(3) through the Poisson map ``phi_k`` (91)
  (:mod:`poissonkit_nonholonomic.revolution`), with Proposition 5 ``X = -P dH + mu X_S`` and the
  e(3) form (93)–(94) of the integrals as claims. The OCR of (85)–(92) itself is not copied
  (its OCR is garbled); this is a reconstruction judged by the core's checks.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import (Scalar, claim_outcome, cross, dot, euler_bivector,
                                            exact, gamma_M, positive)
from poissonkit_nonholonomic.revolution import e3_frame_map, e3_pullback, symmetry_decomposition


def routh_parts(R: Scalar = 2, a: Scalar = sp.Rational(1, 2), m: Scalar = 3, I1: Scalar = 5, I3: Scalar = 7,
                u: Scalar = 10) -> dict[str, Any]:
    """Symbols and expressions of the Routh sphere (field, omega, H, J1, J2, g)."""
    R, m = positive(R, "R"), positive(m, "m")
    I1, I3 = positive(I1, "I1"), positive(I3, "I3")
    a, u = exact(a, "a"), exact(u, "u")
    gam, M = gamma_M("M")
    Idiag = [I1, I1, I3]
    r = [R * gam[0], R * gam[1], R * gam[2] + a]
    rr = dot(r, r)
    A = [1 / (Ii + m * rr) for Ii in Idiag]
    Ar = [A[i] * r[i] for i in range(3)]
    AM = [A[i] * M[i] for i in range(3)]
    omega = [AM[i] + m * dot(r, AM) * Ar[i] / (1 - m * dot(r, Ar)) for i in range(3)]
    U = u * gam[2]
    dU = [sp.diff(U, x) for x in gam]
    gdot = cross(gam, omega)
    rdot = [R * v for v in gdot]
    Mdot = [x + y + z for x, y, z in zip(cross(M, omega), [m * c for c in cross(rdot, cross(omega, r))],
                                         cross(gam, dU))]
    H = dot(M, omega) / 2 + U
    g = sp.sqrt(I1 * I3 + m * dot(r, [Idiag[i] * r[i] for i in range(3)]))
    J1 = dot(M, r)
    J2 = g * omega[2]
    return dict(gamma=gam, M=M, omega=omega, field=gdot + Mdot, H=H, J1=J1, J2=J2, g=g,
                params={"R": R, "a": a, "m": m, "I1": I1, "I3": I3, "u": u})


def routh_sphere(R: Scalar = 2, a: Scalar = sp.Rational(1, 2), m: Scalar = 3, I1: Scalar = 5, I3: Scalar = 7,
                 u: Scalar = 10) -> HamiltonianSystem:
    """Routh sphere on a horizontal plane with the Jellett and Routh integrals.

    Parameters
    ----------
    R
        Radius of the sphere.
    a
        Offset of the centre of mass from the geometric centre along the symmetry axis.
    m
        Mass.
    I1, I3
        Principal moments about the centre of mass (``I2 = I1``).
    u
        Potential ``U = u gamma3`` (``u = m g_grav a``-type constant; 0 for inertial rolling).
    """
    p = routh_parts(R, a, m, I1, I3, u)
    gam, M = p["gamma"], p["M"]
    coords = gam + M
    P = euler_bivector(p["field"], coords, M, p["H"])
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, coords),
        hamiltonian=p["H"],
        multiplier=sp.Integer(1),
        casimirs={"C=(gamma,gamma)": dot(gam, gam)},
        integrals={"H": p["H"], "J1=(M,r) (Jellett)": p["J1"], "J2=g omega3 (Routh)": p["J2"]},
        measure=1 / p["g"],
        params=p["params"],
        name="nh.routh_sphere",
        doc="Routh sphere on a plane, survey (97)-(98); rank-2 Euler-field "
            "bivector with X = P dH exactly (Poisson only for u = 0; the rank-4 Poisson "
            "bivector of §5.2 is nh.routh_sphere_rank4).",
        original=dict(zip(coords, p["field"])),
        constraints=(dot(gam, gam) - 1,),
    )


CASIMIR_CHOICES = ("jellett", "routh")


@lru_cache(maxsize=8)
def _rank4(R: sp.Expr, a: sp.Expr, m: sp.Expr, I1: sp.Expr, I3: sp.Expr, casimir: str):
    """Rows of the map ``phi_k`` and the pulled-back bivector (cached: ~5-10 s per parameter set)."""
    gam, M = gamma_M("M")
    G = sp.Symbol("_g", positive=True)  # g(gamma), kept a symbol while the bracket is assembled
    r = [R * gam[0], R * gam[1], R * gam[2] + a]
    g2 = sp.expand(I1 * I3 + m * (I1 * (r[0] ** 2 + r[1] ** 2) + I3 * r[2] ** 2))
    # J2 = g omega3 = (I1 M3 + m r3 (r, M)) / g
    routh_row = [m * r[2] * r[0] / G, m * r[2] * r[1] / G, (I1 + m * r[2] ** 2) / G]
    if casimir == "jellett":  # (gamma, L) = J1, L3 = J2 / I1 (the survey's "J2 = I1 L3")
        c_row, p_row = r, [v / I1 for v in routh_row]
    else:  # (gamma, L) = J2, L3 = J1
        c_row, p_row = routh_row, r
    A, B = e3_frame_map(gam, c_row, p_row)
    P = e3_pullback(gam, M, A, B, radical=(G, g2))
    g = sp.sqrt(g2)
    return P, A.xreplace({G: g}), B.xreplace({G: g})


def routh_sphere_rank4(R: Scalar = 2, a: Scalar = sp.Rational(1, 2), m: Scalar = 3, I1: Scalar = 5,
                       I3: Scalar = 7, u: Scalar = 10, casimir: str = "jellett") -> HamiltonianSystem:
    """Routh sphere with the rank-4 Poisson bivector P^(k) of survey §5.2 (Casimir J_k).

    The structure is the pull-back of e(3) through the Poisson map ``phi_k`` (91):
    ``(gamma, L) = J_k``, ``(e3 x gamma, L) = (e3 x gamma, M)`` and ``L3 = J2 / I1``
    (``k = 1``, Jellett) or ``L3 = J1`` (``k = 2``, Routh), see
    :mod:`poissonkit_nonholonomic.revolution`. The Hamiltonian part of the dynamics is
    ``N P dH`` with ``N = -1``; the full field (32) is ``X = -P dH + mu X_S`` (Proposition 5),
    a claim checked by :func:`routh_prop5` — so ``original`` is not set: integrating this system
    gives the Hamiltonian part only; the dynamics is ``nh.routh_sphere``.

    Parameters
    ----------
    R, a, m, I1, I3, u
        As :func:`routh_sphere`.
    casimir
        ``"jellett"`` (``P^(1)``, Casimir ``J1 = (M, r)``) or ``"routh"`` (``P^(2)``, Casimir
        ``J2 = g omega3``).
    """
    if casimir not in CASIMIR_CHOICES:
        raise InputError(f"casimir must be one of {CASIMIR_CHOICES}, got {casimir!r}")
    p = routh_parts(R, a, m, I1, I3, u)
    q = p["params"]
    P, _, _ = _rank4(q["R"], q["a"], q["m"], q["I1"], q["I3"], casimir)
    gam, M = p["gamma"], p["M"]
    coords = gam + M
    J1, J2 = p["J1"], p["J2"]
    cas, other = (("J1=(M,r) (Jellett)", J1), ("J2=g omega3 (Routh)", J2)) \
        if casimir == "jellett" else (("J2=g omega3 (Routh)", J2), ("J1=(M,r) (Jellett)", J1))
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, coords),
        hamiltonian=p["H"],
        multiplier=sp.Integer(-1),
        casimirs={"C=(gamma,gamma)": dot(gam, gam), cas[0]: cas[1]},
        integrals={"H": p["H"], other[0]: other[1]},
        measure=1 / p["g"],
        params={**q, "casimir": casimir},
        name="nh.routh_sphere_rank4",
        doc="Routh sphere, rank-4 Poisson bivector P^(k) of survey §5.2 pulled back from e(3) by "
            "the map (91); X = -P dH + mu X_S (Prop. 5) is a claim.",
        constraints=(dot(gam, gam) - 1,),
    )


def _system_parts(system) -> tuple[dict, sp.Matrix, sp.Matrix, sp.Matrix]:
    q = system.params
    p = routh_parts(q["R"], q["a"], q["m"], q["I1"], q["I3"], q["u"])
    P, A, B = _rank4(q["R"], q["a"], q["m"], q["I1"], q["I3"], q["casimir"])
    return p, P, A, B


def routh_prop5(system) -> tuple[bool, str, str]:
    """Prop. 5: the field (32) is X = -P dH + mu X_S with mu linear in M (P = P^(k), X_S of (74))"""
    p, P, _, _ = _system_parts(system)
    return symmetry_decomposition(p["field"], P, p["H"], sp.Integer(-1), p["gamma"], p["M"])


def routh_field_integrals(system) -> tuple[bool, str, str]:
    """The field (32) (with gravity) conserves H, (gamma,gamma), J1, J2 and has the measure g^-1 (77)"""
    from poissonkit.structure.checks import is_first_integral, is_invariant_measure

    p, _, _, _ = _system_parts(system)
    coords = p["gamma"] + p["M"]
    X = dict(zip(coords, p["field"]))
    ints = {"H": p["H"], "C": dot(p["gamma"], p["gamma"]), "J1": p["J1"], "J2": p["J2"]}
    r1 = is_first_integral(X, ints, coords=coords, method="random", seed=5)
    method = "exact arithmetic at random rational points (off the sphere too)"
    if not r1.holds:
        return claim_outcome(r1, method)
    return claim_outcome(is_invariant_measure(X, 1 / p["g"], coords=coords, method="random",
                                              seed=5), method)


def _e3(names=("gamma", "L")) -> Bivector:
    from poissonkit.structure.blocks import e3

    return e3("gamma_M", names=names)


def routh_poisson_map(system) -> tuple[bool, str, str]:
    """(91): phi_k (gamma, M) -> (gamma, L = A(gamma) M) takes P^(k) to e(3); (gamma, L) = J_k"""
    from poissonkit.structure.checks import check_vanishing

    p, P, A, _ = _system_parts(system)
    gam, M = p["gamma"], p["M"]
    coords = gam + M
    L = list(A * sp.Matrix(M))
    phi = list(gam) + L
    Q = _e3()
    Jac = sp.Matrix([[sp.diff(f, x) for x in coords] for f in phi])
    lhs = Jac * P * Jac.T
    rhs = Q.matrix.xreplace(dict(zip(Q.coords, phi)))
    exprs = {f"{{{Q.coords[i]}, {Q.coords[j]}}}": lhs[i, j] - rhs[i, j]
             for i in range(6) for j in range(i + 1, 6)}
    Jk = p["J1"] if system.params["casimir"] == "jellett" else p["J2"]
    exprs["(gamma, L) - J_k"] = dot(gam, L) - Jk
    res = check_vanishing(exprs, coords=coords, method="random", seed=5)
    return claim_outcome(res, "exact arithmetic at random rational points (false-positive bound "
                              f"{res.false_positive_bound:.1e})")


def routh_e3_hamiltonian(system) -> tuple[bool, str, str]:
    """(93)-(94): on e(3), H = A L3^2 + B (L1 g2 - L2 g1)^2 + b C L3 + b^2 D + U, b = (gamma,L), and the other integral is const * L3"""
    from poissonkit.structure.checks import check_vanishing

    p, _, _, B = _system_parts(system)
    gam = p["gamma"]
    b, K, L3 = sp.symbols("_b _K _L3", real=True)
    # L with (gamma, L) = b, L1 gamma2 - L2 gamma1 = K, L3 = L3
    W = sp.Matrix([list(gam), [gam[1], -gam[0], 0], [0, 0, 1]])
    Lv = W.LUsolve(sp.Matrix([b, K, L3]))
    Mv = B * Lv
    sub = dict(zip(p["M"], Mv))
    Ht = p["H"].xreplace(sub) - p["params"]["u"] * gam[2]
    other = p["J2"] if system.params["casimir"] == "jellett" else p["J1"]
    scale = p["params"]["I1"] if system.params["casimir"] == "jellett" else 1
    # Ht is quadratic in (b, K, L3) by construction (M linear in L, H - U quadratic in M), so
    # the form (93) means: no K L3 and K b terms (Ht even in K) and coefficients depending on
    # gamma3 only on the sphere (Ht invariant under a rotation about e3 by arccos(3/5), an angle
    # of infinite order, hence under all of them). Point identities: no large derivatives.
    c, sn = sp.Rational(3, 5), sp.Rational(4, 5)
    rotated = {gam[0]: c * gam[0] - sn * gam[1], gam[1]: sn * gam[0] + c * gam[1]}
    exprs = {"H(K) - H(-K)": Ht - Ht.xreplace({K: -K}),
             "H(R gamma) - H(gamma)": Ht.xreplace(rotated) - Ht,
             "H(0)": Ht.xreplace({b: 0, K: 0, L3: 0}),
             "other integral - const L3": other.xreplace(sub) - scale * L3}
    res = check_vanishing(exprs, (dot(gam, gam) - 1,), coords=list(gam) + [b, K, L3],
                          method="random", seed=5)
    return claim_outcome(res, "exact arithmetic at random rational points on (gamma,gamma) = 1")


RANK4_CLAIMS = (routh_prop5, routh_field_integrals, routh_poisson_map, routh_e3_hamiltonian)


def routh_gyrostat_parts(R: Scalar = 2, a: Scalar = sp.Rational(1, 2), m: Scalar = 3, I1: Scalar = 5,
                         I3: Scalar = 7, u: Scalar = 10, s: Scalar = sp.Rational(3, 2)) -> dict[str, Any]:
    """The Routh sphere with a rotor ``S = (0, 0, s)`` on the axis (survey (95)–(96)) and its
    shifted linear integrals (not in the survey: derived here, checked by the tests).

    The field is (32) with ``M x omega`` replaced by ``(M + S) x omega`` (as in (49)); ``H`` and
    the measure ``g^{-1}`` are unchanged. The linear integrals shift by functions of ``gamma3``::

        J1_s = (M, r) + s R gamma3
        J2_s = g omega3 + s R m W(gamma3),   W' = (R gamma3 + a) / g   on (gamma, gamma) = 1,

    with ``g^2 = alpha gamma3^2 + beta gamma3 + delta`` on the sphere, ``alpha = m R^2 (I3 - I1)``,
    ``beta = 2 m R a I3``, ``delta = I1 I3 + m I1 R^2 + m I3 a^2``. ``W`` is not algebraic (a
    logarithm for ``I3 > I1``, an arcsine — written as an arctangent — for ``I3 < I1``), as the
    survey says of the shifted integrals; it is written with ``g`` itself in place of ``sqrt`` of
    the quadratic, which is the same function on the sphere and keeps a single radical for the
    exact checks.

    Raises
    ------
    InputError
        ``I1 == I3`` (not implemented), or a logarithm argument that vanishes on the sphere.
    """
    p = routh_parts(R, a, m, I1, I3, u)
    q = p["params"]
    s = exact(s, "s")
    R, a, m, I1, I3 = q["R"], q["a"], q["m"], q["I1"], q["I3"]
    gam, M, om, g = p["gamma"], p["M"], p["omega"], p["g"]
    z = gam[2]
    alpha, beta = m * R**2 * (I3 - I1), 2 * m * R * a * I3
    delta = I1 * I3 + m * I1 * R**2 + m * I3 * a**2
    if alpha == 0:
        raise InputError("routh_gyrostat_parts: I1 == I3 is not implemented")
    if alpha > 0:
        # on the sphere (2 alpha z + beta)^2 - 4 alpha g^2 = beta^2 - 4 alpha delta, so the
        # argument 2 sqrt(alpha) g + 2 alpha z + beta is positive for every gamma3 in [-1, 1]
        # iff beta^2 < 4 alpha delta or 2 alpha z + beta >= 0 already at gamma3 = -1
        if not (beta**2 < 4 * alpha * delta or beta >= 2 * alpha):
            raise InputError("routh_gyrostat_parts: the logarithm's argument vanishes on the "
                             "sphere")
        arg = 2 * sp.sqrt(alpha) * g + 2 * alpha * z + beta
        base = sp.log(arg) / sp.sqrt(alpha)
    else:
        # -asin((2 alpha z + beta) / sqrt(beta^2 - 4 alpha delta)) / sqrt(-alpha), written as an
        # arctangent of the same quantity so that g is the only radical (equal on the sphere)
        base = -sp.atan((2 * alpha * z + beta) / (2 * sp.sqrt(-alpha) * g)) / sp.sqrt(-alpha)
    W = (R / alpha) * g + (a - R * beta / (2 * alpha)) * base
    extra = cross([0, 0, s], om)
    field = list(p["field"][:3]) + [f + e for f, e in zip(p["field"][3:], extra)]
    return dict(gamma=gam, M=M, omega=om, g=g, H=p["H"], field=field, W=W,
                J1=p["J1"] + s * R * z, J2=p["J2"] + s * R * m * W,
                params={**q, "s": s})
