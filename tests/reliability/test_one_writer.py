"""One writer per output folder: an OS lock in ``--out`` (``poissonkit.files.lock``).

Before, two runs started together into one empty folder both passed the "folder not empty"
check and mixed their files (one's summary beside the other's trajectory, both exit 0), and a
``--resume`` started during a live run deleted that run's files."""

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

from poissonkit.files.lock import LOCK_NAME, FolderLockedError, lock_folder
from poissonkit.numerics.checkpoint import checkpoints

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
EXIT_BUSY = 6


def _popen(out: Path, *extra: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "poissonkit", "run", str(TWO), "--no-progress", "--no-plots",
         "--out", str(out), *extra],
        env=checkout_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_the_lock_is_exclusive_and_released(tmp_path):
    with lock_folder(tmp_path / "out") as path:
        assert path.name == LOCK_NAME and path.exists()
        with pytest.raises(FolderLockedError, match="another poissonkit process"), \
                lock_folder(tmp_path / "out"):
            pass  # pragma: no cover
    assert not (tmp_path / "out" / LOCK_NAME).exists()
    with lock_folder(tmp_path / "out"):  # released: taken again
        pass


def test_a_lock_held_by_another_process_is_refused_and_freed_when_it_dies(tmp_path):
    code = ("import sys, time; from poissonkit.files.lock import lock_folder\n"
            "with lock_folder(sys.argv[1]):\n    print('held', flush=True); time.sleep(600)\n")
    holder = subprocess.Popen([sys.executable, "-c", code, str(tmp_path)], env=checkout_env(),
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        with pytest.raises(FolderLockedError), lock_folder(tmp_path):
            pass  # pragma: no cover
    finally:
        holder.send_signal(signal.SIGKILL)  # no clean-up: the kernel releases the lock
        holder.wait()
    with lock_folder(tmp_path):
        pass


@pytest.mark.slow
def test_two_runs_started_together_never_both_write(tmp_path):
    out = tmp_path / "out"
    common = ("--duration", "0.002", "--step", "1e-7", "--save-every", "100")
    procs = [_popen(out, *common, "--energy-tol", tol) for tol in ("1e-3", "2e-3")]
    results = [(p.wait(timeout=900), *p.communicate()) for p in procs]
    codes = sorted(r[0] for r in results)
    # one wrote; the other was refused (busy folder, or a folder already holding its files)
    assert codes[0] == 0 and codes[1] in (1, EXIT_BUSY), results
    loser = next(r for r in results if r[0] != 0)
    assert loser[2].count("\n") == 1 and "Traceback" not in loser[2]
    winner_tol = 1e-3 if results[0][0] == 0 else 2e-3
    summary = json.loads((out / "summary.json").read_text())
    assert summary["energy_tol"] == winner_tol  # the summary is the winner's
    with np.load(out / "trajectory.npz") as z:
        assert len(z["t"]) == summary["saved_rows"]


@pytest.mark.slow
def test_a_resume_during_a_live_run_is_refused(tmp_path):
    out = tmp_path / "out"
    live = _popen(out, "--duration", "0.05", "--step", "1e-8", "--save-every", "1000",
                  "--checkpoint-every", "100000")
    try:
        deadline = time.monotonic() + 600
        while not checkpoints(out / "checkpoints"):
            assert live.poll() is None, live.communicate()
            assert time.monotonic() < deadline
            time.sleep(0.05)
        resume = subprocess.run(
            [sys.executable, "-m", "poissonkit", "run", str(TWO), "--duration", "0.05",
             "--step", "1e-8", "--save-every", "1000", "--no-progress", "--no-plots",
             "--out", str(out), "--resume"], env=checkout_env(), capture_output=True, text=True,
            timeout=600, check=False)
        assert resume.returncode == EXIT_BUSY, resume.stderr
        assert resume.stderr.count("\n") == 1 and "another poissonkit process" in resume.stderr
        live.send_signal(signal.SIGINT)  # the live run was not disturbed: it stops cleanly
        _, err = live.communicate(timeout=300)
    finally:
        if live.poll() is None:
            live.kill()
    assert live.returncode == 130 and "Traceback" not in err, err
    assert json.loads((out / "summary.json").read_text())["status"] == "interrupted"
