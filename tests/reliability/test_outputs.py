"""Outputs that never lie: atomic files, no mixing with an earlier run's folder, bounded memory
for long trajectories, SIGINT leaves a readable partial result."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from checkout_env import checkout_env  # type: ignore[import-not-found]
from reliability_helpers import bound_pair, orbit_state  # type: ignore[import-not-found]

from poissonkit import cli
from poissonkit.errors import InputError
from poissonkit.numerics import solve
from poissonkit.numerics.checkpoint import TrajectoryStream, checkpoints, read_trajectory
from poissonkit.report import atomic

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"


def test_atomic_write_keeps_old_content_on_failure(tmp_path):
    path = tmp_path / "summary.json"
    atomic.write_json(path, {"run": 1})
    with pytest.raises(RuntimeError):
        with atomic.atomic_path(path) as tmp:
            tmp.write_text('{"run": 2, "half')  # a writer dying half-way
            raise RuntimeError("killed")
    assert json.loads(path.read_text()) == {"run": 1}
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]  # no temporary left


def test_existing_output_folder_is_refused_unless_overwrite(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text('{"scene": "an earlier run"}')
    (out / "stray.txt").write_text("from another run")
    args = ["run", str(TWO), "--duration", "0.001", "--out", str(out), "--no-progress",
            "--no-plots"]
    assert cli.main(args) == 1  # refused with a typed error before anything runs
    assert (out / "summary.json").read_text() == '{"scene": "an earlier run"}'
    with pytest.raises(atomic.OutputExistsError, match="--overwrite"):
        atomic.prepare_output_dir(out)
    atomic.prepare_output_dir(out, overwrite=True)  # what --overwrite does
    assert not any(out.iterdir())
    with pytest.raises(InputError, match="not a folder"):
        (out / "x").write_text("")
        atomic.prepare_output_dir(out / "x")


def test_streamed_trajectory_keeps_memory_bounded(tmp_path):
    steps, max_rows = 200_000, 1000
    stream = TrajectoryStream(tmp_path / "parts", max_rows=max_rows)
    sol = solve(bound_pair(), orbit_state(), steps * 1e-3, "splitting4", step=1e-3,
                save_every=1, stream=stream)
    assert sol.extra["streamed_rows"] == steps + 1
    # rows held at once: the spill limit plus one compiled chunk buffer, not 2e5
    assert sol.extra["peak_rows_in_memory"] <= 2 * max_rows + 1
    assert len(sol.t) == 2  # the solution itself holds start and end only
    ref = solve(bound_pair(), orbit_state(), steps * 1e-3, "splitting4", step=1e-3)
    t, y = read_trajectory(tmp_path / "parts")
    assert np.array_equal(t, ref.t) and np.array_equal(y, ref.y)
    assert sol.y[-1].tobytes() == ref.y[-1].tobytes()


def _start_long_run(out: Path, *extra: str) -> subprocess.Popen:
    # the two-magnet scene's own 0.05 s in 5e6 steps: far longer than the test waits
    return subprocess.Popen(
        [sys.executable, "-m", "poissonkit", "run", str(TWO), "--duration", "0.05", "--step",
         "1e-8", "--save-every", "1000", "--checkpoint-every", "100000", "--out", str(out),
         "--no-progress", "--no-plots", *extra],
        env=checkout_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _wait_for_checkpoint(proc: subprocess.Popen, out: Path) -> None:
    deadline = time.monotonic() + 600
    while not checkpoints(out / "checkpoints"):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.05)


def test_sigint_stops_cleanly_with_readable_partial_result(tmp_path):
    out = tmp_path / "out"
    proc = _start_long_run(out)
    _wait_for_checkpoint(proc, out)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 130, stderr  # the documented "interrupted" exit code
    assert "interrupt" in stderr and "Traceback" not in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert "interrupted at step" in summary["message"]
    assert 0 < summary["t_reached_s"] < 0.05
    data = np.load(out / "trajectory.npz")
    assert data["t_si"][-1] == pytest.approx(summary["t_reached_s"], rel=1e-12)
    assert np.all(np.diff(data["t"]) > 0) and np.all(np.isfinite(data["y"]))
    assert not list(out.glob(".*.tmp*"))  # no half-written file
    assert checkpoints(out / "checkpoints")  # and it can be resumed (see the SIGKILL test)


@pytest.mark.slow
def test_cli_sigkill_then_resume_matches_uninterrupted_run(tmp_path):
    out = tmp_path / "killed"
    proc = _start_long_run(out)
    _wait_for_checkpoint(proc, out)
    time.sleep(0.5)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (out / "summary.json").exists()
    resumed = subprocess.run(
        [sys.executable, "-m", "poissonkit", "run", str(TWO), "--duration", "0.05", "--step",
         "1e-8", "--save-every", "1000", "--out", str(out), "--no-progress", "--no-plots",
         "--resume"], env=checkout_env(), capture_output=True, text=True, timeout=1800)
    assert resumed.returncode == 0, resumed.stderr
    ref = tmp_path / "ref"
    assert cli.main(["run", str(TWO), "--duration", "0.05", "--step", "1e-8", "--save-every",
                     "1000", "--out", str(ref), "--no-progress", "--no-plots"]) == 0
    a, b = np.load(out / "trajectory.npz"), np.load(ref / "trajectory.npz")
    assert a["y"][-1].tobytes() == b["y"][-1].tobytes()
    assert np.array_equal(a["t"], b["t"]) and np.array_equal(a["y"], b["y"])
    assert json.loads((out / "summary.json").read_text())["resumed_from"].startswith("checkpoint-")
