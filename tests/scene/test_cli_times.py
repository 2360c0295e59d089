"""``poissonkit run --step/--duration/--save-dt`` in the scene's time unit, or with a suffix.

Truths used: a Julian year is 365.25 days of 86 400 s (IAU); a bare number on the command line
is in the scene's time unit (seconds for an SI scene, exactly as before: the same float); a
suffix names one of the allow-listed units; nothing else is read (no expression is evaluated).
"""

from __future__ import annotations

import argparse
import re

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.commands.time_options import (CliTime, in_scene_unit, parse_time,
                                              scene_seconds, time_argument)
from poissonkit.errors import InputError
from poissonkit.numerics.integrators.base import progress_bar, progress_in_unit
from poissonkit.numerics.unitsystem import SI, UnitSystem
from poissonkit.report.run_checks import check_times

YEAR, DAY = 365.25 * 86_400.0, 86_400.0
AU_YR = UnitSystem("AU", "yr", "Msun")

SCENE = """
name = "sun_earth"
[units]
length = "AU"
time = "yr"
mass = "Msun"
[[bodies]]
name = "sun"
mass = 1.0
r = [0.0, 0.0, 0.0]
[[bodies]]
name = "earth"
mass = 3.0e-6
a = 1.0
[interactions]
potential = "gravity"
[run]
method = "splitting4"
step = 0.01
duration = 1.0
"""


@pytest.mark.parametrize("text, value, unit", [
    ("100yr", 100.0, "yr"), ("3day", 3.0, "day"), ("0.5s", 0.5, "s"), ("2 hr", 2.0, "hr"),
    ("1e3", 1e3, None), ("1.5e-3 s", 1.5e-3, "s"), (".5", 0.5, None), ("10 years", 10.0, "yr"),
    ("4 D", 4.0, "day"), ("1Myr", 1.0, "Myr")])
def test_times_parse_to_a_number_and_an_allowed_unit(text, value, unit):
    t = parse_time(text)
    assert isinstance(t, float) and float(t) == value and t.unit == unit


@pytest.mark.parametrize("text", ["1+1", "__import__('os')", "3 furlongs", "yr", "", "1e",
                                  "nan", "inf", "2*yr", "1_000"])
def test_anything_else_is_refused(text):
    with pytest.raises(InputError, match="not a time|unknown time unit"):
        parse_time(text)
    with pytest.raises(argparse.ArgumentTypeError):
        time_argument(text)


def test_a_bare_number_is_in_the_scene_time_unit():
    bare = CliTime(0.001)
    assert scene_seconds(bare, SI, "--step") == 0.001  # SI: the number as it was
    assert scene_seconds(CliTime(2.0), AU_YR, "--duration") == 2.0 * YEAR
    assert scene_seconds(parse_time("3day"), AU_YR, "--step") == 3.0 * DAY
    assert scene_seconds(parse_time("3day"), SI, "--step") == 3.0 * DAY
    assert scene_seconds("0.5yr", SI, "--step") == 0.5 * YEAR  # a summary's text
    assert scene_seconds(None, AU_YR, "--step") is None
    assert in_scene_unit(3.0 * DAY, AU_YR) == pytest.approx(3.0 / 365.25, rel=1e-15)
    nbody = UnitSystem(G=1.0)
    assert scene_seconds(CliTime(20.0), nbody, "--duration") == 20.0
    with pytest.raises(InputError, match="N-body units"):
        scene_seconds(parse_time("20yr"), nbody, "--duration")


def test_messages_quote_times_in_the_scene_unit():
    with pytest.raises(InputError, match=r"the step 2 yr is longer than the run's duration "
                                         r"1 yr"):
        check_times(2.0, 1.0, None, YEAR, AU_YR)
    with pytest.raises(InputError, match=r"--save-dt 3 yr is not shorter .* 1 yr"):
        check_times(None, 1.0, 3.0 * YEAR, YEAR, AU_YR)
    with pytest.raises(InputError, match=r"the step 2 s is longer than the run's duration 1 s"):
        check_times(2.0, 1.0, None, 1.0)  # SI: seconds, as before


def test_the_progress_bar_counts_in_the_scene_unit(capsys):
    with progress_in_unit(2.0, "yr"):  # two years per internal unit
        bar = progress_bar(True, 50.0, "wisdom_holman")
        assert bar is not None
        bar.update(25.0)
        line = str(bar)
        bar.close()
    assert "50/100 yr" in line, line


def _spec(tmp_path, *options, text: str = SCENE):
    from poissonkit.commands.run import add_arguments, build_spec

    scene = tmp_path / "sun_earth.toml"
    scene.write_text(text)
    parser = argparse.ArgumentParser()
    add_arguments(parser)
    args = parser.parse_args([str(scene), *options])
    return build_spec(args), args


def _seconds(spec, value):
    from poissonkit.report.run_units import time_unit

    return float(value) * time_unit(spec)


def test_run_options_of_an_au_year_scene_are_in_years(tmp_path):
    spec, args = _spec(tmp_path, "--step", "0.002", "--duration", "2")
    assert _seconds(spec, spec.t_end) == pytest.approx(2.0 * YEAR, rel=1e-14)
    assert _seconds(spec, spec.step) == pytest.approx(0.002 * YEAR, rel=1e-14)
    assert (args.step, args.duration) == (0.002, 2.0)  # what the summary records
    spec, args = _spec(tmp_path, "--step", "1day", "--duration", "730.5day")
    assert _seconds(spec, spec.t_end) == pytest.approx(2.0 * YEAR, rel=1e-14)
    assert _seconds(spec, spec.step) == pytest.approx(DAY, rel=1e-14)
    assert args.duration == pytest.approx(2.0, rel=1e-15) and type(args.duration) is float
    spec, _ = _spec(tmp_path)  # the scene's own run table
    assert _seconds(spec, spec.t_end) == pytest.approx(YEAR, rel=1e-14)


def test_run_options_of_an_si_scene_are_the_seconds_they_were(tmp_path):
    from poissonkit.report.run_units import time_unit

    si = (SCENE.split("[units]")[0] + SCENE.split('mass = "Msun"')[1]).replace(
        "mass = 1.0", "mass = 1.989e30").replace("mass = 3.0e-6", "mass = 5.97e24").replace(
        "a = 1.0", "a = 1.496e11").replace("step = 0.01", "step = 1.0e5").replace(
        "duration = 1.0", "duration = 3.0e7")
    spec, args = _spec(tmp_path, "--step", "86400", "--duration", "1e7", text=si)
    assert "units" not in spec.metadata  # an SI scene
    assert spec.step == 86400.0 / time_unit(spec)  # the old formula, bit for bit
    assert spec.t_end == 1e7 / time_unit(spec)
    assert args.step == 86400.0
    spec2, _ = _spec(tmp_path, "--step", "1day", text=si)
    assert spec2.step == spec.step


def test_run_help_says_times_are_in_the_scene_unit(capsys):
    with pytest.raises(SystemExit):
        cli.main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--step TIME" in text and "--duration TIME" in text and "--save-dt TIME" in text
    assert "in the scene's time unit (seconds for an SI scene) or with a unit" in text


def test_a_bad_time_is_a_usage_error_naming_the_option(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["run", "--duration", "3 furlongs"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "--duration" in err and "unknown time unit 'furlongs'" in err


@pytest.mark.slow  # a Wisdom–Holman run of the outer Solar System, with figures
def test_outer_solar_system_run_in_years_speaks_days_and_au(tmp_path, capsys):
    xr = pytest.importorskip("xarray")
    import json

    out = tmp_path / "out"
    code = cli.main(["run", "outer_solar_system", "--duration", "10yr", "--save-dt", "0.5yr",
                     "--out", str(out)])
    assert code == 0
    err = capsys.readouterr().err.replace("\r", "\n")
    assert re.search(r"\d/3652 day", err), err[-2000:]  # the bar counts the scene's days
    with xr.open_dataset(out / "trajectory.nc") as ds:
        t = ds["time"].values
        assert ds["time"].attrs["units"] == "day"
        assert t[-1] == pytest.approx(10 * 365.25, rel=1e-12)  # the scene's days
        np.testing.assert_allclose(np.diff(t)[:-1], 182.625, rtol=1e-12)  # 0.5 yr apart
    summary = json.loads((out / "summary.json").read_text())
    assert summary["options"]["duration"] == pytest.approx(3652.5, rel=1e-15)  # scene days
    html = (out / "trajectory.html").read_text()
    assert "[AU]" in html and " day" in html
