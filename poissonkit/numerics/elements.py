"""Keplerian orbital elements ↔ Cartesian states, with REBOUND's names and conventions.

Elements (angles in radians): semi-major axis ``a`` (negative for a hyperbola, as REBOUND),
eccentricity ``e``, inclination ``inc``, longitude of the ascending node ``Omega``, argument of
pericentre ``omega``, and the position on the orbit as mean anomaly ``M`` or true anomaly ``f``.
``mu = G (m_primary + m)`` is the gravitational parameter of the two-body problem.

Which primary (:func:`elements_of`, :func:`states_from_elements`): a body's elements are about
the named primary body, or, when none is named, *Jacobi* elements about the centre of mass of
all bodies before it with ``mu = G (Σ m_<i + m_i)`` — REBOUND's ``sim.add(primary=None)`` and
``sim.orbits()``.

Kepler's equation ``M = E - e sin E`` (``e < 1``) and ``M = e sinh H - H`` (``e > 1``) is solved
by Newton's method from Danby's starting value (elliptic) or ``asinh(M/e)`` (hyperbolic), with
bisection bounds that keep every iterate inside the bracket of the root, so it converges for
every ``e`` in ``[0, 1)`` and ``(1, ∞)``, including ``e → 1`` at small ``M``. Parabolic orbits
(``e = 1`` exactly) are refused.

Output ranges: ``Omega``, ``omega``, ``f``, ``M`` in ``[0, 2π)`` (REBOUND's ``orbits()`` gives
some of them in ``(-π, π]``: compare modulo 2π). For an orbit in the reference plane
(``sin inc = 0``) ``Omega = 0``; for a circular orbit ``omega = 0`` and ``f`` is counted from
the node (REBOUND's conventions).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from poissonkit.errors import InputError

TWO_PI = 2.0 * np.pi
#: Newton iterations of Kepler's equation at most (bisection-safeguarded: ~5 suffice).
_MAX_ITER = 100
#: ``sin(inc)`` and ``e`` below this count as zero (the node / pericentre is undefined).
_TINY = 1e-15

__all__ = ["OrbitalElements", "cartesian", "dominant_body", "elements", "elements_of",
           "eccentric_anomaly", "gravity_si", "system_elements",
           "mean_to_true", "states_from_elements", "true_to_mean"]


@dataclass(frozen=True)
class OrbitalElements:
    """Osculating elements (arrays of one shape; angles in radians, ``a`` in the length unit).

    ``P`` is the period (``nan`` for an unbound orbit), ``n`` the mean motion, ``pomega`` the
    longitude of pericentre ``Omega + omega`` and ``l`` the mean longitude ``pomega + M``.
    """

    a: np.ndarray
    e: np.ndarray
    inc: np.ndarray
    Omega: np.ndarray
    omega: np.ndarray
    f: np.ndarray
    M: np.ndarray
    P: np.ndarray
    n: np.ndarray

    @property
    def pomega(self) -> np.ndarray:
        """Longitude of pericentre ``Omega + omega`` in ``[0, 2π)``."""
        return np.mod(self.Omega + self.omega, TWO_PI)

    @property
    def l(self) -> np.ndarray:  # noqa: E743 (REBOUND's name)
        """Mean longitude ``Omega + omega + M`` in ``[0, 2π)``."""
        return np.mod(self.Omega + self.omega + self.M, TWO_PI)

    #: Names of the elements, in the order of :meth:`as_dict`.
    NAMES = ("a", "e", "inc", "Omega", "omega", "f", "M", "P", "n", "pomega", "l")

    def as_dict(self) -> dict[str, np.ndarray]:
        """``{name: array}`` for every name in :attr:`NAMES`."""
        return {k: np.asarray(getattr(self, k)) for k in self.NAMES}


def eccentric_anomaly(M: np.ndarray | float, e: np.ndarray | float) -> np.ndarray:
    """Solve Kepler's equation for the eccentric anomaly ``E`` (``e < 1``) or the hyperbolic
    anomaly ``H`` (``e > 1``), elementwise.

    Raises
    ------
    InputError
        For a negative or non-finite ``e``, ``e = 1`` or a non-finite ``M``.
    """
    M = np.asarray(M, dtype=float)
    e = np.asarray(e, dtype=float)
    M, e = np.broadcast_arrays(M, e)
    if not (np.all(np.isfinite(M)) and np.all(np.isfinite(e))) or np.any(e < 0):
        raise InputError(f"Kepler's equation needs finite M and e >= 0, got M={M!r}, e={e!r}")
    if np.any(e == 1.0):
        raise InputError("a parabolic orbit (e = 1) has no mean anomaly; give f instead")
    out = np.empty_like(M)
    ell = e < 1
    out[ell] = _elliptic(M[ell], e[ell])
    out[~ell] = _hyperbolic(M[~ell], e[~ell])
    return out


def _bracketed_newton(x: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                      residual: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
                      ) -> np.ndarray:
    """The root of an increasing ``g`` inside ``[lo, hi]`` from ``x``, elementwise: Newton steps
    (``residual(x) = (g, g')``) that keep the bracket, bisection where a step leaves it."""
    for _ in range(_MAX_ITER):
        g, dg = residual(x)
        lo = np.where(g < 0, x, lo)
        hi = np.where(g > 0, x, hi)
        new = x - g / dg
        outside = ~((new > lo) & (new < hi)) | ~np.isfinite(new)
        new = np.where(outside, 0.5 * (lo + hi), new)
        done = np.abs(new - x) <= 4e-16 * np.maximum(1.0, np.abs(x))
        x = new
        if np.all(done):
            break
    return x


def _elliptic(M: np.ndarray, e: np.ndarray) -> np.ndarray:
    """``E`` with ``E - e sin E = M`` for ``0 <= e < 1``; Newton inside ``[m - e, m + e]``
    (``m`` = ``M`` reduced to ``(-π, π]``, where ``E - M`` has the sign of ``m``)."""
    turns = np.round(M / TWO_PI)
    m = M - turns * TWO_PI
    lo = np.where(m >= 0, m, m - e)
    hi = np.where(m >= 0, m + e, m)
    E = np.clip(m + 0.85 * e * np.sign(m), lo, hi)  # Danby (1987)
    E = _bracketed_newton(E, lo, hi, lambda x: (x - e * np.sin(x) - m, 1.0 - e * np.cos(x)))
    return E + turns * TWO_PI


def _hyperbolic(M: np.ndarray, e: np.ndarray) -> np.ndarray:
    """``H`` with ``e sinh H - H = M`` for ``e > 1``; Newton inside a bracket of the root
    (the left side is increasing; ``|H| <= asinh(|M| / (e - 1))`` bounds it)."""
    s = np.sign(M)
    m = np.abs(M)
    lo = np.zeros_like(m)
    hi = np.arcsinh(m / (e - 1.0)) + 1.0
    H = np.clip(np.arcsinh(m / e), lo, hi)
    H = _bracketed_newton(H, lo, hi, lambda x: (e * np.sinh(x) - x - m, e * np.cosh(x) - 1.0))
    return s * H


def mean_to_true(M: np.ndarray | float, e: np.ndarray | float) -> np.ndarray:
    """True anomaly ``f`` of mean anomaly ``M`` (elliptic or hyperbolic ``e``)."""
    e = np.asarray(e, dtype=float)
    E = eccentric_anomaly(M, e)
    with np.errstate(invalid="ignore"):
        ell = 2.0 * np.arctan2(np.sqrt(1.0 + e) * np.sin(E / 2),
                               np.sqrt(np.abs(1.0 - e)) * np.cos(E / 2))
        hyp = 2.0 * np.arctan(np.sqrt(np.abs((e + 1.0) / (e - 1.0))) * np.tanh(E / 2))
    return np.where(e < 1, ell, hyp)


def true_to_mean(f: np.ndarray | float, e: np.ndarray | float) -> np.ndarray:
    """Mean anomaly ``M`` of true anomaly ``f`` (``nan`` beyond a hyperbola's asymptotes)."""
    f = np.asarray(f, dtype=float)
    e = np.asarray(e, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        E = 2.0 * np.arctan2(np.sqrt(np.abs(1.0 - e)) * np.sin(f / 2),
                             np.sqrt(1.0 + e) * np.cos(f / 2))
        ell = E - e * np.sin(E)
        H = 2.0 * np.arctanh(np.sqrt(np.abs((e - 1.0) / (e + 1.0))) * np.tan(f / 2))
        hyp = e * np.sinh(H) - H
    return np.where(e < 1, ell, hyp)


def cartesian(mu: float | np.ndarray, a: float | np.ndarray, e: float | np.ndarray = 0.0,
              inc: float | np.ndarray = 0.0, Omega: float | np.ndarray = 0.0,
              omega: float | np.ndarray = 0.0, *, M: float | np.ndarray | None = None,
              f: float | np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Relative position and velocity ``(r, v)`` (shape ``(..., 3)``) of elements about a
    primary with ``mu = G (m_primary + m)`` (REBOUND's ``reb_particle_from_orbit``).

    Give ``M`` or ``f`` (neither: ``f = 0``). ``a < 0`` with ``e > 1`` is a hyperbola.

    Raises
    ------
    InputError
        Both ``M`` and ``f``; ``mu <= 0``; ``e < 0`` or ``e = 1``; an ``a`` whose sign does not
        match ``e`` (``a > 0`` for ``e < 1``, ``a < 0`` for ``e > 1``); ``f`` beyond a
        hyperbola's asymptotes.
    """
    if M is not None and f is not None:
        raise InputError("give the mean anomaly M or the true anomaly f, not both")
    mu, a, e, inc, Omega, omega = (np.asarray(x, dtype=float)
                                   for x in (mu, a, e, inc, Omega, omega))
    if np.any(~(mu > 0)):
        raise InputError(f"mu = G (m_primary + m) must be > 0, got {mu!r}")
    if np.any(~(e >= 0)) or np.any(e == 1.0):
        raise InputError(f"e must be >= 0 and not 1 (parabola), got {e!r}")
    if np.any((e < 1) & ~(a > 0)) or np.any((e > 1) & ~(a < 0)):
        raise InputError(f"a must be > 0 for a bound orbit (e < 1) and < 0 for a hyperbola "
                         f"(e > 1), got a={a!r}, e={e!r}")
    f = mean_to_true(M, e) if M is not None else np.asarray(0.0 if f is None else f, float)
    cf, sf = np.cos(f), np.sin(f)
    if np.any((e > 1) & (1.0 + e * cf <= 0)):
        raise InputError(f"f = {f!r} lies beyond the asymptotes of the hyperbola (e = {e!r})")
    p = a * (1.0 - e * e)
    d = p / (1.0 + e * cf)
    v0 = np.sqrt(mu / p)
    cO, sO, co, so, ci, si = (np.cos(Omega), np.sin(Omega), np.cos(omega), np.sin(omega),
                              np.cos(inc), np.sin(inc))
    cu, su = co * cf - so * sf, so * cf + co * sf  # cos, sin of the argument of latitude
    r = np.stack([d * (cO * cu - sO * su * ci), d * (sO * cu + cO * su * ci), d * su * si], -1)
    v = np.stack([v0 * ((e + cf) * (-ci * co * sO - cO * so) - sf * (co * cO - ci * so * sO)),
                  v0 * ((e + cf) * (ci * co * cO - sO * so) - sf * (co * sO + ci * so * cO)),
                  v0 * ((e + cf) * co * si - sf * si * so)], -1)
    return r, v


def elements(mu: float | np.ndarray, r: np.ndarray, v: np.ndarray) -> OrbitalElements:
    """Osculating elements of relative positions ``r`` and velocities ``v`` (``(..., 3)``)
    about a primary with ``mu = G (m_primary + m)``.

    Raises
    ------
    InputError
        For shapes that are not ``(..., 3)``, ``mu <= 0`` or a body on its primary.
    """
    r = np.asarray(r, dtype=float)
    v = np.asarray(v, dtype=float)
    mu = np.asarray(mu, dtype=float)
    if r.shape[-1:] != (3,) or v.shape != r.shape:
        raise InputError(f"positions and velocities must both be (..., 3), got {r.shape} and "
                         f"{v.shape}")
    if np.any(~(mu > 0)):
        raise InputError(f"mu = G (m_primary + m) must be > 0, got {mu!r}")
    d = np.linalg.norm(r, axis=-1)
    if np.any(d == 0):
        raise InputError("a body sits on its primary: its orbital elements are undefined")
    v2 = np.einsum("...i,...i->...", v, v)
    rv = np.einsum("...i,...i->...", r, v)
    h = np.cross(r, v)
    hn = np.linalg.norm(h, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = 1.0 / (2.0 / d - v2 / mu)
        ecos = hn * hn / (mu * d) - 1.0  # e cos f
        esin = hn * rv / (mu * d)  # e sin f
        e = np.hypot(ecos, esin)
        inc = np.arctan2(np.hypot(h[..., 0], h[..., 1]), h[..., 2])
        flat = np.hypot(h[..., 0], h[..., 1]) <= _TINY * hn
        Omega = np.where(flat, 0.0, np.arctan2(h[..., 0], -h[..., 1]))
        cO, sO = np.cos(Omega), np.sin(Omega)
        # argument of latitude: the angle from the node line to r, about h
        hhat = h / hn[..., None]
        node = np.stack([cO, sO, np.zeros_like(cO)], -1)
        u = np.arctan2(np.einsum("...i,...i->...", np.cross(node, r), hhat),
                       np.einsum("...i,...i->...", node, r))
        circular = e <= _TINY
        f = np.where(circular, u, np.arctan2(esin, ecos))
        omega = np.where(circular, 0.0, u - f)
        n = np.sqrt(mu / np.abs(a) ** 3)
        P = np.where(e < 1, TWO_PI / n, np.nan)
    M = true_to_mean(f, e)
    return OrbitalElements(a=a, e=e, inc=inc, Omega=np.mod(Omega, TWO_PI),
                           omega=np.mod(omega, TWO_PI), f=np.mod(f, TWO_PI),
                           M=np.where(e < 1, np.mod(M, TWO_PI), M), P=P, n=n)


def _primaries(masses: np.ndarray, primary: int | None, i: int, r: np.ndarray, v: np.ndarray
               ) -> tuple[float, np.ndarray, np.ndarray]:
    """``(mass, position, velocity)`` of body ``i``'s primary: body ``primary`` or the centre
    of mass of bodies ``0 … i-1`` (Jacobi)."""
    if primary is not None:
        return float(masses[primary]), r[..., primary, :], v[..., primary, :]
    m = masses[:i]
    total = float(m.sum())
    rc = np.einsum("k,...ki->...i", m, r[..., :i, :]) / total
    vc = np.einsum("k,...ki->...i", m, v[..., :i, :]) / total
    return total, rc, vc


def elements_of(masses: np.ndarray, r: np.ndarray, v: np.ndarray, G: float,
                primary: int | None = None) -> OrbitalElements:
    """Elements of every body (arrays ``(..., N)``) from positions and velocities
    ``(..., N, 3)`` (REBOUND's ``sim.orbits(primary=...)``, whose list starts at body 1).

    Parameters
    ----------
    masses
        ``(N,)`` masses in the unit of ``G``.
    r, v
        Positions and velocities, bodies on the second-to-last axis.
    G
        Newton's constant in the units of the inputs.
    primary
        Index of the body all elements are about; ``None``: Jacobi elements (each body about
        the centre of mass of the bodies before it). The primary, or body 0 of Jacobi
        elements, has no orbit: ``nan``.
    """
    masses = np.asarray(masses, dtype=float)
    r = np.asarray(r, dtype=float)
    v = np.asarray(v, dtype=float)
    N = masses.shape[0]
    if r.shape[-2:] != (N, 3) or v.shape != r.shape:
        raise InputError(f"positions and velocities must be (..., {N}, 3) for {N} masses, got "
                         f"{r.shape} and {v.shape}")
    if primary is not None and not 0 <= primary < N:
        raise InputError(f"primary index {primary} is not one of the {N} bodies")
    centre = 0 if primary is None else primary
    rows: list[OrbitalElements | None] = []
    for i in range(N):
        if i == centre:  # the primary about itself: no orbit
            rows.append(None)
            continue
        mp, rp, vp = _primaries(masses, primary, i, r, v)
        rows.append(elements(G * (mp + masses[i]), r[..., i, :] - rp, v[..., i, :] - vp))
    shape = r.shape[:-2]
    out = {name: np.stack([np.full(shape, np.nan) if row is None else getattr(row, name)
                           for row in rows], -1)
           for name in ("a", "e", "inc", "Omega", "omega", "f", "M", "P", "n")}
    return OrbitalElements(**out)


def states_from_elements(masses: np.ndarray, G: float,
                         orbits: list[dict[str, float] | None],
                         primaries: list[int | None] | None = None,
                         states: list[tuple[np.ndarray, np.ndarray] | None] | None = None
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities ``(N, 3)`` of bodies added one by one, as REBOUND's
    ``sim.add(m=..., a=..., primary=...)``.

    Parameters
    ----------
    masses
        ``(N,)`` masses in the unit of ``G``.
    G
        Newton's constant in the units of the result.
    orbits
        Per body: ``None`` for a body given by its state (``states[i]``), else the keyword
        arguments of :func:`cartesian` (``a``, ``e``, ``inc``, ``Omega``, ``omega``, ``M`` or
        ``f``) without ``mu``.
    primaries
        Per body: the index of an earlier body it orbits, or ``None`` (Jacobi: the centre of
        mass of every earlier body).
    states
        Per body given by its state: ``(r, v)``; ``None`` elsewhere (default: the origin at
        rest).
    """
    masses = np.asarray(masses, dtype=float)
    N = masses.shape[0]
    r = np.zeros((N, 3))
    v = np.zeros((N, 3))
    for i in range(N):
        given = states[i] if states is not None else None
        orbit = orbits[i]
        if orbit is None:
            if given is not None:
                r[i], v[i] = given
            continue
        if i == 0:
            raise InputError("the first body has nothing to orbit: give its position")
        primary = primaries[i] if primaries is not None else None
        if primary is not None and not 0 <= primary < i:
            raise InputError(f"body {i}: its primary must be an earlier body, got {primary}")
        mp, rp, vp = _primaries(masses, primary, i, r, v)
        dr, dv = cartesian(G * (mp + masses[i]), **orbit)
        r[i], v[i] = rp + dr, vp + dv
    return r, v


def gravity_si(system: object) -> float | None:
    """Newton's constant [SI] of ``system``'s all-pairs gravity, or ``None`` if it has none
    or is not a system of moving point masses (whose elements would mean nothing)."""
    from poissonkit.numerics.nbody.system import NBodySystem

    if not isinstance(system, NBodySystem):
        return None
    if system.n_tops or system.n_moving != len(system.bodies) or system.n_moving < 2:
        return None
    try:
        G = float(system.gravity_constant())
    except InputError:
        return None
    scales = system.scales
    if scales is not None:  # G [L³ / (M T²)] of the internal units
        G *= scales.unit("length") ** 3 / (scales.unit("mass") * scales.unit("time") ** 2)
    return G


def dominant_body(masses: np.ndarray, ratio: float = 10.0) -> int | None:
    """Index of a body heavier than ``ratio`` times all the others together, or ``None``."""
    masses = np.asarray(masses, dtype=float)
    k = int(np.argmax(masses))
    return k if masses[k] >= ratio * (masses.sum() - masses[k]) else None


def system_elements(system: object, y: np.ndarray, primary: int | str | None = "dominant"
                    ) -> OrbitalElements:
    """Elements (SI lengths) of every body of a point-mass system with gravity at the states
    ``y`` (rows): arrays ``(time, N)``, ``nan`` for the primary (body 0 for Jacobi elements).

    Parameters
    ----------
    system
        An :class:`~poissonkit.numerics.nbody.NBodySystem` of moving point masses with one
        all-pairs gravity interaction.
    y
        States (rows, internal units).
    primary
        A body (name or index) all elements are about; ``None``: Jacobi elements in the order
        of the bodies; ``"dominant"``: about the body heavier than ten times all the others,
        Jacobi elements if there is none.

    Raises
    ------
    InputError
        If the system has no gravity or holds tops or fixed bodies, or ``primary`` names no
        body.
    """
    from poissonkit.numerics.nbody.system import NBodySystem

    G = gravity_si(system)
    if G is None or not isinstance(system, NBodySystem):
        raise InputError("orbital elements need a system of moving point masses with one "
                         "all-pairs gravity interaction")
    bodies = system.bodies
    masses = np.array([float(b.mass) for b in bodies])
    names = [b.name for b in bodies]
    if primary == "dominant":
        primary = dominant_body(masses)
    if isinstance(primary, str):  # a name
        if primary not in names:
            raise InputError(f"primary {primary!r} is not a body; bodies: {', '.join(names)}")
        primary = names.index(primary)
    parts = system.unpack(np.atleast_2d(np.asarray(y, dtype=float)), si=True)
    r, p = parts["r"], parts["p"]
    return elements_of(masses, r, p / masses[:, None], G, primary)
