"""The Chaplygin ball: on a plane (survey (34)–(40)), its gyrostat (49), and on a sphere in the
Borisov–Mamaev–Fedorov case ``kappa = -1`` ((50)–(56)). Formulas: survey (34)–(56).

Variables ``x = (gamma, M)``: the unit normal and the angular momentum about the contact point,
both in the body frame. ``I = diag(I1, I2, I3)`` are the principal moments about the centre,
``d = m b^2`` (mass times radius squared), ``A = (I + d E)^{-1}``, ``g = sqrt(1 - d (gamma, A gamma))``.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from poissonkit.structure.bivector import Bivector
from poissonkit.structure.deformed import chaplygin_ball_system
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import (Scalar, Triple, block, cross, dot, eps_matrix, gamma_M,
                                            positive, three)


def _ball_parts(I1, I2, I3, d):
    I = [positive(I1, "I1"), positive(I2, "I2"), positive(I3, "I3")]
    d = positive(d, "d")
    gam, M = gamma_M("M")
    a = [1 / (Ii + d) for Ii in I]
    Ag = [a[i] * gam[i] for i in range(3)]
    Q = 1 - d * dot(gam, Ag)  # g^2; (35) with E, valid on all of R^6
    g = sp.sqrt(Q)
    MAg = dot(M, Ag)
    omega = [a[i] * M[i] + d * MAg / Q * Ag[i] for i in range(3)]  # (35)
    return I, d, gam, M, a, Ag, Q, g, MAg, omega


def _from_core(I1: Scalar, I2: Scalar, I3: Scalar, d: Scalar, S: tuple[sp.Expr, ...] | None,
               *, casimirs: tuple[str, str], integrals: tuple[str, str], name: str,
               doc: str) -> HamiltonianSystem:
    """The core's Chaplygin ball (:func:`poissonkit.structure.deformed.chaplygin_ball_system`,
    the one definition of the model) under this plugin's names, parameters and constraint."""
    I = (positive(I1, "I1"), positive(I2, "I2"), positive(I3, "I3"))
    d = positive(d, "d")
    core = chaplygin_ball_system(I=I, d=d, S=S)
    gam, _M = gamma_M("M")
    params: dict[str, object] = {"I1": I[0], "I2": I[1], "I3": I[2], "d": d}
    if S is not None:
        params["S"] = tuple(S)
    return HamiltonianSystem(
        structure=core.structure, hamiltonian=core.hamiltonian, multiplier=core.multiplier,
        casimirs=dict(zip(casimirs, core.casimirs.values(), strict=True)),
        integrals=dict(zip(integrals, core.integrals.values(), strict=True)),
        measure=core.measure, params=params, name=name, doc=doc,
        original=core.original, constraints=(dot(gam, gam) - 1,))


def chaplygin_ball(I1: Scalar = 1, I2: Scalar = 2, I3: Scalar = 3, d: Scalar = 1) -> HamiltonianSystem:
    """Chaplygin ball rolling on a plane, survey (34)–(40).

    ``X = -g^{-1} P_g dH`` with ``H = (M, omega)/2``; Casimirs ``(gamma, gamma)``,
    ``(gamma, M)``; integral ``(M, M)``; invariant measure ``g^{-1} dgamma dM``. The model is
    :func:`poissonkit.structure.deformed.chaplygin_ball_system` (``pk.chaplygin_ball`` is its
    bracket) with this plugin's names and the constraint ``(gamma, gamma) = 1``.

    Parameters
    ----------
    I1, I2, I3
        Principal moments of inertia about the centre of mass (numbers or sympy symbols).
    d
        ``m b^2`` (mass times the ball's radius squared).

    Returns
    -------
    HamiltonianSystem
        ``structure = P_g`` of (38) in the ``[v]_eps`` form, ``multiplier = -1/g``.
    """
    return _from_core(I1, I2, I3, d, None, casimirs=("H3=(gamma,gamma)", "H4=(gamma,M)"),
                      integrals=("H1=(M,omega)", "H2=(M,M)"), name="nh.chaplygin_ball",
                      doc="Chaplygin ball on a plane, survey (34)-(40): X = -g^{-1} P_g dH.")


def chaplygin_gyrostat(I1: Scalar = 1, I2: Scalar = 2, I3: Scalar = 3, d: Scalar = 1,
                       S: Triple = (1, 0, -1)) -> HamiltonianSystem:
    """Chaplygin ball with a rotor (gyrostat), survey (49).

    ``Mdot = (M + S) x omega``, ``gammadot = gamma x omega``; bracket ``P_sg`` with the correction
    term ``(M, A gamma)`` (not ``(M + S, A gamma)``, which does not reproduce (49)). Built from
    :func:`poissonkit.structure.deformed.chaplygin_ball_system` with ``S``.

    Parameters
    ----------
    I1, I2, I3, d
        As in :func:`chaplygin_ball`.
    S
        Constant gyrostatic momentum (3-vector).
    """
    return _from_core(I1, I2, I3, d, three(S, "S"),
                      casimirs=("H3=(gamma,gamma)", "H4=(gamma,M+S)"),
                      integrals=("H1=(M,omega)", "H2=(M+S,M+S)"), name="nh.chaplygin_gyrostat",
                      doc="Chaplygin ball with a rotor, survey (49): X = -g^{-1} P_sg dH.")


def bmf_parts(I1: Scalar = 1, I2: Scalar = 2, I3: Scalar = 3, d: Scalar = 1) -> dict[str, Any]:
    """Pieces of the BMF system (54)–(56): ``b``, ``g``, ``s``, ``H1``, ``H2``, ``P_b``, ``omega``.

    Used by :func:`chaplygin_ball_sphere_bmf` and by the decomposition check (55).
    """
    I, d, gam, M, a, Ag, Q, g, MAg, omega = _ball_parts(I1, I2, I3, d)
    b = [I[1] + I[2] - I[0] + d, I[2] + I[0] - I[1] + d, I[0] + I[1] - I[2] + d]  # (53)
    trB = sum(b)
    B = sp.diag(*b)
    Bg = [b[i] * gam[i] for i in range(3)]
    gg = dot(gam, gam)
    G = eps_matrix(gam)
    Theta = dot(gam, Bg) * G + sp.Matrix(cross(gam, Bg)) * sp.Matrix(gam).T \
        - B * eps_matrix(Bg) / (2 * d)
    C2 = dot(gam, [b[i] * M[i] for i in range(3)])
    gM = dot(gam, M)
    xi = [C2 + b[k] * gM for k in range(3)]
    den = (b[0] + b[1]) * (b[1] + b[2]) * (b[0] + b[2])
    MM = sp.zeros(3, 3)
    Lam = sp.zeros(3, 3)
    for i in range(3):
        for j in range(3):
            if i == j:
                continue
            k = 3 - i - j
            e = sp.LeviCivita(i, j, k)
            MM[i, j] = -e * (gam[k] * xi[k] - gg * b[k] * M[k] + b[k] ** 2 * M[k] / (2 * d))
            Lam[i, j] = -e * b[k] * gam[k] * ((b[i] + b[j]) * xi[k]
                                              + (b[k] - b[i]) * (b[k] - b[j]) * gam[k] * M[k]) / den
    c = 2 * d * gg - trB
    P = block(sp.zeros(3), g * Theta, -g * Theta.T, g * MM + c / g * Lam)  # (54)
    hat = -G  # standard hat: hat(v) w = v x w
    s = (B + 2 * d * hat * hat).det()  # (56), = det(B + 2d gamma^ gamma^)
    H1 = dot(M, [a[i] * M[i] for i in range(3)]) + d * MAg**2 / Q
    H2 = dot(M, M)
    return dict(I=I, d=d, gamma=gam, M=M, b=b, trB=trB, g=g, Q=Q, s=sp.expand(s), H1=H1, H2=H2,
                C2=C2, P=P, c=c, omega=omega)


def chaplygin_ball_sphere_bmf(I1: Scalar = 1, I2: Scalar = 2, I3: Scalar = 3,
                              d: Scalar = 1) -> HamiltonianSystem:
    """Chaplygin ball rolling on a sphere, Borisov–Mamaev–Fedorov case ``kappa = -1`` (50)–(56).

    Proposition 3: ``X = (d / (g s)) P_b dH`` with ``H = (2d (gamma, gamma) - tr B) H1 + 2 H2``
    (note the ``+`` sign, unlike the plane). Casimirs ``(gamma, gamma)`` and ``(gamma, B M)``;
    invariant measure ``g^{-1}``. The decomposition (55) is checked separately
    (:func:`poissonkit_nonholonomic.claims.bmf_decomposition`).
    """
    p = bmf_parts(I1, I2, I3, d)
    gam, M, omega = p["gamma"], p["M"], p["omega"]
    H = p["c"] * p["H1"] + 2 * p["H2"]
    original = dict(zip(gam + M, [-w for w in cross(gam, omega)] + cross(M, omega)))  # (50)
    return HamiltonianSystem(
        structure=Bivector.from_matrix(p["P"], gam + M),
        hamiltonian=H,
        multiplier=p["d"] / (p["g"] * p["s"]),
        casimirs={"H3=(gamma,gamma)": dot(gam, gam), "C2=(gamma,B M)": p["C2"]},
        integrals={"H1=(M,omega)": p["H1"], "H2=(M,M)": p["H2"]},
        measure=1 / p["g"],
        params={"I1": p["I"][0], "I2": p["I"][1], "I3": p["I"][2], "d": p["d"]},
        name="nh.chaplygin_ball_sphere_bmf",
        doc="Chaplygin ball on a sphere, BMF case kappa = -1, survey (50)-(56): "
            "X = d/(g s) P_b dH (survey (50)–(56)).",
        original=original,
        constraints=(dot(gam, gam) - 1,),
    )
