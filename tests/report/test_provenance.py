"""Self-describing results: summary.json records what made the run (versions, command line,
options, the scene itself, units), trajectory.nc is a dataset with units, and
``poissonkit run --from-summary`` runs the same scene again with the same result."""

from __future__ import annotations

import hashlib
import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

import poissonkit
from poissonkit import cli

xr = pytest.importorskip("xarray")

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
QUIET = ["--no-progress", "--no-plots"]


def _run(monkeypatch, *args: str) -> int:
    argv = ["poissonkit", "run", *args]
    monkeypatch.setattr(sys, "argv", argv)  # what a shell would hand the entry point
    return cli.main(argv[1:])


@pytest.fixture(scope="module")
def scene_copy(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("scene") / "my_magnets.toml"
    shutil.copy(TWO, path)
    return path


def test_summary_records_versions_command_options_scene_and_units(tmp_path, monkeypatch,
                                                                  scene_copy):
    out = tmp_path / "out"
    assert _run(monkeypatch, str(scene_copy), "--duration", "0.002", "--out", str(out),
                *QUIET) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["versions"]["poissonkit"] == poissonkit.__version__
    plugins = {p["name"]: p for p in s["versions"]["plugins"]}
    assert plugins["magnets"]["status"] == "ok" and plugins["magnets"]["version"]
    assert s["command_line"] == ["poissonkit", "run", str(scene_copy), "--duration", "0.002",
                                 "--out", str(out), *QUIET]
    assert s["options"]["duration"] == 0.002 and s["options"]["method"] is None
    assert s["options"]["no_plots"] is True
    text = scene_copy.read_text()
    src = s["scene_source"]
    assert src["kind"] == "file" and src["text"] == text
    assert src["sha256"] == hashlib.sha256(text.encode()).hexdigest()
    assert src["path"] == str(scene_copy.resolve())
    assert src["resolved"]["potential"] == "dumbbell"
    assert [b["name"] for b in src["resolved"]["bodies"]] == ["left", "right"]
    units = s["units"]["internal_unit_in_si"]
    scales = s["parameters"]["scales"]
    assert units["length"] == scales["length"] and units["time"] == scales["time"]
    assert units["momentum"] == pytest.approx(scales["length"] * scales["mass"] / scales["time"])
    assert s["units"]["si_units"]["angular_momentum"] == "kg m2 s-1"
    # the keys that were there before keep their meaning
    assert s["scene"] == "two_magnets" and s["steps"] == 20
    assert s["t_end_s"] == pytest.approx(0.002)


def test_trajectory_dataset_has_bodies_components_and_si_units(tmp_path, monkeypatch):
    out = tmp_path / "out"
    assert _run(monkeypatch, str(TWO), "--duration", "0.002", "--out", str(out), *QUIET) == 0
    npz = np.load(out / "trajectory.npz")
    with xr.open_dataset(out / "trajectory.nc") as ds:
        ds.load()
    assert ds["position"].dims == ("time", "body", "component")
    assert list(ds["body"].values) == ["left", "right"]
    assert list(ds["component"].values) == ["x", "y", "z"]
    assert ds["position"].attrs["units"] == "m"
    assert ds["momentum"].attrs["units"] == "kg m s-1"
    assert ds["angular_momentum"].attrs["units"] == "kg m2 s-1"
    assert ds["time"].attrs["units"] == "s"
    np.testing.assert_array_equal(ds["time"].values, npz["t_si"])
    np.testing.assert_array_equal(ds["y"].values, npz["y"])
    # positions in metres from the raw state and the recorded length unit
    layout = list(npz["layout"])
    length = ds.attrs["internal_unit_length"]
    assert ds.attrs["internal_unit_length_units"] == "m"
    right_x = npz["y"][:, layout.index("right.r_x")] * length
    np.testing.assert_allclose(ds["position"].sel(body="right", component="x"), right_x,
                               rtol=1e-15)
    assert ds["position"].sel(body="right", component="x")[0] == pytest.approx(0.04)
    # axes stay unit vectors; the npz carries the same scales
    np.testing.assert_allclose(np.linalg.norm(ds["axis"].values, axis=-1), 1.0, rtol=1e-12)
    kinds = list(npz["scale_kinds"])
    assert npz["scale_si"][kinds.index("length")] == length
    assert npz["scale_units"][kinds.index("energy")] == "J"
    assert npz["scale_si"][kinds.index("time")] == pytest.approx(npz["t_si"][1] / npz["t"][1])


def test_dataset_of_a_system_without_bodies_is_state_by_time():
    from poissonkit.report.trajectory import trajectory_dataset

    t = np.linspace(0.0, 1.0, 5)
    y = np.column_stack([np.cos(t), np.sin(t)])
    ds = trajectory_dataset(object(), t, y, scales=None, time_unit=2.0)
    assert ds["y"].dims == ("time", "state")
    assert list(ds["state"].values) == ["y0", "y1"]
    assert "body" not in ds.dims
    np.testing.assert_array_equal(ds["time"].values, 2.0 * t)
    assert ds.attrs["system_in_si"] == 1


def test_from_summary_reruns_a_scene_file_from_its_copy(tmp_path, monkeypatch, scene_copy):
    a, b = tmp_path / "a", tmp_path / "b"
    assert _run(monkeypatch, str(scene_copy), "--duration", "0.003", "--method", "splitting6",
                "--out", str(a), *QUIET) == 0
    scene_copy.write_text("this is no longer a scene [")  # the summary's copy is what counts
    try:
        assert _run(monkeypatch, "--from-summary", str(a / "summary.json"), "--out", str(b),
                    *QUIET) == 0
    finally:
        shutil.copy(TWO, scene_copy)
    ya, yb = np.load(a / "trajectory.npz")["y"], np.load(b / "trajectory.npz")["y"]
    assert ya.shape == yb.shape and ya.shape[0] == 31
    np.testing.assert_array_equal(ya[-1], yb[-1])  # bit-identical
    sa, sb = (json.loads((d / "summary.json").read_text()) for d in (a, b))
    assert sb["method"] == "splitting6" and sb["steps"] == sa["steps"]
    assert sb["scene_source"]["text"] == sa["scene_source"]["text"]
    assert sb["rerun_of"] == str((a / "summary.json").resolve())


def test_from_summary_reruns_the_seed_scene(tmp_path, monkeypatch):
    a, b = tmp_path / "a", tmp_path / "b"
    assert _run(monkeypatch, "--periods", "1", "--tilt", "0.02", "--out", str(a), *QUIET) == 0
    assert _run(monkeypatch, "--from-summary", str(a / "summary.json"), "--out", str(b),
                *QUIET) == 0
    ya, yb = np.load(a / "trajectory.npz")["y"], np.load(b / "trajectory.npz")["y"]
    np.testing.assert_array_equal(ya[-1], yb[-1])
    sb = json.loads((b / "summary.json").read_text())
    assert sb["scene_source"]["kind"] == "registered"
    assert sb["scene_source"]["resolved_name"] == "seed000"
    assert sb["options"]["tilt"] == 0.02 and sb["options"]["periods"] == 1.0
    # and the re-run differs from a run without the recorded options (the test can fail)
    c = tmp_path / "c"
    assert _run(monkeypatch, "--periods", "1", "--out", str(c), *QUIET) == 0
    assert not np.array_equal(np.load(c / "trajectory.npz")["y"][-1], yb[-1])


def test_from_summary_without_provenance_is_refused(tmp_path, monkeypatch):
    old = tmp_path / "summary.json"
    old.write_text(json.dumps({"scene": "seed000", "method": "splitting6"}))
    assert _run(monkeypatch, "--from-summary", str(old), "--out", str(tmp_path / "o"),
                *QUIET) == 1
    assert _run(monkeypatch, "--from-summary", str(tmp_path / "missing.json"), "--out",
                str(tmp_path / "o"), *QUIET) == 1


def test_solution_to_xarray_carries_the_internal_scales():
    from poissonkit.numerics import solve
    from poissonkit.scene import build_run, load_scene

    spec = build_run(load_scene(TWO))
    sol = solve(spec.system, spec.y0, 5 * spec.step, method="splitting4", step=spec.step)
    ds = sol.to_xarray()
    sc = spec.system.scales
    assert ds.attrs["internal_unit_length"] == sc.length == spec.metadata["scales"]["length"]
    assert ds.attrs["internal_unit_energy_units"] == "J"
    np.testing.assert_allclose(ds["t_si"].values, sol.t * spec.metadata["time_unit_s"],
                               rtol=1e-15)
    assert ds["t_si"].values[-1] == pytest.approx(5e-4)  # the scene's step is 1e-4 s
    assert ds["t_si"].attrs["units"] == "s"


def test_a_malformed_summary_is_a_one_line_error(tmp_path, monkeypatch, capsys):
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 10_000 + "]" * 10_000)
    huge = tmp_path / "huge.json"
    huge.write_text('{"options": ' + "9" * 100_000 + "}")
    for bad in (deep, huge):
        assert _run(monkeypatch, "--from-summary", str(bad), "--out", str(tmp_path / "o"),
                    *QUIET) == 1
        err = capsys.readouterr().err
        assert "--from-summary" in err and "Traceback" not in err


def test_repeatable_options_are_recorded_as_lists_and_replayed():
    """``--param`` is repeatable: the summary keeps it a list of strings, so a re-run passes
    the same scene parameters (and a hand-edited non-string entry is a typed error)."""
    import argparse

    from poissonkit.errors import InputError
    from poissonkit.report.provenance import options_of, rerun_options

    args = argparse.Namespace(param=["spin_rpm=1500", "mass=0.022"], step=0.1, out="x")
    options = options_of(args)
    assert options["param"] == ["spin_rpm=1500", "mass=0.022"]
    summary = {"options": json.loads(json.dumps(options)),
               "scene_source": {"kind": "registered", "name": "levitron"}}
    replay = rerun_options(summary, Path("."))
    assert replay["param"] == ["spin_rpm=1500", "mass=0.022"] and "out" not in replay
    summary["options"]["param"] = ["spin_rpm=1500", 3]
    with pytest.raises(InputError, match="list of strings"):
        rerun_options(summary, Path("."))
