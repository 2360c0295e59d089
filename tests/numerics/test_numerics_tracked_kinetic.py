"""Time-transformed splittings with a tracked kinetic energy (``track_kinetic=True``) and of
order 10 (``TimeTransformedSplitting(order=10)``): order against analytic truth with fast spins, the round-off floor of the
recomputed ``T + p_t`` on the seed's close encounter and its removal (against heyoka at its
tightest tolerance), events, a bit-identical resume and an unchanged default."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from numerics_helpers import orbit_state  # type: ignore[import-not-found]
from oracles import KeplerOrbit, free_top_axis  # type: ignore[import-not-found]

from poissonkit.numerics import Collision, TwoBodySystem, solve
from poissonkit.numerics.checkpoint import Checkpoint
from poissonkit.numerics.integrators.time_transformed import TimeTransformedSplitting

TRACKED = {"track_kinetic": True}


def fast_spinning_kepler():
    """Two tops (1/I = 1) in the Kepler potential -1/r, e = 0.6 from the apocentre, spinning so
    fast that T ≈ 435 |V| at the start (the seed encounter: 445); truth: the exact orbit and the exact
    precession of both axes, over one period and past the pericentre."""
    r = sp.Symbol("r", real=True)
    system = TwoBodySystem(None, None, 1.0, 1.0, -1 / r, reduced_mass=1.0)
    orbit = KeplerOrbit(mu=1.0, a=1.0, e=0.6, mean_anomaly=np.pi)
    m1, m2 = np.array([6.0, -4.0, 18.0]), np.array([-10.0, 8.0, 2.0])
    n1, n2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.6, 0.8])
    t_end = 2 * np.pi + 0.4
    x0, v0 = orbit.state(0.0)
    x, v = orbit.state(t_end)
    truth = np.concatenate([x, v, free_top_axis(n1, m1, 1.0, t_end), m1,
                            free_top_axis(n2, m2, 1.0, t_end), m2])
    return system, system.pack(x0, v0, n1, m1, n2, m2), t_end, truth


@pytest.mark.parametrize("name,order,steps", [("logh8", 8, (0.2, 0.1)),
                                              ("logh10", 10, (0.6, 0.3))])
def test_tracked_kinetic_energy_keeps_the_order_against_the_exact_solution(name, order, steps):
    system, y0, t_end, truth = fast_spinning_kepler()
    errs = []
    for h in steps:
        sol = solve(system, y0, t_end, TimeTransformedSplitting(order, exponent=0.5,
                                                                track_kinetic=True), step=h)
        assert sol.t[-1] == t_end and sol.extra["track_kinetic"]
        errs.append(float(np.max(np.abs(sol.y[-1] - truth))))
    slope = np.log2(errs[0] / errs[1])
    assert errs[1] > 1e-12, errs
    assert order - 0.35 <= slope <= order + 1.2, (errs, slope)


def test_tracked_and_recomputed_agree_to_the_truncation_error():
    # the same method in exact arithmetic: far apart only by round-off
    system, y0, t_end, _ = fast_spinning_kepler()
    a = solve(system, y0, t_end, "logh8", step=0.1, options={"exponent": 0.5})
    b = solve(system, y0, t_end, "logh8", step=0.1, options={"exponent": 0.5, **TRACKED})
    assert a.steps == b.steps
    assert 0 < np.max(np.abs(a.y[-1] - b.y[-1])) < 1e-10


@pytest.fixture(scope="module")
def seed_encounter():
    """The seed's close encounter (pericentre 0.43 l, 10 orbital periods, T/|V| = 445) and the
    final state of heyoka's Taylor integrator at tol 1e-16 (agrees with its quadruple-precision
    run to 1.3e-12, docs/performance.md)."""
    pytest.importorskip("heyoka")
    import importlib.util
    from pathlib import Path

    from poissonkit_magnets import seed000

    path = Path(__file__).parents[2] / "benchmarks" / "bench_seed_orbit.py"
    spec_ = importlib.util.spec_from_file_location("bench_seed_orbit", path)
    bench = importlib.util.module_from_spec(spec_)
    spec_.loader.exec_module(bench)
    import heyoka as hy

    spec = seed000.default_run(periods=10, tilt=0.01, momentum_factor=0.8)
    ode = bench.heyoka_system(seed000.nondimensional_parameters())[0]
    ta = hy.taylor_adaptive(ode, np.array(spec.y0, dtype=float), tol=1e-16)
    ta.propagate_until(float(spec.t_end))
    return spec, np.array(ta.state)


def test_tracking_removes_the_round_off_floor_of_fast_spins(seed_encounter):
    from poissonkit.numerics.workprecision import final_state_error

    spec, ref = seed_encounter

    def error(track: bool, h: float) -> float:
        integ = TimeTransformedSplitting(10, exponent=0.5, track_kinetic=track)
        sol = solve(spec.system, spec.y0, spec.t_end, integ, step=h, save_every=10**9)
        return final_state_error(sol.y[-1], ref)

    # recomputed T + p_t: a clock error that grows as the step shrinks (measured 2.6e-9)
    assert error(False, 0.05) > 5e-10
    # tracked: the truncation error, then the splittings' own round-off (measured 2e-11, 1.4e-11)
    assert error(True, 0.07) < 1e-10
    assert error(True, 0.05) < 1e-10


def test_collision_is_located_with_a_tracked_kinetic_energy(dipole_pair):
    # the located event replaces the state by ordinary steps: T + p_t is resynchronised
    y0 = dipole_pair.pack([1.5, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 3], [1, 0, 0], [0, 2, 0])
    sol = solve(dipole_pair, y0, 50.0, "logh6", step=0.01, events=[Collision(0.9)],
                options={"shift": 10.0, **TRACKED})
    ref = solve(dipole_pair, y0, 50.0, "dop853", tol=1e-10, events=[Collision(0.9)])
    assert sol.events and sol.events[0].kind == "collision"
    assert abs(sol.events[0].time - ref.events[0].time) < 1e-6


def test_interrupted_tracked_run_resumes_bit_identically(tmp_path, dipole_pair):
    calls = {"n": 0}

    def stop() -> bool:
        calls["n"] += 1
        return calls["n"] == 5

    ck = Checkpoint(tmp_path / "ck", 50)
    opts = {"shift": 10.0, **TRACKED}
    kw = dict(step=0.01, save_every=3, checkpoint=ck, options=opts)
    part = solve(dipole_pair, orbit_state(spin=20.0), 4.0, "logh6", stop=stop, **kw)
    assert part.extra["interrupted"] and part.t[-1] < 4.0
    full = solve(dipole_pair, orbit_state(spin=20.0), 4.0, "logh6", resume=True, **kw)
    ref = solve(dipole_pair, orbit_state(spin=20.0), 4.0, "logh6", step=0.01, save_every=3,
                options=opts)
    assert np.array_equal(full.t, ref.t) and np.array_equal(full.y, ref.y)


def test_default_is_untracked_and_names_no_tracking(dipole_pair):
    sol = solve(dipole_pair, orbit_state(), 1.0, "logh4", step=0.01)
    assert "track_kinetic" not in sol.extra


def test_close_approach_choice_against_heyoka(seed_encounter):
    # the planner's choice for a tight error on an attractive approach: order 10, tracked,
    # shift 3 |V(y0)|; on the seed encounter, at the same number of force evaluations, its error
    # is far below the fixed-step splitting8_bce's (measured 1.9e-10 against about 1e-9)
    from poissonkit.numerics.workprecision import final_state_error
    from poissonkit.scene.planner.choice import close_approach_integrator

    spec, ref = seed_encounter
    integ = close_approach_integrator(spec.system, spec.y0, 1e-8)
    assert isinstance(integ, TimeTransformedSplitting)
    assert integ.order == 10 and integ.track_kinetic and integ.exponent == 1.0
    assert integ.shift == pytest.approx(3 * 0.6075056163985896, rel=1e-12)
    sol = solve(spec.system, spec.y0, spec.t_end, integ, step=0.085, save_every=10**9)
    err = final_state_error(sol.y[-1], ref)
    h = spec.t_end * 19 / sol.nfev  # splitting8_bce: 19 evaluations per step
    bce = solve(spec.system, spec.y0, spec.t_end, "splitting8_bce", step=h, save_every=10**9)
    assert bce.nfev == pytest.approx(sol.nfev, rel=1e-3)
    assert err < 1e-9 and err < final_state_error(bce.y[-1], ref) / 2
    assert close_approach_integrator(spec.system, spec.y0, 1e-7) == "splitting8_bce"


def test_close_approach_choice_needs_a_well(dipole_pair):
    from poissonkit.errors import InputError
    from poissonkit.scene.planner.choice import close_approach_integrator

    def state(axis2):
        return dipole_pair.pack([1.5, 0, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], axis2, [0, 0, 0])

    repulsive, attractive = state([-1, 0, 0]), state([1, 0, 0])  # V(y0) = +0.64, -0.55
    with pytest.raises(InputError, match="attractive"):
        TimeTransformedSplitting.for_close_approach(dipole_pair, repulsive)
    assert close_approach_integrator(dipole_pair, repulsive, 1e-10) == "splitting8_bce"
    chosen = close_approach_integrator(dipole_pair, attractive, 1e-10)
    assert isinstance(chosen, TimeTransformedSplitting)
    assert chosen.shift == pytest.approx(3 * 0.5486968449931413, rel=1e-12)


def test_tracked_kinetic_energy_on_the_nbody_path_against_dop853():
    # three dipolar tops (N-body layout: the kick's work from its increments on a zero state);
    # both loops converge to the same DOP853 solution, the tracked one with its invariants
    from numerics_helpers import BOUND, assert_invariants_at_roundoff, unit  # type: ignore[import-not-found]
    from scipy.integrate import solve_ivp

    from poissonkit.numerics import AllPairs, Body, NBodySystem

    system = NBodySystem([Body(f"b{k}", 1.0 + k, 2.0 + k) for k in range(3)], [AllPairs(BOUND)])
    rng = np.random.default_rng(7)
    nu = np.array([unit(v) for v in rng.normal(size=(3, 3))])
    y0 = system.pack(np.array([[0, 0, 0], [1.3, 0.2, 0], [0.1, 1.4, 0.3]]),
                     rng.normal(size=(3, 3)) * 0.3, nu, rng.normal(size=(3, 3)) * 2)
    ref = solve_ivp(system.rhs, (0.0, 1.0), y0, method="DOP853", rtol=1e-13, atol=1e-14).y[:, -1]
    opts = {"shift": 100.0}
    plain = solve(system, y0, 1.0, "logh8", step=0.05, options=opts)
    tracked = solve(system, y0, 1.0, "logh8", step=0.05, options={**opts, **TRACKED})
    e_plain = np.max(np.abs(plain.y[-1] - ref))
    e_tracked = np.max(np.abs(tracked.y[-1] - ref))
    assert e_tracked < 1e-8 and abs(e_tracked - e_plain) < 0.01 * e_plain + 1e-12
    assert_invariants_at_roundoff(system, tracked)
