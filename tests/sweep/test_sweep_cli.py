"""``poissonkit sweep`` as a user runs it: a real client process, interrupted and resumed.

Truth: the same points run in a plain loop in this process (no Dask, no store).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from poissonkit import cli
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, reduce_run
from poissonkit.sweeps.params import design_from
from poissonkit_magnets.seed000_sweep import SeedScene

ROOT = Path(__file__).resolve().parents[2]
ARGS = ["--param", "spin_ratio=0:20:3", "--param", "tilt=0:0.1:3", "--periods", "4"]


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    return env


def _completed(store: Path) -> int:
    import zarr

    try:
        return int(np.asarray(zarr.open_group(str(store), mode="r")["completed"][...]).sum())
    except Exception:  # noqa: BLE001 - not created yet
        return 0


@pytest.mark.slow  # two client processes, each starting a cluster and compiling on its worker
def test_interrupted_client_resumes_to_the_same_dataset(tmp_path):
    out = tmp_path / "run"
    store = out / "sweep.zarr"
    cmd = [sys.executable, "-m", "poissonkit", "sweep", "seed000", *ARGS, "--workers", "1",
           "--batch-size", "1", "--no-progress", "--no-plot", "--out", str(out)]
    proc = subprocess.Popen(cmd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 300
    while _completed(store) < 2 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.2)
    assert proc.poll() is None, "the sweep finished before it could be interrupted"
    proc.send_signal(signal.SIGINT)  # Ctrl-C of the client process
    proc.wait(timeout=120)
    partial = _completed(store)
    assert 2 <= partial < 9
    done = subprocess.run(cmd + ["--resume"], env=_env(), capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    ds = xr.open_zarr(store).load()
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())
    scene = SeedScene(periods=4)
    prep = scene.prepare()
    design = design_from(["spin_ratio=0:20:3", "tilt=0:0.1:3"])
    for k, values in design.points():
        ref = reduce_run(scene.run(prep, values), DEFAULT_OUTCOMES)
        idx = np.unravel_index(k, design.shape)
        for n in DEFAULT_OUTCOMES:
            np.testing.assert_array_equal(float(ds[n].values[idx]), float(ref[n]), err_msg=n)


@pytest.mark.slow  # starts a two-worker cluster that compiles the N-body kernels
def test_cli_sweeps_a_toml_scene_on_two_workers(tmp_path, capsys):
    out = tmp_path / "toml"
    code = cli.main(["sweep", str(ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"),
                     "--param", "bodies.right.r.0=0.025,0.04", "--param", "bodies.right.p.1=0,1e-4",
                     "--workers", "2", "--no-progress", "--out", str(out)])
    assert code == 0
    ds = xr.open_zarr(out / "sweep.zarr").load()
    assert dict(ds.sizes) == {"bodies.right.r.0": 2, "bodies.right.p.1": 2}
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())
    assert (out / "stability_map.png").is_file()
    assert "0 failed" in capsys.readouterr().out


@pytest.mark.parametrize("argv,needle", [
    (["sweep", "seed000"], "--param"),
    (["sweep", "seed000", "--param", "colour=1,2"], "colour"),
    (["sweep", "seed000", "--param", "tilt=0:1"], "--random"),
    (["sweep", "seed000", "--param", "tilt=0,1", "--outcomes", "fate,joy"], "joy"),
    (["sweep", "nowhere.toml", "--param", "run.step=1e-4"], "nowhere.toml"),
    (["sweep", "seed000", "--param", "tilt=0", "--scheduler", "localhost"], "tcp://"),
])
def test_bad_input_fails_before_any_work(argv, needle, tmp_path, capsys):
    assert cli.main(argv + ["--out", str(tmp_path / "o")]) == 1
    assert needle in capsys.readouterr().err
