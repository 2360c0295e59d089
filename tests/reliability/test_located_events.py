"""Events located inside the step, against independent answers: the head-on collision time of
two coaxial dipoles released at rest (mpmath quadrature) and a grazing encounter that a
step-end check misses (scipy DOP853 at tight tolerance with its own root finder)."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from reliability_helpers import MU, dipole_pair  # type: ignore[import-not-found]
from scipy.integrate import solve_ivp

from poissonkit.errors import CollisionError, InputError
from poissonkit.numerics import solve
from poissonkit.numerics.events import ClosestApproach, Collision, Escape

D0, RC = 1.5, 0.6


@pytest.fixture(scope="module")
def pair():
    return dipole_pair()


def collision_time(d: float, rc: float) -> float:
    """Coaxial aligned dipoles: U = -2/r^3, so mu r'^2/2 = 2 (1/r^3 - 1/d^3) from rest;
    t(rc) = int_rc^d dr / sqrt((4/mu)(1/r^3 - 1/d^3)) (tanh-sinh copes with the 1/sqrt end)."""
    mpmath.mp.dps = 30
    d, rc = mpmath.mpf(d), mpmath.mpf(rc)
    return float(mpmath.quad(lambda r: 1 / mpmath.sqrt(4 / mpmath.mpf(MU) * (r**-3 - d**-3)),
                             [rc, d]))


def head_on(pair):
    return pair.pack([D0, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0])


@pytest.mark.parametrize("method, kw, bound", [
    ("splitting6", {"step": 0.01}, 1e-9),      # integrator error ~1e-11 at this step
    ("splitting4", {"step": 0.001}, 1e-9),
    ("midpoint", {"step": 0.0005}, 1e-6),      # order 2: the trajectory's own error dominates
    ("dop853", {"tol": 1e-12}, 1e-9),
])
def test_head_on_collision_time_matches_quadrature(pair, method, kw, bound):
    exact = collision_time(D0, RC)
    sol = solve(pair, head_on(pair), 50.0, method, events=[Collision(RC)], **kw)
    (ev,) = sol.events
    assert ev.kind == "collision"
    # the located bracket is tight (default: 1e-9 of the step) ...
    assert ev.time_error <= 1e-9 * kw.get("step", 1.0) + 1e-15
    # ... and the located time is the true one to within the method's error
    assert abs(ev.time - exact) < bound
    assert ev.value == pytest.approx(RC, abs=1e-8)
    assert sol.t[-1] == ev.time  # stopped at the event, the last state is the event's
    assert np.linalg.norm(sol.y[-1][:3]) == pytest.approx(RC, abs=1e-8)  # layout: r first
    # the step-end check alone would have been late by up to a step
    if "step" in kw:
        assert ev.time < sol.t[-2] + kw["step"]


def test_time_tol_is_honoured(pair):
    sol = solve(pair, head_on(pair), 50.0, "splitting6", step=0.01,
                events=[Collision(RC, time_tol=1e-4)])
    assert 0 < sol.events[0].time_error <= 1e-4
    assert abs(sol.events[0].time - collision_time(D0, RC)) <= 1e-4 + 1e-9


# ------------------------------------------------------------------ grazing encounter
B, X0, V_REL, WATCH = 3.0, 25.0, 5.0, 4.0


def fly_by(pair):
    """Relative position (X0, B, 0) moving at -V_REL along x: closest approach ~B near
    t = X0/V_REL = 5, in the middle of the step [4, 6] of a step-2 run."""
    return pair.pack([X0, B, 0], [-MU * V_REL, 0, 0], [0, 0, 1], [0, 0, 0], [0, 0, 1], [0, 0, 0])


def _reference_encounter(pair):
    """DOP853 at rtol 1e-13 on the same equations, scipy's own event location: the time and
    distance of closest approach (r.p = 0) and the first time |r| = WATCH (if any)."""
    y0 = fly_by(pair)

    def radial(t, y):
        return y[0] * y[3] + y[1] * y[4] + y[2] * y[5]

    def inside(t, y):
        return np.linalg.norm(y[:3]) - WATCH

    res = solve_ivp(lambda t, y: pair.rhs(t, y), (0, 10), y0, method="DOP853", rtol=1e-13,
                    atol=1e-13, events=[radial, inside])
    t_min = res.t_events[0][0]
    d_min = float(np.linalg.norm(res.y_events[0][0][:3]))
    t_in = res.t_events[1][0] if len(res.t_events[1]) else None
    return t_min, d_min, t_in


def test_grazing_encounter_missed_by_step_ends_is_located(pair):
    t_min, d_min, t_in = _reference_encounter(pair)
    assert d_min < WATCH and t_in is not None
    # every step end stays outside the threshold: a step-end check sees nothing
    plain = solve(pair, fly_by(pair), 10.0, "splitting6", step=2.0)
    assert np.all(np.linalg.norm(plain.y[:, :3], axis=1) > WATCH)
    sol = solve(pair, fly_by(pair), 10.0, "splitting6", step=2.0, events=[Collision(WATCH)])
    (ev,) = sol.events
    assert ev.kind == "collision" and ev.time_error <= 2e-9
    assert ev.time == pytest.approx(t_in, abs=1e-4)  # weak interaction: splitting6 is accurate
    assert ev.value == pytest.approx(WATCH, abs=1e-6)


def test_closest_approach_is_recorded_and_the_run_goes_on(pair):
    t_min, d_min, _ = _reference_encounter(pair)
    sol = solve(pair, fly_by(pair), 10.0, "splitting6", step=2.0,
                events=[ClosestApproach(WATCH)])
    (ev,) = sol.events
    assert ev.kind == "closest_approach"
    assert ev.time == pytest.approx(t_min, abs=1e-4)
    assert ev.value == pytest.approx(d_min, rel=1e-4)  # a step of 2: the method's own error
    assert sol.t[-1] == 10.0  # not terminal


def test_escape_is_located(pair):
    y0 = fly_by(pair)

    def radius(y):
        return float(pair.kernels.max_radius(np.ascontiguousarray(y), pair.data))

    limit = 1.05 * radius(y0)  # reached on the way out, after the encounter

    def out(t, y):
        return radius(y) - limit

    out.terminal = True
    ref = solve_ivp(lambda t, y: pair.rhs(t, y), (0, 20), y0, method="DOP853", rtol=1e-13,
                    atol=1e-13, events=[out])
    sol = solve(pair, y0, 20.0, "splitting6", step=0.5, events=[Escape(limit)])
    (ev,) = sol.events
    assert ev.kind == "escape" and ev.time == pytest.approx(ref.t_events[0][0], abs=1e-5)
    assert ev.value == pytest.approx(limit, rel=1e-9)


def test_event_as_error_and_bad_events(pair):
    with pytest.raises(CollisionError, match="t = "):
        solve(pair, head_on(pair), 50.0, "splitting4", step=0.01,
              events=[Collision(RC, error=True)])
    for bad in (lambda: Collision(-1.0), lambda: Collision(float("nan")),
                lambda: Escape(0.0), lambda: Collision(1.0, time_tol=0.0),
                lambda: solve(pair, head_on(pair), 1.0, "splitting4", step=0.1, events=["x"]),
                lambda: solve(pair, head_on(pair), 1.0, "dop853", events=[ClosestApproach(1)])):
        with pytest.raises(InputError):
            bad()


def test_seed_magnets_touching_on_an_unstable_orbit_are_located():
    """The seed's two-body form with the run command's contact event: on an unstable tilted
    orbit the 20 mm cylinders touch; just before the located time they are apart, at it they
    touch (geometric distance of the two cylinders, computed here from the states)."""
    from poissonkit_magnets import seed000

    from poissonkit.commands.run import _with_contact
    from poissonkit.scene.geometry import distance, shape_of

    spec = _with_contact(seed000.default_run(periods=0.1, spin_ratio=2.0, tilt=0.3))
    (contact,) = spec.events
    sol = solve(spec.system, spec.y0, spec.t_end, spec.method, step=spec.step,
                events=spec.events)
    (ev,) = sol.events
    assert ev.kind == "contact" and ev.time < spec.t_end

    def gap(y):
        u = spec.system.unpack(y)
        a, h = contact.shapes[0].radius, contact.shapes[0].half_length
        return distance(shape_of(np.zeros(3), u["nu1"], a, h), shape_of(u["r"], u["nu2"], a, h),
                        rtol=1e-14)

    # the last saved step end before the contact: apart; the located state: touching
    assert gap(sol.y[-2]) > 1e-3 * contact.shapes[0].radius
    assert gap(sol.y[-1]) < 1e-6 * contact.shapes[0].radius
    assert ev.time_error <= 1e-9 * spec.step
