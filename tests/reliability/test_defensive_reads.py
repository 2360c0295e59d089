"""Files read defensively, messages in the user's units.

* A checkpoint whose checksum matches but whose content has the wrong types (a hand-made or
  foreign file) is a ``CheckpointError``; before, the resume raised ``AttributeError``,
  ``TypeError`` or ``KeyError``.
* ``poissonkit view`` on a damaged folder is one line of typed error; before: ``IndexError``,
  plotly's ``ValueError``, ``IsADirectoryError``.
* ``run`` checks its times in seconds before it starts; before: "step 100.0 is longer than
  t_end − t0 = 5.0" for ``--step 1 --duration 0.05``, "t_eval must be a non-empty 1-D sequence"
  for a ``--save-dt`` as long as the run, and two values of one ``--param`` were resolved
  silently.
"""

from __future__ import annotations

import hashlib
import io
import json
from pathlib import Path

import numpy as np
import pytest
from reliability_helpers import bound_pair, orbit_state  # type: ignore[import-not-found]

from poissonkit import cli
from poissonkit.numerics import solve
from poissonkit.numerics.checkpoint import (
    MAGIC,
    Checkpoint,
    CheckpointError,
    checkpoints,
    read_checkpoint,
)

ROOT = Path(__file__).resolve().parents[2]
TWO = ROOT / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"
QUIET = ["--no-progress", "--no-plots"]


def _forge(path: Path, arrays: dict, meta: object) -> None:
    """Write a checkpoint with a valid checksum around any content."""
    buf = io.BytesIO()
    np.savez(buf, meta=np.array(json.dumps(meta)), **arrays)
    payload = buf.getvalue()
    path.write_bytes(MAGIC + f"{hashlib.sha256(payload).hexdigest()} {len(payload)}\n".encode()
                     + payload)


def _meta(key, value):
    def edit(arrays, meta):
        meta[key] = value
        return arrays, meta
    return edit


def _array(key, value):
    def edit(arrays, meta):
        if value is None:
            arrays.pop(key)
        else:
            arrays[key] = value
        return arrays, meta
    return edit


CONTENT = {
    "meta-list": lambda a, m: (a, [1, 2]),
    "meta-string": lambda a, m: (a, "x"),
    "records-string": _meta("records", "x"),
    "records-bad-entry": _meta("records", [{"kind": 1}]),
    "records-extra-key": _meta("records", [{"kind": "contact", "step": 1, "time": 0.1,
                                            "value": 1.0, "evil": 1}]),
    "nfev-string": _meta("nfev", "3"),
    "every-zero": _meta("every", 0),
    "problem-missing": _meta("problem", None),
    "stream-string": _meta("stream_parts", "a"),
    "y-missing": _array("y", None),
    "t-text": _array("t", np.array("abc")),
    "steps-float": _array("steps", np.float64(3.5)),
    "hist-2d": _array("hist", np.zeros((2, 2))),
}


@pytest.mark.parametrize("damage", list(CONTENT))
def test_checkpoint_content_of_the_wrong_type_is_refused(tmp_path, damage):
    ck = Checkpoint(tmp_path / "ck", 50, keep=1)
    solve(bound_pair(), orbit_state(), 0.2, "splitting4", step=1e-3, checkpoint=ck)
    (path,) = checkpoints(ck.folder)
    arrays, meta = read_checkpoint(path)  # the real one reads
    _forge(path, *CONTENT[damage](dict(arrays), dict(meta)))
    with pytest.raises(CheckpointError, match="refusing it|not a checkpoint archive"):
        read_checkpoint(path)
    with pytest.raises(CheckpointError, match="no valid checkpoint"):
        solve(bound_pair(), orbit_state(), 0.4, "splitting4", step=1e-3, checkpoint=ck,
              resume=True)


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("view") / "out"
    assert cli.main(["run", str(TWO), "--duration", "0.0002", "--step", "1e-5", "--out",
                     str(out), *QUIET]) == 0
    return out


def _all_nan(path: Path) -> None:
    import xarray as xr

    with xr.open_dataset(path, engine="scipy") as ds:
        ds = ds.load()
    for k in ds.data_vars:
        if ds[k].dtype.kind == "f":
            ds[k].values[...] = np.nan
    path.unlink()
    ds.to_netcdf(path, engine="scipy")


def _truncate_to(n: int):
    return lambda p: p.write_bytes(p.read_bytes()[:n])


VIEW_DAMAGE = {
    **{f"truncated-{n}": _truncate_to(n) for n in (0, 4, 50, 400, 3000)},
    "truncated-half": lambda p: p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2]),
    "all-nan": _all_nan,
    "garbage": lambda p: p.write_bytes(b"CDF\x01" + bytes(range(256)) * 4),
}


@pytest.mark.parametrize("damage", [*VIEW_DAMAGE, "html-is-a-folder"])
def test_view_of_a_damaged_folder_is_one_line(run_folder, tmp_path, capsys, damage):
    import shutil

    out = tmp_path / "out"
    shutil.copytree(run_folder, out)
    if damage == "html-is-a-folder":
        (out / "trajectory.html").mkdir()
    else:
        VIEW_DAMAGE[damage](out / "trajectory.nc")
    capsys.readouterr()
    assert cli.main(["view", str(out), "--no-open"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("poissonkit view: error:") and err.count("\n") == 1, err


@pytest.mark.parametrize(("args", "message"), [
    (["--step", "1", "--duration", "0.05"],
     "the step 1 s is longer than the run's duration 0.05 s"),
    (["--save-dt", "0.05", "--duration", "0.05"],
     "--save-dt 0.05 s is not shorter than the run's duration 0.05 s"),
    (["--save-dt", "0.1", "--duration", "0.05"], "not shorter than the run's duration 0.05 s"),
    (["--save-dt", "1e-12", "--duration", "0.05"], "--save-dt 1e-12 s over 0.05 s gives"),
])
def test_times_are_checked_in_seconds_before_the_run(tmp_path, capsys, args, message):
    out = tmp_path / "o"
    assert cli.main(["run", str(TWO), *args, "--out", str(out), *QUIET]) == 1
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


def test_two_values_of_one_param_are_refused(tmp_path, capsys):
    assert cli.main(["run", "seed000", "--param", "tilt=0.1", "--param", "tilt=0.2", "--out",
                     str(tmp_path / "o"), *QUIET]) == 1
    assert "--param tilt is given twice" in capsys.readouterr().err


def test_a_long_save_dt_says_its_cost_before_it_starts():
    from poissonkit.report.run_checks import save_dt_cost

    # 0.05 s every 1e-7 s: 5e5 samples + the first and last state, 25 numbers a row
    note = save_dt_cost(1e-7, 0.05, 1.0, 24)
    assert note is not None and "500,002 rows" in note and "95 MiB" in note
    assert save_dt_cost(1e-3, 0.05, 1.0, 24) is None
