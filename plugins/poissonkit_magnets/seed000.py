"""The seed 000 scene: two cylinder magnets ("dumbbells") on a circular orbit.

Zub, *Mathematical model of magnetically interacting rigid bodies*, Maple table "Parameters of
cylindrical magnets (dumb-bells)" and the circular-orbit momentum ``P_orb``. Everything here is
derived from the geometry at full precision with :mod:`mpmath` (``dps`` digits), then rounded to
floats only where the numerics need them.

Derivation (see ``docs/seed000.md``)
------------------------------------
* ``V = pi (d/2)^2 h``, ``m_cyl = rho V``, reduced mass ``m = m_cyl/2`` (two equal magnets).
* Inertia of a solid cylinder about its centre: transverse ``I_perp = m_cyl (3 a^2 + h^2)/12``,
  axial ``I_axial = m_cyl a^2/2`` (``a = d/2``); ``alpha = 1/I_perp``. This convention
  reproduces the seed's printed ``mI`` to all 20 printed digits.
* ``J_Fe = mu/V`` (the seed derives the magnetisation from the moment, not the other way round).
* Dumbbell model: charges ``±kappa = ±mu/(2l)`` at ``±l nu`` with ``l = h/2``
  (FORMULAS.md §1, (16)).
* Circular orbit: the seed's ``GetP_orb(mu1, mu2, l1, l2, R_orb, m)`` balances centrifugal and
  magnetic force, ``P^2/(m R) = |F(R)|``. The seed does not print ``R_orb``; the radius
  ``R_orb = 10 mm`` (= ``l``) with both axes perpendicular to the orbital plane and *antiparallel*
  (side by side, attracting) reproduces the printed ``P_orb = 6.4910356642626862477e-4 N s`` to all
  20 printed digits. The parallel side-by-side pair has the same ``|F|`` but repels, so it has
  no circular orbit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import mpmath
import numpy as np

from poissonkit.errors import InputError, IntegrationError
from poissonkit.numerics.units import Scales

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
    """Dumbbell pair energy U(r, c1, c2, c3), seed eq. (16) (FORMULAS.md §1), in mpmath.

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


# --------------------------------------------------------------------------------------------
# The default scene as an integrable problem


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


def default_run(*, periods: float = 20.0, method: str = "splitting6", step: float | None = None,
                tol: float | None = None, spin_ratio: float = 20.0, tilt: float = 0.0,
                radius_factor: float = 1.0, momentum_factor: float = 1.0):
    """The built-in scene of ``poissonkit run``: the seed orbit as a :class:`RunSpec`.

    The system is the seed's own 18-variable centre-of-mass form
    (:class:`~poissonkit.numerics.twobody.TwoBodySystem`, reduced mass, state
    ``(r, p, ν', m', ν'', m'')``): it is what the seed integrates, its plots are in the relative
    coordinate ``r`` anyway, and it is the smallest state (18 instead of 24 numbers, one pair)
    for the speed comparisons. :func:`nbody_system` gives the same scene as a general N-body
    system (two tops) and :func:`nbody_state` converts states; a test checks they agree.

    Parameters
    ----------
    periods
        Duration in orbital periods (internal time ``2 pi periods``).
    method, step, tol
        Integrator registry name; fixed step (internal time) or tolerance. Without either, a
        fixed-step method uses ``T_orb/200`` and an adaptive one its own default tolerance.
    spin_ratio, tilt, radius_factor, momentum_factor
        See :func:`initial_state`.
    """
    from poissonkit.numerics.runspec import RunSpec

    if not (math.isfinite(periods) and periods > 0):
        raise InputError(f"seed000: periods must be > 0, got {periods!r}")
    t = parameter_table()
    o = circular_orbit(table=t)
    system = seed_system(t, o)
    y0 = initial_state(spin_ratio=spin_ratio, tilt=tilt, radius_factor=radius_factor,
                       momentum_factor=momentum_factor, orbit=o, table=t)
    if step is None and tol is None:
        from poissonkit.numerics.workprecision import method_kind

        if method_kind(method) == "step":  # adaptive methods use their own default tolerance
            step = 2 * math.pi / 200
    meta = metadata(t, o, periods=periods, spin_ratio=spin_ratio, tilt=tilt,
                    radius_factor=radius_factor, momentum_factor=momentum_factor,
                    system="TwoBodySystem (seed eq. 20, 18 variables, reduced mass)")
    return RunSpec(name="seed000", system=system, y0=y0, t_end=2 * math.pi * periods,
                   method=method, step=step, tol=tol, metadata=meta)


def scene_run(*, periods: float = 20.0, duration: float | None = None,
              method: str = "splitting6", step: float | None = None, tol: float | None = None,
              tilt: float = 0.0, spin_ratio: float = 20.0):
    """The registered ``seed000`` scene: :func:`default_run` with run options in SI.

    This is what ``poissonkit run`` (no argument, or ``poissonkit run seed000``) calls through
    the scene registry.

    Parameters
    ----------
    periods
        Duration in orbital periods (ignored if ``duration`` is given).
    duration
        Duration [s]; converted with the orbital period ``T_orb``.
    method, tol
        Integrator registry name and tolerance of adaptive methods.
    step
        Fixed step [s]; converted to the internal time unit ``1/omega_orb``. Default ``T_orb/200``
        for fixed-step methods.
    tilt, spin_ratio
        See :func:`initial_state`.

    Returns
    -------
    RunSpec
        The seed orbit, ready for :func:`poissonkit.solve`.
    """
    if duration is not None:
        periods = duration / float(circular_orbit().period)
    if step is not None:  # seconds -> internal time (unit 1/omega_orb)
        step = step / float(scales().time)
    return default_run(periods=periods, method=method, step=step, tol=tol, tilt=tilt,
                       spin_ratio=spin_ratio)


def nbody_state(y18: np.ndarray) -> np.ndarray:
    """Two-body state ``(r, p, nu', m', nu'', m'')`` -> N-body state of :func:`nbody_system`.

    Equal masses, centre of mass at the origin and at rest: ``r_1 = -r/2``, ``r_2 = r/2``,
    ``p_1 = -p``, ``p_2 = p`` (``p = mu rdot = M rdot_2`` with ``mu = M/2``).
    """
    y = np.asarray(y18, dtype=float)
    if y.shape[-1] != 18:
        from poissonkit.errors import DimensionError

        raise DimensionError(f"two-body state must have 18 entries, got {y.shape}")
    r, p = y[..., 0:3], y[..., 3:6]
    return np.concatenate([-r / 2, -p, r / 2, p, y[..., 6:18]], axis=-1)


def relative_orbit(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(r, p)`` of the seed's 18-variable form from N-body states (rows) of
    :func:`nbody_system`."""
    y = np.asarray(y, dtype=float)
    return y[..., 6:9] - y[..., 0:3], (y[..., 9:12] - y[..., 3:6]) / 2


def dumbbell_potential():
    """The pair potential used: the magnets plugin's ``"dumbbell"`` when registered, else the
    same energy (seed eq. (16), FORMULAS.md §1) as a sympy expression in ``r, c1, c2, c3``."""
    from poissonkit.errors import UnknownNameError
    from poissonkit.plugin import potential

    t = parameter_table()
    params = {"moment1": float(t.mu), "moment2": float(t.mu), "half_length1": float(t.l),
              "half_length2": float(t.l), "mu0": float(t.mu0)}
    try:
        return potential("dumbbell"), params
    except UnknownNameError:
        import sympy as sp

        r, c1, c2, c3 = sp.symbols("r c1 c2 c3", real=True)
        l = sp.Float(float(t.l))
        K = sp.Float(float(t.mu0 * (t.mu / (2 * t.l)) ** 2 / (4 * mpmath.pi)))
        expr = K * sum(e1 * e2 / sp.sqrt(r**2 + 2 * l**2 + 2 * r * l * (e2 * c2 - e1 * c1)
                                         - 2 * e1 * e2 * l**2 * c3)
                       for e1 in (1, -1) for e2 in (1, -1))
        return expr, {}


def seed_system(table: SeedTable | None = None, orbit: CircularOrbit | None = None):
    """The seed scene as a :class:`~poissonkit.numerics.twobody.TwoBodySystem` (SI reduced mass
    at full precision, ``alpha`` of both magnets, dumbbell potential), integrated in the internal
    units of :func:`scales`."""
    from poissonkit.numerics.twobody import TwoBodySystem

    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    pot, params = dumbbell_potential()
    return TwoBodySystem(None, None, float(t.alpha), float(t.alpha), pot, params,
                         scales=scales(o, t), reduced_mass=float(t.m))


def nbody_system(table: SeedTable | None = None, orbit: CircularOrbit | None = None):
    """The same scene as an :class:`~poissonkit.numerics.nbody.NBodySystem`: two tops
    ``"magnet1"``, ``"magnet2"`` (state order ``r_1, p_1, r_2, p_2, ν_1, m_1, ν_2, m_2``)."""
    from poissonkit.numerics.nbody import Body, Interaction, NBodySystem

    t = table or parameter_table()
    o = orbit or circular_orbit(table=t)
    pot, params = dumbbell_potential()
    bodies = [Body("magnet1", mass=float(t.m_cyl), alpha=float(t.alpha)),
              Body("magnet2", mass=float(t.m_cyl), alpha=float(t.alpha))]
    return NBodySystem(bodies, [Interaction(0, 1, pot, params)], scales=scales(o, t))


@dataclass(frozen=True)
class OrbitFate:
    """How a perturbed seed orbit ends.

    Attributes
    ----------
    kind
        ``"bounded"`` (distance stayed within the escape radius and above contact for the whole
        run), ``"collision"`` or ``"escape"``.
    r_min, r_max
        Smallest and largest centre distance seen, in units of ``R_orb``.
    t_end
        Time reached, in orbital periods (the event time if one fired).
    max_energy_error
        Largest relative energy error of the run (trust the verdict only when it is small).
    """

    kind: str
    r_min: float
    r_max: float
    t_end: float
    max_energy_error: float


def axis_distance(y: np.ndarray, half_length: float) -> np.ndarray:
    """Smallest distance between the two magnets' axis segments, per state (rows).

    Segment 1 is ``[-l ν', +l ν']`` about the origin, segment 2 ``r + [-l ν'', +l ν'']``
    (relative coordinates of the 18-variable form, internal units). Two cylinders of radius
    ``a`` overlap when this distance is below ``2a`` (capsule bound: exact for side-by-side
    contact, slightly early at the rims). Vectorised closest-points of two segments.
    """
    y = np.atleast_2d(np.asarray(y, dtype=float))
    l = float(half_length)
    d1 = 2 * l * y[:, 6:9]
    d2 = 2 * l * y[:, 12:15]
    p1 = -l * y[:, 6:9]
    p2 = y[:, 0:3] - l * y[:, 12:15]
    w = p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    b = np.einsum("ij,ij->i", d1, d2)
    c = np.einsum("ij,ij->i", d1, w)
    f = np.einsum("ij,ij->i", d2, w)
    den = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > 1e-14 * a * e, np.clip((b * f - c * e) / den, 0.0, 1.0), 0.0)
        t = (b * s + f) / e
        t_c = np.clip(t, 0.0, 1.0)
        s = np.where(t != t_c, np.clip((b * t_c - c) / a, 0.0, 1.0), s)
    diff = (p1 + s[:, None] * d1) - (p2 + t_c[:, None] * d2)
    return np.linalg.norm(diff, axis=1)


def orbit_fate(*, spin_ratio: float, tilt: float, periods: float = 20.0,
               radius_factor: float = 1.0, momentum_factor: float = 1.0,
               escape_distance: float = 3.0, method: str = "splitting8",
               step: float = 2 * math.pi / 400) -> OrbitFate:
    """Integrate a perturbed seed orbit and classify it (the seed's stability statement).

    Contact: the magnets' axis segments come closer than ``2a = 2.5 mm`` (see
    :func:`axis_distance`; the dumbbell model's poles would otherwise pass through each other).
    Escape: the centre distance exceeds ``escape_distance * R_orb``. The run is classified on its
    saved states up to the first event; the energy error is that of this part.
    """
    from poissonkit.numerics.events import Escape
    from poissonkit.numerics.solver import solve

    t = parameter_table()
    orbit = circular_orbit(table=t)
    spec = default_run(periods=periods, method=method, step=step, spin_ratio=spin_ratio,
                       tilt=tilt, radius_factor=radius_factor, momentum_factor=momentum_factor)
    contact = float(2 * t.a / orbit.radius)
    l_nd = float(t.l / orbit.radius)
    try:
        # the two-body escape test measures a body's distance from the centre of mass (r/2)
        sol = solve(spec.system, spec.y0, spec.t_end, method=method, step=step,
                    events=(Escape(escape_distance / 2),))
        y, tt = np.asarray(sol.y), np.asarray(sol.t)
        kind = sol.events[0].kind if sol.events else "bounded"
    except IntegrationError as exc:  # blow-up after an unresolved contact
        y, tt, kind = np.asarray(getattr(exc, "y", np.empty((0, 18)))), np.empty(0), "collision"
        if y.size == 0:
            raise
    ok = np.all(np.isfinite(y), axis=1)
    hit = np.nonzero(~ok | (axis_distance(np.where(ok[:, None], y, 0.0), l_nd) < contact))[0]
    if hit.size:
        kind = "collision"
        y, tt = y[: max(hit[0], 1)], tt[: max(hit[0], 1)]
    r = np.linalg.norm(y[:, :3], axis=1)
    H = np.asarray(spec.system.energy(y), dtype=float)
    ee = float(np.max(np.abs(H - H[0])) / abs(H[0]))
    return OrbitFate(kind=kind, r_min=float(r.min()), r_max=float(r.max()),
                     t_end=float(tt[-1]) / (2 * math.pi), max_energy_error=ee)


def main() -> None:  # pragma: no cover - convenience
    """Print the seed's table and orbit."""
    t = parameter_table()
    for line in t.lines():
        print(line)
    o = circular_orbit(table=t)
    print(f"R_orb = {mpmath.nstr(o.radius, 20)} m  ({o.configuration}, axes normal to the orbit)")
    print(f"P_orb = {mpmath.nstr(o.momentum, 20)} N*s")
    print(f"T_orb = {mpmath.nstr(o.period, 20)} s")


if __name__ == "__main__":  # pragma: no cover
    main()
