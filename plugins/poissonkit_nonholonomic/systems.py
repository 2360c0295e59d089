"""Catalogue of the non-holonomic systems: registry names -> builders and typed parameters."""

from __future__ import annotations

from dataclasses import replace

import sympy as sp

from poissonkit.plugin.contributions import Param, SystemEntry
from poissonkit_nonholonomic.ball import (chaplygin_ball, chaplygin_ball_sphere_bmf,
                                          chaplygin_gyrostat)
from poissonkit_nonholonomic.claims import CLAIMS
from poissonkit_nonholonomic.general import generalized_chaplygin, p_gf_system
from poissonkit_nonholonomic.paraboloid import ball_on_paraboloid, ball_on_paraboloid_rank4
from poissonkit_nonholonomic.routh import routh_sphere, routh_sphere_rank4
from poissonkit_nonholonomic.routh_gyrostat import routh_gyrostat_rank4
from poissonkit_nonholonomic.separation import chaplygin_spheroconical
from poissonkit_nonholonomic.suslov import (suslov, suslov_potential, suslov_rank2_bivector,
                                            suslov_rank4)
from poissonkit_nonholonomic.veselova import veselova, veselova_gyrostat

TAG = "nonholonomic"
#: Tag of entries whose bracket is deliberately not Poisson: an almost-Poisson bracket kept
#: because ``X = N P dH`` reproduces the equations of motion (``poissonkit verify`` then
#: expects the Jacobi identity to fail).
ALMOST_POISSON = "almost-poisson"


def _f(name: str, default: float, doc: str, positive: bool = True) -> Param:
    return Param(name, "float", doc, default=default, positive=positive)


_BALL = (_f("I1", 1.0, "principal moment of inertia about the centre [kg m^2]"),
         _f("I2", 2.0, "principal moment of inertia [kg m^2]"),
         _f("I3", 3.0, "principal moment of inertia [kg m^2]"),
         _f("d", 1.0, "m b^2: mass times the ball's radius squared [kg m^2]"))
_ROUTH = (_f("R", 2.0, "radius of the sphere [m]"),
          Param("a", "float", "offset of the centre of mass along the axis [m]", 0.5),
          _f("m", 3.0, "mass [kg]"),
          _f("I1", 5.0, "equatorial moment about the centre of mass [kg m^2]"),
          _f("I3", 7.0, "axial moment about the centre of mass [kg m^2]"),
          Param("u", "float", "potential U = u gamma3 [J]", 10.0))
_PARABOLOID = (_f("m", 3.0, "mass [kg]"),
               _f("R", 0.5, "radius of the ball, R < 1/(2c) [m]"),
               _f("c", 0.5, "the centre moves on z = c (x^2 + y^2) [1/m]"),
               Param("G", "float", "weight m g in U = G z_c [N]", 30.0))
_VES = (_f("a1", 1.0, "inverse principal moment a1 = 1/I1 [1/(kg m^2)]"),
        _f("a2", 2.0, "inverse principal moment a2 [1/(kg m^2)]"),
        _f("a3", 3.0, "inverse principal moment a3 [1/(kg m^2)]"))


def entries() -> list[SystemEntry]:
    """Every non-holonomic system, tagged ``"nonholonomic"``."""
    built = [
        SystemEntry("nh.chaplygin_ball", chaplygin_ball.__doc__.strip().splitlines()[0],
                    _BALL, build=chaplygin_ball, tags=(TAG, "rolling")),
        SystemEntry("nh.chaplygin_gyrostat", chaplygin_gyrostat.__doc__.strip().splitlines()[0],
                    _BALL + (Param("S", "vector", "gyrostatic momentum [kg m^2/s]",
                                   default=(1.0, 0.0, -1.0)),),
                    build=chaplygin_gyrostat, tags=(TAG, "rolling", "gyrostat")),
        SystemEntry("nh.chaplygin_spheroconical",
                    chaplygin_spheroconical.__doc__.strip().splitlines()[0],
                    (_f("I1", 1.0, "principal moment of inertia (distinct I_i) [kg m^2]"),
                     _f("I2", 2.0, "principal moment of inertia [kg m^2]"),
                     _f("I3", 3.0, "principal moment of inertia [kg m^2]"),
                     _f("d", 1.0, "m b^2: mass times the ball's radius squared [kg m^2]")),
                    build=chaplygin_spheroconical, tags=(TAG, "rolling", "separation")),
        SystemEntry("nh.chaplygin_ball_sphere_bmf",
                    chaplygin_ball_sphere_bmf.__doc__.strip().splitlines()[0], _BALL,
                    build=chaplygin_ball_sphere_bmf, tags=(TAG, "rolling")),
        SystemEntry("nh.veselova", veselova.__doc__.strip().splitlines()[0], _VES,
                    build=veselova, tags=(TAG,)),
        SystemEntry("nh.veselova_gyrostat", veselova_gyrostat.__doc__.strip().splitlines()[0],
                    _VES + (Param("k", "vector", "rotor momentum [kg m^2/s]",
                                  default=(1.0, 1.0, 0.0)),),
                    build=veselova_gyrostat, tags=(TAG, "gyrostat")),
        SystemEntry("nh.routh_sphere", routh_sphere.__doc__.strip().splitlines()[0],
                    _ROUTH,
                    build=routh_sphere, tags=(TAG, "rolling", ALMOST_POISSON)),
        SystemEntry("nh.routh_sphere_rank4", routh_sphere_rank4.__doc__.strip().splitlines()[0],
                    _ROUTH + (Param("casimir", "str", "which linear integral is the Casimir: "
                           "'jellett' (P^(1)) or 'routh' (P^(2))", "jellett"),),
                    build=routh_sphere_rank4, tags=(TAG, "rolling")),
        SystemEntry("nh.routh_gyrostat_rank4",
                    routh_gyrostat_rank4.__doc__.strip().splitlines()[0],
                    _ROUTH + (Param("s", "float", "axial gyrostatic momentum S = (0, 0, s) "
                                    "[kg m^2/s]; I1 != I3", sp.Rational(3, 2)),
                              Param("casimir", "str", "which shifted linear integral is the "
                                    "Casimir: 'jellett' or 'routh'", "jellett")),
                    build=routh_gyrostat_rank4, tags=(TAG, "rolling", "gyrostat")),
        SystemEntry("nh.suslov", suslov.__doc__.strip().splitlines()[0],
                    (_f("I11", 2.0, "inertia I11 [kg m^2]"), _f("I22", 1.0, "inertia I22 [kg m^2]"),
                     Param("I13", "float", "inertia I13 [kg m^2]", 0.5),
                     # exactly one third, as in the survey's example (a float would read 0.333...)
                     Param("I23", "float", "inertia I23 [kg m^2]", sp.Rational(1, 3))),
                    build=suslov, tags=(TAG,)),
        SystemEntry("nh.suslov_rank2", suslov_rank2_bivector.__doc__.strip().splitlines()[0],
                    (_f("I11", 2.0, "inertia I11 [kg m^2]"), _f("I22", 1.0, "inertia I22 [kg m^2]"),
                     Param("c", "vector", "g(gamma) = gamma x c", default=(0.0, 0.0, 1.0))),
                    build=suslov_rank2_bivector, tags=(TAG,)),
        SystemEntry("nh.suslov_rank4", suslov_rank4.__doc__.strip().splitlines()[0],
                    (_f("I22", 1.0, "inertia I22 [kg m^2]"),
                     Param("I23", "float", "inertia I23 != 0 [kg m^2]; I11 = I22 + I23^2/I22",
                           1.0)),
                    build=suslov_rank4, tags=(TAG,)),
        SystemEntry("nh.suslov_potential", suslov_potential.__doc__.strip().splitlines()[0],
                    (_f("I11", 2.0, "inertia I11 [kg m^2]"), _f("I22", 1.0, "inertia I22 [kg m^2]"),
                     Param("U", "str", "potential in gamma_x, gamma_y, gamma_z",
                           default="3*gamma_z + gamma_x**2*gamma_y")),
                    build=suslov_potential, tags=(TAG,)),
        SystemEntry("nh.generalized_chaplygin",
                    generalized_chaplygin.__doc__.strip().splitlines()[0], (),
                    build=generalized_chaplygin, tags=(TAG, "class")),
        SystemEntry("nh.p_gf", p_gf_system.__doc__.strip().splitlines()[0],
                    (Param("with_phi", "bool", "add Remark 5's phi term", default=False),),
                    build=p_gf_system, tags=(TAG, "class")),
        SystemEntry("nh.ball_on_paraboloid", ball_on_paraboloid.__doc__.strip().splitlines()[0],
                    (_f("mu", 0.25, "moment of inertia about the centre, I = mu E [kg m^2]"),)
                    + _PARABOLOID, build=ball_on_paraboloid,
                    tags=(TAG, "rolling", ALMOST_POISSON)),
        SystemEntry("nh.ball_on_paraboloid_rank4",
                    ball_on_paraboloid_rank4.__doc__.strip().splitlines()[0],
                    (_f("mu", 0.25, "moment of inertia about the centre, I = mu E [kg m^2]; "
                        "mu/(mu + m R^2) must be 1/4"),) + _PARABOLOID,
                    build=ball_on_paraboloid_rank4, tags=(TAG, "rolling")),
    ]
    # the survey's system-specific claims (decompositions, Poisson maps) run with `verify`
    return [replace(e, claims=CLAIMS.get(e.name, ())) for e in built]
