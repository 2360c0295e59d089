"""Routh sphere with an axial rotor and the shifted rank-4 bivector of survey (96) (§5.4).

With a gyrostatic momentum ``S = (0, 0, s)`` on the symmetry axis (95), the survey states that
the solutions of (12) are "shifts" of those without the rotor::

    P_s^(k) = P^(k) - [[0, 0], [0, S_x]],      S_x = [[0, -S3, S2], [S3, 0, -S1], [-S2, S1, 0]]

(the OCR of (96) shows only ``P^(k) -``, a block ``0 0 / 0 S`` and the words "the rank-2
bivector P is shifted"; the block is read as the cross-product matrix ``S_x`` defined after
(49)). So only ``{M1, M2}`` changes, by ``+s``. The survey then says that ``X = mu^{-1}
P_s^(k) dH + lambda_k X_S`` with *the same* coefficients as without the rotor, and the Casimir
``J_k`` becomes the shifted integral ``J_k^(s) = J_k + s int v1^(k) dgamma3``.

Here ``P^(k)`` is the rank-4 bivector of :mod:`poissonkit_nonholonomic.routh` (pulled back from
e(3)), the shifted integrals are those of
:func:`poissonkit_nonholonomic.routh.routh_gyrostat_parts`, and every statement is a check:
Jacobi of ``P_s`` (registered structure, checked by ``verify``), ``(gamma, gamma)`` and
``J_k^(s)`` as its Casimirs, and the claim :func:`shifted_bivector_96` that the gyrostat's field
is ``-P_s dH + mu X_S`` with the ``mu`` of the rotor-free sphere. The opposite sign of the shift
fails these checks (tested), so the reading of the block is fixed by the checks, not assumed.
"""

from __future__ import annotations

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import Scalar, claim_outcome, dot
from poissonkit_nonholonomic.revolution import symmetry_field
from poissonkit_nonholonomic.routh import CASIMIR_CHOICES, _rank4, routh_gyrostat_parts, routh_parts


def shifted_bivector(P: sp.MatrixBase, s: sp.Expr, sign: int = 1) -> sp.Matrix:
    """``P - [[0, 0], [0, S_x]]`` for ``S = (0, 0, s)`` in the order ``(gamma, M)`` (survey (96)).

    Parameters
    ----------
    P
        The 6x6 matrix of ``P^(k)``.
    s
        The axial gyrostatic momentum.
    sign
        ``+1`` is (96); ``-1`` (the opposite shift) exists for the negative control.

    Returns
    -------
    sympy.Matrix
        ``P`` with ``{M1, M2}`` increased by ``sign * s``.
    """
    if sign not in (1, -1):
        raise InputError("sign must be +1 or -1")
    out = sp.Matrix(P)
    out[3, 4] += sign * s
    out[4, 3] -= sign * s
    return out


def _parts(R, a, m, I1, I3, u, s, casimir: str, sign: int = 1):
    if casimir not in CASIMIR_CHOICES:
        raise InputError(f"casimir must be one of {CASIMIR_CHOICES}, got {casimir!r}")
    gp = routh_gyrostat_parts(R, a, m, I1, I3, u, s)
    q = gp["params"]
    P, _, _ = _rank4(q["R"], q["a"], q["m"], q["I1"], q["I3"], casimir)
    return gp, P, shifted_bivector(P, q["s"], sign)


def routh_gyrostat_rank4(R: Scalar = 2, a: Scalar = sp.Rational(1, 2), m: Scalar = 3,
                         I1: Scalar = 5, I3: Scalar = 7, u: Scalar = 10,
                         s: Scalar = sp.Rational(3, 2), casimir: str = "jellett"
                         ) -> HamiltonianSystem:
    """Routh sphere with an axial rotor, the shifted rank-4 bivector P_s^(k) of survey (96).

    Parameters
    ----------
    R, a, m, I1, I3, u
        As :func:`poissonkit_nonholonomic.routh.routh_sphere` (``I1 != I3``).
    s
        Gyrostatic momentum along the symmetry axis, ``S = (0, 0, s)``.
    casimir
        ``"jellett"`` (``k = 1``, Casimir ``J1 + s R gamma3``) or ``"routh"`` (``k = 2``,
        Casimir ``g omega3 + s m R W(gamma3)``).

    Returns
    -------
    HamiltonianSystem
        Structure ``P_s^(k)``, ``N = -1``; the full field is ``-P_s dH + mu X_S`` (claim
        :func:`shifted_bivector_96`), so ``original`` is not set, as for
        ``nh.routh_sphere_rank4``.
    """
    gp, _P, Ps = _parts(R, a, m, I1, I3, u, s, casimir)
    gam, M = gp["gamma"], gp["M"]
    coords = list(gam) + list(M)
    names = {"jellett": "J1_s=(M,r)+s R gamma3", "routh": "J2_s=g omega3+s m R W(gamma3)"}
    own = "J1" if casimir == "jellett" else "J2"
    return HamiltonianSystem(
        structure=Bivector.from_matrix(Ps, coords),
        hamiltonian=gp["H"],
        multiplier=sp.Integer(-1),
        casimirs={"C=(gamma,gamma)": dot(gam, gam), names[casimir]: gp[own]},
        # the other shifted integral (a logarithm / arctangent of gamma3) is checked at random
        # points by the claim shifted_integrals_96: exact proofs of it exceed verify's budget
        integrals={"H": gp["H"]},
        measure=1 / gp["g"],
        params={**gp["params"], "casimir": casimir},
        name="nh.routh_gyrostat_rank4",
        doc="Routh sphere with an axial rotor: P_s = P^(k) - diag(0, S_x) of survey (96); "
            "X = -P_s dH + mu X_S with the rotor-free mu is a claim.",
        constraints=(dot(gam, gam) - 1,),
    )


def shifted_bivector_96(system) -> tuple[bool, str, str]:
    """(96): the rotor's field is X_s = -P_s dH + mu X_S with the same mu as X = -P dH + mu X_S without it"""
    from poissonkit.structure.checks import check_vanishing

    q = system.params
    gp, P, Ps = _parts(q["R"], q["a"], q["m"], q["I1"], q["I3"], q["u"], q["s"], q["casimir"])
    plain = routh_parts(q["R"], q["a"], q["m"], q["I1"], q["I3"], q["u"])
    gam, M = gp["gamma"], gp["M"]
    coords = list(gam) + list(M)
    dH = sp.Matrix([sp.diff(gp["H"], x) for x in coords])
    XS = symmetry_field(gam, M)
    # mu of the rotor-free sphere: the X_S-component of X + P dH in the (M1, M2) plane
    Y0 = sp.Matrix(plain["field"]) + P * dH
    mu = (Y0[3] * XS[3] + Y0[4] * XS[4]) / (XS[3] ** 2 + XS[4] ** 2)
    Y = sp.Matrix(gp["field"]) + Ps * dH
    exprs = {f"(X_s + P_s dH - mu X_S)_{x}": Y[i] - mu * XS[i] for i, x in enumerate(coords)}
    res = check_vanishing(exprs, (dot(gam, gam) - 1,), coords=coords, method="random", seed=5)
    return claim_outcome(res, "exact arithmetic at random rational points on (gamma, gamma) = 1 "
                              f"(false-positive bound {res.false_positive_bound:.1e})")


def shifted_integrals_96(system) -> tuple[bool, str, str]:
    """(95)-(96): J1_s, J2_s and H are conserved by the rotor's field X_s and Poisson-commute with H for P_s"""
    from poissonkit.structure.checks import check_vanishing

    q = system.params
    gp, _P, Ps = _parts(q["R"], q["a"], q["m"], q["I1"], q["I3"], q["u"], q["s"], q["casimir"])
    coords = list(gp["gamma"]) + list(gp["M"])
    grad = {k: sp.Matrix([sp.diff(gp[k], x) for x in coords]) for k in ("H", "J1", "J2")}
    exprs = {}
    for k in ("J1", "J2", "H"):
        exprs[f"X_s({k}_s)"] = sum(d * f for d, f in zip(grad[k], gp["field"]))
    for k in ("J1", "J2"):
        exprs[f"{{{k}_s, H}}_(P_s)"] = (grad[k].T * Ps * grad["H"])[0, 0]
    res = check_vanishing(exprs, (dot(gp["gamma"], gp["gamma"]) - 1,), coords=coords,
                          method="random", seed=7)
    return claim_outcome(res, "exact arithmetic at random rational points on (gamma, gamma) = 1 "
                              f"(false-positive bound {res.false_positive_bound:.1e})")


GYROSTAT_RANK4_CLAIMS = (shifted_bivector_96, shifted_integrals_96)
