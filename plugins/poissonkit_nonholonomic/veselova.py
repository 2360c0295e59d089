"""The Veselova system (survey (57)–(69)) and its gyrostat (70).

A rigid body with ``A = I^{-1} = diag(a1, a2, a3)`` subject to the constraint ``(omega, gamma) = 0``
(Veselova). In the variables ``K`` of (61) the equations are ``Kdot = K x omega``,
``gammadot = gamma x omega`` and ``X = -g^{-1} P_v dH`` with ``g = (gamma, A gamma)^{1/2}``.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from poissonkit.structure.deformed import veselova as veselova_bracket
from poissonkit.structure.deformed import veselova_gyrostat as veselova_gyrostat_bracket
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import Scalar, Triple, cross, dot, gamma_M, positive, three


def _parts(a1, a2, a3, second="K"):
    a = [positive(a1, "a1"), positive(a2, "a2"), positive(a3, "a3")]
    gam, K = gamma_M(second)
    Ag = [a[i] * gam[i] for i in range(3)]
    Q = dot(gam, Ag)
    return a, gam, K, Ag, Q, sp.sqrt(Q)


def veselova_maps(a1: Scalar = 1, a2: Scalar = 2, a3: Scalar = 3) -> dict[str, Any]:
    """``M(K)`` (inverse of (61)) and ``omega = A M(K)`` in the variables ``(gamma, K)``."""
    a, gam, K, Ag, Q, g = _parts(a1, a2, a3)
    coef = dot([(1 - a[i]) * K[i] for i in range(3)], gam) / Q
    Mv = [K[i] + coef * gam[i] for i in range(3)]
    return dict(gamma=gam, K=K, M=Mv, omega=[a[i] * Mv[i] for i in range(3)], g=g)


def veselova(a1: Scalar = 1, a2: Scalar = 2, a3: Scalar = 3) -> HamiltonianSystem:
    """Veselova system in the variables ``(gamma, K)`` of (61)–(66).

    ``structure = P_v`` of (65) with the Casimir value ``b`` replaced by the function
    ``(gamma, K)`` (then (66) holds on every level); ``multiplier = -1/g``;
    ``H = (K, A_g K)/2``. ``original`` is (62): ``Kdot = K x omega``, ``omega = A M(K)``.

    Parameters
    ----------
    a1, a2, a3
        Inverse principal moments of inertia, ``A = I^{-1}``.
    """
    a, gam, K, _Ag, Q, g = _parts(a1, a2, a3)
    E_A = [1 - ai for ai in a]
    # inverse of (61): M = K + ((E - A) K, gamma) / (A gamma, gamma) * gamma
    coef = dot([E_A[i] * K[i] for i in range(3)], gam) / Q
    Mv = [K[i] + coef * gam[i] for i in range(3)]
    omega = [a[i] * Mv[i] for i in range(3)]
    # (64): A_g = A - g^-2 (E - A) gamma gamma^T (E - A)
    u = [E_A[i] * gam[i] for i in range(3)]
    H1 = dot(K, [a[i] * K[i] for i in range(3)]) - dot(u, K) ** 2 / Q
    b = dot(gam, K)
    original = dict(zip(gam + K, cross(gam, omega) + cross(K, omega)))
    return HamiltonianSystem(
        structure=veselova_bracket(a=a),  # (65), the core's one definition, b = (gamma, K)
        hamiltonian=H1 / 2,
        multiplier=-1 / g,
        casimirs={"H3=(gamma,gamma)": dot(gam, gam), "H4=(gamma,K)": b},
        integrals={"H1=(K,A_g K)": H1, "H2=(K,K)": dot(K, K)},
        measure=1 / g,
        params={"a1": a[0], "a2": a[1], "a3": a[2]},
        name="nh.veselova",
        doc="Veselova system in K variables, survey (61)-(66): X = -g^{-1} P_v dH "
            " (survey (57)–(69)).",
        original=original,
        constraints=(dot(gam, gam) - 1,),
    )


def veselova_original_field(a1: Scalar = 1, a2: Scalar = 2, a3: Scalar = 3) -> dict[str, Any]:
    """The original equations (58) in ``(gamma, M)`` with the multiplier ``lambda``.

    Returns a dict with ``coords``, ``field`` (list), ``lam`` (the multiplier) and ``K`` (the map
    (61) ``K(gamma, M)``), for the push-forward check (62) and the oracle of survey (57)–(69).
    """
    a, gam, M, Ag, Q, g = _parts(a1, a2, a3, second="M")
    omega = [a[i] * M[i] for i in range(3)]
    AM = omega
    lam = dot(cross(AM, M), Ag) / Q
    field = cross(gam, omega) + [c + lam * gam[i] for i, c in enumerate(cross(M, omega))]
    gg = dot(gam, gam)
    E_A_M = [(1 - a[i]) * M[i] for i in range(3)]
    Kmap = [M[i] - dot(E_A_M, gam) / gg * gam[i] for i in range(3)]
    return dict(coords=gam + M, field=field, lam=lam, K=Kmap, a=a)


def veselova_gyrostat(a1: Scalar = 1, a2: Scalar = 2, a3: Scalar = 3, k: Triple = (1, 1, 0)) -> HamiltonianSystem:
    """Veselova gyrostat, survey (70).

    ``Kdot = (K + k) x omega``, ``omega = A (K - S gamma)``,
    ``S = (A K - K - k, gamma) / (A gamma, gamma)``; ``H = [(A K, K) - (A K - K - k, gamma)^2 /
    (A gamma, gamma)] / 2`` (minus sign); ``P_k = g [[0, Gamma], [Gamma, [K + k]_eps + S Gamma]]``.
    """
    a, gam, K, _Ag, Q, g = _parts(a1, a2, a3)
    k = three(k, "k")
    Kk = [K[i] + k[i] for i in range(3)]
    w = [a[i] * K[i] - K[i] - k[i] for i in range(3)]
    S = dot(w, gam) / Q
    omega = [a[i] * (K[i] - S * gam[i]) for i in range(3)]
    H = (dot([a[i] * K[i] for i in range(3)], K) - dot(w, gam) ** 2 / Q) / 2
    original = dict(zip(gam + K, cross(gam, omega) + cross(Kk, omega)))
    return HamiltonianSystem(
        structure=veselova_gyrostat_bracket(a=a, k=k),  # (70), the core's one definition
        hamiltonian=H,
        multiplier=-1 / g,
        casimirs={"(gamma,gamma)": dot(gam, gam), "(K+k,gamma)": dot(Kk, gam)},
        integrals={"H": H, "(K+k,K+k)": dot(Kk, Kk)},
        measure=1 / g,
        params={"a1": a[0], "a2": a[1], "a3": a[2], "k": tuple(k)},
        name="nh.veselova_gyrostat",
        doc="Veselova gyrostat, survey (70): X = -g^{-1} P_k dH.",
        original=original,
        constraints=(dot(gam, gam) - 1,),
    )
