"""Seed 000's parameter table: the magnets' geometry, mass, inertia and moment at full precision.

Zub, *Mathematical model of magnetically interacting rigid bodies*, Maple table "Parameters of
cylindrical magnets (dumb-bells)". Everything is derived from the geometry with :mod:`mpmath`
(``dps`` digits), then rounded to floats only where the numerics need them (``docs/seed000.md``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import mpmath

from poissonkit.errors import InputError


#: The seed's inputs (SI), as exact decimal strings.
DIAMETER = "2.5e-3"  # m
HEIGHT = "20e-3"  # m
DENSITY = "7800"  # kg/m^3
MOMENT = "0.15546875"  # A m^2, the seed's mu1 = mu2
ORBIT_RADIUS = "0.01"  # m, found by reproducing the seed's P_orb (module docstring)

#: The seed's printed values (Maple, 20 digits), for comparison in reports and tests.
SEED_PRINTED: Mapping[str, str] = {
    "V": "0.98174770424681038703e-7",
    "m_cyl": "0.00076576320931251210188",
    "m": "0.00038288160465625605093",
    "I_perp": "0.25824566564054770102e-7",
    "I_axial": "0.59825250727540007960e-9",
    "alpha": "0.38722818348939904682e8",
    "J_Fe": "1.5835916837643585909e6",
    "mu": "0.15546875",
    "l": "0.010000000000000000000",
    "P_orb": "6.4910356642626862477e-4",
}

#: Configurations of the two axes relative to the orbital plane: (c1, c2, c3) on the orbit.
CONFIGURATIONS: Mapping[str, tuple[int, int, int]] = {
    # axes perpendicular to the orbital plane, opposite: attracting, circular orbit exists
    "antiparallel": (0, 0, -1),
    # axes perpendicular to the plane, equal: repelling (no circular orbit)
    "parallel": (0, 0, 1),
    # axes along the line of centres, head to tail: attracting
    "coaxial": (1, 1, 1),
}


@dataclass(frozen=True)
class SeedTable:
    """The seed's parameter table, every entry an ``mpmath.mpf`` at the precision it was built.

    Attributes are in SI: ``V`` [m^3], ``m_cyl`` [kg], ``m`` (reduced mass) [kg],
    ``I_perp``/``I_axial`` [kg m^2], ``alpha = 1/I_perp`` [1/(kg m^2)], ``mu`` [A m^2],
    ``J_Fe`` [A/m], ``l`` (dumbbell half-length) [m], ``a`` (radius) [m], ``h`` [m],
    ``mu0`` [T m/A].
    """

    V: Any
    m_cyl: Any
    m: Any
    I_perp: Any
    I_axial: Any
    alpha: Any
    mu: Any
    J_Fe: Any
    l: Any
    a: Any
    h: Any
    mu0: Any
    dps: int

    def as_floats(self) -> dict[str, float]:
        """Every entry rounded to a Python float."""
        return {k: float(getattr(self, k)) for k in
                ("V", "m_cyl", "m", "I_perp", "I_axial", "alpha", "mu", "J_Fe", "l", "a", "h",
                 "mu0")}

    def lines(self, digits: int = 20) -> list[str]:
        """The table as the seed prints it (``name = value unit``), ``digits`` significant."""
        s = lambda x: mpmath.nstr(x, digits)  # noqa: E731
        return [
            f"V = {s(self.V)} m^3",
            f"m_cyl = {s(self.m_cyl)} kg",
            f"m = {s(self.m)} kg   (reduced mass)",
            f"mI = [{s(self.I_perp)}, {s(self.I_perp)}, {s(self.I_axial)}] kg*m^2",
            f"alpha1 = alpha2 = {s(self.alpha)} kg^-1*m^-2",
            f"J_Fe = {s(self.J_Fe)} A/m",
            f"mu1 = mu2 = {s(self.mu)} A*m^2",
            f"l1 = l2 = {s(self.l)} m",
        ]


def parameter_table(dps: int = 30, *, diameter: str | float = DIAMETER,
                    height: str | float = HEIGHT, density: str | float = DENSITY,
                    moment: str | float = MOMENT) -> SeedTable:
    """Derive the seed's parameter table from the magnet geometry at ``dps`` digits.

    Parameters
    ----------
    dps
        Decimal digits of the mpmath computation.
    diameter, height, density, moment
        Cylinder diameter [m], height [m], density [kg/m^3] and dipole moment [A m^2]; strings
        are read exactly (decimal), floats as given.

    Returns
    -------
    SeedTable

    Raises
    ------
    InputError
        If a value is not a positive finite number.
    """
    with mpmath.workdps(dps):
        vals = {}
        for name, v in (("diameter", diameter), ("height", height), ("density", density),
                        ("moment", moment)):
            try:
                x = mpmath.mpf(v)
            except (TypeError, ValueError):
                raise InputError(f"seed000: {name} must be a number, got {v!r}") from None
            if not (mpmath.isfinite(x) and x > 0):
                raise InputError(f"seed000: {name} must be positive and finite, got {v!r}")
            vals[name] = x
        a = vals["diameter"] / 2
        h = vals["height"]
        V = mpmath.pi * a**2 * h
        m_cyl = vals["density"] * V
        I_perp = m_cyl * (3 * a**2 + h**2) / 12
        I_axial = m_cyl * a**2 / 2
        mu = vals["moment"]
        return SeedTable(V=+V, m_cyl=+m_cyl, m=m_cyl / 2, I_perp=+I_perp, I_axial=+I_axial,
                         alpha=1 / I_perp, mu=+mu, J_Fe=mu / V, l=h / 2, a=+a, h=+h,
                         mu0=4 * mpmath.pi * mpmath.mpf("1e-7"), dps=dps)


def dumbbell_energy(r, c1, c2, c3, *, mu1, mu2, l1, l2, mu0):
    """Dumbbell pair energy U(r, c1, c2, c3), Zub's seed eq. (16), in mpmath.

    Charges ``±mu/(2l)`` at ``±l nu``; used here as an independent high-precision oracle.
    """
    k1, k2 = mu1 / (2 * l1), mu2 / (2 * l2)
    total = 0
    for e1 in (1, -1):
        for e2 in (1, -1):
            R2 = r**2 + l1**2 + l2**2 + 2 * r * (e2 * l2 * c2 - e1 * l1 * c1) \
                - 2 * e1 * e2 * l1 * l2 * c3
            total += e1 * e2 / mpmath.sqrt(R2)
    return mu0 * k1 * k2 / (4 * mpmath.pi) * total


def radial_force(radius, table: SeedTable | None = None, configuration: str = "antiparallel"):
    """``F_r = -dU/dr`` of the dumbbell pair in a fixed configuration (negative = attraction).

    Closed-form derivative of (16) at fixed ``c1, c2, c3`` (all mpmath).
    """
    t = table or parameter_table()
    if configuration not in CONFIGURATIONS:
        raise InputError(f"seed000: unknown configuration {configuration!r}; available: "
                         + ", ".join(CONFIGURATIONS))
    c1, c2, c3 = CONFIGURATIONS[configuration]
    with mpmath.workdps(t.dps):
        r = mpmath.mpf(radius)
        K = t.mu0 * (t.mu / (2 * t.l)) ** 2 / (4 * mpmath.pi)
        dU = 0
        for e1 in (1, -1):
            for e2 in (1, -1):
                R2 = (r**2 + 2 * t.l**2 + 2 * r * t.l * (e2 * c2 - e1 * c1)
                      - 2 * e1 * e2 * t.l**2 * c3)
                dU += -e1 * e2 * (r + t.l * (e2 * c2 - e1 * c1)) / R2 ** mpmath.mpf(1.5)
        return -K * dU
