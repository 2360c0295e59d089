"""The Suslov problem (survey §7, (122)–(127)). Formulas: survey (122)–(127).

A rigid body with the constraint ``omega3 = 0`` (``a = e3``); inertia tensor
``I = [[I11, 0, I13], [0, I22, I23], [I13, I23, I33]]``. Coordinates ``(gamma, omega)``;
``omega3`` is kept and is a trivial integral.

The rank-4 bivector (126) and Proposition 9 (garbled in the survey's OCR)
are reconstructed from the survey's OCR in :func:`suslov_rank4_parts` and checked by the
claims :func:`suslov_rank4_jacobi`, :func:`suslov_rank4_casimirs` and :func:`suslov_prop9`
(docs/nonholonomic/suslov.md says which parts are read from the OCR).
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from poissonkit.errors import InputError
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.casimirs import is_casimir, rank
from poissonkit.structure.jacobi import is_zero_expression, jacobiator_terms
from poissonkit.structure.parsing import as_expr, parse_expression
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import (Scalar, Triple, cross, dot, euler_bivector, exact,
                                            positive, vec)


def _gamma_dot(gam, w) -> list[sp.Expr]:
    """``gamma x omega`` on the constraint ``omega3 = 0`` (as printed in (123)); ``omega3`` is a
    passive coordinate with ``omega3' = 0``."""
    return [-gam[2] * w[1], gam[2] * w[0], gam[0] * w[1] - gam[1] * w[0]]


_HALF, _THIRD = sp.Rational(1, 2), sp.Rational(1, 3)  # defaults of suslov (survey (127))


def suslov(I11: Scalar = 2, I22: Scalar = 1, I13: Scalar = _HALF,
           I23: Scalar = _THIRD) -> HamiltonianSystem:
    """Inertial Suslov system (123)–(125).

    ``I11 omega1' = -omega2 (I13 omega1 + I23 omega2)``, ``I22 omega2' = omega1 (I13 omega1 + I23
    omega2)``, ``gamma' = gamma x omega``; energy ``H1``, ``(gamma, gamma)``, ``omega3``; invariant
    measure ``1/(I13 omega1 + I23 omega2)``.

    The rank-4 bivector (126) is not reconstructed (garbled OCR); the system is registered with
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
        doc="Suslov problem, inertial case (123)-(125) (survey (122)–(127)); rank-2 Euler-field "
            "bivector.",
        original=dict(zip(coords, field)),
        constraints=(),
    )


def suslov_rank2_bivector(I11: Scalar = 2, I22: Scalar = 1, c: Triple = (0, 0, 1)) -> HamiltonianSystem:
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
            "g = gamma x c (survey (122)–(127)).",
    )


def suslov_potential(I11: Scalar = 2, I22: Scalar = 1, U: str | sp.Expr = "3*gamma_z + gamma_x**2*gamma_y"
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
    # a user's string goes through the allow-list parser; anything else must already be a
    # sympy expression or a number (as_expr refuses strings and never evals)
    Uexpr = parse_expression(U, gam) if isinstance(U, str) else as_expr(U, "potential U")
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
        params={"I11": I11, "I22": I22, "U": Uexpr},
        name="nh.suslov_potential",
        doc="Suslov problem in a potential field, survey §7.2 (127): X = P d((gamma,gamma)/2); "
            "Poisson iff U = mu gamma3 + V(gamma1, gamma2) (survey (122)–(127)).",
        original=dict(zip(gam + w, field)),
    )


# --------------------------------------------------------------------------- rank 4: (126), Prop. 9
def suslov_rank4_parts(I22: Scalar = 1, I23: Scalar = 1, I11: Scalar | None = None) -> dict[str, Any]:
    """The pieces of the survey's rank-4 bivector (126) and of Proposition 9 (§7.1).

    Case ``I13 = 0``, ``I23**2 = (I11 - I22) I22``, where ``H4 = (f, gamma)``,
    ``f = I omega = (I11 omega1, I22 omega2, I23 omega2)`` (on ``omega3 = 0``) is an integral.
    With ``h1 = I11 gamma1``, ``h2 = I22 gamma2 + I23 gamma3``, ``D = I23 gamma2 - I22 gamma3``
    and, in the order ``(gamma, omega)``:

    * ``P'``: only ``{gamma_i, gamma_j} = h2**2 / (I23 D) * A_ij`` with
      ``A = [[0, -I23 w2, I22 w2], [I23 w2, 0, -I11 w1], [-I22 w2, I11 w1, 0]]``
      (``A = -eps f``); Casimirs ``H4, omega1, omega2, omega3``;
    * ``P''``: ``{omega1, omega2} = H4``, ``{omega1, gamma_j} = h2 C_j``,
      ``{omega2, gamma_j} = -h1 C_j`` with ``C = -gamma + m (gamma, gamma) / (m, gamma)``,
      ``m = (0, -I23, I22)``, i.e. ``C = (-gamma1, (I23 (gamma1^2 + gamma3^2) + I22 gamma2
      gamma3) / D, -(I22 (gamma1^2 + gamma2^2) + I23 gamma2 gamma3) / D)``;
      Casimirs ``H4, (gamma, gamma), omega3``;
    * ``P = P' + P''`` (the survey's ``a = b = 1``), rank 4, Casimirs ``H4, omega3``;
    * Prop. 9: ``X = alpha1 P dH1 + alpha2 P dH2``, ``x = omega1 gamma2 - omega2 gamma1``::

        alpha1 = -omega2 (I23 x + (I11 - I22) omega1 gamma3)
                 / (I11 H4 (I22 x + I23 omega1 gamma3))
        alpha2 = -I23 (I23 (omega1 gamma1 gamma2 - omega2 gamma1^2 - omega2 gamma3^2)
                       - (omega1 gamma1 + omega2 gamma2) I22 gamma3) / (2 H4 h2^2)

    The entries of ``P'``, the ``omega``-block of ``P''`` and both ``alpha`` are read from the
    OCR (``alpha2`` with a leading minus the OCR does not show); the ``gamma``-``omega`` block of
    ``P''`` is solved from the stated Casimirs and matches the OCR's visible factors (see
    docs/nonholonomic/suslov.md).

    Parameters
    ----------
    I22, I23
        Inertia components (``I22 > 0``, ``I23 != 0``).
    I11
        ``None`` (default) for ``I11 = I22 + I23**2 / I22``, the survey's condition. Another
        value builds the same formulas off the condition (Prop. 9 then fails: for tests).

    Returns
    -------
    dict
        ``gamma``, ``omega``, ``coords``, ``I11``, ``I22``, ``I23``, ``H1``, ``H2``, ``H4``,
        ``P1`` (``P'``), ``P2`` (``P''``), ``P``, ``alpha1``, ``alpha2`` and ``field`` (the
        equations (123) with ``I13 = 0``, ``omega3`` passive).

    Raises
    ------
    InputError
        ``I22 <= 0``, ``I23 == 0`` or ``I11 <= 0``.
    """
    I22 = positive(I22, "I22")
    I23 = exact(I23, "I23")
    if I23 == 0:
        raise InputError("I23 must be nonzero: the rank-4 bivector (126) divides by I23")
    I11 = I22 + I23**2 / I22 if I11 is None else positive(I11, "I11")
    gam, w = vec("gamma"), vec("omega")
    coords = list(gam) + list(w)
    f = [I11 * w[0], I22 * w[1], I23 * w[1]]
    H4 = dot(f, gam)
    h1, h2 = I11 * gam[0], I22 * gam[1] + I23 * gam[2]
    D = I23 * gam[1] - I22 * gam[2]
    A = sp.Matrix([[0, -I23 * w[1], I22 * w[1]],
                   [I23 * w[1], 0, -I11 * w[0]],
                   [-I22 * w[1], I11 * w[0], 0]])
    P1 = sp.zeros(6, 6)
    P1[0:3, 0:3] = A * (h2**2 / (I23 * D))
    m = [sp.Integer(0), -I23, I22]
    gg = dot(gam, gam)
    C = [sp.cancel(-gam[i] + m[i] * gg / dot(m, gam)) for i in range(3)]
    P2 = sp.zeros(6, 6)
    for j in range(3):
        P2[3, j], P2[j, 3] = h2 * C[j], -h2 * C[j]
        P2[4, j], P2[j, 4] = -h1 * C[j], h1 * C[j]
    P2[3, 4], P2[4, 3] = H4, -H4
    x = w[0] * gam[1] - w[1] * gam[0]
    alpha1 = -w[1] * (I23 * x + (I11 - I22) * w[0] * gam[2]) \
        / (I11 * H4 * (I22 * x + I23 * w[0] * gam[2]))
    alpha2 = -I23 * (I23 * (w[0] * gam[0] * gam[1] - w[1] * gam[0]**2 - w[1] * gam[2]**2)
                     - (w[0] * gam[0] + w[1] * gam[1]) * I22 * gam[2]) / (2 * H4 * h2**2)
    s = I23 * w[1]  # I13 omega1 + I23 omega2 with I13 = 0
    field = _gamma_dot(gam, w) + [-w[1] * s / I11, w[0] * s / I22, sp.Integer(0)]
    return {"gamma": gam, "omega": w, "coords": coords, "I11": I11, "I22": I22, "I23": I23,
            "H1": (I11 * w[0]**2 + I22 * w[1]**2) / 2, "H2": gg, "H4": H4,
            "P1": P1, "P2": P2, "P": P1 + P2, "alpha1": alpha1, "alpha2": alpha2,
            "field": field}


def suslov_rank4(I22: Scalar = 1, I23: Scalar = 1, I11: Scalar | None = None) -> HamiltonianSystem:
    """Suslov problem, rank-4 bivector P = P' + P'' (126) with Proposition 9 (§7.1).

    Case ``I13 = 0``, ``I23**2 = (I11 - I22) I22`` (``I11`` is derived unless given). The
    structure is ``P = P' + P''`` of :func:`suslov_rank4_parts`; Casimirs ``H4 = (I omega,
    gamma)`` and ``omega3``. The Suslov field (123) is *not* ``N P dH`` for one ``H``: it is
    ``alpha1 P dH1 + alpha2 P dH2`` (Prop. 9, checked by :func:`suslov_prop9`). The system is
    registered with the Hamiltonian ``H1`` (its flow ``P dH1`` is the first term of Prop. 9) and
    the integral ``H2 = (gamma, gamma)``, so the report's "first integral" line is the
    involution ``{H1, H2} = 0`` behind the survey's Lagrangian level sets.
    """
    p = suslov_rank4_parts(I22, I23, I11)
    w = p["omega"]
    return HamiltonianSystem(
        structure=Bivector.from_matrix(p["P"], p["coords"]),
        hamiltonian=p["H1"],
        multiplier=sp.Integer(1),
        casimirs={"H4=(I omega,gamma)": p["H4"], "H3=omega3": w[2]},
        integrals={"H2=(gamma,gamma)": p["H2"]},
        params={"I11": p["I11"], "I22": p["I22"], "I23": p["I23"]},
        name="nh.suslov_rank4",
        doc="Suslov problem, I13 = 0, I23^2 = (I11-I22) I22: rank-4 bivector P = P' + P'' "
            "(126), reconstructed from the OCR; Hamiltonian H1; the Suslov field is "
            "alpha1 P dH1 + alpha2 P dH2 (Prop. 9, a separate claim).",
    )


def _rank4_parts_of(system: HamiltonianSystem) -> dict[str, Any]:
    p = system.params
    return suslov_rank4_parts(I22=p["I22"], I23=p["I23"], I11=p["I11"])


def _poisson(P: sp.Matrix, coords) -> list[str]:
    """Jacobiator components that do not vanish (exact: each put over one denominator)."""
    terms = jacobiator_terms(Bivector.from_matrix(P, coords))
    return [f"Jac{key}" for key, e in terms.items() if not is_zero_expression(e)]


def suslov_rank4_jacobi(system: HamiltonianSystem) -> tuple[bool, str, str]:
    """(126): P', P'' and P = P' + P'' satisfy [P, P] = 0 (P', P'' compatible)"""
    p = _rank4_parts_of(system)
    bad = {name: _poisson(p[key], p["coords"]) for key, name in
           (("P1", "P'"), ("P2", "P''"), ("P", "P'+P''"))}
    detail = "; ".join(f"{k}: {', '.join(v)} nonzero" for k, v in bad.items() if v)
    return (not detail, detail,
            "exact (symbolic): every Jacobiator component over a common denominator")


def suslov_rank4_casimirs(system: HamiltonianSystem) -> tuple[bool, str, str]:
    """(126): P' has Casimirs H4, omega1..3 and P'' has H4, (gamma,gamma), omega3; ranks 2, 2, 4"""
    p = _rank4_parts_of(system)
    coords, w = p["coords"], p["omega"]
    wanted = {"P'": ("P1", {"H4": p["H4"], "omega1": w[0], "omega2": w[1], "omega3": w[2]}, 2),
              "P''": ("P2", {"H4": p["H4"], "(gamma,gamma)": p["H2"], "omega3": w[2]}, 2),
              "P": ("P", {"H4": p["H4"], "omega3": w[2]}, 4)}
    problems = []
    for name, (key, cas, r) in wanted.items():
        B = Bivector.from_matrix(p[key], coords)
        problems += [f"{c} is not a Casimir of {name}" for c, F in cas.items()
                     if not is_casimir(B, F)]
        got = int(rank(B, seed=126))
        if got != r:
            problems.append(f"rank {name} = {got}, expected {r}")
    return (not problems, "; ".join(problems),
            "exact Casimir test; generic rank at random exact points")


def suslov_prop9(system: HamiltonianSystem) -> tuple[bool, str, str]:
    """Prop. 9: the Suslov field (123) equals alpha1 P dH1 + alpha2 P dH2"""
    p = _rank4_parts_of(system)
    coords = p["coords"]
    P = p["P"]
    grad = [sp.Matrix([sp.diff(F, x) for x in coords]) for F in (p["H1"], p["H2"])]
    Y = p["alpha1"] * (P * grad[0]) + p["alpha2"] * (P * grad[1])
    bad = [f"d{x}/dt: {sp.factor(sp.together(Y[i] - p['field'][i]))}"
           for i, x in enumerate(coords) if not is_zero_expression(Y[i] - p["field"][i])]
    return (not bad, "; ".join(bad), "exact (symbolic)")


#: The claims of ``nh.suslov_rank4`` (for :data:`poissonkit_nonholonomic.claims.CLAIMS`).
RANK4_CLAIMS = (suslov_rank4_jacobi, suslov_rank4_casimirs, suslov_prop9)
