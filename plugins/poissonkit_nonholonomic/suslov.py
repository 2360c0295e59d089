"""The Suslov problem (survey §7, (122)–(127)). Formulas: FORMULAS.md §12.

A rigid body with the constraint ``omega3 = 0`` (``a = e3``); inertia tensor
``I = [[I11, 0, I13], [0, I22, I23], [I13, I23, I33]]``. Coordinates ``(gamma, omega)``;
``omega3`` is kept and is a trivial integral.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from poissonkit.structure.bivector import Bivector
from poissonkit.structure.parsing import parse_expression
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import (
    cross,
    dot,
    euler_bivector,
    exact,
    positive,
    vec,
)


def _gamma_dot(gam, w) -> list[sp.Expr]:
    """``gamma x omega`` on the constraint ``omega3 = 0`` (as printed in (123)); ``omega3`` is a
    passive coordinate with ``omega3' = 0``."""
    return [-gam[2] * w[1], gam[2] * w[0], gam[0] * w[1] - gam[1] * w[0]]


def suslov(I11: Any = 2, I22: Any = 1, I13: Any = sp.Rational(1, 2),
           I23: Any = sp.Rational(1, 3)) -> HamiltonianSystem:
    """Inertial Suslov system (123)–(125).

    ``I11 omega1' = -omega2 (I13 omega1 + I23 omega2)``, ``I22 omega2' = omega1 (I13 omega1 + I23
    omega2)``, ``gamma' = gamma x omega``; energy ``H1``, ``(gamma, gamma)``, ``omega3``; invariant
    measure ``1/(I13 omega1 + I23 omega2)``.

    The rank-4 bivector (126) is not reconstructed (FORMULAS.md §13); the system is registered with
    the rank-2 bivector ``X ^ Z / (2 H1)`` (``Z`` the Euler field in ``omega``), which is Poisson
    because the field is homogeneous (``[Z, X] = X``) and reproduces ``X`` with ``N = 1``.
    """
    I11, I22 = positive(I11, "I11"), positive(I22, "I22")
    I13, I23 = exact(I13, "I13"), exact(I23, "I23")
    gam, w = vec("gamma"), vec("omega")
    s = I13 * w[0] + I23 * w[1]
    field = _gamma_dot(gam, w) + [-w[1] * s / I11, w[0] * s / I22, sp.Integer(0)]
    H1 = (I11 * w[0] ** 2 + I22 * w[1] ** 2) / 2
    coords = gam + w
    integrals = {"H1": H1}
    if I13 == 0:
        # (125): H4 = (I omega, gamma), conserved iff I23^2 = (I11 - I22) I22
        integrals["H4=(I omega,gamma) [needs I23^2=(I11-I22)I22]"] = \
            I11 * w[0] * gam[0] + I22 * w[1] * gam[1] + I23 * w[1] * gam[2]
    P = euler_bivector(field, coords, w[:2], H1)
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, coords),
        hamiltonian=H1,
        multiplier=sp.Integer(1),
        casimirs={"H2=(gamma,gamma)": dot(gam, gam), "H3=omega3": w[2]},
        integrals=integrals,
        measure=1 / s,
        params={"I11": I11, "I22": I22, "I13": I13, "I23": I23},
        name="nh.suslov",
        doc="Suslov problem, inertial case (123)-(125) (FORMULAS.md §12); rank-2 Euler-field "
            "bivector.",
        original=dict(zip(coords, field)),
        constraints=(),
    )


def suslov_rank2_bivector(I11: Any = 2, I22: Any = 1, c: Any = (0, 0, 1)) -> HamiltonianSystem:
    """The rank-2 bivector of §7.1: ``{gamma_i, omega1} = -g_i I22 omega2``,
    ``{gamma_i, omega2} = g_i I11 omega1`` with ``g(gamma) = gamma x c`` (so ``(g, gamma) = 0``).

    Returned as a system whose Casimirs are the survey's claims: ``H1``, ``omega3`` and
    ``(gamma, gamma)`` (the last because ``(g, gamma) = 0``). It carries no dynamics
    (``hamiltonian = 0``).
    """
    I11, I22 = positive(I11, "I11"), positive(I22, "I22")
    cv = [exact(x, "c") for x in c]
    gam, w = vec("gamma"), vec("omega")
    gv = cross(gam, cv)
    row = [-I22 * w[1], I11 * w[0], sp.Integer(0)]
    P = sp.zeros(6, 6)
    for i in range(3):
        for j in range(3):
            P[i, 3 + j] = gv[i] * row[j]
            P[3 + j, i] = -gv[i] * row[j]
    H1 = (I11 * w[0] ** 2 + I22 * w[1] ** 2) / 2
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, gam + w),
        hamiltonian=sp.Integer(0),
        casimirs={"H1": H1, "omega3": w[2], "(gamma,gamma)": dot(gam, gam)},
        params={"I11": I11, "I22": I22, "c": tuple(cv)},
        name="nh.suslov_rank2",
        doc="Suslov §7.1 rank-2 bivector W_ij = g_i(gamma) (-I22 w2, I11 w1, 0)_j with "
            "g = gamma x c (FORMULAS.md §12).",
    )


def suslov_potential(I11: Any = 2, I22: Any = 1, U: Any = "3*gamma_z + gamma_x**2*gamma_y"
                     ) -> HamiltonianSystem:
    """Suslov problem in a potential field, §7.2, (127): ``X = P dH`` with ``H = (gamma, gamma)/2``.

    The bivector is Poisson iff ``U = mu gamma3 + V(gamma1, gamma2)``; for other potentials the
    Jacobi check fails (as the survey states). Casimirs: ``E = H1 + U`` and ``omega3``.

    Parameters
    ----------
    I11, I22
        Principal moments (``I13 = I23 = 0``).
    U
        Potential: a string in ``gamma_x, gamma_y, gamma_z`` (parsed with the allow-list parser)
        or a sympy expression.
    """
    I11, I22 = positive(I11, "I11"), positive(I22, "I22")
    gam, w = vec("gamma"), vec("omega")
    Uexpr = parse_expression(U, gam) if isinstance(U, str) else sp.sympify(U)
    dU = [sp.diff(Uexpr, x) for x in gam]
    P = sp.zeros(6, 6)

    def put(i, j, v):
        P[i, j] = v
        P[j, i] = -v

    put(0, 2, -w[1])
    put(1, 2, w[0])
    put(3, 1, dU[2] / I11)
    put(3, 2, -dU[1] / I11)
    put(4, 0, -dU[2] / I22)
    put(4, 2, dU[0] / I22)
    field = _gamma_dot(gam, w) + [(gam[1] * dU[2] - gam[2] * dU[1]) / I11,
                             (gam[2] * dU[0] - gam[0] * dU[2]) / I22, sp.Integer(0)]
    H1 = (I11 * w[0] ** 2 + I22 * w[1] ** 2) / 2
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, gam + w),
        hamiltonian=dot(gam, gam) / 2,
        casimirs={"E=H1+U": H1 + Uexpr, "omega3": w[2]},
        params={"I11": I11, "I22": I22, "U": str(Uexpr)},
        name="nh.suslov_potential",
        doc="Suslov problem in a potential field, survey §7.2 (127): X = P d((gamma,gamma)/2); "
            "Poisson iff U = mu gamma3 + V(gamma1, gamma2) (FORMULAS.md §12).",
        original=dict(zip(gam + w, field)),
    )
