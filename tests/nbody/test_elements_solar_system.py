"""Issue 32's acceptance test: the outer Solar System written by orbital elements in AU, years
and solar masses in a scene file, run with ``wisdom_holman`` and ``table = "10_6_4"``, checked
against REBOUND on the same initial state: the placement by elements (``sim.add``), the energy,
and the state and elements after 20 years against REBOUND's IAS15 (accurate to round-off).

Truth used: REBOUND (``sim.add(primary=...)``, ``sim.orbits()``, ``sim.energy()``, IAS15).
The elements are J2000 mean elements of the giant planets rounded from JPL's "approximate
positions of the planets" (Standish), heliocentric ecliptic; any plausible numbers would do.
"""

from __future__ import annotations

import math

import numpy as np
import pytest


rebound = pytest.importorskip("rebound", reason="REBOUND is the reference (pip install rebound)")
xr = pytest.importorskip("xarray")

pytestmark = pytest.mark.slow  # a Wisdom–Holman kernel for five bodies compiles for minutes

DEG = math.pi / 180
#: name, mass [Msun], a [AU], e, inc, Omega, varpi, mean longitude L [deg]
PLANETS = (
    ("jupiter", 9.547919e-4, 5.2026, 0.04849, 1.303, 100.46, 14.33, 34.40),
    ("saturn", 2.858860e-4, 9.5549, 0.05551, 2.489, 113.67, 93.06, 49.94),
    ("uranus", 4.366244e-5, 19.2184, 0.04630, 0.773, 74.01, 173.01, 313.23),
    ("neptune", 5.151389e-5, 30.1104, 0.00899, 1.770, 131.78, 48.12, 304.88),
)
SUN = 1.00000597682
DURATION = 20.0  # yr
STEP = 0.02  # yr: about 600 steps per Jupiter orbit


def _elements(row):
    _, _, a, e, inc, Om, varpi, L = row
    return dict(a=a, e=e, inc=inc * DEG, Omega=Om * DEG, omega=(varpi - Om) * DEG,
                M=(L - varpi) * DEG)


def _scene_text(options: bool) -> str:
    lines = ['name = "outer_planets_by_elements"',
             "[units]", 'length = "AU"', 'time = "yr"', 'mass = "Msun"',
             "[[bodies]]", 'name = "sun"', f"mass = {SUN!r}", "r = [0.0, 0.0, 0.0]"]
    for row in PLANETS:
        lines += ["[[bodies]]", f'name = "{row[0]}"', f"mass = {row[1]!r}", 'primary = "sun"']
        lines += [f"{k} = {v!r}" for k, v in _elements(row).items()]
    lines += ["[interactions]", 'potential = "gravity"',
              "[run]", 'method = "wisdom_holman"', f"step = {STEP!r}",
              f"duration = {DURATION!r}", "save_dt = 1.0"]
    if options:
        lines += ["[run.options]", 'table = "10_6_4"']
    return "\n".join(lines) + "\n"


def _run(tmp_path) -> tuple[xr.Dataset, float, float, str]:
    """``(dataset, energy at t = 0, max relative energy error, method)`` of the run, through
    through the command line, with ``[run.options] table = "10_6_4"``."""
    import json

    from poissonkit import cli
    from poissonkit.scene.loader import load_scene

    path = tmp_path / "outer.toml"
    path.write_text(_scene_text(options=True))
    assert load_scene(path).run.options == {"table": "10_6_4"}
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--out", str(out), "--no-progress", "--no-plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    ds = xr.open_dataset(out / "trajectory.nc", engine="scipy").load()
    u = _units()
    energy = summary["energy_reference_J"] / u.si_per_unit("energy")
    return ds, energy, summary["max_rel_energy_error"], summary["method"]


def _units():
    from poissonkit.numerics.unitsystem import UnitSystem

    return UnitSystem("AU", "yr", "Msun")


def _reference() -> rebound.Simulation:
    sim = rebound.Simulation()
    sim.G = _units().G
    sim.add(m=SUN)
    for row in PLANETS:
        sim.add(m=row[1], primary=sim.particles[0], **_elements(row))
    return sim


def _wrap(d):
    return (np.asarray(d) + np.pi) % (2 * np.pi) - np.pi


def test_outer_solar_system_by_elements_matches_rebound(tmp_path):
    ds, energy, energy_error, method = _run(tmp_path)
    assert "10_6_4" in method
    assert ds.position.attrs["units"] == "AU" and ds.time.attrs["units"] == "yr"
    sim = _reference()
    # the same initial state: bodies placed by elements as REBOUND places them
    r0 = ds.position.values[0]
    v0 = ds.momentum.values[0] / ds.mass.values[:, None]
    np.testing.assert_allclose(r0, [p.xyz for p in sim.particles], rtol=0, atol=1e-13 * 30)
    np.testing.assert_allclose(v0, [p.vxyz for p in sim.particles], rtol=0, atol=1e-14 * 3)
    assert energy == pytest.approx(sim.energy(), rel=1e-12)
    # the elements of t = 0 in the dataset are the scene's, about the sun
    for k, row in enumerate(PLANETS, start=1):
        el = _elements(row)
        assert ds.a.values[0, k] == pytest.approx(el["a"], rel=1e-12)
        assert abs(_wrap(ds.M.values[0, k] - el["M"])) < 1e-10
    # REBOUND's IAS15 from the very state the run started from, to the end
    ref = rebound.Simulation()
    ref.G = sim.G
    for m, r, v in zip(ds.mass.values, r0, v0):
        ref.add(m=float(m), x=r[0], y=r[1], z=r[2], vx=v[0], vy=v[1], vz=v[2])
    ref.integrator = "ias15"
    e0 = ref.energy()
    ref.integrate(float(ds.time.values[-1]), exact_finish_time=1)
    assert abs(ref.energy() - e0) / abs(e0) < 1e-13
    assert ds.time.values[-1] == pytest.approx(DURATION, rel=1e-12)
    np.testing.assert_allclose(ds.position.values[-1], [p.xyz for p in ref.particles],
                               rtol=0, atol=1e-8)
    orbits = ref.orbits(primary=ref.particles[0])
    for k, o in enumerate(orbits, start=1):
        assert ds.a.values[-1, k] == pytest.approx(o.a, rel=1e-9)
        assert ds.e.values[-1, k] == pytest.approx(o.e, rel=1e-7, abs=1e-10)
        assert ds.inc.values[-1, k] == pytest.approx(o.inc, rel=1e-8)
        for name in ("Omega", "omega", "M"):
            assert abs(_wrap(ds[name].values[-1, k] - getattr(o, name))) < 1e-7, name
    # the energy error of a tenth-order method at 600 steps an orbit: round-off
    assert energy_error < 1e-11
