"""Every registered integrator reaches its declared order (the registry-wide convergence check).

One parametrised test iterates :func:`poissonkit.integrators` — built-in and plugin entries alike —
and runs each entry, with its default options, through the same check (as diffrax's order test
does): the error against a known solution over a ladder of steps ``h_k = T / N_k`` (ratio √2).
The slope of ``log(error)`` against ``log(h)`` over the three smallest steps whose error is
still far above round-off (and below 1e-3, the asymptotic range) must equal the declared order
to ±0.3. Methods that choose their own steps from a tolerance (scipy's) are checked by
convergence instead: the error falls as ``tol`` falls. An order of 0 declares a variable order
(LSODA), so only convergence is claimed and checked.

The problem comes from what the entry declares, not from its name:

* ``point_masses_only`` (the hierarchical Wisdom–Holman family): a star and two planets of mass
  1e-2 (for two bodies alone the Kepler drift is the exact flow and there would be no error to
  measure); truth: a DOP853 solve of Newton's equations written out in ``oracles`` at rtol 1e-13;
* the ``time_transformed`` family (``logh2`` ... ``logh10``): the same two tops on an eccentric
  Kepler orbit (e = 0.5, from the pericentre over 2.5 periods, so the run ends at the
  apocentre), where the physical step varies threefold along the orbit. On the e = 0.3 orbit
  below, ending 0.1 period after the pericentre, the order-10 composition reaches round-off
  within four rungs of the ladder (1e-7 at 8 steps, 3e-13 at 23) and the ordinary step of the
  remaining time that ends every time-transformed run (taken where the motion is fastest)
  makes the last errors erratic: a slope of 13.4 from three points of which two are
  pre-asymptotic. Ending at the apocentre, where that last step is slow, and over 2.5 periods,
  every order is seen on six or more rungs;
* ``needs_splitting`` (splittings): a Kepler orbit (e = 0.3) of two
  symmetric tops that spin freely; truth: the exact orbit and the exact precession of both axes
  (``oracles.KeplerOrbit``, ``oracles.free_top_axis``);
* anything else (implicit, scipy, a plugin's general method): the free asymmetric rigid body;
  truth: Jacobi's elliptic-function solution (``oracles.euler_top``).

Where an entry declares the ``compensated`` option it is switched on, so that round-off stays
below the errors of the high-order tables at small steps.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest
import sympy as sp
from oracles import (  # type: ignore[import-not-found]
    KeplerOrbit,
    euler_top,
    free_top_axis,
    nbody_gravity_reference,
)

import poissonkit as pk
from poissonkit.numerics import AllPairs, Body, NBodySystem, TwoBodySystem, solve
from poissonkit.numerics.integrators.capabilities import TIME_TRANSFORMED

INTEGRATORS = sorted(pk.integrators().items())
#: steps per run: 8 · √2^k, rounded (each run ends exactly at T)
LADDER = sorted({round(8 * 2 ** (k / 2)) for k in range(19)})  # 8 ... 4096
SLOPE_TOL = 0.3
EPS = np.finfo(float).eps


@dataclass
class Problem:
    """A system, a start state, an end time and the exact (or reference) end state."""

    system: Any
    y0: np.ndarray
    t_end: float
    truth: np.ndarray
    #: smallest error trusted (reference accuracy), besides the round-off of the run itself
    floor: float = 0.0


def kepler_with_free_tops(e: float = 0.3, periods: float = 1.1) -> Problem:
    """Two tops (1/I = 1) in the Kepler potential -1/r (reduced mass 1): an orbit of
    eccentricity ``e`` from the pericentre, each axis precessing about its fixed spin; over
    ``periods`` periods."""
    r = sp.Symbol("r", real=True)
    system = TwoBodySystem(None, None, 1.0, 1.0, -1 / r, reduced_mass=1.0)
    orbit = KeplerOrbit(mu=1.0, a=1.0, e=e)
    m1, m2 = np.array([0.3, -0.2, 0.9]), np.array([-0.5, 0.4, 0.1])
    n1, n2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.6, 0.8])
    t_end = periods * orbit.period
    x0, v0 = orbit.state(0.0)
    x, v = orbit.state(t_end)
    truth = np.concatenate([x, v, free_top_axis(n1, m1, 1.0, t_end), m1,
                            free_top_axis(n2, m2, 1.0, t_end), m2])
    return Problem(system, system.pack(x0, v0, n1, m1, n2, m2), t_end, truth)


def star_and_two_planets() -> Problem:
    """A star and two planets of mass 1e-2 on eccentric, mutually inclined orbits (G = 1)."""
    m = np.array([1.0, 1e-2, 1e-2])
    x1, v1 = KeplerOrbit(mu=1.01, a=1.0, e=0.05, mean_anomaly=0.3).state(0.0)
    x2, v2 = KeplerOrbit(mu=1.02, a=1.7, e=0.1, inclination=0.1, mean_anomaly=2.0).state(0.0)
    x = np.array([np.zeros(3), x1, x2])
    v = np.array([np.zeros(3), v1, v2])
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    system = NBodySystem([Body(n, mk) for n, mk in zip(("star", "b", "c"), m)],
                         [AllPairs("gravity", {"G": 1.0})])
    t_end = 2 * math.pi
    xr, vr = nbody_gravity_reference(m, x, v, t_end)
    y0 = system.pack(x, m[:, None] * v)
    return Problem(system, y0, t_end, system.pack(xr, m[:, None] * vr), floor=1e-10)


def free_rigid_body() -> Problem:
    """so(3) with H = m1²/2 + m2²/4 + m3²/6 (moments 1, 2, 3), over t = 5."""
    from poissonkit.numerics.system import compile_system
    from poissonkit.structure import HamiltonianSystem, so3

    P = so3()
    c = P.coords
    inertia = np.array([1.0, 2.0, 3.0])
    system = compile_system(HamiltonianSystem(P, sum(c[k] ** 2 / (2 * inertia[k])
                                                     for k in range(3))))
    # the bracket's sign sets the sense of time: {m1, m2} = s m3 gives m' = -s (m x omega),
    # while the oracle solves Euler's m' = m x omega
    s = sp.simplify(P.bracket(c[0], c[1]) / c[2])
    m0, t_end = np.array([0.6, 0.9, -0.4]), 5.0
    return Problem(system, m0, t_end, euler_top(m0, inertia, -float(s) * t_end))


def problem_for(entry: Any) -> Problem:
    caps = entry.capabilities
    if caps.point_masses_only:
        return _cached("planets", star_and_two_planets)
    if entry.family == TIME_TRANSFORMED.family:
        return _cached("eccentric kepler", lambda: kepler_with_free_tops(e=0.5, periods=2.5))
    if caps.needs_splitting:
        return _cached("kepler", kepler_with_free_tops)
    return _cached("rigid", free_rigid_body)


_PROBLEMS: dict[str, Problem] = {}


def _cached(key: str, build: Any) -> Problem:
    if key not in _PROBLEMS:
        _PROBLEMS[key] = build()
    return _PROBLEMS[key]


def tolerance_driven(entry: Any) -> bool:
    """scipy's methods choose every step from ``tol`` (a given step is only the first)."""
    return entry.family == "scipy" or entry.order == 0


def _options(entry: Any) -> dict[str, Any]:
    return {"compensated": True} if any(p.name == "compensated" for p in entry.params) else {}


def _error(problem: Problem, name: str, options: dict[str, Any], **kw: Any) -> float:
    sol = solve(problem.system, problem.y0, problem.t_end, name, options=options, **kw)
    assert sol.t[-1] == pytest.approx(problem.t_end, rel=1e-14)
    return float(np.max(np.abs(sol.y[-1] - problem.truth)))


def observed_order(problem: Problem, name: str, options: dict[str, Any]) -> tuple[float, list]:
    """Least-squares slope of log(error) over log(step) on the three smallest steps in the
    asymptotic range above round-off; also every (N, error) measured, for the message."""
    measured, usable = [], []
    for n in LADDER:
        err = _error(problem, name, options, step=problem.t_end / n)
        measured.append((n, err))
        # round-off grows with the number of steps, unless the sums are compensated
        scale = EPS * max(1.0, float(np.abs(problem.truth).max()))
        roundoff = scale * (1000 if options.get("compensated") else 200 * n)
        if max(roundoff, problem.floor) <= err <= 1e-3:
            usable.append((n, err))
        elif usable:  # below the floor: smaller steps only measure round-off
            break
    assert len(usable) >= 3, f"fewer than three steps in the asymptotic range: {measured}"
    n, err = np.array(usable[-3:]).T
    slope = np.polyfit(np.log(problem.t_end / n), np.log(err), 1)[0]
    return float(slope), measured


@pytest.mark.parametrize("name,entry", INTEGRATORS, ids=[n for n, _ in INTEGRATORS])
def test_every_integrator_reaches_its_declared_order(name, entry):
    problem = problem_for(entry)
    options = _options(entry)
    if tolerance_driven(entry):
        tols = (1e-4, 1e-6, 1e-8, 1e-10)
        errs = [_error(problem, name, options, tol=tol) for tol in tols]
        assert all(b < a for a, b in itertools.pairwise(errs)), (tols, errs)  # converges
        assert errs[-1] < 1e-3 * errs[0] and errs[-1] < 1e-7, (tols, errs)
        return
    assert entry.order > 0, f"{name}: a fixed-step method must declare its order"
    slope, measured = observed_order(problem, name, options)
    assert abs(slope - entry.order) <= SLOPE_TOL, (
        f"{name}: observed order {slope:.2f}, declared {entry.order}; (N, error): {measured}")


def test_the_check_fails_for_a_wrong_declared_order():
    """Negative control: splitting4's errors do not pass as order 2 or 6."""
    entry = pk.integrators()["splitting4"]
    slope, _ = observed_order(problem_for(entry), "splitting4", _options(entry))
    assert abs(slope - 4) <= SLOPE_TOL
    assert abs(slope - 2) > SLOPE_TOL and abs(slope - 6) > SLOPE_TOL


@pytest.mark.parametrize("declared", [8, 12])
def test_the_check_fails_for_logh10_declared_8_or_12(declared):
    """Negative control of the time-transformed problem: logh10's errors pass as order 10 and
    would not pass as 8 or 12 (a superconvergent slope, as the 13.4 of the e = 0.3 orbit, would
    fail the first assertion)."""
    entry = pk.integrators()["logh10"]
    slope, measured = observed_order(problem_for(entry), "logh10", _options(entry))
    assert abs(slope - entry.order) <= SLOPE_TOL, (slope, measured)
    assert abs(slope - declared) > SLOPE_TOL, (slope, measured)


def test_logh10_on_the_e03_orbit_is_why_the_family_has_its_own_problem():
    """The reported failure: on the e = 0.3 orbit of the splittings, ending just past the
    pericentre, logh10 shows 13.4 (too few rungs above round-off, made erratic by the ordinary
    last step of the remaining time)."""
    slope, measured = observed_order(_cached("kepler", kepler_with_free_tops), "logh10", {})
    assert abs(slope - 10) > SLOPE_TOL, (slope, measured)


def test_the_kit_checks_the_time_transformed_family_on_its_problem():
    """poissonkit.testing's check_integrator (what plugin authors run) picks the same eccentric
    orbit for the family and passes logh10's order."""
    from poissonkit.testing import check_integrator

    check_integrator("logh10", checks=("order",))
