"""Problems with known solutions for :func:`~poissonkit.testing.check_integrator`, chosen from
what an integrator declares (its capabilities), never from its name."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from poissonkit.testing import oracles


@dataclass(frozen=True)
class Problem:
    """A system, its start state, an end time, the exact end state and the smallest error
    that can be trusted (the reference's accuracy)."""

    name: str
    system: Any
    y0: np.ndarray
    t_end: float
    truth: np.ndarray
    floor: float = 0.0


def kepler_with_free_tops() -> Problem:
    """Two tops (1/I = 1) in the Kepler potential ``−1/r`` (reduced mass 1), an e = 0.3 orbit
    from the pericentre, each axis precessing about its spin; over 1.1 periods."""
    return _kepler_tops("kepler_with_free_tops", 0.3, 1.1)


def eccentric_kepler_with_free_tops() -> Problem:
    """The tops of :func:`kepler_with_free_tops` on an e = 0.5 orbit over 2.5 periods, ending
    at the apocentre: for time-transformed methods, whose step varies threefold along it.

    A time-transformed run ends with an ordinary step of the remaining time; on the e = 0.3
    orbit, ending just past the pericentre, that step makes the order-10 errors erratic (a
    slope of 13.4 over rungs that are not yet asymptotic); at the apocentre it is slow."""
    return _kepler_tops("eccentric_kepler_with_free_tops", 0.5, 2.5)


def _kepler_tops(name: str, e: float, periods: float) -> Problem:
    """Two free tops on a Kepler orbit of eccentricity ``e`` (a = 1, period 2π) from the
    pericentre, over ``periods`` periods."""
    import sympy as sp

    from poissonkit.numerics import TwoBodySystem

    r = sp.Symbol("r", real=True)
    system = TwoBodySystem(None, None, 1.0, 1.0, -1 / r, reduced_mass=1.0)
    m1, m2 = np.array([0.3, -0.2, 0.9]), np.array([-0.5, 0.4, 0.1])
    n1, n2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.6, 0.8])
    t_end = periods * 2 * math.pi
    x0, v0 = oracles.kepler_state(0.0, e)
    x, v = oracles.kepler_state(t_end, e)
    truth = np.concatenate([x, v, oracles.free_top_axis(n1, m1, 1.0, t_end), m1,
                            oracles.free_top_axis(n2, m2, 1.0, t_end), m2])
    return Problem(name, system, system.pack(x0, v0, n1, m1, n2, m2), t_end, truth)


def star_and_two_planets() -> Problem:
    """A star and two planets of mass 1e-2 (G = 1) over one inner period; reference DOP853."""
    from poissonkit.numerics import AllPairs, Body, NBodySystem

    m = np.array([1.0, 1e-2, 1e-2])
    x1, v1 = oracles.kepler_state(0.3, 0.05, mu=1.01)
    x2, v2 = oracles.kepler_state(1.0, 0.1, mu=1.02, a=1.7)
    x2 = np.array([x2[0], x2[1] * math.cos(0.1), x2[1] * math.sin(0.1)])
    v2 = np.array([v2[0], v2[1] * math.cos(0.1), v2[1] * math.sin(0.1)])
    x = np.array([np.zeros(3), x1, x2])
    v = np.array([np.zeros(3), v1, v2])
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    system = NBodySystem([Body(n, mk) for n, mk in zip(("star", "b", "c"), m)],
                         [AllPairs("gravity", {"G": 1.0})])
    t_end = 2 * math.pi
    xr, vr = oracles.point_masses_reference(m, x, v, t_end)
    return Problem("star_and_two_planets", system, system.pack(x, m[:, None] * v), t_end,
                   system.pack(xr, m[:, None] * vr), floor=1e-10)


def free_fall(r0: float = 1.0) -> tuple[Any, np.ndarray, float]:
    """Two unit masses at rest ``r0`` apart (G = 1): the system, its state and ``mu``."""
    from poissonkit.numerics import AllPairs, Body, NBodySystem

    system = NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity", {"G": 1.0})])
    y0 = system.pack([[0.0, 0.0, 0.0], [r0, 0.0, 0.0]], np.zeros((2, 3)))
    return system, y0, 2.0


def oscillator() -> Problem:
    """The harmonic oscillator ``H = (q² + p²)/2`` on the canonical plane, compiled from its
    symbolic form (for methods that need one); exact: a rotation, over ``t = 5``."""
    from poissonkit.numerics.system import compile_system
    from poissonkit.structure import HamiltonianSystem, canonical

    P = canonical(1)
    q, p = P.coords
    system = compile_system(HamiltonianSystem(P, (q ** 2 + p ** 2) / 2))
    # the sense of rotation follows the bracket's sign: q' = {q, H} = s p
    s = float(P.bracket(q, p))
    t_end = 5.0
    truth = np.array([math.cos(t_end), -s * math.sin(t_end)])
    return Problem("oscillator", system, np.array([1.0, 0.0]), t_end, truth)


_BUILDERS = {"planets": star_and_two_planets, "kepler": kepler_with_free_tops,
             "eccentric kepler": eccentric_kepler_with_free_tops, "oscillator": oscillator}
_CACHE: dict[str, Problem] = {}


def _cached(key: str) -> Problem:
    if key not in _CACHE:
        _CACHE[key] = _BUILDERS[key]()
    return _CACHE[key]


def problem_for(entry: Any) -> Problem:
    """The first problem the integrator of ``entry`` takes (``solve`` refuses the others from
    the declared capabilities, before any work): point masses for ``point_masses_only``, else
    the Kepler orbit of two tops (the eccentric one for the time-transformed family), else the
    oscillator compiled from its symbolic form."""
    from poissonkit.errors import CapabilityError
    from poissonkit.numerics import solve
    from poissonkit.numerics.integrators.capabilities import TIME_TRANSFORMED

    kepler = "eccentric kepler" if entry.family == TIME_TRANSFORMED.family else "kepler"
    keys = ("planets",) if entry.capabilities.point_masses_only else (kepler, "oscillator")
    for key in keys:
        p = _cached(key)
        try:
            solve(p.system, p.y0, p.t_end / 1000, entry.name, step=p.t_end / 1000)
        except CapabilityError:
            continue
        return p
    return _cached(keys[-1])
