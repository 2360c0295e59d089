"""``NBodySystem(..., units=...)``: bodies written in AU, years and solar masses from Python.

Truths used: REBOUND (``sim.units = ('AU', 'yr', 'Msun')``) on the same initial state, with
its ``G`` set to ours (the two differ by 3e-10 from their solar-mass constants, checked
separately): its energy, its Jacobi elements (``sim.orbits()``) and its WHFast trajectory;
Kepler's third law in N-body units (``G = 1``: a circular orbit of radius 1 about a unit mass
has period 2π); the default (SI) system is the one it was, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit.errors import InputError
from poissonkit.numerics import AllPairs, Body, NBodySystem, solve
from poissonkit.numerics.elements import system_elements
from poissonkit.numerics.nbody.user_units import as_unit_system
from poissonkit.numerics.unitsystem import SI, UnitSystem

rebound = pytest.importorskip("rebound")

AU_YR = UnitSystem("AU", "yr", "Msun")
#: Sun, Jupiter, Saturn (masses in M☉, elements about the Jacobi centre, angles in radians)
PLANETS = (("jupiter", 9.547919e-4, dict(a=5.2026, e=0.0484, inc=0.0228, Omega=1.7536,
                                          omega=4.7799, M=0.6)),
           ("saturn", 2.858860e-4, dict(a=9.5549, e=0.0555, inc=0.0434, Omega=1.9838,
                                         omega=5.9236, M=2.1)))


def _rebound() -> rebound.Simulation:
    sim = rebound.Simulation()
    sim.units = ("AU", "yr", "Msun")
    sim.G = AU_YR.G  # the same constant: what is compared is the dynamics
    sim.add(m=1.0)
    for _, m, orbit in PLANETS:
        sim.add(m=m, **orbit)
    return sim


def _system(units=("AU", "yr", "Msun")) -> tuple[NBodySystem, np.ndarray]:
    sim = _rebound()
    masses = np.array([p.m for p in sim.particles])
    r = np.array([p.xyz for p in sim.particles])
    v = np.array([p.vxyz for p in sim.particles])
    system = NBodySystem([Body("sun", 1.0)] + [Body(n, m) for n, m, _ in PLANETS],
                         [AllPairs("gravity")], units=units)
    return system, system.pack(r, masses[:, None] * v)


def test_constants_agree_with_rebound_to_their_solar_mass():
    sim = rebound.Simulation()
    sim.units = ("AU", "yr", "Msun")
    assert AU_YR.G == pytest.approx(sim.G, rel=1e-9)
    assert AU_YR.G == pytest.approx(4 * math.pi ** 2, rel=1e-4)  # Kepler: 1 AU, 1 yr, 1 M☉


def test_units_are_taken_as_rebound_names_them():
    assert as_unit_system(("Msun", "AU", "yr")) == AU_YR  # any order, as sim.units
    assert as_unit_system({"length": "AU", "time": "yr", "mass": "Msun"}) == AU_YR
    assert as_unit_system(None) is SI and as_unit_system(AU_YR) is AU_YR
    assert as_unit_system({"G": 1.0}).is_nbody
    with pytest.raises(InputError, match="two time units"):
        as_unit_system(("yr", "day", "Msun"))
    with pytest.raises(InputError, match="unknown unit 'parsnip'"):
        as_unit_system(("AU", "parsnip"))
    with pytest.raises(InputError, match="units must be"):
        as_unit_system(42)  # type: ignore[arg-type]


def test_units_and_scales_are_refused_together():
    from poissonkit.numerics.units import Scales

    with pytest.raises(InputError, match="not both"):
        NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity")],
                    scales=Scales(length=1.0, mass=1.0, time=1.0), units=AU_YR)


def test_gravity_takes_g_of_the_units_unless_given():
    system, _ = _system()
    assert system.gravity_constant() == AU_YR.G and system.units == AU_YR
    given = NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity", {"G": 2.0})],
                        units=AU_YR)
    assert given.gravity_constant() == 2.0
    nbody = NBodySystem([Body("a", 1.0), Body("b", 1.0)], [AllPairs("gravity")],
                        units={"G": 1.0})
    assert nbody.gravity_constant() == 1.0


def test_the_si_default_is_unchanged():
    bodies = [Body("a", 2e30), Body("b", 6e24)]
    plain = NBodySystem(bodies, [AllPairs("gravity")])
    si = NBodySystem(bodies, [AllPairs("gravity")], units=SI)
    assert plain.units is SI and plain.interactions[0].params == {}
    assert plain.interactions == si.interactions  # nothing filled in: the same kernels
    assert plain.gravity_constant() == si.gravity_constant() == 6.6743e-11
    for name in ("mass", "body_slot", "cutoff"):
        np.testing.assert_array_equal(getattr(plain.data, name), getattr(si.data, name))


def test_initial_energy_and_elements_match_rebound():
    sim = _rebound()
    system, y0 = _system()
    assert float(system.energy(y0)) == pytest.approx(sim.energy(), rel=1e-14)
    el = system_elements(system, y0[None], primary=None)  # Jacobi, as sim.orbits()
    for k, o in enumerate(sim.orbits(), start=1):
        for key in ("a", "e", "inc", "Omega", "omega", "M"):
            assert getattr(el, key)[0, k] == pytest.approx(getattr(o, key), rel=1e-12,
                                                           abs=1e-12), (k, key)


@pytest.mark.slow  # a Wisdom–Holman kernel compiles for this system
def test_a_wisdom_holman_run_in_years_matches_whfast():
    sim = _rebound()
    sim.integrator = "whfast"
    sim.dt = 0.05  # years
    system, y0 = _system()
    sol = solve(system, y0, 100.0, method="wisdom_holman", step=0.05)
    sim.integrate(100.0, exact_finish_time=0)
    assert sol.t[-1] == 100.0 and sim.t == pytest.approx(100.0, rel=1e-12)
    r = system.unpack(sol.y[-1:])["r"][0]
    np.testing.assert_allclose(r, np.array([p.xyz for p in sim.particles]), rtol=0, atol=1e-9)
    e0 = float(system.energy(y0))
    assert abs(float(system.energy(sol.y[-1])) - sim.energy()) < 1e-9 * abs(e0)
    el = sol.orbital_elements(primary=None)
    for k, o in enumerate(sim.orbits(), start=1):
        assert el.a[-1, k] == pytest.approx(o.a, rel=1e-9)
        assert el.e[-1, k] == pytest.approx(o.e, rel=1e-7)


@pytest.mark.slow  # a splitting compiles for this system (minutes on a cold cache)
def test_the_solution_speaks_the_units():
    xr = pytest.importorskip("xarray")
    system, y0 = _system()
    sol = solve(system, y0, 2.0, method="splitting4", step=0.01)
    assert sol.t[-1] == 2.0  # years, as written
    ds = sol.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert ds["time"].attrs["units"] == "yr" and float(ds["time"][-1]) == 2.0
    assert (ds.attrs["units_length"], ds.attrs["units_mass"]) == ("AU", "Msun")
    assert ds.attrs["units_G"] == AU_YR.G
    el = sol.orbital_elements()  # about the dominant Sun, in AU
    assert el.a[0, 1] == pytest.approx(5.2, rel=0.01)


@pytest.mark.slow  # the same splitting kernel as above
def test_the_progress_bar_counts_the_units(capsys):
    system, y0 = _system()
    solve(system, y0, 2.0, method="splitting4", step=0.01, progress=True)
    bar = capsys.readouterr().err
    assert "/2.00 yr" in bar and "/2.00 t" not in bar, bar[-300:]  # years, not internal t


@pytest.mark.slow  # the kernels compile for G = 1
def test_kepler_period_in_nbody_units():
    system = NBodySystem([Body("m", 1.0), Body("p", 1e-12)], [AllPairs("gravity")],
                         units={"G": 1.0})
    y0 = system.pack([[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [0, 1e-12, 0]])
    sol = solve(system, y0, 2 * math.pi, method="splitting6", step=2 * math.pi / 2000)
    r = system.unpack(sol.y[-1:])["r"][0]
    np.testing.assert_allclose(r[1], [1.0, 0.0, 0.0], atol=1e-9)  # one full turn


def test_an_overlap_is_reported_in_the_units():
    system = NBodySystem([Body("a", 1.0), Body("b", 1e-3)], [AllPairs("gravity")], units=AU_YR)
    with pytest.raises(InputError, match=r"same position \[1\.0, 0\.0, 0\.0\] \(AU\)") as e:
        system.pack([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]], np.zeros((2, 3)))  # checks it
    assert type(e.value).__name__ == "OverlapError"
