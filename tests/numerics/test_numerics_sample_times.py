"""``solve(t_eval=...)``: states at requested times for every kind of method.

Independent truth: the two-body Kepler problem, whose relative position at any time follows from
Kepler's equation (the shared oracle ``tests/oracles.py``, not poissonkit).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import KeplerOrbit  # type: ignore[import-not-found]

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.sample_times import check_sample_times, uniform_times

MU = 1.001  # G (m_star + m_planet), G = 1
A, E = 1.0, 0.3
PERIOD = 2 * math.pi * math.sqrt(A**3 / MU)


def kepler_relative_position(t: np.ndarray) -> np.ndarray:
    """Relative position at times ``t`` of the orbit starting at pericentre on x."""
    return KeplerOrbit(mu=MU, a=A, e=E).state(np.asarray(t, dtype=float))[0]


@pytest.fixture(scope="module")
def kepler():
    m = np.array([1.0, 1e-3])
    v_peri = math.sqrt(MU * (1 + E) / (A * (1 - E)))
    rel_x = np.array([A * (1 - E), 0.0, 0.0])
    rel_v = np.array([0.0, v_peri, 0.0])
    x = np.array([-m[1] / m.sum() * rel_x, m[0] / m.sum() * rel_x])
    v = np.array([-m[1] / m.sum() * rel_v, m[0] / m.sum() * rel_v])
    system = NBodySystem([Body("star", m[0]), Body("planet", m[1])],
                         [AllPairs("gravity", {"G": 1.0})])
    return system, system.pack(x, m[:, None] * v)


def relative(system, y):
    r = system.unpack(np.atleast_2d(y))["r"]
    return r[:, 1] - r[:, 0]


@pytest.mark.parametrize("method,kw,err", [
    ("splitting6", {"step": PERIOD / 400}, 1e-8),      # fixed step
    ("midpoint", {"step": PERIOD / 4000}, 1e-4),       # fixed step, implicit
    ("dop853", {"tol": 1e-11}, 1e-8),                  # adaptive (scipy)
    ("wisdom_holman", {"step": PERIOD / 200}, 1e-4),   # fixed step, Kepler drift
    ("logh4", {"step": 0.02}, 1e-7),                   # time-transformed (fictitious step)
    ("splitting4", {"step": PERIOD / 200, "options": {"adaptive": True}}, 1e-5),
])
def test_states_at_requested_times_match_kepler(kepler, method, kw, err):
    system, y0 = kepler
    t_end = 1.3 * PERIOD
    wanted = np.sort(np.random.default_rng(1).uniform(0, t_end, 7))
    sol = solve(system, y0, t_end, method=method, t_eval=wanted, **kw)
    # the start, exactly the requested times, and the end
    assert np.array_equal(sol.t, np.concatenate(([0.0], wanted, [t_end])))
    got = relative(system, sol.y)
    assert np.max(np.abs(got - kepler_relative_position(sol.t))) < err


def test_fixed_step_samples_are_the_plain_runs_states(kepler):
    system, y0 = kepler
    h = PERIOD / 300
    plain = solve(system, y0, 30 * h * 10, method="splitting4", step=h, save_every=30)
    sampled = solve(system, y0, 30 * h * 10, method="splitting4", step=h,
                    t_eval=uniform_times(0.0, 30 * h * 10, 30 * h))
    assert sampled.steps == plain.steps == 300
    np.testing.assert_allclose(sampled.t, plain.t, rtol=1e-14, atol=0)
    np.testing.assert_allclose(sampled.y, plain.y, rtol=0, atol=1e-12)


def test_a_sample_between_steps_is_reached_by_exact_stepping(kepler):
    system, y0 = kepler
    h = PERIOD / 100
    sol = solve(system, y0, 10 * h, method="splitting6", step=h, t_eval=[2.5 * h])
    assert sol.t[1] == 2.5 * h
    assert sol.steps == 3 + 8  # ceil(2.5) steps to the sample, ceil(7.5) after it
    assert np.max(np.abs(relative(system, sol.y[1]) - kepler_relative_position([2.5 * h]))) \
        < 1e-9


def test_bad_sample_times_are_typed_errors(kepler):
    system, y0 = kepler
    with pytest.raises(InputError, match="strictly increasing"):
        solve(system, y0, 1.0, step=0.1, t_eval=[0.5, 0.2])
    with pytest.raises(InputError, match=r"\[t0, t_end\]"):
        solve(system, y0, 1.0, step=0.1, t_eval=[0.5, 2.0])
    with pytest.raises(InputError, match="NaN"):
        solve(system, y0, 1.0, step=0.1, t_eval=[0.5, float("nan")])
    with pytest.raises(InputError, match="not both"):
        solve(system, y0, 1.0, step=0.1, t_eval=[0.5], save_every=3)
    with pytest.raises(InputError, match="positive"):
        uniform_times(0.0, 1.0, 0.0)
    with pytest.raises(InputError, match="at most"):
        uniform_times(0.0, 1.0, 1e-9)


def test_end_points_are_not_duplicated():
    inner = check_sample_times([0.0, 0.5, 1.0 - 1e-13], 0.0, 1.0)
    assert inner.tolist() == [0.5]
    assert uniform_times(0.0, 1.0, 0.25).tolist() == [0.25, 0.5, 0.75]
