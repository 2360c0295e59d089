"""Fuzzing kills: ``poissonkit run`` killed at a drawn phase boundary (injected kill point,
:mod:`poissonkit.report.killpoints`), at a drawn occurrence, with drawn checkpoint and save
intervals, its resume possibly killed again; then resumed until it ends.

Property: the final ``trajectory.npz`` is bit-identical to an uninterrupted run's, or the resume
refuses in one line with a typed error, and only where that is right (killed before its first
checkpoint: nothing to resume; or finished already, with its trajectory intact). Counted as
failures: a traceback, a hang (a subprocess over its time limit), silent data loss (exit 0 but
other rows). Each example runs several processes (seconds each), so this target is in the slow
suite only: ``pytest -m slow tests/fuzz/test_fuzz_kill_points.py``
(``POISSONKIT_FUZZ_KILL_EXAMPLES`` examples, default 30).
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fuzzkit import COUNTS, slow
from poissonkit.numerics.checkpoint import checkpoints
from poissonkit.report.killpoints import ENV, PHASES

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scenes" / "two_magnets.toml"
EXAMPLES = int(os.environ.get("POISSONKIT_FUZZ_KILL_EXAMPLES", "30"))
TIMEOUT_S = 300  # a process over this is a hang
_REFERENCES: dict[tuple[int, int], dict[str, bytes]] = {}


def _env(kill: str | None) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "plugins"),
                                         env.get("PYTHONPATH", "")])
    env.pop(ENV, None)
    if kill:
        env[ENV] = kill
    return env


def _run(out: Path, steps: int, save_every: int, *extra: str,
         kill: str | None = None) -> subprocess.CompletedProcess:
    args = [sys.executable, "-m", "poissonkit", "run", str(TWO), "--duration",
            repr(steps * 1e-6), "--step", "1e-6", "--save-every", str(save_every),
            "--no-progress", "--no-plots", "--out", str(out), *extra]
    c = COUNTS.setdefault("kill points", Counter())
    try:
        done = subprocess.run(args, env=_env(kill), capture_output=True, text=True,
                              timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        c["hangs"] += 1
        raise AssertionError(f"hang: {args} (kill {kill})") from None
    c["processes"] += 1
    if "Traceback" in done.stderr:
        c["tracebacks"] += 1
        raise AssertionError(f"traceback: {done.stderr}")
    return done


def _arrays(path: Path) -> dict[str, bytes]:
    with np.load(path) as z:
        return {k: z[k].tobytes() for k in z.files}


def _reference(tmp: Path, steps: int, save_every: int) -> dict[str, bytes]:
    key = (steps, save_every)
    if key not in _REFERENCES:
        out = tmp / f"ref-{steps}-{save_every}"
        done = _run(out, steps, save_every)
        assert done.returncode == 0, done.stderr
        _REFERENCES[key] = _arrays(out / "trajectory.npz")
    return _REFERENCES[key]


@pytest.fixture(scope="module", autouse=True)
def _print_counts():
    yield
    c = COUNTS.get("kill points", Counter())
    print(f"\nkill points: {dict(sorted(c.items()))}", file=sys.__stderr__)


_kills = st.one_of(st.none(), st.tuples(st.sampled_from(PHASES), st.integers(1, 6)))


@slow
@settings(max_examples=EXAMPLES, deadline=TIMEOUT_S * 10 * 1000, database=None,
          suppress_health_check=list(HealthCheck))
@given(steps=st.integers(150, 600), every=st.integers(15, 250), save_every=st.integers(1, 5),
       first=st.tuples(st.sampled_from(PHASES), st.integers(1, 6)), again=_kills)
def test_kill_at_drawn_points_then_resume(tmp_path_factory, steps, every, save_every, first,
                                         again):
    c = COUNTS.setdefault("kill points", Counter())
    c["tried"] += 1
    tmp = tmp_path_factory.mktemp("kill")
    ref = _reference(tmp_path_factory.getbasetemp(), steps, save_every)
    out = tmp / "out"
    done = _run(out, steps, save_every, "--checkpoint-every", str(every),
                kill=f"{first[0]}@{first[1]}")
    kills = [again and f"{again[0]}@{again[1]}", None, None]
    while done.returncode == -9:
        c["killed"] += 1
        had_checkpoint = bool(checkpoints(out / "checkpoints"))
        done = _run(out, steps, save_every, "--resume", kill=kills.pop(0) if kills else None)
        if done.returncode == 1:  # a refusal: right only before the first checkpoint
            assert done.stderr.count("\n") == 1, done.stderr
            if "no checkpoint" in done.stderr:
                assert not had_checkpoint, done.stderr
                c["refused: killed before the first checkpoint"] += 1
                c["typed_error"] += 1
                return
            assert "already finished" in done.stderr, done.stderr
            break
    if done.returncode == 0:  # the kill point was not reached: a finished run; resume refuses
        again_done = _run(out, steps, save_every, "--resume")
        assert again_done.returncode == 1 and "already finished" in again_done.stderr
    got = _arrays(out / "trajectory.npz")
    if got != ref:
        c["silent data loss"] += 1
        raise AssertionError(f"trajectory differs from the uninterrupted run ({first}, {again})")
    c["ok"] += 1
