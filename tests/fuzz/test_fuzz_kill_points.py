"""Fuzzing kills: ``poissonkit run`` killed at a drawn phase boundary (injected kill point,
:mod:`poissonkit.killpoints`), at a drawn occurrence within the run's reach, with drawn
checkpoint and save intervals, its first resume possibly killed again (``truncate`` included);
then resumed until it ends.

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
from checkout_env import checkout_env  # type: ignore[import-not-found]
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fuzzkit import COUNTS, slow
from poissonkit.numerics.checkpoint import checkpoints
from poissonkit.killpoints import ENV, PHASES

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
EXAMPLES = int(os.environ.get("POISSONKIT_FUZZ_KILL_EXAMPLES", "30"))
TIMEOUT_S = 300  # a process over this is a hang
_REFERENCES: dict[tuple[int, int], dict[str, bytes]] = {}


def _env(kill: str | None) -> dict[str, str]:
    return checkout_env(**{ENV: kill or None})


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


def _occurrences(phase: str, checkpoints_written: int) -> int:
    """How many times a run reaches ``phase``: once per checkpoint, once per part (one per
    checkpoint plus the last), or once."""
    if phase.startswith("checkpoint"):
        return checkpoints_written
    if phase.startswith("part"):
        return checkpoints_written + 1
    return 1


@slow
@settings(max_examples=EXAMPLES, deadline=TIMEOUT_S * 10 * 1000, database=None,
          suppress_health_check=list(HealthCheck))
@given(data=st.data(), steps=st.integers(150, 600), save_every=st.integers(1, 5))
def test_kill_at_drawn_points_then_resume(tmp_path_factory, data, steps, save_every):
    every = data.draw(st.integers(15, steps // 2), label="checkpoint every")
    n_ck = (steps - 1) // every
    first_phase = data.draw(st.sampled_from([p for p in PHASES if p != "truncate"]))
    first = (first_phase, data.draw(st.integers(1, _occurrences(first_phase, n_ck))))
    again_phase = data.draw(st.one_of(st.none(), st.sampled_from(PHASES)))
    again = None if again_phase is None else \
        (again_phase, data.draw(st.integers(1, max(1, _occurrences(again_phase, n_ck) // 2))))
    c = COUNTS.setdefault("kill points", Counter())
    c["tried"] += 1
    tmp = tmp_path_factory.mktemp("kill")
    ref = _reference(tmp_path_factory.getbasetemp(), steps, save_every)
    out = tmp / "out"
    done = _run(out, steps, save_every, "--checkpoint-every", str(every),
                kill=f"{first[0]}@{first[1]}")
    kills = [again and f"{again[0]}@{again[1]}", None, None]
    outcome = "not killed (finished; --resume refused it)" if done.returncode == 0 \
        else "killed, resumed bit-identical"
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
            outcome = "killed after its summary: refused as finished, intact"
            break
    assert done.returncode in (0, 1), done.stderr
    if done.returncode == 0:  # finished now: a further resume refuses it
        again_done = _run(out, steps, save_every, "--resume")
        assert again_done.returncode == 1 and "already finished" in again_done.stderr
    got = _arrays(out / "trajectory.npz")
    if got != ref:
        c["silent data loss"] += 1
        raise AssertionError(f"trajectory differs from the uninterrupted run ({first}, {again})")
    assert not [q for q in out.rglob(".*") if ".tmp" in q.name]  # no temporary left
    assert not (out / "trajectory.parts").exists()
    c[outcome] += 1
    c["ok"] += 1
