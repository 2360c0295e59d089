"""Seed 000's circular orbit: its radius and momentum, internal units and initial states."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mpmath
import numpy as np

from poissonkit.errors import InputError
from poissonkit.numerics.units import Scales
from poissonkit_magnets.seed000.table import (ORBIT_RADIUS, SEED_PRINTED, SeedTable,
                                              parameter_table, radial_force)


@dataclass(frozen=True)
class CircularOrbit:
    """A circular relative orbit of the two magnets (SI, mpmath values).

    Attributes
    ----------
    radius
        Orbit radius ``R`` [m] (distance between the centres).
    momentum
        ``P_orb`` [N s], from ``P^2/(m R) = |F(R)|``.
    period
        ``T_orb = 2 pi R m / P`` [s].
    omega
        Orbital angular frequency ``2 pi / T`` [rad/s].
    configuration
        Name in :data:`CONFIGURATIONS`.
    """

    radius: Any
    momentum: Any
    period: Any
    omega: Any
    configuration: str


def circular_orbit(radius: str | float = ORBIT_RADIUS, table: SeedTable | None = None,
                   configuration: str = "antiparallel") -> CircularOrbit:
    """Momentum and period of the circular orbit at ``radius`` (the seed's GetP_orb/GetT_orb).

    Raises
    ------
    InputError
        If the configuration repels at that radius (no circular orbit) or the radius is not
        positive.
    """
    t = table or parameter_table()
    with mpmath.workdps(t.dps):
        R = mpmath.mpf(radius)
        if not R > 0:
            raise InputError(f"seed000: orbit radius must be > 0, got {radius!r}")
        F = radial_force(R, t, configuration)
        if not F < 0:
            raise InputError(f"seed000: the {configuration} pair repels at r = {radius} m "
                             "(no circular orbit)")
        P = mpmath.sqrt(t.m * R * (-F))
        T = 2 * mpmath.pi * R * t.m / P
        return CircularOrbit(radius=R, momentum=P, period=T, omega=2 * mpmath.pi / T,
                             configuration=configuration)


def find_orbit_radius(momentum: str | float = SEED_PRINTED["P_orb"],
                      table: SeedTable | None = None, configuration: str = "antiparallel",
                      bracket: tuple[float, float] = (2.5e-3, 1.0)):
    """Invert :func:`circular_orbit`: the radius whose orbit momentum is ``momentum``.

    Bisection-safe root finding (``mpmath.findroot`` with the anderson solver) on ``bracket``;
    used to recover the radius the seed does not print.
    """
    t = table or parameter_table()
    with mpmath.workdps(t.dps):
        P = mpmath.mpf(momentum)
        g = lambda R: P**2 / (t.m * R) + radial_force(R, t, configuration)  # noqa: E731
        return mpmath.findroot(g, tuple(mpmath.mpf(b) for b in bracket), solver="anderson")


def scales(orbit: CircularOrbit | None = None, table: SeedTable | None = None) -> Scales:
    """Internal units of the seed scene: length ``R_orb``, mass = reduced mass, time
    ``1/omega_orb`` -- so the orbit has radius 1, momentum 1 and period ``2 pi`` internally."""
    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    return Scales(length=float(o.radius), mass=float(t.m), time=float(1 / o.omega))


def initial_state(*, spin_ratio: float = 20.0, tilt: float = 0.0, radius_factor: float = 1.0,
                  momentum_factor: float = 1.0, orbit: CircularOrbit | None = None,
                  table: SeedTable | None = None) -> np.ndarray:
    """Nondimensional 18-variable initial state ``(r, p, nu', m', nu'', m'')`` of the seed orbit.

    The orbit lies in the xy-plane: ``r = (R, 0, 0)``, ``p = (0, P, 0)``; ``nu' = +z``,
    ``nu'' = -z`` (antiparallel, attracting). Each top spins about its own axis,
    ``m = s nu`` with ``alpha |m| = spin_ratio * omega_orb`` (gyroscopic stiffness; with
    ``tilt = 0`` the spin does not change the orbit, it is an exact relative equilibrium).

    Parameters
    ----------
    spin_ratio
        ``alpha |m| / omega_orb`` of each top (0: no spin).
    tilt
        Both axes are tilted by this angle [rad] towards +x (the line of centres), a perturbation
        of the relative equilibrium; ``m`` stays along ``nu``.
    radius_factor, momentum_factor
        Multiply the initial radius / momentum (perturbations: ``!= 1`` gives an ellipse-like
        orbit).
    """
    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    sc = scales(o, t)
    alpha_nd = float(t.alpha) * sc.mass * sc.length**2
    for name, v in (("spin_ratio", spin_ratio), ("tilt", tilt), ("radius_factor", radius_factor),
                    ("momentum_factor", momentum_factor)):
        if not math.isfinite(v):
            raise InputError(f"seed000: {name} must be finite, got {v!r}")
    if radius_factor <= 0:
        raise InputError(f"seed000: radius_factor must be > 0, got {radius_factor!r}")
    s = spin_ratio / alpha_nd  # |m| in internal units (omega_orb = 1)
    n1 = np.array([math.sin(tilt), 0.0, math.cos(tilt)])
    n2 = np.array([math.sin(tilt), 0.0, -math.cos(tilt)])
    # P = 1 in internal units for the exact orbit of radius 1
    p = float(o.momentum) / sc.unit("momentum")
    return np.concatenate([[radius_factor, 0.0, 0.0], [0.0, p * momentum_factor, 0.0],
                           n1, s * n1, n2, s * n2])


def nondimensional_parameters(table: SeedTable | None = None,
                              orbit: CircularOrbit | None = None) -> dict[str, float]:
    """The pair-potential and body parameters in internal units.

    Returns ``reduced_mass``, ``alpha1``, ``alpha2``, ``moment1``, ``moment2``, ``half_length1``,
    ``half_length2``, ``mu0``: moments are scaled so that ``mu0 mu^2/(4 pi)`` is in internal
    energy x length^3 units with ``mu0`` kept at ``4 pi 1e-7`` (the moment unit absorbs the scale).
    """
    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    sc = scales(o, t)
    # U ~ mu0 mu^2 / (4 pi L^3); keep mu0, rescale mu so that U comes out in energy units
    moment_unit = math.sqrt(sc.energy * sc.length**3)
    mu = float(t.mu) / moment_unit
    l_nd = float(t.l) / sc.length
    alpha_nd = float(t.alpha) * sc.mass * sc.length**2
    return {"reduced_mass": float(t.m) / sc.mass, "alpha1": alpha_nd, "alpha2": alpha_nd,
            "moment1": mu, "moment2": mu, "half_length1": l_nd, "half_length2": l_nd,
            "mu0": float(t.mu0)}


def metadata(table: SeedTable | None = None, orbit: CircularOrbit | None = None,
             **extra: Any) -> dict[str, Any]:
    """SI parameters and derived orbit quantities, for ``summary.json``."""
    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    sc = scales(o, t)
    out: dict[str, Any] = {
        "scene": "seed000",
        "model": "dumbbell",
        "configuration": o.configuration,
        "parameters_SI": t.as_floats(),
        "P_orb": float(o.momentum),
        "P_orb_digits": mpmath.nstr(o.momentum, 20),
        "T_orb": float(o.period),
        "R_orb": float(o.radius),
        "scales": {"length": sc.length, "mass": sc.mass, "time": sc.time},
        "seed_printed": dict(SEED_PRINTED),
    }
    out.update(extra)
    return out
