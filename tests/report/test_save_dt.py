"""``poissonkit run --save-dt SECONDS``: states at requested physical times, for a fixed-step
and an adaptive method (the two methods must agree at the sample times)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.report.trajectory import open_trajectory

pytest.importorskip("xarray")
ROOT = Path(__file__).resolve().parents[2]
QUIET = ["--no-progress", "--no-plots"]


def _run(monkeypatch, *args: str) -> int:
    argv = ["poissonkit", "run", *args]
    monkeypatch.setattr(sys, "argv", argv)
    return cli.main(argv[1:])


def test_fixed_step_and_adaptive_methods_save_at_the_same_times(tmp_path, monkeypatch):
    runs = {}
    for label, extra in (("fixed", []), ("adaptive", ["--method", "dop853", "--tol", "1e-12"])):
        out = tmp_path / label
        assert _run(monkeypatch, "two_magnets", "--duration", "0.002", "--save-dt", "0.0003",
                    "--out", str(out), *QUIET, *extra) == 0
        runs[label] = open_trajectory(out / "trajectory.nc")
    want = np.r_[np.arange(7) * 0.0003, 0.002]
    for ds in runs.values():
        np.testing.assert_allclose(ds["time"].values, want, rtol=1e-12, atol=0)
    fixed, adaptive = (runs[k]["position"].values for k in ("fixed", "adaptive"))
    scale = np.max(np.abs(fixed))
    assert np.max(np.abs(fixed - adaptive)) < 1e-9 * scale


def test_save_dt_refuses_options_that_choose_rows_themselves(tmp_path, monkeypatch, capsys):
    code = _run(monkeypatch, "two_magnets", "--duration", "0.002", "--save-dt", "0.0005",
                "--checkpoint-every", "10", "--out", str(tmp_path / "o"), *QUIET)
    assert code == 1
    assert "--save-dt" in capsys.readouterr().err
    assert _run(monkeypatch, "two_magnets", "--save-dt", "-1", "--out",
                str(tmp_path / "p"), *QUIET) == 1


def test_a_scene_file_saves_at_its_run_save_dt(tmp_path, monkeypatch):
    import tomllib

    scene = (ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml").read_text()
    text = scene.replace("[run]", "[run]\nsave_dt = 0.0004", 1)
    assert tomllib.loads(text)["run"]["save_dt"] == 0.0004
    path = tmp_path / "sampled.toml"
    path.write_text(text)
    out = tmp_path / "out"
    assert _run(monkeypatch, str(path), "--duration", "0.002", "--out", str(out), *QUIET) == 0
    times = open_trajectory(out / "trajectory.nc")["time"].values
    np.testing.assert_allclose(times, np.arange(6) * 0.0004, rtol=1e-12, atol=1e-18)
    # the command line's --save-every wins over the scene's save_dt
    out2 = tmp_path / "out2"
    assert _run(monkeypatch, str(path), "--duration", "0.002", "--save-every", "5", "--out",
                str(out2), *QUIET) == 0
    assert len(open_trajectory(out2 / "trajectory.nc")["time"]) == 5


def test_save_dt_and_save_every_in_one_scene_are_refused():
    from poissonkit.errors import SceneError
    from poissonkit.scene import loads_scene

    text = (ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml").read_text()
    with pytest.raises(SceneError, match="give one"):
        loads_scene(text.replace("[run]", "[run]\nsave_dt = 0.0004\nsave_every = 2", 1))
