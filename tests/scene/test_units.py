"""Unit systems of scenes (``[units]``) and bodies given by orbital elements.

Truth used: the IAU/CODATA constants as published (au = 149 597 870 700 m exactly, Julian year
365.25 days, nominal GM_sun = 1.3271244e20 m³/s²), REBOUND's unit tables and its
``sim.add(m=..., a=..., primary=...)`` for the placement of bodies by elements, and hand
conversions for the scene's numbers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from poissonkit import conventions as cv
from poissonkit.errors import InputError, SceneError
from poissonkit.numerics.unitsystem import SI, UnitSystem
from poissonkit.report.run_units import display_unit, scene_step, scene_time_unit, unit_system
from poissonkit.scene.schema import scene_from_mapping

AU = 149_597_870_700.0
DAY = 86_400.0


def _planets(units: dict | None = None, **extra) -> dict:
    """Sun, Jupiter by heliocentric elements, Saturn by Jacobi elements (AU, day, Msun)."""
    data = {
        "name": "planets",
        "units": {"length": "AU", "time": "day", "mass": "Msun"} if units is None else units,
        "bodies": [
            {"name": "sun", "mass": 1.0, "r": [0.0, 0.0, 0.0]},
            {"name": "jupiter", "mass": 9.5e-4, "primary": "sun", "a": 5.2, "e": 0.048,
             "inc": 0.0228, "Omega": 1.75, "omega": 4.78, "M": 0.6},
            {"name": "saturn", "mass": 2.9e-4, "a": 9.55, "e": 0.054, "inc": 0.043,
             "Omega": 1.98, "omega": 5.92, "f": 2.0},
        ],
        "interactions": {"potential": "gravity"},
        "run": {"method": "splitting4", "step": 10.0, "duration": 1000.0},
    }
    data.update(extra)
    return data


# ---------------------------------------------------------------- the unit system

def test_constants_are_the_iau_and_codata_values():
    assert cv.ASTRONOMICAL_UNIT == AU
    assert cv.JULIAN_YEAR == 365.25 * DAY
    assert cv.GM_SUN == 1.3271244e20
    assert cv.SOLAR_MASS * cv.NEWTON_G == pytest.approx(1.3271244e20, rel=1e-15)
    assert cv.PARSEC == pytest.approx(3.0856775814913673e16, rel=1e-15)
    u = UnitSystem("AU", "day", "Msun")
    assert u.G == pytest.approx(1.3271244e20 * DAY ** 2 / AU ** 3, rel=1e-14)
    # within 3e-10 of the classical Gaussian value k² (k = 0.01720209895)
    assert u.G == pytest.approx(0.01720209895 ** 2, rel=1e-9)


def test_the_unit_names_are_reboundss_and_mean_the_same_seconds_and_metres():
    rebound = pytest.importorskip("rebound")
    from rebound import units as ru

    for name in ("m", "cm", "km", "au", "pc"):
        assert UnitSystem(length=name).si_per_unit("length") == pytest.approx(
            ru.lengths_SI[name], rel=1e-9)
    for name in ("s", "hr", "day", "yr", "kyr", "myr", "gyr"):
        assert UnitSystem(time=name).si_per_unit("time") == ru.times_SI[name]
    # REBOUND takes GM from JPL's Horizons and G from CODATA 2014; the GM agree to 1e-9
    for name in ("msun", "mearth", "mjupiter"):
        ours = UnitSystem(mass=name).si_per_unit("mass") * cv.NEWTON_G
        assert ours == pytest.approx(ru.masses_SI[name] * ru.G_SI, rel=1e-6)
    assert rebound is not None


def test_names_ignore_case_and_unknown_names_list_the_known_ones():
    assert UnitSystem("au", "DAY", "msun") == UnitSystem("AU", "day", "Msun")
    with pytest.raises(InputError, match="unknown length unit 'lightyear'; one of m, cm"):
        UnitSystem(length="lightyear")
    with pytest.raises(InputError, match="G alone"):
        UnitSystem("AU", G=1.0)
    with pytest.raises(InputError, match="positive"):
        UnitSystem(G=-1.0)


def test_labels_in_text_and_in_cf_style():
    u = UnitSystem("AU", "yr", "Msun")
    assert u.label("momentum") == "M☉ AU/yr"
    assert u.label("energy") == "M☉ AU²/yr²"
    assert u.label("momentum", text=False) == "Msun AU yr-1"
    assert u.label("G") == "AU³/(M☉ yr²)"
    assert SI.label("energy") == "J" and SI.label("momentum") == "kg m/s"
    assert UnitSystem(G=1.0).label("velocity") == "L/T"


@pytest.mark.parametrize("exponent", range(-12, 21))
def test_display_units_of_lengths_never_use_a_prefix_that_reads_as_a_unit(exponent):
    value = 4.0 * 10.0 ** exponent
    unit = display_unit("length", [value])
    assert not unit.label.endswith(("Tm", "Gm", "Mm", "Pm", "T", "G"))
    shown = value * unit.factor
    assert 1e-3 <= shown < 1e4
    if value >= 1e9:
        assert unit.label.endswith("AU")


def test_display_units_speak_the_scenes_units():
    u = UnitSystem("AU", "yr", "Msun")
    assert display_unit("length", [4.5e12], u).label == "AU"
    assert display_unit("time", [3.15e9], u).label == "yr"
    assert display_unit("time", [3.15e9], u)([cv.JULIAN_YEAR])[0] == pytest.approx(1.0)


# ---------------------------------------------------------------- scenes

def test_an_si_scene_is_untouched():
    data = _planets()
    del data["units"]
    for body in data["bodies"][1:]:
        for k in ("primary", "a", "e", "inc", "Omega", "omega", "M", "f"):
            body.pop(k, None)
    data["bodies"][1]["r"] = [7.8e11, 0.0, 0.0]
    data["bodies"][2]["r"] = [1.4e12, 0.0, 0.0]
    plain = scene_from_mapping(data)
    explicit = scene_from_mapping({**data, "units": {"length": "m", "time": "s"}})
    assert plain == explicit and plain.units.is_si
    assert plain.bodies[1]["r"] == (7.8e11, 0.0, 0.0)  # the very floats given


def test_a_scene_in_au_and_days_is_read_in_those_units_and_held_in_si():
    s = scene_from_mapping(_planets())
    assert s.units == UnitSystem("AU", "day", "Msun")
    assert s.run.step == 10.0 * DAY and s.run.duration == 1000.0 * DAY
    assert s.bodies[0]["mass"] == pytest.approx(cv.SOLAR_MASS, rel=1e-15)
    r_jup = np.array(s.bodies[1]["r"]) / AU
    assert 5.2 * (1 - 0.048) < np.linalg.norm(r_jup) < 5.2 * (1 + 0.048)


def test_bodies_by_elements_are_placed_as_rebound_adds_them():
    rebound = pytest.importorskip("rebound", reason="REBOUND places bodies by elements")
    s = scene_from_mapping(_planets())
    u = s.units
    sim = rebound.Simulation()
    sim.G = u.G
    sim.add(m=1.0)
    sim.add(m=9.5e-4, primary=sim.particles[0], a=5.2, e=0.048, inc=0.0228, Omega=1.75,
            omega=4.78, M=0.6)
    sim.add(m=2.9e-4, a=9.55, e=0.054, inc=0.043, Omega=1.98, omega=5.92, f=2.0)  # Jacobi
    for body, p in zip(s.bodies, sim.particles):
        r = np.array(body["r"]) / AU
        v = np.array(body.get("p", (0.0, 0.0, 0.0))) / body["mass"] / (AU / DAY)
        np.testing.assert_allclose(r, p.xyz, rtol=0, atol=1e-14 * 10)
        np.testing.assert_allclose(v, p.vxyz, rtol=0, atol=1e-16 * 10)


def test_velocity_v_is_momentum_over_mass():
    data = _planets()
    data["bodies"][1] = {"name": "jupiter", "mass": 9.5e-4, "r": [5.0, 0.0, 0.0],
                         "v": [0.0, 0.0075, 0.0]}
    s = scene_from_mapping(data)
    assert s.bodies[1]["p"][1] == pytest.approx(9.5e-4 * cv.SOLAR_MASS * 0.0075 * AU / DAY,
                                                rel=1e-14)


@pytest.mark.parametrize("change, message", [
    (lambda d: d["units"].update(length="lightyear"), "units.length: unknown length unit"),
    (lambda d: d["units"].update(G=1.0), "units"),
    (lambda d: d["units"].update(speed="c"), "units.speed: unknown key"),
    (lambda d: d["bodies"][1].update(r=[1.0, 0.0, 0.0]), r"bodies\[1\].r: a body given by"),
    (lambda d: d["bodies"][1].update(primary="moon"), r"bodies\[1\].primary: 'moon' is not"),
    (lambda d: d["bodies"][1].update(f=0.1), "M or the true anomaly f, not both"),
    (lambda d: d["bodies"][1].pop("a"), r"bodies\[1\].a: missing"),
    (lambda d: d["bodies"][1].update(e=1.0), "parabola"),
    (lambda d: d["bodies"][0].update(a=1.0), "first body has nothing to orbit"),
    (lambda d: d["bodies"][1].update(v=[0.0, 0.0, 0.0], p=[0.0, 0.0, 0.0]), "not both"),
    (lambda d: d["run"].update(step=2000.0),
     "run.step: 2000 day is longer than run.duration 1000 day"),
])
def test_typed_errors_name_the_field(change, message):
    data = _planets()
    change(data)
    with pytest.raises(SceneError, match=message):
        scene_from_mapping(data)


def test_nbody_units_keep_the_numbers_and_give_gravity_that_G():
    data = _planets(units={"G": 1.0})
    s = scene_from_mapping(data)
    assert s.units.is_nbody and s.potential_params == {"G": 1.0}
    assert s.bodies[0]["mass"] == 1.0 and s.run.step == 10.0
    r = np.linalg.norm(s.bodies[1]["r"])
    assert 5.2 * (1 - 0.048) < r < 5.2 * (1 + 0.048)


def test_parameters_in_metres_convert_and_tesla_stays():
    from poissonkit.scene.units import si_params
    from poissonkit.plugin.contributions import Entry, Param

    entry = Entry("demo", "", (Param("spacing", unit="m"), Param("B", unit="T"),
                               Param("G", unit="m^3/(kg s^2)")))
    u = UnitSystem("AU", "day", "Msun")
    out = si_params(entry, {"spacing": 2.0, "B": 0.5, "G": u.G}, u)
    assert out["spacing"] == 2.0 * AU and out["B"] == 0.5
    assert out["G"] == pytest.approx(cv.NEWTON_G, rel=1e-14)


# ---------------------------------------------------------------- what a run writes

def test_run_metadata_and_trajectory_speak_the_scenes_units():
    from poissonkit.report.trajectory import trajectory_dataset
    from poissonkit.scene.build import build_run

    pytest.importorskip("xarray")
    spec = build_run(scene_from_mapping(_planets()))
    u = unit_system(spec)
    assert u == UnitSystem("AU", "day", "Msun")
    assert scene_step(spec) == pytest.approx(10.0, rel=1e-14)
    assert scene_time_unit(spec)[1] == "day"
    t = np.array([0.0, spec.step])
    y = np.stack([spec.y0, spec.y0])
    ds = trajectory_dataset(spec.system, t, y, scales=spec.system.scales,
                            time_unit=spec.metadata["time_unit_s"], units=u)
    assert ds.position.attrs["units"] == "AU" and ds.time.attrs["units"] == "day"
    assert ds.momentum.attrs["units"] == "Msun AU day-1"
    assert ds.time.values[1] == pytest.approx(10.0, rel=1e-14)
    np.testing.assert_allclose(ds.mass.values, [1.0, 9.5e-4, 2.9e-4], rtol=1e-14)
    # velocities from the file: momentum / mass; the elements of t = 0 are the scene's
    assert ds.a.values[0, 1] == pytest.approx(5.2, rel=1e-13)  # about the dominant sun
    assert ds.M.values[0, 1] == pytest.approx(0.6, abs=1e-12)
    assert math.isnan(ds.a.values[0, 0])
    assert ds.attrs["units_length_in_si"] == AU


def test_nbody_units_reach_the_gravity_an_assembly_names():
    from poissonkit.scene.build import build_run

    data = {"units": {"G": 1.0},
            "assembly": {"name": "ring", "params": {"n": 5, "ring_radius": 1.0, "mass": 1.0,
                                                    "potential": "gravity"}},
            "run": {"duration": 1.0, "step": 0.01}}
    spec = build_run(scene_from_mapping(data))
    s = spec.system.scales
    G = spec.system.gravity_constant() * s.length ** 3 / (s.mass * s.time ** 2)
    assert G == pytest.approx(1.0, rel=1e-14)


def test_the_unit_system_is_read_from_a_run_or_its_metadata():
    u = UnitSystem("AU", "yr", "Msun")
    meta = {"units": u.as_dict()}
    assert unit_system(meta) == u and unit_system({}) == SI and unit_system(None) == SI
    assert unit_system({"units": UnitSystem(G=1.0).as_dict()}).is_nbody
