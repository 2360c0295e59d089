"""Splitting tables of order 8 and 10 (``poissonkit.numerics.integrators.compositions``):
orders against exact and independent truth, invariants with the loop options, resume, events.

* ``splitting10_ss``: Sofroniou & Spaletta's s35odr10 composition of Strang steps;
* ``splitting8_bce``: Blanes, Casas & Escorihuela-Tomàs's 19-stage order-8 RKN splitting.

The registry-wide checks of ``test_numerics_splitting.py`` (order against DOP853, invariants at
huge steps) run over these entries too.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numerics_helpers import orbit_state  # type: ignore[import-not-found]
from oracles import KeplerOrbit  # type: ignore[import-not-found]

from poissonkit.numerics import AllPairs, Body, Collision, NBodySystem, solve
from poissonkit.numerics.checkpoint import Checkpoint
from poissonkit.numerics.integrators.compositions import TABLES
from poissonkit.numerics.integrators.splitting import SCHEMES
from poissonkit.plugin import entries

NAMES = ("splitting8_bce", "splitting10_ss")


def test_tables_are_registered_symmetric_and_consistent():
    found = entries("integrator")
    for name in NAMES:
        e, s = found[name], SCHEMES[name]
        assert e.family == "splitting" and e.order == s.order == TABLES[name].order
        integ = e.factory(**e.resolve_params({}))
        assert integ.order == s.order and integ.name == name
        assert math.isclose(math.fsum(s.a), 1.0, abs_tol=1e-15)
        assert math.isclose(math.fsum(s.b), 1.0, abs_tol=1e-15)
        assert s.a == tuple(reversed(s.a)) and s.b == tuple(reversed(s.b))
    ss, bce = SCHEMES["splitting10_ss"], SCHEMES["splitting8_bce"]
    # 35 Strang stages: 35 kicks between 36 drifts; the derived central weight is the
    # paper's (SUNDIALS prints it to 32 digits)
    assert len(ss.b) == 35 and not ss.nystrom and ss.evaluations == 35
    assert abs(TABLES["splitting10_ss"].weights[17] - 0.049317735759594537917680008339338) < 3e-17
    # 19 kicks between 20 drifts, drift first; central kick and drifts from the sums
    assert len(bce.b) == 19 and bce.nystrom and not bce.fsal and bce.evaluations == 19
    assert bce.a[0] == 0.0505805 and bce.a[1] == 0.149999


def _kepler_errors(name: str, e: float, steps: tuple[float, ...]) -> list[float]:
    """Final errors after one period of a closed-form Kepler orbit (exact truth); compensated
    so that round-off stays below the smallest error."""
    t_end = 2 * math.pi
    system = NBodySystem([Body("sun", 1.0, fixed=True, position=(0, 0, 0)), Body("p", 1.0)],
                         [AllPairs("gravity", {"G": 1.0})])
    orbit = KeplerOrbit(mu=1.0, a=1.0, e=e)  # pericentre on +x at t = 0
    x0, v0 = orbit.state(0.0)
    xr, vr = orbit.state(t_end)
    errs = []
    for h in steps:
        y = solve(system, system.pack(x0[None], v0[None]), t_end, name, step=h,
                  options={"compensated": True}).y[-1]
        parts = system.unpack(y)
        errs.append(max(np.abs(parts["r"][0] - xr).max(), np.abs(parts["p"][0] - vr).max()))
    return errs


#: step pairs of 21 and 42 steps per period, in the asymptotic range of each table; the
#: registry-wide check (test_integrator_order.py) measures the same orders on an exact Kepler
#: orbit in the default run, so this variant (its own compensated system, ~27 s cold) is slow
@pytest.mark.slow
@pytest.mark.parametrize("name,e", [("splitting8_bce", 0.3), ("splitting10_ss", 0.5)])
def test_order_on_a_closed_form_kepler_orbit(name, e):
    errs = _kepler_errors(name, e, (0.3, 0.15))
    p = SCHEMES[name].order
    slope = math.log2(errs[0] / errs[1])
    assert errs[1] > 1e-11, errs  # far above the compensated round-off (~1e-15)
    assert p - 0.3 <= slope <= p + 0.6, (errs, slope)


@pytest.fixture(scope="module")
def pair_truth(dipole_pair):
    """Spinning dipole pair over t = 2: the compensated order-8 and order-10 tables at tiny
    steps (independent discretisations), checked against DOP853 at tol 1e-13."""
    y0, t_end = orbit_state(), 2.0
    runs = {name: solve(dipole_pair, y0, t_end, name, step=h,
                        options={"compensated": True}).y[-1]
            for name, h in (("splitting8_bce", 0.002), ("splitting10_ss", 0.005))}
    dop = solve(dipole_pair, y0, t_end, "dop853", tol=1e-13, options={"atol": 1e-15}).y[-1]
    for y in runs.values():
        assert np.abs(y - dop).max() < 1e-13
    return y0, t_end, runs


@pytest.mark.parametrize("name,truth", [("splitting8_bce", "splitting10_ss"),
                                        ("splitting10_ss", "splitting8_bce")])
def test_order_on_the_spinning_dipole_pair(dipole_pair, pair_truth, name, truth):
    # 5 and 10 steps: the step divides t_end, so halving it is exact
    y0, t_end, runs = pair_truth
    errs = [np.abs(solve(dipole_pair, y0, t_end, name, step=h).y[-1] - runs[truth]).max()
            for h in (0.4, 0.2)]
    p = SCHEMES[name].order
    slope = math.log2(errs[0] / errs[1])
    assert errs[1] > 1e-12, errs  # three decades above the truth's agreement with DOP853
    assert p - 0.35 <= slope <= p + 0.6, (errs, slope)


def test_rkn8_beats_the_order8_composition_at_equal_force_evaluations(dipole_pair, pair_truth):
    y0, t_end, runs = pair_truth
    h = 0.2
    h_old = h * 15 / 19  # splitting8 (s15odr8) costs 15 kicks per step, splitting8_bce 19
    err_new = np.abs(solve(dipole_pair, y0, t_end, "splitting8_bce", step=h).y[-1]
                     - runs["splitting10_ss"]).max()
    err_old = np.abs(solve(dipole_pair, y0, t_end, "splitting8", step=h_old).y[-1]
                     - runs["splitting10_ss"]).max()
    assert err_new * 10 < err_old, (err_new, err_old)


def _encounter(periods: int = 2):
    from poissonkit_magnets import seed000

    return seed000.default_run(periods=periods, tilt=0.01, momentum_factor=0.8)


@pytest.mark.parametrize("opts", [{"compensated": True}, {"adaptive": True},
                                  {"adaptive": True, "compensated": True}],
                         ids=["compensated", "adaptive", "both"])
@pytest.mark.parametrize("name", NAMES)
def test_loop_options_keep_invariants_and_the_trajectory(name, opts):
    spec = _encounter()
    system, y0, t_end = spec.system, np.asarray(spec.y0, dtype=float), float(spec.t_end)
    sol = solve(system, y0, t_end, name, step=0.05, options=opts, save_every=20)
    c0, j0 = system.casimirs(y0), system.angular_momentum(y0)
    dc = np.max(np.abs(system.casimirs(sol.y) - c0))
    dj = np.max(np.linalg.norm(system.angular_momentum(sol.y) - j0, axis=-1)) / np.linalg.norm(j0)
    # round-off only: a random walk over ~40 sub-flows per step, ~100 times smaller with the
    # compensated increments
    tol = 1e-13 if opts.get("compensated") else 1e-12
    assert dc < tol and dj < tol, (dc, dj)
    # the same trajectory as the plain fixed-step loop at a finer step
    plain = solve(system, y0, t_end, name, step=0.025, save_every=10**9)
    scale = np.abs(plain.y[-1]).max()
    assert np.abs(sol.y[-1] - plain.y[-1]).max() < 1e-7 * scale
    assert sol.extra["compensated"] == opts.get("compensated", False)
    assert sol.extra["adaptive"] == opts.get("adaptive", False)


@pytest.mark.parametrize("opts", [{}, {"compensated": True}], ids=["plain", "compensated"])
@pytest.mark.parametrize("name", NAMES)
def test_stop_then_resume_is_bit_identical(tmp_path, name, opts):
    spec = _encounter()
    y0, t_end, h = np.asarray(spec.y0, dtype=float), float(spec.t_end), 0.05
    calls = {"n": 0}

    def stop() -> bool:
        calls["n"] += 1
        return calls["n"] == 3

    ck = Checkpoint(tmp_path / "ck", 17)
    part = solve(spec.system, y0, t_end, name, step=h, options=opts, checkpoint=ck, stop=stop,
                 save_every=5)
    assert part.extra["interrupted"] and part.t[-1] < t_end
    full = solve(spec.system, y0, t_end, name, step=h, options=opts, checkpoint=ck, resume=True,
                 save_every=5)
    ref = solve(spec.system, y0, t_end, name, step=h, options=opts, save_every=5)
    assert "resumed_from" in full.extra
    assert np.array_equal(full.t, ref.t) and full.y.tobytes() == ref.y.tobytes()


@pytest.mark.parametrize("name", NAMES)
def test_collision_event_is_located_where_the_reference_finds_it(dipole_pair, name):
    # head-on fall from rest: the contact time does not depend on the method beyond its error
    y0 = dipole_pair.pack([1.5, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0])
    ref = solve(dipole_pair, y0, 50.0, "splitting4", step=0.001, events=[Collision(0.9)])
    sol = solve(dipole_pair, y0, 50.0, name, step=0.05, events=[Collision(0.9)])
    assert sol.events and sol.events[0].kind == "collision"
    assert abs(sol.events[0].time - ref.events[0].time) < 1e-6
    assert sol.t[-1] < 50.0 and sol.events[0].value < 0.9
