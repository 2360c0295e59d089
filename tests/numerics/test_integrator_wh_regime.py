"""Wisdom–Holman says when a run leaves its regime, as a status in the result.

Reproduced first on the code before the change: a Jupiter of 34 masses passing 10⁹ m from the
Sun (Saturn outside) under ``wisdom_holman`` with a step of ten days ran "done", with no word,
while its positions were off by 1e-5 of the orbit (energy error 1e-7). Truth: REBOUND's IAS15
(an independent code, to machine precision) on the same initial states. The flagged runs are
those whose error is orders of magnitude above the same method's at a step that resolves the
pericentre, or above the hierarchical error ``ε h²`` of an unperturbed configuration.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from planet_systems import ias15  # type: ignore[import-not-found]

from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.integrators.base import LEFT_REGIME

G = 6.6743e-11
M_SUN, M_JUP, M_SAT = 1.98847e30, 34 * 1.89813e27, 5.683e26
R_JUP, R_SAT = 7.785e11, 1.4335e12  # m
DAY = 86400.0


def _orbit_speed(mu: float, r: float, q: float) -> float:
    """Speed at apocentre ``r`` of an orbit with pericentre ``q`` (vis-viva)."""
    return math.sqrt(mu * (2 / r - 2 / (r + q)))


def sun_jupiter_saturn(q_jup: float = R_JUP, q_sat: float = R_SAT, saturn: bool = True):
    """Both planets start at apocentre (Jupiter at +x, Saturn at −x); barycentric, SI."""
    m = np.array([M_SUN, M_JUP, M_SAT][:3 if saturn else 2])
    x = np.array([[0, 0, 0], [R_JUP, 0, 0], [-R_SAT, 0, 0]], dtype=float)[:len(m)]
    v = np.array([[0, 0, 0], [0, _orbit_speed(G * (M_SUN + M_JUP), R_JUP, q_jup), 0],
                  [0, -_orbit_speed(G * m.sum(), R_SAT, q_sat), 0]])[:len(m)]
    x -= (m[:, None] * x).sum(0) / m.sum()
    v -= (m[:, None] * v).sum(0) / m.sum()
    names = ("sun", "jupiter", "saturn")[:len(m)]
    system = NBodySystem([Body(n, mk) for n, mk in zip(names, m)],
                         [AllPairs("gravity", {"G": G})])
    return system, system.pack(x, m[:, None] * v), m, x, v


def _run(system, y0, m, x, v, t_end, step):
    sol = solve(system, y0, t_end, method="wisdom_holman", step=step)
    err = np.abs(system.unpack(sol.y[-1], si=True)["r"] - ias15(m, x, v, t_end, G)).max() / R_JUP
    return sol, err


def _jupiter_period(q: float) -> float:
    a = (R_JUP + q) / 2
    return 2 * math.pi * math.sqrt(a**3 / (G * (M_SUN + M_JUP)))


def test_unresolved_pericentre_passage_is_reported():
    system, y0, m, x, v = sun_jupiter_saturn(q_jup=1e9)
    t_end = 0.6 * _jupiter_period(1e9)  # past the pericentre passage at half a period
    coarse, err_coarse = _run(system, y0, m, x, v, t_end, 10 * DAY)
    fine, err_fine = _run(system, y0, m, x, v, t_end, 1200.0)
    assert err_fine < 1e-9 and err_coarse > 1e3 * err_fine  # IAS15: the coarse run is off
    assert coarse.extra["status"] == LEFT_REGIME
    assert coarse.extra["regime"][0].startswith("step above the pericentre time scale: jupiter")
    assert "left the wisdom_holman regime" in coarse.message
    assert "left the wisdom_holman regime" in coarse.summary()["message"]
    assert "status" not in fine.extra and fine.message == "done"  # 1200 s resolves it


def test_outer_body_close_to_the_central_body_is_reported():
    t_end = 1.5 * _jupiter_period(R_JUP)
    plain, err_plain = _run(*sun_jupiter_saturn(), t_end, DAY)
    plunging, err_plunging = _run(*sun_jupiter_saturn(q_sat=5e10), t_end, DAY)
    assert "status" not in plain.extra and err_plain < 1e-8
    assert err_plunging > 1e3 * err_plain  # Saturn inside Jupiter's orbit: H_I is not small
    assert plunging.extra["status"] == LEFT_REGIME
    assert any(r.startswith("close approach to the central body: saturn")
               for r in plunging.extra["regime"])


def test_two_bodies_are_exact_and_never_reported():
    system, y0, m, x, v = sun_jupiter_saturn(q_jup=1e9, saturn=False)
    sol, err = _run(system, y0, m, x, v, 0.6 * _jupiter_period(1e9), 10 * DAY)
    assert err < 1e-8  # H_I = 0: the Kepler flow is the solution, whatever the step
    assert "status" not in sol.extra and sol.message == "done"


@pytest.mark.parametrize("save_every", [1, 7])
def test_the_check_leaves_the_trajectory_unchanged(save_every):
    # the same run with the regime test disabled (its result forced empty) is bit-identical
    from poissonkit.numerics.integrators.wisdom_holman import integrator as wh

    system, y0, *_ = sun_jupiter_saturn(q_jup=1e9)
    t_end = 0.6 * _jupiter_period(1e9)
    on = solve(system, y0, t_end, method="wisdom_holman", step=DAY, save_every=save_every)
    original = wh.regime_problems
    wh.regime_problems = lambda *a, **k: []
    try:
        off = solve(system, y0, t_end, method="wisdom_holman", step=DAY, save_every=save_every)
    finally:
        wh.regime_problems = original
    assert on.extra["status"] == LEFT_REGIME and "status" not in off.extra
    np.testing.assert_array_equal(on.y, off.y)
    np.testing.assert_array_equal(on.t, off.t)


def test_sweep_outcome_left_regime_reads_the_status():
    from poissonkit.sweeps.outcomes import reduce_run
    from poissonkit.sweeps.targets import RunRecord

    system, y0, *_ = sun_jupiter_saturn(q_jup=1e9)
    t_end = 0.6 * _jupiter_period(1e9)
    found = []
    for step in (10 * DAY, 1200.0):
        sol = solve(system, y0, t_end, method="wisdom_holman", step=step)
        rec = RunRecord(sol, "bounded", math.nan, np.ones(1), 1.0, 1.0, 1.0)
        found.append(reduce_run(rec, ["left_regime"])["left_regime"])
    assert found == [1, 0]


def test_sample_times_carry_the_pieces_regime_status():
    """With ``t_eval`` the run is made of pieces; a piece that leaves the regime marks the
    whole run (truth: the same coarse run without ``t_eval`` is flagged)."""
    system, y0, m, x, v = sun_jupiter_saturn(q_jup=1e9)
    t_end = 0.6 * _jupiter_period(1e9)
    sampled = solve(system, y0, t_end, method="wisdom_holman", step=10 * DAY,
                    t_eval=np.linspace(0.0, t_end, 7)[1:-1])
    assert sampled.extra["status"] == LEFT_REGIME
    assert any(r.startswith("step above the pericentre time scale: jupiter")
               for r in sampled.extra["regime"])
    assert "left the wisdom_holman regime" in sampled.message
