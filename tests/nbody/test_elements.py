"""Orbital elements ↔ Cartesian states against REBOUND (both directions), and Kepler's equation
against its definition."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.numerics.elements import (
    cartesian,
    eccentric_anomaly,
    elements,
    elements_of,
    mean_to_true,
    states_from_elements,
    true_to_mean,
)

rebound = pytest.importorskip("rebound", reason="REBOUND is the reference for orbital elements "
                              "(pip install rebound)")

G = 1.3
#: (mass, elements, primary index or None): elliptic, near-parabolic retrograde, hyperbolic,
#: and one about a named primary that is not the first body.
ORBITS = [
    (1e-3, dict(a=1.0, e=0.1, inc=0.2, Omega=0.3, omega=0.4, M=0.5), None),
    (2e-3, dict(a=2.5, e=0.95, inc=2.9, Omega=-2.0, omega=4.0, M=0.01), None),
    (1e-5, dict(a=-1.5, e=1.7, inc=0.5, Omega=1.0, omega=2.0, M=3.0), None),
    (1e-4, dict(a=0.3, e=0.3, inc=0.1, Omega=0.2, omega=0.3, f=1.0), 1),
]


def _wrap(d: np.ndarray) -> np.ndarray:
    return (np.asarray(d) + np.pi) % (2 * np.pi) - np.pi


def _reference():
    sim = rebound.Simulation()
    sim.G = G
    sim.add(m=1.0)
    for m, el, primary in ORBITS:
        sim.add(m=m, primary=None if primary is None else sim.particles[primary], **el)
    return sim


def test_states_from_elements_match_rebound_add():
    sim = _reference()
    masses = np.array([p.m for p in sim.particles])
    r, v = states_from_elements(masses, G, [None] + [el for _, el, _ in ORBITS],
                                [None] + [p for _, _, p in ORBITS])
    R = np.array([p.xyz for p in sim.particles])
    V = np.array([p.vxyz for p in sim.particles])
    np.testing.assert_allclose(r, R, rtol=0, atol=1e-14 * np.abs(R).max())
    np.testing.assert_allclose(v, V, rtol=0, atol=1e-14 * np.abs(V).max())


@pytest.mark.parametrize("primary", [None, 0])
def test_elements_match_rebound_orbits(primary):
    sim = _reference()
    masses = np.array([p.m for p in sim.particles])
    R = np.array([p.xyz for p in sim.particles])
    V = np.array([p.vxyz for p in sim.particles])
    el = elements_of(masses, R, V, G, primary)
    ref = sim.orbits(primary=None if primary is None else sim.particles[0])
    assert np.isnan(el.a[0])
    for k, o in enumerate(ref, start=1):
        for name in ("a", "e", "inc"):
            assert getattr(el, name)[k] == pytest.approx(getattr(o, name), rel=1e-13, abs=1e-14)
        for name in ("Omega", "omega", "f", "M"):
            assert abs(_wrap(getattr(el, name)[k] - getattr(o, name))) < 1e-12, (k, name)
        if o.e < 1:
            assert el.P[k] == pytest.approx(o.P, rel=1e-13)


def test_round_trip_over_many_random_orbits():
    rng = np.random.default_rng(1)
    n = 2000
    e = np.concatenate([rng.uniform(0, 0.999999, n // 2), rng.uniform(1.001, 20, n // 2)])
    a = np.where(e < 1, 1.0, -1.0) * rng.uniform(0.1, 10, n)
    inc = rng.uniform(0.01, np.pi - 0.01, n)
    Om, om, M = (rng.uniform(0, 2 * np.pi, n) for _ in range(3))
    M = np.where(e < 1, M, rng.uniform(-20, 20, n))
    r, v = cartesian(2.0, a, e, inc, Om, om, M=M)
    back = elements(2.0, r, v)
    np.testing.assert_allclose(back.a, a, rtol=1e-9)
    np.testing.assert_allclose(back.e, e, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(back.inc, inc, atol=1e-10)
    assert np.abs(_wrap(back.Omega - Om)).max() < 1e-10
    assert np.abs(_wrap(back.M - M)).max() < 1e-7  # near-parabolic M is ill-conditioned


@pytest.mark.parametrize("e", [0.0, 1e-8, 0.5, 0.9, 0.99, 0.999999, 1 - 1e-12, 1.0001, 5.0, 1e4])
def test_kepler_equation_is_solved_for_every_eccentricity(e):
    M = np.concatenate([np.linspace(-50, 50, 2001), [1e-12, -1e-12, np.pi, -np.pi]])
    E = eccentric_anomaly(M, e)
    residual = (E - e * np.sin(E) - M) if e < 1 else (e * np.sinh(E) - E - M)
    assert np.abs(residual).max() <= 1e-14 * np.maximum(1, np.abs(M)).max() * max(1, e)


def test_anomalies_round_trip():
    f = np.linspace(-3.1, 3.1, 101)
    for e in (0.0, 0.3, 0.97):
        assert np.abs(_wrap(mean_to_true(true_to_mean(f, e), e) - f)).max() < 1e-11


def test_typed_errors_for_impossible_orbits():
    with pytest.raises(InputError, match="parabol"):
        cartesian(1.0, 1.0, 1.0)
    with pytest.raises(InputError, match="a must be > 0"):
        cartesian(1.0, -1.0, 0.5)
    with pytest.raises(InputError, match="not both"):
        cartesian(1.0, 1.0, 0.1, M=0.1, f=0.2)
    with pytest.raises(InputError, match="asymptotes"):
        cartesian(1.0, -1.0, 2.0, f=2.5)
    with pytest.raises(InputError, match="primary"):
        elements(1.0, np.zeros(3), np.ones(3))


def test_solution_orbital_elements_stay_those_of_the_kepler_orbit():
    """Two point masses: the relative orbit is a fixed Kepler ellipse (truth: the elements the
    state was built from), whatever the step; ``sol.orbital_elements()`` returns them at every
    saved state, about the heavy body (``"dominant"``) and by name."""
    from poissonkit.numerics import AllPairs, Body, NBodySystem, solve

    G, masses = 6.674e-11, np.array([2.0e30, 1.0e24])
    orbit = dict(a=1.5e11, e=0.3, inc=0.4, Omega=1.1, omega=0.7, M=0.2)
    r, v = states_from_elements(masses, G, [None, orbit], primaries=[None, 0])
    system = NBodySystem([Body("sun", masses[0]), Body("planet", masses[1])],
                         [AllPairs("gravity", {"G": G})])
    y0 = system.pack(r, masses[:, None] * v)  # a system built without scales runs in SI
    sol = solve(system, y0, 3.0e7, method="wisdom_holman", step=2.0e5)
    for primary in ("dominant", "sun", 0):
        el = sol.orbital_elements(primary)
        assert np.all(np.isnan(el.a[:, 0]))
        for name in ("a", "e", "inc", "Omega", "omega"):
            got = getattr(el, name)[:, 1]
            assert np.allclose(got, orbit[name], rtol=1e-9, atol=1e-9), (name, got[:3])
    with pytest.raises(InputError):
        sol.orbital_elements("pluto")
