"""Wisdom–Holman tables of Blanes et al. (2013) and the WHT96 symplectic correctors: orders,
invariants and the gravity-only kick; REBOUND's IAS15 (machine precision) is the truth.

The generalised order ``(r_1, r_2, …)`` of a table is checked where its ``ε h^{r_1}`` term
dominates (planet masses ``ε`` = 1e-6, so ``ε² h^{r_2}`` is far below it) and, at ``ε`` = 1e-3,
where the lower ``ε²``/``ε³`` orders take over.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import kepler_step_mp  # type: ignore[import-not-found]
from planet_systems import ias15, two_planets  # type: ignore[import-not-found]

from poissonkit.errors import InputError
from poissonkit.numerics import solve
from poissonkit.numerics.integrators.wh_tables import (
    CORRECTOR_ORDERS,
    TABLE_ORDERS,
    blanes_coefficients,
    corrector_operators,
)
from poissonkit.numerics.integrators.wisdom_holman import kepler_drift

TABLES = sorted(TABLE_ORDERS)


def slope(system, y0, ref, t_end, options, steps, method="wisdom_holman"):
    """log2 of the error ratios under step halving (errors in the planets' positions)."""
    err = []
    for h in steps:
        sol = solve(system, y0, t_end, method=method, step=h, options=options)
        err.append(np.abs(system.unpack(sol.y[-1])["r"] - ref).max())
    return [math.log2(a / b) for a, b in zip(err, err[1:])], err


@pytest.mark.parametrize("table", TABLES)
def test_tables_are_symmetric_consistent_splittings(table):
    c, d = blanes_coefficients(table)
    assert len(c) == len(d) + 1
    assert math.isclose(c.sum(), 1.0, rel_tol=1e-15) and math.isclose(d.sum(), 1.0,
                                                                         rel_tol=1e-15)
    np.testing.assert_array_equal(c, c[::-1])
    np.testing.assert_array_equal(d, d[::-1])


def test_unknown_tables_and_corrector_orders_are_typed_errors():
    with pytest.raises(InputError, match="table"):
        blanes_coefficients("12_8_4")
    with pytest.raises(InputError, match="corrector order"):
        corrector_operators(9)
    system, y0, *_ = two_planets(1e-3)
    with pytest.raises(InputError):
        solve(system, y0, 1.0, "wisdom_holman", step=0.1, options={"correctors": 11,
                                                                   "stages": 2})
    with pytest.raises(InputError):
        solve(system, y0, 1.0, "wisdom_holman_corrected", step=0.1,
              options={"stages": 2, "correctors": 5})


@pytest.mark.parametrize("order", CORRECTOR_ORDERS)
def test_corrector_operators_are_antisymmetric_in_the_drifts(order):
    ops = corrector_operators(order)
    # Z(∓a_k, ±b) … Z(±a_k, ∓b): a mirrored, b mirrored, both with the sign flipped
    np.testing.assert_array_equal(ops[:, 0], -ops[::-1, 0])
    np.testing.assert_array_equal(ops[:, 1], -ops[::-1, 1])
    assert len(ops) == {3: 2, 5: 4, 7: 6, 11: 10, 17: 16}[order]


@pytest.mark.parametrize("table", TABLES)
def test_leading_epsilon_order_of_each_table(table):
    """ε = 1e-6: the ε h^{r_1} term dominates; halving the step divides the error by
    ≈ 2^{r_1} (r_1 = 8 or 10)."""
    system, y0, m, x, v = two_planets(1e-6)
    t_end = 24.0
    ref = ias15(m, x, v, t_end)
    r1 = TABLE_ORDERS[table][0]
    (p,), err = slope(system, y0, ref, t_end, {"table": table}, (1.2, 0.6))
    assert err[0] > 1e-11  # far above round-off (which could only flatten the slope)
    assert p > r1 - 1.2, (p, err)


@pytest.mark.parametrize("table", TABLES)
def test_table_order_at_larger_masses(table):
    """ε = 1e-3: the ε²/ε³ terms of order ≥ 4 take over; still ≥ fourth order."""
    system, y0, m, x, v = two_planets(1e-3)
    t_end = 24.0
    ref = ias15(m, x, v, t_end)
    (p,), err = slope(system, y0, ref, t_end, {"table": table}, (0.6, 0.3))
    assert p > 3.6, (p, err)


@pytest.mark.parametrize("order", [3, 5])
def test_symplectic_corrector_raises_the_epsilon_order(order):
    """ε = 1e-6: processed Wisdom–Holman; the plain map's ε h² term is gone and the error falls
    at least as h^order (higher orders hit round-off at such small ε)."""
    system, y0, m, x, v = two_planets(1e-6)
    t_end = 24.0
    ref = ias15(m, x, v, t_end)
    (p0,), e0 = slope(system, y0, ref, t_end, {}, (0.4, 0.2))
    (p,), err = slope(system, y0, ref, t_end, {"correctors": order}, (0.4, 0.2))
    assert 1.8 < p0 < 2.3, e0
    assert p > order - 0.5, (p, err)
    assert err[-1] < 1e-2 * e0[-1]


def test_modified_kernel_with_correctors_removes_the_eps_squared_term():
    """ε = 1e-4: with the corrector of order 11 the plain map is limited by ε² h²; the kernel
    with the corrector kick (half of SABAC_1's) removes it: error ∝ h⁴ or faster, far below."""
    system, y0, m, x, v = two_planets(1e-4)
    t_end = 24.0
    ref = ias15(m, x, v, t_end)
    (p_plain,), e_plain = slope(system, y0, ref, t_end, {"correctors": 11}, (0.4, 0.2))
    (p_mod,), e_mod = slope(system, y0, ref, t_end, {"stages": 1, "correctors": 11},
                            (0.4, 0.2), method="wisdom_holman_corrected")
    assert 1.7 < p_plain < 2.5, e_plain
    assert p_mod > 3.5, e_mod
    assert e_mod[-1] < 0.05 * e_plain[-1]


@pytest.mark.parametrize("options,method", [({"table": "10_6_4"}, "wisdom_holman"),
                                            ({"table": "h8_4_4"}, "wisdom_holman"),
                                            ({"correctors": 11}, "wisdom_holman"),
                                            ({"stages": 1, "correctors": 17},
                                             "wisdom_holman_corrected")])
def test_momenta_to_roundoff_and_bounded_energy(options, method):
    system, y0, *_ = two_planets(1e-2)
    P0, L0, E0 = system.linear_momentum(y0), system.angular_momentum(y0), system.energy(y0)
    sol = solve(system, y0, 300.0, method, step=0.5, save_every=10, options=options)
    assert np.abs(system.linear_momentum(sol.y) - P0).max() < 1e-15
    assert np.abs(system.angular_momentum(sol.y) - L0).max() < 1e-13 * np.linalg.norm(L0)
    E = system.energy(sol.y)
    assert np.abs(E / E0 - 1).max() < 1e-3


@pytest.mark.slow  # compiles the general-kernel loop and a cutoff force kernel (~1-2 min cold)
def test_gravity_only_kick_matches_the_general_force_kernel():
    """A (never reached) cutoff sends the same system through the general pair kernel."""
    fast, y0, *_ = two_planets(1e-2)
    general, y1, *_ = two_planets(1e-2, cutoff=1e6)
    for opts in ({"stages": 3}, {"table": "10_6_4"}):
        a = solve(fast, y0, 20.0, "wisdom_holman", step=0.1, options=opts).y[-1]
        b = solve(general, y1, 20.0, "wisdom_holman", step=0.1, options=opts).y[-1]
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_kepler_drift_is_accurate_to_roundoff_against_a_40_digit_solution():
    rng = np.random.default_rng(5)
    worst = 0.0
    for k in range(30):
        e = (0.05, 0.5, 0.9)[k % 3]
        x = np.array([[1.0, 0.0, 0.0]])
        v = np.array([[0.0, math.sqrt(1 + e), 0.1]])
        kepler_drift(x, v, 0, 1.0, rng.uniform(0, 20))  # a random point of the orbit
        dt = rng.uniform(0.01, 1.0)
        xr, vr = kepler_step_mp(x[0], v[0], 1.0, dt)  # 40 digits
        kepler_drift(x, v, 0, 1.0, dt)
        worst = max(worst, np.abs(x[0] - xr).max() / np.abs(xr).max(),
                    np.abs(v[0] - vr).max() / np.abs(vr).max())
    assert worst < 2e-15


SAME_MAPS = [
    ("saba10_6_4", {}, "wisdom_holman", {"table": "10_6_4"}),
    ("saba8_6_4", {}, "wisdom_holman", {"table": "8_6_4"}),
    ("saba10_4", {}, "wisdom_holman", {"table": "10_4"}),
    ("sabah_8_4_4", {}, "wisdom_holman", {"table": "h8_4_4"}),
    ("sabah_8_6_4", {}, "wisdom_holman", {"table": "h8_6_4"}),
    ("sabah_10_6_4", {}, "wisdom_holman", {"table": "h10_6_4"}),
    ("saba4", {}, "wisdom_holman", {"stages": 4}),
    ("sabacm_2", {}, "wisdom_holman_corrected", {"stages": 2}),
    ("sabacm_4", {}, "wisdom_holman_corrected", {"stages": 4}),
    ("whfast", {"corrector": 3}, "wisdom_holman", {"correctors": 3}),
    ("whfast", {"corrector": 11}, "wisdom_holman", {"correctors": 11}),
    ("whfast", {"corrector": 17, "kernel": "modifiedkick"}, "wisdom_holman_corrected",
     {"stages": 1, "correctors": 17}),
]


def _outer_solar_system():
    from importlib import util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_vs_rebound.py"
    spec = util.spec_from_file_location("bench_vs_rebound", path)
    bench = util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    return bench


@pytest.mark.parametrize("name,settings,method,options", SAME_MAPS)
def test_same_map_as_rebound(name, settings, method, options):
    """The same method in REBOUND (an independent implementation of the published tables)
    gives the same state after 100 steps of 0.75 yr on the outer Solar System, to round-off;
    a different table of similar accuracy is 100 × farther off (so the comparison can fail)."""
    bench = _outer_solar_system()
    m, x, v = bench.outer_solar_system()
    system, y0 = bench.poissonkit_system(m, x, v)
    h = 0.75 * bench.YEAR
    sim = bench.rebound_sim(m, x, v, name, {"safe_mode": 0} | settings, h)
    sim.integrate(99.5 * h, exact_finish_time=0)  # exactly 100 steps
    assert sim.t == pytest.approx(100 * h, rel=1e-12)
    ref = np.array([[p.x, p.y, p.z] for p in sim.particles])
    sol = solve(system, y0, 100 * h, method, step=h, options=options)
    assert np.abs(system.unpack(sol.y[-1])["r"] - ref).max() < 2e-11  # AU, positions ~5-30
    if "table" in options:
        other = {"table": "h8_4_4" if options["table"] != "h8_4_4" else "10_4"}
        sol = solve(system, y0, 100 * h, "wisdom_holman", step=h, options=other)
        # another accurate table already differs by 100 × the tolerance
        assert np.abs(system.unpack(sol.y[-1])["r"] - ref).max() > 2e-9
