"""``--resume`` never deletes a finished run's results, whatever is damaged in its folder.

A finished, checkpointed run holds ``summary.json`` (the commit record), ``trajectory.npz``,
``trajectory.nc`` and its last checkpoints. Before, a damaged summary (truncated, deleted,
``status`` null or ``"interrupted"``, ``[]``) made ``--resume`` take the run for an interrupted
one: it deleted the complete trajectory and the summary, and only then failed on the missing
parts. Now every such folder is refused in one line and keeps every byte.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from poissonkit import cli

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
RUN = ["run", str(TWO), "--duration", "0.0002", "--step", "1e-6", "--no-progress", "--no-plots"]


def _truncate(p: Path) -> None:
    p.write_bytes(p.read_bytes()[:-2])


def _status(value: object):
    def damage(p: Path) -> None:
        doc = json.loads(p.read_text())
        doc["status"] = value
        p.write_text(json.dumps(doc))
    return damage


#: damage to summary.json -> what is done to it
SUMMARY_DAMAGE = {
    "truncated": _truncate,
    "deleted": Path.unlink,
    "status-null": _status(None),
    "status-interrupted": _status("interrupted"),
    "list": lambda p: p.write_text("[]"),
}


def _bytes(out: Path) -> dict[str, bytes]:
    return {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*"))
            if p.is_file() and p.name != ".poissonkit.lock"}


@pytest.fixture(scope="module")
def finished(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("finished") / "out"
    assert cli.main([*RUN, "--checkpoint-every", "50", "--out", str(out)]) == 0
    return out


def _copy(finished: Path, tmp_path: Path) -> Path:
    out = tmp_path / "out"
    shutil.copytree(finished, out)
    return out


@pytest.mark.parametrize("damage", list(SUMMARY_DAMAGE))
def test_resume_keeps_every_byte_of_a_finished_run_with_a_damaged_summary(
        finished, tmp_path, capsys, damage):
    out = _copy(finished, tmp_path)
    SUMMARY_DAMAGE[damage](out / "summary.json")
    before = _bytes(out)
    assert len(before) >= 3  # trajectory.npz, trajectory.nc, checkpoints
    capsys.readouterr()
    assert cli.main([*RUN, "--out", str(out), "--resume"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "finished" in err and "trajectory.npz" in err
    assert _bytes(out) == before


def _damage_file(out: Path, name: str, how: str) -> None:
    p = next(q for q in sorted(out.rglob("*")) if q.is_file() and q.name.startswith(name))
    if how == "delete":
        p.unlink()
    elif how == "truncate":
        p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2])
    else:  # flip
        data = bytearray(p.read_bytes())
        data[len(data) // 2] ^= 0xFF
        p.write_bytes(bytes(data))


@pytest.mark.parametrize("name", ["trajectory.npz", "trajectory.nc", "checkpoint-"])
@pytest.mark.parametrize("how", ["delete", "truncate", "flip"])
@pytest.mark.parametrize("summary", ["intact", "deleted"])
def test_resume_of_a_damaged_finished_run_removes_nothing(finished, tmp_path, capsys, name, how,
                                                          summary):
    """Damage to each file a finished run holds (and to the summary with it): refused, nothing
    removed or changed."""
    out = _copy(finished, tmp_path)
    _damage_file(out, name, how)
    if summary == "deleted":
        (out / "summary.json").unlink()
    before = _bytes(out)
    capsys.readouterr()
    assert cli.main([*RUN, "--out", str(out), "--resume"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert _bytes(out) == before


def test_a_flipped_byte_in_a_compressed_member_is_damage_not_a_traceback(finished, tmp_path,
                                                                           capsys):
    """Found by the fuzz: a byte flipped near the start of ``trajectory.npz`` made zlib raise
    ``zlib.error`` from ``np.load``, a traceback from ``--resume``."""
    out = _copy(finished, tmp_path)
    p = out / "trajectory.npz"
    data = bytearray(p.read_bytes())
    data[len(data) // 32] ^= 0xFF
    p.write_bytes(bytes(data))
    before = _bytes(out)
    capsys.readouterr()
    assert cli.main([*RUN, "--out", str(out), "--resume"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "trajectory.npz is damaged" in err, err
    assert _bytes(out) == before
