"""The Levitron's base is a solid: the top stops where it touches it, and the run says how it
ended (flip told from fall by the axis); every physical parameter can be found and set."""

from __future__ import annotations

import json

import numpy as np
import pytest
from poissonkit_magnets import levitron as lev

from poissonkit.cli import main as cli_main
from poissonkit.geometry import distance, shape_of
from poissonkit.numerics.events import ball_cylinder_gap


def test_ball_cylinder_gap_agrees_with_the_gap_solver():
    """The closed form against the alternating-projection solver (independent code)."""
    rng = np.random.default_rng(2)
    axis = np.array([0.3, -0.2, 0.93])
    axis /= np.linalg.norm(axis)
    cyl = shape_of([0.1, 0.0, -0.2], axis, 4.0, 0.5)
    for _ in range(200):
        c = rng.uniform(-7, 7, 3)
        ball = shape_of(c, None, 0.3)
        got = ball_cylinder_gap(ball, cyl)
        ref = distance(ball, cyl)
        if ref > 1e-6:
            assert got == pytest.approx(ref, rel=1e-6, abs=1e-6)
        else:
            assert got <= 1e-6


def test_scenes_json_lists_every_levitron_parameter_with_units(capsys):
    assert cli_main(["scenes", "--json"]) == 0
    listed = {r["name"]: r for r in json.loads(capsys.readouterr().out)}
    params = {p["name"]: p for p in listed["levitron"]["parameters"]}
    for name, unit in [("spin_rpm", "rpm"), ("mass", "kg"), ("moment", "A m^2"),
                       ("I1", "kg m^2"), ("I3", "kg m^2"), ("polarization", "T"),
                       ("inner_radius", "m"), ("outer_radius", "m"), ("thickness", "m"),
                       ("g", "m/s^2"), ("offset", "m"), ("axis_tilt", "rad"),
                       ("top_radius", "m")]:
        assert params[name]["unit"] == unit and params[name]["doc"]
    assert params["I1"]["default"] == lev.LevitronParameters().I1
    assert params["contact"]["default"] == "stop"


def test_scenes_text_lists_parameters(capsys):
    assert cli_main(["scenes"]) == 0
    out = capsys.readouterr().out
    assert "--param I3" in out and "kg m^2" in out and "--param spin_ratio" in out


def test_unknown_physical_parameter_is_refused():
    from poissonkit.errors import InputError

    with pytest.raises(InputError, match="unknown parameters"):
        lev.scene_run(spin_rpm=1200.0, radius=0.01)
    with pytest.raises(InputError, match="contact"):
        lev.scene_run(contact="maybe")


@pytest.mark.slow
def test_below_the_window_the_top_touches_the_base_and_its_fate_is_reported(tmp_path, capsys):
    out = tmp_path / "run"
    code = cli_main(["run", "levitron", "--param", "spin_rpm=500", "--out", str(out),
                     "--no-progress", "--no-plot"])
    assert code == 4  # stopped by a contact, not 3 (energy error)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "contact"
    (event,) = summary["events"]
    assert event["kind"] == "contact" and 0.1 < event["time_s"] < 0.3
    assert summary["max_rel_energy_error"] < 1e-6
    # the run reports the fate itself, in the summary and on the terminal
    assert summary["outcome"]["fate"] == "flip"
    assert summary["outcome"]["contact"].startswith("top touched the base at t = 0.178")
    assert "outcome: the top flipped" in capsys.readouterr().out
    # the scene's outcome on the saved trajectory: the axis turned up before the contact
    from poissonkit.numerics.events import EventRecord
    from poissonkit.plugin.registry import scene
    from poissonkit.scene.registered import scene_outcome

    spec = scene("levitron").load(**scene("levitron").resolve_params({"spin_rpm": 500.0}))
    traj = np.load(out / "trajectory.npz")
    outcome = scene_outcome(spec, traj["t"], traj["y"],
                            [EventRecord(**{k: event[k] for k in
                                            ("kind", "step", "time", "value")})])
    assert outcome["fate"] == "flip"
    assert outcome["contact"].startswith("top touched the base at t = 0.178")
    z = traj["y"][-1, 2] * summary["units"]["internal_unit_in_si"]["length"]
    assert z == pytest.approx(lev.LevitronParameters().top_radius, abs=1e-6)


@pytest.mark.slow
def test_sweep_tells_flip_from_fall_by_the_axis():
    from poissonkit_magnets.levitron_sweep import LevitronScene, _fine_fate

    scene = LevitronScene(periods=1.0)
    prep = scene.prepare()
    fates = {rpm: _fine_fate(scene.run(prep, {"spin_rpm": rpm})) for rpm in (500, 700, 1200)}
    assert fates == {500: 1, 700: 2, 1200: 0}  # flip, fall (axis tilted ~58°), bounded
