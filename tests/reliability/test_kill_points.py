"""Kill a checkpointed ``poissonkit run`` at every phase boundary (injected kill points,
:mod:`poissonkit.killpoints`), resume it, and compare the trajectory with an
uninterrupted run's, bit for bit; a kill after the commit record (``summary.json``) leaves a
finished run that ``--resume`` refuses, untouched."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from checkout_env import checkout_env  # type: ignore[import-not-found]

from poissonkit.killpoints import ENV, PHASES

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
#: 1000 steps, a checkpoint (and a part) every 100: 10 checkpoints, 11 parts, 1001 rows
RUN = ["run", str(TWO), "--duration", "0.001", "--step", "1e-6", "--no-progress", "--no-plots"]
EVERY = ["--checkpoint-every", "100"]

#: phase -> (kill spec, does the resume finish the run (True) or refuse a finished one (False))
CASES = {
    "part-tmp": ("part-tmp@3", True),
    "part-written": ("part-written@3", True),
    "checkpoint-tmp": ("checkpoint-tmp@3", True),
    "checkpoint-written": ("checkpoint-written@3", True),
    "truncate": ("truncate@1", True),  # killed again while the resume removes a stale part
    "gather-tmp": ("gather-tmp@1", True),
    "gather-written": ("gather-written@1", True),
    "summary-written": ("summary-written@1", False),
    "parts-removing": ("parts-removing@1", False),
}
FAST = {"part-written", "gather-tmp", "parts-removing"}  # the others run with -m slow


def _env(kill: str | None = None) -> dict[str, str]:
    return checkout_env(**{ENV: kill or None})


def _run(out: Path, *extra: str, kill: str | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "poissonkit", *RUN, "--out", str(out), *extra],
                          env=_env(kill), capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> dict[str, np.ndarray]:
    out = tmp_path_factory.mktemp("reference") / "out"
    done = _run(out)
    assert done.returncode == 0, done.stderr
    with np.load(out / "trajectory.npz") as z:
        return {k: z[k] for k in z.files}


def test_every_phase_is_covered():
    assert set(CASES) == set(PHASES)


@pytest.mark.parametrize("phase", [p if p in FAST else pytest.param(p, marks=pytest.mark.slow)
                                   for p in PHASES])
def test_kill_at_phase_then_resume_is_bit_identical(tmp_path, reference, phase):
    kill, resumes = CASES[phase]
    out = tmp_path / "out"
    if phase == "truncate":  # leave a part written after the newest checkpoint first
        assert _run(out, *EVERY, kill="part-written@3").returncode == -9
        killed = _run(out, "--resume", kill=kill)
    else:
        killed = _run(out, *EVERY, kill=kill)
    assert killed.returncode == -9, killed.stderr  # it did die at the kill point
    assert "Traceback" not in killed.stderr
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    resumed = _run(out, "--resume")
    assert "Traceback" not in resumed.stderr
    if resumes:
        assert resumed.returncode == 0, resumed.stderr
        summary = (out / "summary.json").read_text()
        assert '"resumed_from": "checkpoint-' in summary
    else:  # the run had finished: refused in one line, summary and trajectory untouched
        assert resumed.returncode == 1
        assert resumed.stderr.count("\n") == 1 and "already finished" in resumed.stderr
        for name in ("summary.json", "trajectory.npz"):
            assert (out / name).read_bytes() == before[name]
    with np.load(out / "trajectory.npz") as z:
        assert z.files == list(reference)
        for k, v in reference.items():
            assert z[k].dtype == v.dtype and z[k].tobytes() == v.tobytes(), k
    # nothing left behind: no temporary file, no stale parts
    leftovers = [p for p in out.rglob(".*") if ".tmp" in p.name]
    assert not leftovers
    assert not (out / "trajectory.parts").exists()


def test_kill_before_the_first_checkpoint_is_refused_in_one_line(tmp_path):
    out = tmp_path / "out"
    assert _run(out, *EVERY, kill="part-tmp@1").returncode == -9
    resumed = _run(out, "--resume")
    assert resumed.returncode == 1 and "Traceback" not in resumed.stderr
    assert "no checkpoint" in resumed.stderr and resumed.stderr.count("\n") == 1


@pytest.fixture(scope="module")
def killed_while_cleaning(tmp_path_factory) -> Path:
    """A run killed after its summary, while removing its parts (a finished run)."""
    out = tmp_path_factory.mktemp("cleaning") / "out"
    assert _run(out, *EVERY, kill="parts-removing@1").returncode == -9
    return out


@pytest.mark.parametrize("damage", ["truncated", "deleted", "status-null", "status-interrupted",
                                    "list"])
def test_a_finished_run_killed_while_cleaning_keeps_its_files_when_its_summary_is_damaged(
        tmp_path, killed_while_cleaning, damage):
    import json
    import shutil

    out = tmp_path / "out"
    shutil.copytree(killed_while_cleaning, out)
    summary = out / "summary.json"
    if damage == "truncated":
        summary.write_bytes(summary.read_bytes()[:-2])
    elif damage == "deleted":
        summary.unlink()
    elif damage == "list":
        summary.write_text("[]")
    else:
        doc = json.loads(summary.read_text())
        doc["status"] = None if damage == "status-null" else "interrupted"
        summary.write_text(json.dumps(doc))
    def files() -> dict[str, bytes]:  # (the lock file of the killed run is not a result)
        return {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*")
                if p.is_file() and p.name != ".poissonkit.lock"}

    before = files()
    resumed = _run(out, "--resume")
    assert resumed.returncode == 1 and "Traceback" not in resumed.stderr
    assert resumed.stderr.count("\n") == 1 and "finished" in resumed.stderr, resumed.stderr
    assert files() == before
