"""The Routh sphere: a dynamically symmetric, unbalanced ball rolling on a plane (survey §5.5,
(30)–(33), (77), (97)–(98)). Formulas: FORMULAS.md §11.

``I = diag(I1, I1, I3)``, ``r(gamma) = (R gamma1, R gamma2, R gamma3 + a)`` (centre of mass to the
contact point), ``U = u gamma3`` (gravity). Integrals: energy, Jellett ``J1 = (M, r)``, Routh
``J2 = g omega3`` with ``g = sqrt(I1 I3 + m (r, I r))``; invariant measure ``g^{-1}``.

The survey's rank-4 bivector ((82), (85)–(92)) is not reconstructed (FORMULAS.md §13). The system
is registered with the rank-2 bivector ``P = X ^ Z / Z(H)`` of
:func:`poissonkit_nonholonomic.common.euler_bivector`, which reproduces ``X`` exactly; it is
Poisson for ``u = 0`` and fails the Jacobi identity for ``u != 0`` (reported by the checks).
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from poissonkit.structure.bivector import Bivector
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import (
    cross,
    dot,
    euler_bivector,
    exact,
    gamma_M,
    positive,
)


def routh_parts(R: Any = 2, a: Any = sp.Rational(1, 2), m: Any = 3, I1: Any = 5, I3: Any = 7,
                u: Any = 10) -> dict[str, Any]:
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


def routh_sphere(R: Any = 2, a: Any = sp.Rational(1, 2), m: Any = 3, I1: Any = 5, I3: Any = 7,
                 u: Any = 10) -> HamiltonianSystem:
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
        doc="Routh sphere on a plane, survey (97)-(98) (FORMULAS.md §11); rank-2 Euler-field "
            "bivector (Poisson only for u = 0; the survey's rank-4 bivector is not reconstructed).",
        original=dict(zip(coords, p["field"])),
        constraints=(dot(gam, gam) - 1,),
    )
