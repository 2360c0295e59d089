"""``poissonkit run`` end to end on the seed 000 scene: files, summary fields and their values.

Truth used: the orbit radius and period of the seed (P_orb printed in the seed, radius 10 mm,
see test_seed000_table.py) — the integrated orbit must stay on the circle of radius R_orb and
its angular momentum must be conserved; invariant drifts are bounded by stated tolerances.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from poissonkit import cli
from poissonkit_magnets import seed000


def test_run_writes_summary_trajectory_and_plots(tmp_path):
    out = tmp_path / "out"
    code = cli.main(["run", "--out", str(out), "--no-progress", "--periods", "2"])
    assert code == 0
    for name in ("summary.json", "trajectory.npz", "angular_momentum_z.png", "radius_and_x.png",
                 "orbit.png", "drifts.png"):
        assert (out / name).is_file(), name
    s = json.loads((out / "summary.json").read_text())
    for key in ("P_orb", "T_orb", "method", "steps", "wall_time_s", "compile_time_s",
                "max_rel_energy_error",
                "max_rel_casimir_drift", "max_rel_angular_momentum_drift", "parameters"):
        assert key in s, key
    # the seed's printed P_orb (seed text, Maple output)
    assert s["P_orb"] == pytest.approx(6.4910356642626862477e-4, rel=1e-14)
    assert s["T_orb"] == pytest.approx(2 * math.pi * 0.01 * 0.00038288160465625605093
                                       / 6.4910356642626862477e-4, rel=1e-14)
    assert s["t_end_s"] == pytest.approx(2 * s["T_orb"], rel=1e-12)
    assert s["steps"] == 400  # default step T_orb/200
    assert s["method"] == "splitting6"
    # circular orbit: the distance stays at R_orb = 10 mm; order 6 at h = T/200 gives
    # (2 pi/200)^6 ~ 1e-9 per unit time, so 1e-7 is a safe stated bound
    assert s["min_distance_m"] == pytest.approx(0.01, rel=1e-7)
    assert s["max_distance_m"] == pytest.approx(0.01, rel=1e-7)
    # structure preservation: Casimirs and total angular momentum to round-off
    assert s["max_rel_casimir_drift"] < 1e-12
    assert s["max_rel_angular_momentum_drift"] < 1e-12
    assert s["max_rel_energy_error"] < 1e-6
    data = np.load(out / "trajectory.npz")
    assert data["y"].shape == (401, 18) and len(data["layout"]) == 18
    assert data["t_si"][-1] == pytest.approx(2 * s["T_orb"], rel=1e-12)
    # the relative orbit in SI: radius 10 mm along the whole run
    assert np.allclose(np.linalg.norm(data["r_rel_si"], axis=1), 0.01, rtol=1e-7)
    # it went round twice: the polar angle advanced by 4 pi (phase error of order 6 small)
    r = data["r_rel_si"]
    phase = np.unwrap(np.arctan2(r[:, 1], r[:, 0]))
    assert phase[-1] - phase[0] == pytest.approx(4 * math.pi, rel=1e-6)


def test_run_options_duration_and_no_plots(tmp_path):
    out = tmp_path / "o2"
    T = float(seed000.circular_orbit().period)
    code = cli.main(["run", "--out", str(out), "--no-progress", "--no-plots",
                     "--duration", str(0.5 * T), "--step", str(T / 100)])
    assert code == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["t_end_s"] == pytest.approx(0.5 * T, rel=1e-12)
    assert s["steps"] == 50
    assert not list(out.glob("*.png"))


def test_run_rejects_bad_options(tmp_path, capsys):
    assert cli.main(["run", "--out", str(tmp_path), "--periods", "-1", "--no-progress"]) == 1
    assert "periods" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        cli.main(["run", "--step", "1", "--tol", "1e-6"])  # mutually exclusive


def test_run_missing_scene_file_is_a_clear_error(tmp_path, capsys):
    code = cli.main(["run", str(tmp_path / "nope.toml"), "--out", str(tmp_path), "--no-progress"])
    assert code != 0
    err = capsys.readouterr().err
    assert "nope.toml" in err or "scene" in err


def test_sweep_classifies_spin_choices(tmp_path, capsys):
    import xarray as xr

    out = tmp_path / "sweep"
    # the older --grid form still works; the sweep now runs on a local Dask cluster and
    # writes an xarray dataset (Zarr) instead of a CSV file
    code = cli.main(["sweep", "--grid", "spin_ratio=0,20", "--grid", "tilt=0.02",
                     "--periods", "2", "--workers", "1", "--no-progress", "--out", str(out)])
    assert code == 0
    ds = xr.open_zarr(out / "sweep.zarr").load()
    fate = {float(s): ("bounded", "collision", "escape")[int(ds["fate"].sel(spin_ratio=s,
                                                                             tilt=0.02))]
            for s in ds["spin_ratio"].values}
    # the seed's statement: stable only with enough spin (see test_seed000_stability.py)
    assert fate == {0.0: "collision", 20.0: "bounded"}


@pytest.mark.parametrize("argv,needle", [
    (["sweep", "--grid", "colour=1,2"], "colour"),
    (["sweep", "--grid", "spin_ratio"], "PATH="),
    (["sweep", "--grid", "tilt=a,b"], "numbers"),
    (["bench", "--methods", "splitting6,warp9"], "warp9"),
])
def test_sweep_and_bench_reject_bad_input(argv, needle, tmp_path, capsys):
    assert cli.main(argv + ["--out", str(tmp_path)]) == 1
    assert needle in capsys.readouterr().err
