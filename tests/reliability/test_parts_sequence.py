"""Reassembled rows are checked: a missing, duplicated or damaged part is refused with a typed
error (never a gap presented as a trajectory); the streamed gather writes the same npz as the
in-memory writer; a finished run is refused by --resume and left untouched."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from reliability_helpers import bound_pair, orbit_state  # type: ignore[import-not-found]

from poissonkit import cli
from poissonkit.errors import InputError, PoissonkitError
from poissonkit.numerics import solve
from poissonkit.numerics.checkpoint import TrajectoryStream, read_trajectory
from poissonkit.numerics.parts import PartsError, verify_parts
from poissonkit.report import atomic
from poissonkit.report.gather import gather_trajectory
from poissonkit.report.resume import RunFinishedError, prepare_resume
from poissonkit.report.summary import write_trajectory


def _streamed(folder, max_rows=50, steps=400):
    stream = TrajectoryStream(folder, max_rows=max_rows)
    solve(bound_pair(), orbit_state(), steps * 1e-3, "splitting4", step=1e-3, stream=stream)
    return stream


def test_parts_record_their_rows_and_form_one_sequence(tmp_path):
    stream = _streamed(tmp_path / "p")
    infos = verify_parts(stream.folder)
    assert infos[0].first == 0 and infos[-1].stop == stream.rows == 401
    assert all(a.stop == b.first for a, b in zip(infos, infos[1:]))


@pytest.mark.parametrize("damage", ["missing", "duplicate", "truncated", "foreign"])
def test_a_broken_sequence_is_refused(tmp_path, damage):
    stream = _streamed(tmp_path / "p")
    files = stream.part_files()
    if damage == "missing":  # what a kill during an unordered removal used to leave
        files[3].unlink()
    elif damage == "duplicate":  # a part of rows already held, under the next number
        shutil.copy(files[2], files[3])
    elif damage == "truncated":
        files[3].write_bytes(files[3].read_bytes()[:100])
    else:  # parts of a fresh run after another run's: rows restart at 0
        shutil.copy(files[0], stream.folder / f"part-{len(files):06d}.npz")
    with pytest.raises(PartsError) as info:
        read_trajectory(stream.folder)
    assert isinstance(info.value, PoissonkitError)
    with pytest.raises(PartsError):
        gather_trajectory(tmp_path / "t.npz", stream.folder)
    assert not (tmp_path / "t.npz").exists() and not list(tmp_path.glob(".*tmp*"))


def test_resume_refuses_missing_parts_and_removes_nothing(tmp_path):
    stream = _streamed(tmp_path / "p")
    names = [p.name for p in stream.part_files()]
    stream.part_files()[1].unlink()
    with pytest.raises(PartsError, match="missing"):
        TrajectoryStream(stream.folder).truncate(5, 250)
    assert [p.name for p in stream.part_files()] == names[:1] + names[2:]
    with pytest.raises(PartsError, match="rows"):  # a checkpoint counting other rows
        TrajectoryStream(tmp_path / "p").truncate(1, 7)


def test_a_fresh_run_into_a_folder_with_parts_is_refused(tmp_path):
    _streamed(tmp_path / "p")
    with pytest.raises(InputError, match="already holds trajectory parts"):
        solve(bound_pair(), orbit_state(), 0.1, "splitting4", step=1e-3,
              stream=tmp_path / "p")


def test_streamed_gather_writes_the_same_npz(tmp_path):
    stream = _streamed(tmp_path / "p", max_rows=37)
    t, y = read_trajectory(stream.folder)
    extra = {"scale_si": np.array([1.5, 2.5]), "scale_kinds": np.array(["a", "b"])}
    write_trajectory(tmp_path / "ref.npz", t, y, layout=("a",) * 18, time_unit=2.5,
                     r_rel_si=y[:, :3] * 3.0, **extra)
    rows = gather_trajectory(tmp_path / "new.npz", stream.folder, layout=("a",) * 18,
                             time_unit=2.5, row_maps={"r_rel_si": lambda b: b[:, :3] * 3.0},
                             **extra)
    assert rows == len(t)
    with np.load(tmp_path / "ref.npz") as a, np.load(tmp_path / "new.npz") as b:
        assert a.files == b.files
        for k in a.files:
            assert a[k].dtype == b[k].dtype and a[k].shape == b[k].shape
            assert a[k].tobytes() == b[k].tobytes(), k


def test_stale_temporaries_are_removed_and_nothing_else(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic.atomic_path(tmp_path / "trajectory.npz") as tmp:
            tmp.write_bytes(b"half")
            stray = tmp.with_name(tmp.name.replace("trajectory", "summary"))
            shutil.copy(tmp, stray)  # a file a kill (no cleanup) would have left
            raise RuntimeError
    (tmp_path / ".keep").write_text("not ours")
    (tmp_path / "a.tmp").write_text("not ours")
    assert atomic.remove_stale_temps(tmp_path) == [stray]
    assert sorted(p.name for p in tmp_path.iterdir()) == [".keep", "a.tmp"]


def test_resume_of_a_finished_run_is_refused_untouched(tmp_path, capsys):
    out = tmp_path / "out"
    run = ["run", str(cli_scene()), "--duration", "0.0002", "--step", "1e-6", "--no-progress",
           "--no-plots", "--out", str(out)]
    assert cli.main([*run, "--checkpoint-every", "50"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    capsys.readouterr()
    assert cli.main([*run, "--resume"]) == 1
    err = capsys.readouterr().err
    assert "already finished" in err and "201 rows" in err and err.count("\n") == 1
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before
    (out / "trajectory.npz").unlink()  # a finished run whose trajectory is gone: still refused
    with pytest.raises(RunFinishedError, match="trajectory.npz is missing"):
        prepare_resume(out)
    assert (out / "summary.json").read_bytes() == before["summary.json"]


def cli_scene():
    from pathlib import Path

    return Path(__file__).resolve().parents[2] / "poissonkit" / "scene" / "shipped" / "two_magnets.toml"


def test_long_trajectory_dataset_is_a_zarr_store_written_in_parts(tmp_path, monkeypatch):
    import xarray as xr

    from poissonkit.commands import run as run_command

    run = ["run", str(cli_scene()), "--duration", "0.0002", "--step", "1e-6", "--no-progress",
           "--no-plots", "--checkpoint-every", "50"]
    assert cli.main([*run, "--out", str(tmp_path / "nc")]) == 0
    monkeypatch.setattr(run_command, "DATASET_MAX_ROWS", 100)  # 201 rows: above it
    assert cli.main([*run, "--out", str(tmp_path / "zarr")]) == 0
    assert not (tmp_path / "zarr" / "trajectory.nc").exists()
    with xr.open_dataset(tmp_path / "nc" / "trajectory.nc") as a, \
            xr.open_zarr(tmp_path / "zarr" / "trajectory.zarr") as b:
        assert set(a.data_vars) == set(b.data_vars) and a.sizes == b.sizes
        for k in [*a.data_vars, "time", "time_internal"]:
            assert np.array_equal(a[k].values, b[k].values), k
    assert not list((tmp_path / "zarr").glob(".*"))


def test_a_stopped_run_keeps_its_parts_and_resumes_every_row(tmp_path, monkeypatch):
    from poissonkit.commands import run as run_command

    class StopSoon:  # a SIGINT after a few chunks of steps
        def __init__(self) -> None:
            self.calls = 0

        def __enter__(self) -> StopSoon:
            return self

        def __exit__(self, *exc: object) -> None:
            pass

        def __call__(self) -> bool:
            self.calls += 1
            return self.calls >= 3

    run = ["run", str(cli_scene()), "--duration", "0.0003", "--step", "1e-6", "--no-progress",
           "--no-plots"]
    assert cli.main([*run, "--out", str(tmp_path / "ref")]) == 0
    out = tmp_path / "out"
    with monkeypatch.context() as m:
        m.setattr(run_command, "_StopOnSigint", StopSoon)
        assert cli.main([*run, "--checkpoint-every", "40", "--out", str(out)]) == 130
    assert (out / "trajectory.parts").is_dir()  # kept for --resume
    assert cli.main([*run, "--out", str(out), "--resume"]) == 0
    with np.load(tmp_path / "ref" / "trajectory.npz") as a, np.load(out / "trajectory.npz") as b:
        assert a.files == b.files
        assert all(a[k].tobytes() == b[k].tobytes() for k in a.files)
    assert not (out / "trajectory.parts").exists()
