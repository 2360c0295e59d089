"""Swept parameter paths are validated before any run or cluster starts; a sweep in which every
point failed exits non-zero."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from poissonkit import cli
from poissonkit.errors import SceneError
from poissonkit.sweeps.paths import SweepPathError, check_path
from poissonkit.sweeps.targets import TomlScene

ROOT = Path(__file__).resolve().parents[2]
TWO_MAGNETS = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"


@pytest.fixture
def no_cluster(monkeypatch):
    """Fail the test if anything tries to start or reach a Dask cluster."""
    import poissonkit.sweeps.api as api

    def refuse(*_a, **_k):
        raise AssertionError("a cluster was started for a sweep that must be refused")

    monkeypatch.setattr(api, "make_client", refuse)
    monkeypatch.setattr(api, "execute", refuse)


@pytest.mark.parametrize("path,needle", [
    ("interactions.params.screenin_length", "not a parameter of the potential 'dumbbell'"),
    ("interactions.0.screening", "not a parameter"),
    ("bodies.right.mas", "no field 'mas'"),
    ("run.stpe", "no field 'stpe'"),
    ("colour.x", "no section 'colour'"),
    ("assembly.params.n", "names no assembly"),
])
def test_misspelt_paths_are_refused_naming_the_path(path, needle):
    scene = TomlScene.from_file(TWO_MAGNETS)
    with pytest.raises(SweepPathError, match=needle) as info:
        scene.check(path)
    assert info.value.path == path and path in str(info.value)
    assert isinstance(info.value, SceneError)


@pytest.mark.parametrize("path", [
    "interactions.params.mu0", "interactions.params.half_length1", "bodies.right.r.0",
    "bodies.left.mass", "bodies.right.spin", "run.step", "defaults.moment", "run.duration",
])
def test_valid_paths_pass(path):
    assert TomlScene.from_file(TWO_MAGNETS).check(path) == path


def test_pair_params_are_checked_against_the_pairs_own_potential():
    data = {"interactions": {"potential": "dipole",
                             "pair": [{"bodies": ["a", "b"], "potential": "gravity"}]}}
    assert check_path(data, "interactions.pair.0.params.G")[-1] == "G"
    assert check_path(data, "interactions.0.G")[:4] == ["interactions", "pair", "0", "params"]
    with pytest.raises(SweepPathError, match="'gravity'"):
        check_path(data, "interactions.0.mu0")
    check_path(data, "interactions.params.mu0")  # the scene's potential is dipole


def test_fixed_paths_are_checked_when_the_scene_is_made():
    with pytest.raises(SweepPathError, match="run.stpe"):
        TomlScene.from_file(TWO_MAGNETS, fixed={"run.stpe": 1e-4})


@pytest.mark.parametrize("scene,param,needle", [
    (str(TWO_MAGNETS), "interactions.params.screenin_length=1:2:3", "screenin_length"),
    # a shipped scene by name, as `poissonkit run two_magnets` takes it
    ("two_magnets", "interactions.params.screenin_length=1:2:3", "screenin_length"),
    ("seed000", "spin_ratoi=0:1:2", "spin_ratoi"),
])
def test_cli_refuses_a_bad_path_before_any_cluster(scene, param, needle, tmp_path, capsys,
                                                    no_cluster):
    out = tmp_path / "o"
    code = cli.main(["sweep", scene, "--param", param, "--no-progress", "--out", str(out)])
    assert code == 1
    err = capsys.readouterr().err
    assert needle in err and "error" in err
    assert not out.exists()  # no store was created


def test_cli_exit_code_as_a_process(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    out = tmp_path / "o"
    done = subprocess.run([sys.executable, "-m", "poissonkit", "sweep", str(TWO_MAGNETS),
                           "--param", "interactions.params.screenin_length=1:2:3",
                           "--out", str(out)], env=env, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 1
    assert "screenin_length" in done.stderr and "Traceback" not in done.stderr
    assert not out.exists()


def _dataset(failed: list[bool]) -> xr.Dataset:
    n = len(failed)
    return xr.Dataset({"fate": ("x", np.zeros(n, dtype=np.int64)),
                       "failed": ("x", np.array(failed)),
                       "completed": ("x", np.ones(n, dtype=bool)),
                       "error": ("x", np.array(["boom" if f else "" for f in failed],
                                               dtype=object))},
                      coords={"x": np.arange(n, dtype=float)}, attrs={"scene": "fake"})


# some points failed: exit 5 with the failures by kind (it was 0, issue 30)
@pytest.mark.parametrize("failed,code", [([True, True, True], 1), ([True, False, True], 5),
                                         ([False, False], 0)])
def test_cli_exits_non_zero_when_every_point_failed(failed, code, tmp_path, capsys,
                                                    monkeypatch):
    import poissonkit.sweeps as sweeps

    monkeypatch.setattr(sweeps, "sweep", lambda *a, **k: _dataset(failed))
    assert cli.main(["sweep", "seed000", "--param", "tilt=0,1", "--no-plot", "--no-progress",
                     "--out", str(tmp_path / "o")]) == code
    captured = capsys.readouterr()
    assert f"{sum(failed)} failed" in captured.out
    if code == 1:
        assert f"every point failed ({len(failed)} of {len(failed)}); first error: boom" \
            in captured.err
    else:
        assert "every point failed" not in captured.err
    if code == 5:
        assert "2 of 3 runs failed" in captured.err and "x=0: boom" in captured.err


@pytest.mark.slow  # starts a one-worker cluster that compiles the dumbbell kernels
def test_cli_real_sweep_where_every_point_fails_exits_non_zero(tmp_path, capsys):
    # a negative mass is a valid path with an invalid value: refused per point, not up front
    code = cli.main(["sweep", str(TWO_MAGNETS), "--param", "bodies.right.mass=-1,-2",
                     "--workers", "1", "--no-progress", "--no-plot",
                     "--out", str(tmp_path / "o")])
    assert code == 1
    err = capsys.readouterr().err
    assert "every point failed (2 of 2)" in err and "mass" in err
