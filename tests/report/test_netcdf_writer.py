"""``trajectory.nc`` written by scipy alone is the file xarray's scipy engine writes.

Truth used: xarray itself. The description a run builds is turned into an
:class:`xarray.Dataset` and written with ``to_netcdf(engine="scipy")`` (what ``poissonkit run``
did before); the file written without xarray must read back ``.identical()`` to it, with every
array equal to the bit, and be the same bytes. The shipped scenes run through the command line
in this process (the writer is captured on the way); the hand-made descriptions cover what the
scenes do not hold (non-ASCII names, 64-bit integers, booleans, a coordinate of no variable).
A fresh interpreter checks that a run does not import xarray, pandas or dask.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from poissonkit import cli
from poissonkit.report import trajectory
from poissonkit.report.netcdf_writer import DatasetDescription, write_netcdf

xr = pytest.importorskip("xarray")
ROOT = Path(__file__).resolve().parents[2]


def _xarray_file(description: DatasetDescription, path: Path) -> Path:
    description.to_xarray().to_netcdf(path, engine="scipy")
    return path


def _assert_same(ours: Path, theirs: Path) -> None:
    with xr.open_dataset(ours, engine="scipy") as a, xr.open_dataset(theirs, engine="scipy") as b:
        a, b = a.load(), b.load()
        assert a.identical(b)
        for name in b.variables:  # identical() takes NaN == NaN: compare the bits too
            x, y = a[name].values, b[name].values
            assert x.dtype == y.dtype, name
            if x.dtype.kind == "f":
                assert x.tobytes() == y.tobytes(), name
    assert ours.read_bytes() == theirs.read_bytes()


def _run_scene(argv: list[str], out: Path, monkeypatch: pytest.MonkeyPatch
               ) -> DatasetDescription:
    """Run ``poissonkit run`` here and return the description its ``trajectory.nc`` came from."""
    seen: list[DatasetDescription] = []
    write = trajectory.write_description

    def spy(path: Path, description: DatasetDescription) -> Path:
        seen.append(description)
        return write(path, description)

    monkeypatch.setattr(trajectory, "write_description", spy)
    code = cli.main(["run", *argv, "--no-plot", "--no-progress", "--out", str(out)])
    assert code == 0
    assert len(seen) == 1
    return seen[0]


#: The field and planetary scenes compile their own kernels (about a minute each, cold cache).
SLOW = pytest.mark.slow


@pytest.mark.parametrize("argv", [
    ["two_magnets"],
    ["seed000", "--param", "periods=0.2"],  # two-body centre-of-mass form
    pytest.param(["levitron", "--duration", "0.01"], marks=SLOW),  # one top in a ring's field
    pytest.param(["outer_solar_system", "--duration", "300"],  # AU, days, Msun; elements
                 marks=SLOW),
], ids=lambda argv: argv[0])
def test_run_file_is_xarrays_file(argv: list[str], tmp_path: Path,
                                  monkeypatch: pytest.MonkeyPatch) -> None:
    description = _run_scene(argv, tmp_path / "run", monkeypatch)
    written = tmp_path / "run" / "trajectory.nc"
    reference = _xarray_file(description, tmp_path / "xarray.nc")
    _assert_same(written, reference)
    with xr.open_dataset(written, engine="scipy") as ds:  # and what the run had in memory
        assert ds.load().identical(description.to_xarray())


def _hand_made() -> DatasetDescription:
    rng = np.random.default_rng(7)
    values = rng.standard_normal((4, 3, 3))
    values[1, 2, 0] = np.nan
    return DatasetDescription(
        data_vars={
            "position": (("time", "body", "component"), values, {"units": "AU"}),
            "count": (("body",), np.array([1, 2, 2**31 - 1], dtype=np.int64), {}),
            "flag": (("body",), np.array([0, 1, 0], dtype=np.int8), {"long_name": "é"}),
            "weights": (("body",), np.array([1.0, 2.5, -0.0], dtype=np.float32), {}),
        },
        coords={
            "time": (("time",), np.linspace(0.0, 1.0, 4), {"units": "yr"}),
            "time_internal": (("time",), np.arange(4.0), {}),
            "label": (("extra",), np.array(["ünï", "b"]), {}),  # belongs to no variable
            "body": (("body",), np.array(["α Cen A", "Sun", "x"]), {}),
            "component": (("component",), np.array(["x", "y", "z"]), {}),
        },
        attrs={"title": "hand made", "n": 3, "ok": True, "G": 39.47841760435743,
               "text": "ünicode"})


def test_hand_made_description_is_xarrays_file(tmp_path: Path) -> None:
    description = _hand_made()
    _assert_same(write_netcdf(tmp_path / "ours.nc", description),
                 _xarray_file(description, tmp_path / "xarray.nc"))


def test_an_empty_state_is_xarrays_file(tmp_path: Path) -> None:
    """Every body fixed: a state of length 0, a dimension scipy takes as its record one (the
    all-fixed scene of the run-settings tests failed on it first)."""
    description = DatasetDescription(
        data_vars={"y": (("time", "state"), np.zeros((3, 0)), {"units": "internal"})},
        coords={"time": (("time",), np.arange(3.0), {"units": "s"})}, attrs={})
    ours = write_netcdf(tmp_path / "ours.nc", description)
    # the same bytes as xarray's file (which scipy's reader cannot open either: a record
    # dimension with no record, a limit of scipy.io.netcdf left as it was)
    assert ours.read_bytes() == _xarray_file(description, tmp_path / "xarray.nc").read_bytes()


def test_int64_beyond_32_bits_is_refused_like_xarray(tmp_path: Path) -> None:
    description = DatasetDescription(
        data_vars={"big": (("n",), np.array([2**40], dtype=np.int64), {})})
    with pytest.raises(ValueError):
        description.to_xarray().to_netcdf(tmp_path / "xarray.nc", engine="scipy")
    with pytest.raises(ValueError, match="int32"):
        write_netcdf(tmp_path / "ours.nc", description)


WRAPPER = """
import atexit, runpy, sys

def heavy():
    loaded = sorted(m for m in sys.modules if m.split(".")[0] in {"xarray", "pandas", "dask"})
    print("HEAVY=" + ",".join(loaded))

atexit.register(heavy)
sys.argv = ["poissonkit", *sys.argv[1:]]
runpy.run_module("poissonkit", run_name="__main__", alter_sys=True)
"""


def test_run_no_plot_imports_no_xarray_pandas_dask(tmp_path: Path) -> None:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT), str(ROOT / "plugins"), os.environ.get("PYTHONPATH", "")])}
    argv = [sys.executable, "-c", WRAPPER, "run", "two_magnets", "--no-plot", "--no-progress",
            "--out", str(tmp_path / "run")]
    done = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=600,
                          check=False)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "run" / "trajectory.nc").is_file()
    assert "HEAVY=\n" in done.stdout, done.stdout
