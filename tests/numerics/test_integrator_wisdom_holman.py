"""The Wisdom–Holman splitting: order, conservation, errors; REBOUND's IAS15 as the truth.

REBOUND (test extra) integrates the same initial states with IAS15 to machine precision, an
independent code and method.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from planet_systems import ias15, two_planets  # type: ignore[import-not-found]

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.integrators.wisdom_holman import (
    kepler_drift,
    saba_coefficients,
    stumpff,
)
from poissonkit.plugin import entries


def test_registry_entries_are_documented_hierarchical_methods():
    found = entries("integrator")
    for name, order in (("wisdom_holman", 2), ("wisdom_holman_corrected", 4)):
        e = found[name]
        assert e.doc and e.family == "hierarchical" and e.order == order
        assert e.factory(**e.resolve_params({})).order == order


def test_saba_coefficients_are_consistent_and_stumpff_matches_trig():
    for n in (1, 2, 3, 4):
        c, d = saba_coefficients(n)
        assert math.isclose(c.sum(), 1.0, rel_tol=1e-15) and math.isclose(d.sum(), 1.0,
                                                                             rel_tol=1e-15)
        np.testing.assert_allclose(c, c[::-1], atol=1e-15)  # symmetric
    for z in (-30.0, -1.0, 1e-3, 0.5, 7.0, 40.0):
        c0, c1, c2, c3 = stumpff(z)
        s = math.sqrt(abs(z))
        if z > 0:
            ref = (math.cos(s), math.sin(s) / s, (1 - math.cos(s)) / z, (s - math.sin(s)) / s**3)
        else:
            ref = (math.cosh(s), math.sinh(s) / s, (math.cosh(s) - 1) / -z,
                   (math.sinh(s) - s) / s**3)
        np.testing.assert_allclose((c0, c1, c2, c3), ref, rtol=1e-12)


def test_kepler_drift_returns_after_a_period_and_handles_hyperbolae():
    x = np.array([[1.0, 0.0, 0.0]])
    v = np.array([[0.0, 1.3, 0.1]])  # eccentric ellipse, mu = 1
    energy = 0.5 * (v**2).sum() - 1.0
    a = -0.5 / energy
    period = 2 * math.pi * a**1.5
    x0, v0 = x.copy(), v.copy()
    for _ in range(10):
        assert kepler_drift(x, v, 0, 1.0, period / 10)
    np.testing.assert_allclose(x, x0, atol=1e-12)
    np.testing.assert_allclose(v, v0, atol=1e-12)
    # hyperbolic: forward then backward is the identity, energy is kept
    xh, vh = np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 2.0, 0.0]])
    assert kepler_drift(xh, vh, 0, 1.0, 50.0)
    assert math.isclose(0.5 * (vh**2).sum() - 1 / np.linalg.norm(xh), 1.0, rel_tol=1e-12)
    assert kepler_drift(xh, vh, 0, 1.0, -50.0)
    np.testing.assert_allclose(xh, [[1.0, 0.0, 0.0]], atol=1e-10)


def test_orders_against_ias15():
    system, y0, m, x, v = two_planets()
    t_end = 20.0
    ref = ias15(m, x, v, t_end)

    def error(method, stages, h):
        sol = solve(system, y0, t_end, method=method, step=h, options={"stages": stages})
        return np.abs(system.unpack(sol.y[-1])["r"] - ref).max()

    e1 = [error("wisdom_holman", 1, h) for h in (0.1, 0.05)]
    assert 1.8 < math.log2(e1[0] / e1[1]) < 2.3, e1
    e4 = [error("wisdom_holman_corrected", 3, h) for h in (0.4, 0.2)]
    assert math.log2(e4[0] / e4[1]) > 3.6, e4
    # and the corrected method is far more accurate at 4x the step of the plain one
    assert e4[1] < 1e-3 * e1[1]


def test_momenta_are_kept_to_roundoff_at_huge_steps_and_energy_is_bounded():
    system, y0, *_ = two_planets()
    P0 = system.linear_momentum(y0)
    L0 = system.angular_momentum(y0)
    E0 = system.energy(y0)
    for method in ("wisdom_holman", "wisdom_holman_corrected"):
        sol = solve(system, y0, 300.0, method=method, step=0.9, save_every=10)
        P = system.linear_momentum(sol.y)
        L = system.angular_momentum(sol.y)
        assert np.abs(P - P0).max() < 1e-15
        assert np.abs(L - L0).max() < 1e-13 * np.linalg.norm(L0)
        E = system.energy(sol.y)
        assert np.abs(E / E0 - 1).max() < 1e-2  # bounded, no blow-up at ~1/7 of a period


def test_outer_solar_system_agrees_with_ias15():
    """Sun and giant planets (REBOUND's outer Solar System example), 200 years."""
    from importlib import util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_vs_rebound.py"
    spec = util.spec_from_file_location("bench_vs_rebound", path)
    bench = util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    m, x, v = bench.outer_solar_system()
    system, y0 = bench.poissonkit_system(m, x, v)
    t_end = 200 * bench.YEAR
    ref = ias15(m, x, v, t_end)
    sol = solve(system, y0, t_end, method="wisdom_holman_corrected", step=0.2 * bench.YEAR,
                save_every=50)
    r = system.unpack(sol.y[-1])["r"]
    assert np.abs(r - ref).max() < 1e-7  # AU, after 200 years
    E = system.energy(sol.y)
    assert np.abs(E / E[0] - 1).max() < 1e-12


def test_unsuitable_systems_are_typed_errors():
    import sympy as sp

    r = sp.Symbol("r", real=True)
    no_gravity = NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs(-1 / r)])
    y = no_gravity.pack([[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [0, 1, 0]])
    with pytest.raises(InputError, match="gravity"):
        solve(no_gravity, y, 1.0, method="wisdom_holman", step=0.1)
    fixed = NBodySystem([Body("a", 1.0, fixed=True, position=(0, 0, 0)), Body("b", 1.0)],
                        [AllPairs("gravity", {"G": 1.0})])
    y = fixed.pack([[1, 0, 0]], [[0, 1, 0]])
    with pytest.raises(InputError, match="fixed"):
        solve(fixed, y, 1.0, method="wisdom_holman", step=0.1)
    with pytest.raises(InputError):
        solve(fixed, y, 1.0, method="wisdom_holman", step=0.1, options={"stages": 5})
