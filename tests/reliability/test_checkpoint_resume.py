"""Checkpoints: SIGKILL mid-run and resume gives the bit-identical final state; damaged
checkpoints are refused with a typed error; checkpoints only where they can be exact."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from reliability_helpers import KILL_RUNS, bound_pair, orbit_state  # type: ignore[import-not-found]

from poissonkit.errors import InputError, PoissonkitError
from poissonkit.numerics import solve
from poissonkit.numerics.checkpoint import (
    Checkpoint,
    CheckpointError,
    checkpoints,
    newest_checkpoint,
    read_checkpoint,
    read_trajectory,
)

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    return env


def _kill_after_first_checkpoint(folder: Path, method: str) -> None:
    proc = subprocess.Popen([sys.executable, str(HERE / "resumable_run.py"), str(folder), method],
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 600
    try:
        while not checkpoints(folder / "checkpoints"):
            if proc.poll() is not None:
                out, err = proc.communicate()
                raise AssertionError(f"the run ended early ({proc.returncode}): {err.decode()}")
            assert time.monotonic() < deadline, "no checkpoint appeared"
            time.sleep(0.05)
        time.sleep(0.1)  # let it run on past the checkpoint, so that work is lost
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    assert proc.returncode == -signal.SIGKILL, proc.stderr.read().decode()
    assert not (folder / "final.npy").exists(), "the run finished before it was killed"


@pytest.mark.parametrize("method", ["splitting4",
                                    pytest.param("midpoint", marks=pytest.mark.slow)])
def test_sigkill_then_resume_is_bit_identical(tmp_path, method):
    run = KILL_RUNS[method]
    _kill_after_first_checkpoint(tmp_path, method)
    done = subprocess.run([sys.executable, str(HERE / "resumable_run.py"), str(tmp_path), method,
                           "--resume"], env=_env(), capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr
    assert "checkpoint-" in done.stdout  # it did resume, not start over
    resumed = np.load(tmp_path / "final.npy")
    # the uninterrupted run, in this process
    ref = solve(bound_pair(), orbit_state(), run["t_end"], method, step=run["step"],
                save_every=run["save_every"])
    assert resumed.tobytes() == ref.y[-1].tobytes()  # bit-identical, not merely close
    t, y = read_trajectory(tmp_path / "parts")  # the streamed rows: no gap, no duplicate
    assert np.array_equal(t, ref.t) and np.array_equal(y, ref.y)


def _checkpointed(tmp_path, every=50, t_end=1.0):
    ck = Checkpoint(tmp_path / "ck", every)
    sol = solve(bound_pair(), orbit_state(), t_end, "splitting4", step=1e-3, checkpoint=ck)
    return ck, sol


def test_resume_in_process_matches_and_restores_rows(tmp_path):
    stop_at = {"n": 0}

    def stop() -> bool:  # ask to stop after a few chunks
        stop_at["n"] += 1
        return stop_at["n"] == 7

    ck = Checkpoint(tmp_path / "ck", 100)
    part = solve(bound_pair(), orbit_state(), 2.0, "splitting4", step=1e-3, checkpoint=ck,
                 stop=stop, save_every=7)
    assert part.extra["interrupted"] and "interrupted at step 700" in part.message
    full = solve(bound_pair(), orbit_state(), 2.0, "splitting4", step=1e-3, checkpoint=ck,
                 resume=True, save_every=7)
    ref = solve(bound_pair(), orbit_state(), 2.0, "splitting4", step=1e-3, save_every=7)
    assert full.y[-1].tobytes() == ref.y[-1].tobytes()
    assert np.array_equal(full.t, ref.t) and np.array_equal(full.y, ref.y)


@pytest.mark.parametrize("damage", ["truncate", "flip", "header", "empty"])
def test_damaged_checkpoint_is_refused(tmp_path, damage):
    ck, _ = _checkpointed(tmp_path)
    path = checkpoints(ck.folder)[-1]
    data = bytearray(path.read_bytes())
    if damage == "truncate":
        data = data[: len(data) // 2]
    elif damage == "flip":
        data[-100] ^= 0x01
    elif damage == "header":
        data[:5] = b"XXXXX"
    else:
        data = bytearray()
    path.write_bytes(bytes(data))
    with pytest.raises(CheckpointError):
        read_checkpoint(path)
    # resuming falls back to the older valid checkpoint, never loads the damaged one
    older, _, meta = newest_checkpoint(ck.folder)
    assert older != path
    for p in checkpoints(ck.folder):
        if p != path:
            p.write_bytes(p.read_bytes()[:-1])  # damage the others too: nothing valid is left
    with pytest.raises(CheckpointError) as info:
        solve(bound_pair(), orbit_state(), 1.0, "splitting4", step=1e-3, checkpoint=ck,
              resume=True)
    assert isinstance(info.value, PoissonkitError) and "no valid checkpoint" in str(info.value)


def test_checkpoint_of_another_problem_is_refused(tmp_path):
    ck, _ = _checkpointed(tmp_path)
    with pytest.raises(CheckpointError, match="differs"):
        solve(bound_pair(), orbit_state(), 1.0, "splitting4", step=2e-3, checkpoint=ck,
              resume=True)


def test_checkpoint_needs_a_fixed_step_method(tmp_path):
    with pytest.raises(InputError, match="fixed-step"):
        solve(bound_pair(), orbit_state(), 1.0, "dop853", tol=1e-8,
              checkpoint=Checkpoint(tmp_path, 10))
    with pytest.raises(InputError, match="every"):
        Checkpoint(tmp_path, 0)
    with pytest.raises(InputError, match="resume"):
        solve(bound_pair(), orbit_state(), 1.0, "splitting4", step=1e-3, resume=True)
