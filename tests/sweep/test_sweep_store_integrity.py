"""A damaged sweep store is never read back as data: resume recomputes what it cannot trust.

Truth: an uninterrupted sweep of the same grid (itself checked against a plain loop over the
scene in this process). Each test damages a copy of its store the way a disk, a user or a
killed client can -- a chunk file deleted, truncated or with flipped bytes, a completion record
deleted or garbled -- resumes it, and requires values identical to the uninterrupted sweep, in
the returned dataset and in the store as xarray opens it, with a warning naming how many points
were recomputed and why.
"""

from __future__ import annotations

import shutil
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import zarr
from hypothesis import given, settings
from hypothesis import strategies as st

from poissonkit.errors import InputError
from poissonkit.sweeps import sweep
from poissonkit.sweeps.integrity import (
    RECORDS,
    StoreRepairWarning,
    chunk_regions,
    chunk_shape,
    record_name,
    region_points,
)
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, reduce_run
from poissonkit.sweeps.params import design_from
from poissonkit_magnets.seed000_sweep import SeedScene

SEED_OPTIONS = {"periods": 4.0}
PARAMS = ["spin_ratio=0:20:4", "tilt=0,0.05,0.1"]  # 12 points
BATCH = 3  # chunks of (1, 3): four batches of three points


def _open(store: Path) -> xr.Dataset:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zarr 3: consolidated metadata not in the spec yet
        with xr.open_zarr(store) as ds:
            return ds.load()


@pytest.fixture(scope="module")
def reference(dask_client, tmp_path_factory):
    """An uninterrupted sweep's store, checked against a plain loop over the scene."""
    store = tmp_path_factory.mktemp("ref") / "ref.zarr"
    sweep("seed000", PARAMS, client=dask_client, store=store, batch_size=BATCH, progress=False,
          **SEED_OPTIONS)
    ds = _open(store)
    scene = SeedScene(**SEED_OPTIONS)
    prep = scene.prepare()
    design = design_from(PARAMS)
    for k, values in list(design.points())[::5]:  # a few points are enough to pin the store
        res = reduce_run(scene.run(prep, values), DEFAULT_OUTCOMES)
        idx = np.unravel_index(k, design.shape)
        for n in DEFAULT_OUTCOMES:
            np.testing.assert_array_equal(float(ds[n].values[idx]), float(res[n]), err_msg=n)
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())
    return store, ds


def _copy(reference, tmp_path: Path) -> Path:
    store = tmp_path / "copy.zarr"
    shutil.copytree(reference[0], store)
    return store


def chunk_file(store: Path, name: str, point: tuple[int, ...]) -> Path:
    """The file holding ``point`` of variable ``name`` (whatever the store's chunking)."""
    arr = zarr.open_group(str(store), mode="r")[name]
    coords = tuple(i // c for i, c in zip(point, arr.chunks))
    return store / name / arr.metadata.encode_chunk_key(coords)


def _truncate(path: Path) -> None:
    with open(path, "r+b") as f:
        f.truncate(max(1, path.stat().st_size // 2))


def _flip(path: Path) -> None:
    data = bytearray(path.read_bytes())
    for k in range(len(data) // 2, len(data)):
        data[k] ^= 0x5A
    path.write_bytes(bytes(data))


def _resume(store: Path, client) -> tuple[xr.Dataset, list[str], list[int]]:
    ran: list[int] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = sweep("seed000", PARAMS, client=client, store=store, resume=True, progress=False,
                   on_batch=lambda done, total: ran.append(done), **SEED_OPTIONS)
    said = [str(w.message) for w in caught if issubclass(w.category, StoreRepairWarning)]
    return ds, said, ran


def assert_same(got: xr.Dataset, ref: xr.Dataset) -> None:
    for name in ref.variables:
        np.testing.assert_array_equal(np.asarray(got[name].values),
                                      np.asarray(ref[name].values), err_msg=str(name))
        assert got[name].attrs == ref[name].attrs, name
    assert got.attrs == ref.attrs


P = (2, 1)  # a point in the third chunk (spin_ratio index 2)

DAMAGES: dict[str, tuple[Callable[[Path], None], int, str]] = {
    # what is done to the copy, how many points must be recomputed, the reason given
    "fate chunk deleted": (lambda s: chunk_file(s, "fate", P).unlink(), 3, "missing chunk"),
    "min_distance chunk deleted": (lambda s: chunk_file(s, "min_distance", P).unlink(), 3,
                                   "missing chunk"),
    "every min_distance chunk deleted": (
        lambda s: [f.unlink() for f in (s / "min_distance").rglob("*") if f.is_file()
                   and f.name != "zarr.json"], 12, "missing chunk"),
    "completed chunk deleted": (lambda s: chunk_file(s, "completed", P).unlink(), 3,
                                "missing chunk"),
    "chunk truncated": (lambda s: _truncate(chunk_file(s, "min_distance", P)), 3,
                        "unreadable chunk"),
    "chunk bytes flipped": (lambda s: _flip(chunk_file(s, "end_time", P)), 3,
                            "unreadable chunk|differ from their checksum"),
    "completion record deleted": (lambda s: shutil.rmtree(s / RECORDS / record_name((2, 0))),
                                  3, "without a completion record"),
    "completion record garbled": (
        lambda s: (s / RECORDS / record_name((2, 0)) / "zarr.json").write_text('{"attrib'), 3,
        "damaged completion record"),
}


@pytest.mark.parametrize("kind", list(DAMAGES))
def test_resume_recomputes_damaged_points_and_says_so(kind, reference, dask_client, tmp_path):
    damage, points, reason = DAMAGES[kind]
    store = _copy(reference, tmp_path)
    damage(store)
    ds, said, ran = _resume(store, dask_client)
    assert_same(ds, reference[1])
    assert_same(_open(store), reference[1])  # the repaired store, as xarray reads it
    assert len(said) == 1, said
    assert f"{points} stored points cannot be trusted" in said[0], said[0]
    assert any(r in said[0] for r in reason.split("|")), said[0]
    assert len(ran) == points // BATCH and ran[-1] == 12  # only the damaged chunks ran
    # and a second resume trusts everything: nothing to say, nothing to run
    again, said, ran = _resume(store, dask_client)
    assert said == [] and ran == []
    assert_same(again, reference[1])


def test_interrupted_sweep_resumes_silently_to_the_same_values(reference, dask_client,
                                                               tmp_path):
    store = tmp_path / "cut.zarr"

    def stop(done, total):
        raise KeyboardInterrupt  # the client stops after its first finished batch

    with pytest.raises(KeyboardInterrupt):
        sweep("seed000", PARAMS, client=dask_client, store=store, batch_size=BATCH,
              progress=False, on_batch=stop, **SEED_OPTIONS)
    with warnings.catch_warnings():
        warnings.simplefilter("error", StoreRepairWarning)  # chunks never reached are no damage
        ds, said, ran = _resume(store, dask_client)
    assert said == [] and ran[0] <= 12 - BATCH
    assert_same(ds, reference[1])
    assert_same(_open(store), reference[1])


def test_batches_own_their_chunks_and_each_has_a_record(reference):
    store = reference[0]
    group = zarr.open_group(str(store), mode="r")
    shape = (4, 3)
    for name in [*DEFAULT_OUTCOMES, "completed", "failed", "error"]:
        assert tuple(group[name].chunks) == (1, 3), name
    for coords, region in chunk_regions(shape, (1, 3)):
        rec = zarr.open_group(store=str(store), path=f"{RECORDS}/{record_name(coords)}",
                              mode="r")
        assert rec.attrs["points"] == region_points(shape, region).size == 3
        assert set(rec.attrs["sha256"]) == {*DEFAULT_OUTCOMES, "completed", "failed", "error"}


def test_damaged_metadata_is_a_typed_error(reference, dask_client, tmp_path):
    store = _copy(reference, tmp_path)
    _truncate(store / "zarr.json")
    with pytest.raises(InputError, match="damaged.*overwrite"):
        sweep("seed000", PARAMS, client=dask_client, store=store, resume=True, progress=False,
              **SEED_OPTIONS)
    # overwriting starts again and gives the uninterrupted values
    sweep("seed000", PARAMS, client=dask_client, store=store, overwrite=True, batch_size=BATCH,
          progress=False, **SEED_OPTIONS)
    assert_same(_open(store), reference[1])


@settings(max_examples=200, deadline=None, database=None)
@given(shape=st.lists(st.integers(1, 9), min_size=1, max_size=4),
       target=st.integers(1, 100))
def test_chunks_partition_the_grid(shape, target):
    """Every point lies in exactly one chunk; no chunk holds more than ``target`` points."""
    chunks = chunk_shape(shape, target)
    seen = np.zeros(int(np.prod(shape)), dtype=int)
    for _, region in chunk_regions(shape, chunks):
        flat = region_points(shape, region)
        assert 1 <= flat.size <= max(1, target)
        seen[flat] += 1
    assert (seen == 1).all()


def test_a_store_without_records_is_recomputed_with_a_warning(reference, dask_client,
                                                              tmp_path):
    """A store as written before the records existed: one chunk per variable, no records."""
    store = tmp_path / "old.zarr"
    old = reference[1].copy(deep=True)
    for v in old.variables.values():
        v.encoding = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        old.to_zarr(store, mode="w")
    assert zarr.open_group(str(store), mode="r")["fate"].chunks == (4, 3)
    ds, said, ran = _resume(store, dask_client)
    assert len(said) == 1 and "12 stored points" in said[0] and "completion record" in said[0]
    assert ran == [12]
    assert_same(ds, reference[1])
    assert_same(_open(store), reference[1])


def test_a_damaged_group_of_records_is_written_again(reference, dask_client, tmp_path):
    """Found by the fuzz: the records' group document garbled, then a chunk lost."""
    store = _copy(reference, tmp_path)
    (store / RECORDS / "zarr.json").write_bytes(b"\xfb{")
    chunk_file(store, "completed", (0, 0)).unlink()
    ds, said, ran = _resume(store, dask_client)
    assert_same(ds, reference[1])
    assert_same(_open(store), reference[1])
    assert len(said) == 1 and "3 stored points" in said[0] and ran == [12]
