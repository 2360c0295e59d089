"""Edge cases of scene runs: every body fixed, ``run.save_every`` honoured, the work estimate
and the ``--max-steps`` / ``run.max_steps`` guard.

Truth used: a run of ``duration / step = n`` fixed steps saved every ``k`` steps keeps
``ceil(n / k) + 1`` rows (t = 0 and the last step always); bodies that are all fixed do not
move, so every saved state equals the first and every drift is exactly 0.
"""

from __future__ import annotations

import json
import warnings
from dataclasses import replace

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.errors import InputError, SceneError
from poissonkit.numerics.workload import (RunPlan, StepLimitError, WorkloadWarning, plan_run,
                                          planned_steps)
from poissonkit.scene import build_run, load_scene
from poissonkit.scene.loader import loads_scene, shipped_scene

TWO = shipped_scene("two_magnets").read_text()  # 0.05 s at 1e-4 s: 500 steps


def _scene(tmp_path, text: str, name: str = "s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _run(tmp_path, scene, *extra: str) -> tuple[int, dict | None, np.lib.npyio.NpzFile | None]:
    out = tmp_path / "out"
    code = cli.main(["run", str(scene), "--out", str(out), "--no-progress", "--no-plots",
                     "--overwrite", *extra])
    summary = json.loads((out / "summary.json").read_text()) \
        if (out / "summary.json").exists() else None
    npz = np.load(out / "trajectory.npz") if (out / "trajectory.npz").exists() else None
    return code, summary, npz


def test_scene_save_every_is_honoured(tmp_path):
    scene = _scene(tmp_path, TWO.replace("duration = 0.05", "duration = 0.05\nsave_every = 10"))
    code, summary, npz = _run(tmp_path, scene)
    assert code == 0 and summary["steps"] == 500
    assert npz["t"].shape == (51,)  # was 501: the scene's value was ignored
    assert summary["options"]["save_every"] == 10 if "options" in summary else True
    code, _, npz = _run(tmp_path, scene, "--save-every", "1")  # the flag wins
    assert code == 0 and npz["t"].shape == (501,)


def test_scene_save_every_must_be_positive():
    with pytest.raises(SceneError, match=r"run\.save_every"):
        loads_scene(TWO.replace("duration = 0.05", "duration = 0.05\nsave_every = 0"))


def test_all_bodies_fixed_gives_a_summary(tmp_path):
    text = TWO.replace('nu = [0.0, 0.0, 1.0]', 'nu = [0.0, 0.0, 1.0]\nfixed = true') \
        .replace('nu = [0.0, 0.0, -1.0]', 'nu = [0.0, 0.0, -1.0]\nfixed = true')
    text = "\n".join(line for line in text.splitlines()
                     if not line.startswith(("p = ", "m = ")))
    code, summary, npz = _run(tmp_path, _scene(tmp_path, text))
    assert code == 0 and summary["status"] == "done"
    assert summary["max_abs_energy_error"] == 0.0
    assert np.all(npz["y"] == npz["y"][:1])


#: Two point masses, both fixed: a scene with an empty state.
STILL = """name = "still"
[[bodies]]
name = "a"
mass = 1.0
r = [0, 0, 0]
fixed = true
[[bodies]]
name = "b"
mass = 2.0
r = [1, 0, 0]
fixed = true
[interactions]
potential = "gravity"
[run]
step = 0.01
duration = {duration}
"""


def test_all_fixed_point_masses_have_an_empty_state(tmp_path):
    text = STILL.format(duration=0.5)
    spec = build_run(loads_scene(text))
    assert spec.system.dim == 0
    code, summary, npz = _run(tmp_path, _scene(tmp_path, text))
    assert code == 0 and summary["status"] == "done" and summary["steps"] == 50
    assert npz["y"].shape == (51, 0)


def test_planned_steps_match_the_integrator():
    spec = build_run(loads_scene(TWO))
    assert planned_steps(spec) == 500
    assert planned_steps(replace(spec, step=None, tol=1e-9)) is None


def test_max_steps_flag_refuses_before_the_run(tmp_path, capsys):
    scene = _scene(tmp_path, TWO)
    code, summary, npz = _run(tmp_path, scene, "--max-steps", "499")
    assert code == 1 and summary is None and npz is None
    err = capsys.readouterr().err
    assert "500 steps" in err and "max_steps = 499" in err and "Traceback" not in err
    code, summary, _ = _run(tmp_path, scene, "--max-steps", "500")
    assert code == 0 and summary["steps"] == 500


def test_a_refused_run_leaves_earlier_outputs_alone(tmp_path):
    scene = _scene(tmp_path, TWO)
    code, first, _ = _run(tmp_path, scene)
    assert code == 0
    code, again, npz = _run(tmp_path, scene, "--max-steps", "10")  # with --overwrite
    assert code == 1 and again == first and npz["t"].shape == (501,)


def test_scene_max_steps_refuses_and_the_flag_overrides(tmp_path):
    scene = _scene(tmp_path, TWO.replace("duration = 0.05", "duration = 0.05\nmax_steps = 100"))
    code, summary, _ = _run(tmp_path, scene)
    assert code == 1 and summary is None
    code, summary, _ = _run(tmp_path, scene, "--max-steps", "1000")
    assert code == 0 and summary["steps"] == 500
    with pytest.raises(SceneError, match=r"run\.max_steps"):
        loads_scene(TWO.replace("duration = 0.05", "duration = 0.05\nmax_steps = -3"))


def _warned(spec, step_s: float) -> RunPlan:
    slow = replace(spec, step=step_s / spec.metadata["time_unit_s"])
    with pytest.warns(WorkloadWarning, match="estimated to take"):
        plan = plan_run(slow)
    assert plan.steps == planned_steps(slow)
    assert plan.seconds > 600 and plan.seconds == plan.steps * plan.seconds_per_step
    with pytest.raises(StepLimitError, match="more than max_steps = 1000000"):
        plan_run(slow, max_steps=10**6)
    return plan


def test_tiny_step_is_estimated_and_warned():
    plan = _warned(build_run(loads_scene(TWO)), 1e-11)  # any machine: > 0.12 µs per step
    assert plan.steps == 5_000_000_000


@pytest.mark.slow
def test_tiny_step_on_planned_cluster_is_estimated_and_warned():
    # the case reported: 1e-9 s on planned_cluster ran for hours without a word
    plan = _warned(build_run(load_scene(shipped_scene("planned_cluster"))), 1e-9)
    assert plan.steps > 10**6


def test_short_runs_are_not_measured_nor_warned():
    spec = build_run(loads_scene(TWO))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plan = plan_run(spec, step_seconds_bound=0.01)
    assert plan == RunPlan(1, 500, 0.01, 5.0)
    assert "500 steps" in plan.describe()


@pytest.mark.parametrize("every, limit", [(0, None), (None, 0), (True, None), (None, 2.5)])
def test_bad_values_are_typed_errors(every, limit):
    spec = build_run(loads_scene(TWO))
    with pytest.raises(InputError):
        plan_run(spec, every, limit, step_seconds_bound=0.0)


def test_all_fixed_sweep_point_is_bounded_without_warnings(tmp_path):
    # the sweep path took the spread of the moving bodies: with none, np.max of an empty array
    from poissonkit.sweeps.targets import TomlScene

    scene = TomlScene.from_file(_scene(tmp_path, STILL.format(duration=0.2)))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        rec = scene.run(scene.prepare(), {"bodies.a.mass": 3.0})
    assert rec.fate == "bounded"
    assert np.all(rec.distance == 1.0)  # the two fixed bodies stay 1 m apart
