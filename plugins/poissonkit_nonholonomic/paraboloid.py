"""A dynamically symmetric ball rolling in a paraboloid of revolution (survey §6, (102)–(121)).

This part of the survey was not checked independently of its OCR; everything here was re-derived
from the physics and judged by poissonkit's own checks (see docs/nonholonomic/ball_on_paraboloid.md
for what was reconstructed from the OCR and what does not verify).

Model. A ball of mass ``m``, radius ``R`` and inertia ``mu E`` about its centre (``d = m R^2``)
rolls without slipping inside the bowl whose *centre surface* is ``z = c (x^2 + y^2)``
(``c > 0``), under gravity ``U = G z_c`` (``G = m g``). All vectors are in the fixed frame:
``gamma`` is the upward unit normal of the surface (``gamma3 > 0``; ``gamma = e3`` at the
bottom), the contact point is ``r_c - R gamma`` (survey: ``a = -R gamma``) and ``M`` is the
angular momentum about the contact point,

    M = mu omega + d gamma x (omega x gamma),    omega = (M + d gamma (gamma, M)/mu) / (mu + d)

on ``(gamma, gamma) = 1``. Equations (104) (Newton–Euler with the reaction eliminated):

    r_c' = R omega x gamma,      M' = d gamma' x (omega x gamma) + R dU/dr_c x gamma,

with the inverse Gauss map ``r_c(gamma) = (-gamma1, -gamma2, (gamma1^2 + gamma2^2)/(2 gamma3)) / (2 c gamma3)``,
which gives ``gamma' = -2 c gamma3 (E - gamma gamma^T) (v1, v2, 0)``, ``v = r_c'``.

Off the sphere the field is extended so that on each sphere ``|gamma| = r`` it is the unit-sphere
field in ``gamma/r``, slowed down by ``1/r`` (``omega``, ``U``, ``H`` of degree 0 in ``gamma``,
``gamma'`` of degree 0, ``M'`` of degree -1; the ``J_k`` extended homogeneously). Then every
claim below holds identically on R^6 and the system needs no constraint.

Integrals: ``H = (M, omega)/2 + U`` (105), ``C = (gamma, gamma)``, the two integrals linear in
``M`` (107), ``J_k = v1^(k)(gamma3) (gamma1 M1 + gamma2 M2) + v2^(k)(gamma3) M3`` with (121)

    v1^(1,2) = gamma3^(+-nu),    v2^(1,2) = gamma3^(1 +- nu) +- nu/(1 -+ nu) gamma3^(+-nu - 1),
    nu = sqrt(kappa),  kappa = mu/(mu + d),

and Remark 14's ``H2 = J1 J2`` (rational, quadratic in ``M``). Invariant measure (106):
``rho = gamma3^(-4)`` (``= 4 c^2 f (f - (1 - gamma3^2) f'/gamma3)`` with the survey's
``f = -1/(2 c gamma3)``).

Bracket. As for the Routh sphere, the registered system carries the rank-2 bivector ``P = X ^ Z / Z(H)`` of
:func:`poissonkit_nonholonomic.common.euler_bivector` (``Z = sum M_i d/dM_i``), which reproduces
``X`` exactly. It is Poisson for ``G = 0`` and fails the Jacobi identity for ``G != 0``. It is
singular at ``M = 0`` (``Z(H) = 2T = 0``): integrate states at rest with
:class:`OriginalFieldSystem`. The rank-4 Poisson bivector ``P^(1)`` of (110) (Casimirs
``(gamma, gamma)``, ``J1``) is built by pull-back from e(3) in :func:`ball_on_paraboloid_rank4`,
with Proposition 7 as the claim :func:`proposition7`.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from poissonkit.errors import InputError
from poissonkit.numerics.conformal import LambdifiedSystem
from poissonkit.structure.bivector import Bivector
from poissonkit.structure.system import HamiltonianSystem
from poissonkit_nonholonomic.common import (Scalar, cross, dot, euler_bivector, exact, gamma_M,
                                            positive)
from poissonkit_nonholonomic.revolution import symmetry_field as revolution_symmetry_field

_QUARTER, _HALF = sp.Rational(1, 4), sp.Rational(1, 2)  # default parameters (exact)

__all__ = ["OriginalFieldSystem", "ball_on_paraboloid", "ball_on_paraboloid_rank4",
           "integral_coefficients", "paraboloid_parts", "proposition7", "symmetry_field"]


def integral_coefficients(kappa: Any, gamma3: sp.Expr) -> dict[str, sp.Expr]:
    """The coefficients (121) of the integrals (107), ``J_k = v1^(k) (g1 M1 + g2 M2) + v2^(k) M3``.

    They solve (108) for the paraboloid (``f = -1/(2 c gamma3)``), which reduce to
    ``gamma v1' + ((1 - kappa) gamma^2 + kappa) v1 - (1 - kappa) gamma v2 = 0`` and
    ``gamma^2 v2' + (1 - kappa) gamma (1 - gamma^2) v2 + ((1 - kappa)(gamma^4 - 2 gamma^2) - kappa) v1 = 0``;
    eliminating ``v2`` leaves Euler's equation ``gamma^2 v1'' + gamma v1' - kappa v1 = 0``.

    Parameters
    ----------
    kappa
        ``mu / (mu + d)`` (``0 < kappa < 1``).
    gamma3
        The symbol (or value) of ``gamma3``.

    Returns
    -------
    dict
        ``nu = sqrt(kappa)``, ``v1_1``, ``v2_1``, ``v1_2``, ``v2_2``.
    """
    nu = sp.sqrt(kappa)
    g = gamma3
    return {"nu": nu,
            "v1_1": g**nu, "v2_1": g**(1 + nu) + nu / (1 - nu) * g**(nu - 1),
            "v1_2": g**(-nu), "v2_2": g**(1 - nu) - nu / (1 + nu) * g**(-nu - 1)}


def paraboloid_parts(mu: Scalar = _QUARTER, m: Scalar = 3, R: Scalar = _HALF,
                     c: Scalar = _HALF, G: Scalar = 30) -> dict[str, Any]:
    """Symbols and expressions of the ball in a paraboloid (field, omega, H, U, J1, J2, rho, ...).

    Raises
    ------
    InputError
        Non-positive ``mu``, ``m``, ``R`` or ``c``, or a ball that does not fit the bowl
        (``R >= 1/(2c)``, the radius of curvature of the centre surface at the bottom: the contact
        surface would not be smooth there).
    """
    mu, m, R, c = positive(mu, "mu"), positive(m, "m"), positive(R, "R"), positive(c, "c")
    G = exact(G, "G")
    if R.is_number and c.is_number and not R < 1 / (2 * c):
        raise InputError(f"the ball does not fit the paraboloid: need R < 1/(2c) = {1 / (2 * c)}, "
                         f"got R = {R}")
    d = m * R**2
    gam, M = gamma_M("M")
    g1, g2, g3 = gam
    gg = dot(gam, gam)
    gM = dot(gam, M)
    # The field is written on all of R^6 so that on each sphere |gamma| = r it is the unit-sphere
    # field (in gamma/r), slowed down by 1/r: then every integral of the unit sphere, extended
    # homogeneously in gamma, is an integral identically (exact checks need no constraints).
    # omega, U, H are homogeneous of degree 0 in gamma, gamma' of degree 0, M' of degree -1.
    omega = [(M[i] + d * gam[i] * gM / (mu * gg)) / (mu + d) for i in range(3)]
    wg = cross(omega, gam)
    v = [R * x / gg for x in wg]  # |gamma| times the centre velocity R omega x gamma/|gamma|
    vh = [v[0], v[1], sp.Integer(0)]
    gvh = dot(gam, vh)
    # inverse Gauss map x = -gamma1/(2c gamma3), y = -gamma2/(2c gamma3) differentiated along the
    # centre velocity, with (gamma, gamma') = 0
    gdot = [-2 * c * g3 * (gg * vh[i] - gam[i] * gvh) / gg for i in range(3)]
    centre = [-g1 / (2 * c * g3), -g2 / (2 * c * g3), (g1**2 + g2**2) / (4 * c * g3**2)]
    U = G * centre[2]
    dU_dr = [sp.Integer(0), sp.Integer(0), G]
    Mdot = [(d * a + R * b) / gg for a, b in zip(cross(gdot, wg), cross(dU_dr, gam))]  # (104)
    H = dot(M, omega) / 2 + U  # (105)
    kappa = mu / (mu + d)
    co = integral_coefficients(kappa, g3)
    S = g1 * M[0] + g2 * M[1]
    nu = co["nu"]
    # (121) with the power of gamma3 factored out: J_k = gamma3^(+-nu) L_k, so that X(J_k) is
    # gamma3^(+-nu) times a rational function (one transcendental atom when nu is irrational)
    L1 = S + (g3 + nu * gg / ((1 - nu) * g3)) * M[2]
    L2 = S + (g3 - nu * gg / ((1 + nu) * g3)) * M[2]
    J1 = g3**nu * L1
    J2 = g3**(-nu) * L2
    H2 = L1 * L2  # Remark 14: J1 J2, the powers cancel
    return {"gamma": gam, "M": M, "omega": omega, "field": gdot + Mdot, "velocity": v,
            "centre": centre, "H": H, "U": U, "J1": J1, "J2": J2, "H2": H2, "rho": g3**-4,
            "kappa": kappa, "nu": nu, "d": d, "coefficients": co,
            "params": {"mu": mu, "m": m, "R": R, "c": c, "G": G}}


def symmetry_field(gamma: Any, M: Any) -> list[sp.Expr]:
    """The SO(2) symmetry field ``X_S`` (74) of rotations about the vertical axis, components on
    ``(gamma, M)``: ``gamma2, -gamma1, 0, M2, -M1, 0``."""
    return revolution_symmetry_field(gamma, M)


def ball_on_paraboloid(mu: Scalar = _QUARTER, m: Scalar = 3, R: Scalar = _HALF,
                       c: Scalar = _HALF, G: Scalar = 30,
                       linear_integrals: bool | None = None) -> HamiltonianSystem:
    """Dynamically symmetric ball rolling in a paraboloid z = c(x^2+y^2), survey (104)-(121).

    ``H = (M, omega)/2 + G z_c``; Casimir ``(gamma, gamma)``; integrals ``J1``, ``J2`` (107) with
    (121) and ``H2 = J1 J2`` (Remark 14); invariant measure ``gamma3^(-4)`` (106). The defaults
    give ``kappa = mu/(mu + m R^2) = 1/4`` (``nu = 1/2``: the integrals are algebraic).

    Parameters
    ----------
    mu
        Moment of inertia of the ball about its centre (``I = mu E``).
    m
        Mass.
    R
        Radius (must be below ``1/(2c)``).
    c
        The centre moves on ``z = c (x^2 + y^2)``.
    G
        Weight ``m g`` in ``U = G z_c`` (0: inertial rolling).
    linear_integrals
        Whether ``J1``, ``J2`` are listed among the integrals. Default (``None``): iff
        ``nu = sqrt(kappa)`` is rational, i.e. ``J1``, ``J2`` are algebraic. For irrational
        ``nu`` they contain ``gamma3**nu`` with an irrational exponent, which the plugin's
        random-point checks (``verify_system``) cannot evaluate; ``H2 = J1 J2`` is always listed
        and ``J1``, ``J2`` are in :func:`paraboloid_parts`.

    Returns
    -------
    HamiltonianSystem
        Coordinates ``(gamma, M)``, ``structure = X ^ Z / Z(H)`` (rank 2; Poisson iff ``G = 0``),
        ``multiplier = 1``, ``original`` = the field (104).
    """
    p = paraboloid_parts(mu, m, R, c, G)
    gam, M = p["gamma"], p["M"]
    coords = gam + M
    P = euler_bivector(p["field"], coords, M, p["H"])
    if linear_integrals is None:
        linear_integrals = bool(p["nu"].is_rational)
    integrals = {"H": p["H"]}
    if linear_integrals:
        integrals.update({"J1 (107),(121)": p["J1"], "J2 (107),(121)": p["J2"]})
    integrals["H2=J1 J2 (Remark 14)"] = p["H2"]
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, coords),
        hamiltonian=p["H"],
        multiplier=sp.Integer(1),
        casimirs={"C=(gamma,gamma)": dot(gam, gam)},
        integrals=integrals,
        measure=p["rho"],
        params=p["params"],
        name="nh.ball_on_paraboloid",
        doc="Ball in a paraboloid of revolution, survey (104)-(121) (reconstructed); "
            "rank-2 Euler-field bivector (Poisson only for G = 0).",
        original=dict(zip(coords, p["field"])),
        # no constraints: every claim holds identically on R^6 (see paraboloid_parts), and the
        # physical states are those with (gamma, gamma) = 1, gamma3 > 0
        constraints=(),
    )


@lru_cache(maxsize=4)
def _rank4(mu: sp.Expr, m: sp.Expr, R: sp.Expr, c: sp.Expr, G: sp.Expr) -> sp.Matrix:
    """The pulled-back bivector P^(1) (cached: ~10-20 s per parameter set)."""
    from poissonkit_nonholonomic.revolution import e3_frame_map, e3_pullback

    p = paraboloid_parts(mu, m, R, c, G)
    gam = p["gamma"]
    g1, g2, g3 = gam
    gg = dot(gam, gam)
    nu = p["nu"]
    root = sp.Symbol("_sqrt_gamma3", positive=True)  # gamma3**nu with nu = 1/2
    w1 = g3 + nu * gg / ((1 - nu) * g3)
    w2 = g3 - nu * gg / ((1 + nu) * g3)
    casimir_row = [root * g1, root * g2, root * w1]  # (gamma, L) = J1
    axial_row = [g1 / root, g2 / root, w2 / root]  # L3 = J2
    A, B = e3_frame_map(gam, casimir_row, axial_row)
    return e3_pullback(gam, p["M"], A, B, radical=(root, g3))


def ball_on_paraboloid_rank4(mu: Scalar = _QUARTER, m: Scalar = 3, R: Scalar = _HALF,
                             c: Scalar = _HALF, G: Scalar = 30) -> HamiltonianSystem:
    """Ball in a paraboloid with the rank-4 Poisson bivector P^(1) of survey (110) (Casimir J1).

    ``P^(1)`` is the pull-back of e(3) through ``(gamma, M) -> (gamma, L)`` with
    ``(gamma, L) = J1``, ``(e3 x gamma, L) = (e3 x gamma, M)``, ``L3 = J2``
    (:mod:`poissonkit_nonholonomic.revolution`), hence Poisson, with Casimirs ``(gamma, gamma)``
    and ``J1``. Proposition 7 (checked by :func:`proposition7`): the field (104) is
    ``X = N P^(1) dH + lambda X_S`` with ``N = -2 c R gamma3^3`` and ``lambda`` linear in ``M``.
    The system's own field is the Hamiltonian part ``N P^(1) dH`` (no ``original``: the dynamics
    is :func:`ball_on_paraboloid`).

    Only for ``kappa = mu/(mu + m R^2) = 1/4`` (``nu = 1/2``, ``J1`` contains
    ``sqrt(gamma3)``): the pull-back handles one square root, not ``gamma3**nu`` in general.

    Raises
    ------
    InputError
        If ``nu != 1/2`` (or the parameters are invalid, see :func:`paraboloid_parts`).
    """
    p = paraboloid_parts(mu, m, R, c, G)
    if p["nu"] != sp.Rational(1, 2):
        raise InputError("ball_on_paraboloid_rank4 needs mu/(mu + m R^2) = 1/4 (nu = 1/2), got "
                         f"kappa = {p['kappa']}")
    q = p["params"]
    P = _rank4(q["mu"], q["m"], q["R"], q["c"], q["G"])
    gam, M = p["gamma"], p["M"]
    return HamiltonianSystem(
        structure=Bivector.from_matrix(P, gam + M),
        hamiltonian=p["H"],
        multiplier=-2 * q["c"] * q["R"] * gam[2] ** 3,
        casimirs={"C=(gamma,gamma)": dot(gam, gam), "J1 (107),(121)": p["J1"]},
        integrals={"H": p["H"], "J2 (107),(121)": p["J2"]},
        params=dict(q),
        name="nh.ball_on_paraboloid_rank4",
        doc="Ball in a paraboloid, rank-4 Poisson bivector P^(1) of survey (110) pulled back from "
            "e(3); X = N P dH + lambda X_S (Prop. 7) is a claim.",
    )


def proposition7(system: HamiltonianSystem, seed: int = 7) -> tuple[bool, str, str]:
    """Prop. 7: the field (104) is X = N P^(1) dH + lambda X_S with lambda linear in M"""
    from poissonkit_nonholonomic.revolution import symmetry_decomposition

    q = system.params
    p = paraboloid_parts(q["mu"], q["m"], q["R"], q["c"], q["G"])
    return symmetry_decomposition(p["field"], system.structure.matrix, p["H"], system.multiplier,
                                  p["gamma"], p["M"], seed=seed)


class OriginalFieldSystem(LambdifiedSystem):
    """:class:`~poissonkit.numerics.conformal.LambdifiedSystem` evaluating ``system.original``.

    The Euler-field bivector is singular at ``M = 0`` (``P dH`` is ``0/0`` there although ``X``
    is regular), so a ball released at rest is integrated with the original field (104). Works
    with :func:`~poissonkit.numerics.conformal.midpoint_python`,
    :func:`~poissonkit.numerics.conformal.solve_direct` (``backend="python"``, ``compiled=``)
    and :func:`~poissonkit.numerics.conformal.invariant_drift`.
    """

    def __init__(self, hsys: HamiltonianSystem) -> None:
        if hsys.original is None:
            raise InputError(f"{hsys.name} has no original equations of motion")
        super().__init__(hsys)
        field = [sp.sympify(hsys.original[x]) for x in hsys.coords]
        self._f = sp.lambdify([hsys.coords], field, modules="math", cse=True)

    def centre(self, y: Any, c: float) -> np.ndarray:
        """Centre positions ``r_c(gamma)`` (rows) for the bowl ``z = c (x^2 + y^2)``."""
        y = np.atleast_2d(np.asarray(y, dtype=float))
        g1, g2, g3 = y[:, 0], y[:, 1], y[:, 2]
        return np.stack([-g1 / (2 * c * g3), -g2 / (2 * c * g3),
                         (g1**2 + g2**2) / (4 * c * g3**2)], axis=1)
