"""Fuzz: resuming damaged sweep stores.

A finished sweep's store is copied and damaged anywhere -- chunk files, completion records,
metadata documents (half of the operations), whole folders -- by 1 to 3 operations (delete, truncate, flip bytes, fill
with random bytes, empty), then resumed. Property: the resume either returns values identical
to the uninterrupted sweep, with the store as xarray opens it identical too, or refuses with a
:class:`~poissonkit.errors.PoissonkitError`; never another exception (a traceback), never a hang,
never silent data loss (a returned or stored value that differs from the uninterrupted sweep's,
NaN standing in for a value included). Counts are kept in :data:`fuzzkit.COUNTS` under
``sweep store`` and the extra ones below.
"""

from __future__ import annotations

import shutil
import tempfile
import time
import warnings
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from fuzzkit import COUNTS, DEADLINE_MS, FAST, SLOW, outcome, slow
from hypothesis import given, settings
from hypothesis import strategies as st

from poissonkit.sweeps import sweep
from poissonkit.sweeps.integrity import StoreRepairWarning

PARAMS = ["spin_ratio=0,10,20", "tilt=0,0.1"]  # 6 points
OPTIONS = {"periods": 2.0}
BATCH = 2  # chunks of (1, 2): three batches

#: ``repaired``: a warning named recomputed points; ``silent_loss``, ``hang``: must stay 0.
EXTRA: Counter = Counter()

OPS = ("delete", "truncate", "flip", "random", "empty")


@pytest.fixture(scope="module")
def client():
    """One in-process worker thread: the scene compiles once, each resume costs little."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                           dashboard_address=None)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def _open(store: Path) -> xr.Dataset:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with xr.open_zarr(store) as ds:
            return ds.load()


@pytest.fixture(scope="module")
def reference(client, tmp_path_factory):
    store = tmp_path_factory.mktemp("fuzzref") / "ref.zarr"
    sweep("seed000", PARAMS, client=client, store=store, batch_size=BATCH, progress=False,
          **OPTIONS)
    files = sorted(p.relative_to(store) for p in store.rglob("*") if p.is_file())
    dirs = sorted(p.relative_to(store) for p in store.rglob("*") if p.is_dir())
    return store, _open(store), files, dirs


def damage(store: Path, target: Path, op: str, data: st.DataObject) -> None:
    path = store / target
    if path.is_dir():
        shutil.rmtree(path, ignore_errors=True)
        return
    if not path.exists():
        return  # an earlier operation removed it
    raw = bytearray(path.read_bytes())
    if op == "delete":
        path.unlink()
    elif op == "truncate":
        path.write_bytes(bytes(raw[:data.draw(st.integers(0, max(0, len(raw) - 1)))]))
    elif op == "flip" and raw:
        for _ in range(data.draw(st.integers(1, 8))):
            k = data.draw(st.integers(0, len(raw) - 1))
            raw[k] ^= 1 << data.draw(st.integers(0, 7))
        path.write_bytes(bytes(raw))
    elif op == "random":
        path.write_bytes(data.draw(st.binary(min_size=0, max_size=64)))
    else:
        path.write_bytes(b"")


def same(got: xr.Dataset, ref: xr.Dataset) -> bool:
    """Every value, coordinate and attribute identical (NaN where the reference has NaN)."""
    if set(got.variables) != set(ref.variables) or got.attrs != ref.attrs:
        return False
    for name in ref.variables:
        a, b = np.asarray(got[name].values), np.asarray(ref[name].values)
        if a.shape != b.shape or got[name].attrs != ref[name].attrs:
            return False
        if a.dtype.kind == "f" or b.dtype.kind == "f":
            if not np.array_equal(a.astype(float), b.astype(float), equal_nan=True):
                return False
        elif [str(x) for x in a.ravel()] != [str(x) for x in b.ravel()]:
            return False
    return True


def check(reference, client, data: st.DataObject) -> None:
    ref_store, ref, files, dirs = reference
    targets = [*files, *dirs]
    metadata = [f for f in files if f.name == "zarr.json"]
    with tempfile.TemporaryDirectory(prefix="pk-fuzz-store-") as tmp:
        store = Path(tmp) / "s.zarr"
        shutil.copytree(ref_store, store)
        n = data.draw(st.integers(1, 3))
        for _ in range(n):
            # half of the damage goes to metadata documents, which are few among the files
            pool = metadata if data.draw(st.booleans()) else targets
            target = data.draw(st.sampled_from(pool))
            damage(store, target, data.draw(st.sampled_from(OPS)), data)
        start = time.monotonic()

        def resume() -> tuple[xr.Dataset, list[str]]:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                ds = sweep("seed000", PARAMS, client=client, store=store, resume=True,
                           progress=False, **OPTIONS)
            return ds, [str(w.message) for w in caught
                        if issubclass(w.category, StoreRepairWarning)]

        try:
            result = outcome("sweep store", resume)
        finally:
            if time.monotonic() - start > DEADLINE_MS / 1000:
                EXTRA["hang"] += 1
        if result is None:
            return  # refused with a typed error
        ds, said = result
        EXTRA["repaired"] += bool(said)
        ok = same(ds, ref) and same(_open(store), ref)
        if not ok:
            EXTRA["silent_loss"] += 1
        assert ok, "a resumed damaged store differs from the uninterrupted sweep"


@settings(FAST, max_examples=min(FAST.max_examples, 12))
@given(data=st.data())
def test_damaged_sweep_store(reference, client, data):
    check(reference, client, data)


@slow
@settings(SLOW, max_examples=min(SLOW.max_examples, 500))
@given(data=st.data())
def test_damaged_sweep_store_slow(reference, client, data):
    check(reference, client, data)


def teardown_module() -> None:
    c = COUNTS.get("sweep store")
    if c is not None:
        print(f"\nsweep store: tried {c['tried']}, identical {c['ok']}, typed errors "
              f"{c['typed_error']}, tracebacks {c['other']}, repaired with a warning "
              f"{EXTRA['repaired']}, hangs {EXTRA['hang']}, silent data loss "
              f"{EXTRA['silent_loss']}")
