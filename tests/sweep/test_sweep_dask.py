"""Sweeps on a real local Dask cluster (worker processes on loopback).

Truth: every point is also run in this process by a plain loop over the scene (no Dask, no
store); the sweep's dataset must hold exactly those numbers, whatever happened to the workers.
"""

from __future__ import annotations

import math
import os
import signal
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from poissonkit.errors import InputError
from poissonkit.sweeps import sweep
from poissonkit.sweeps.execute import builds
from poissonkit.sweeps.outcomes import DEFAULT_OUTCOMES, reduce_run
from poissonkit.sweeps.params import design_from
from poissonkit_magnets.seed000_sweep import SeedScene

SEED_OPTIONS = {"periods": 4.0}  # short runs, small grids

PARAMS = ["spin_ratio=0:20:3", "tilt=0,0.1"]
OUTS = [n for n in DEFAULT_OUTCOMES]


@pytest.fixture(scope="module")
def reference():
    """The same points in a plain loop in this process."""
    scene = SeedScene(**SEED_OPTIONS)
    prep = scene.prepare()
    design = design_from(PARAMS)
    out = {n: np.empty(design.shape, dtype=float) for n in OUTS}
    for k, values in design.points():
        res = reduce_run(scene.run(prep, values), OUTS)
        for n in OUTS:
            out[n].reshape(-1)[k] = res[n]
    return out


def assert_matches(ds, reference):
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())
    for n in OUTS:
        np.testing.assert_array_equal(ds[n].values.astype(float), reference[n], err_msg=n)


def test_sweep_dataset_store_and_kernels_built_once_per_worker(dask_client, reference, tmp_path):
    store = tmp_path / "s.zarr"
    ds = sweep("seed000", PARAMS, client=dask_client, store=store, batch_size=1,
               progress=False, **SEED_OPTIONS)
    assert ds["fate"].dims == ("spin_ratio", "tilt")
    assert ds["spin_ratio"].attrs["units"] == "1" and ds["tilt"].attrs["units"] == "rad"
    assert ds["min_distance"].attrs["units"] == "m"
    for key in ("scene", "method", "step", "poissonkit_version", "design"):
        assert key in ds.attrs, key
    assert_matches(ds, reference)
    # the store opens with plain xarray, with the same numbers and no missing point
    on_disk = xr.open_zarr(store).load()
    assert dict(on_disk.sizes) == {"spin_ratio": 3, "tilt": 2}
    assert_matches(on_disk, reference)
    # 6 tasks over 2 workers: the seed system was built once per worker process, not per task
    per_worker = dask_client.run(builds)
    assert sum(b.get("seed000", 0) for b in per_worker.values()) <= len(per_worker)
    # resuming a finished sweep computes nothing
    calls = []
    again = sweep("seed000", PARAMS, client=dask_client, store=store, resume=True,
                  progress=False, on_batch=lambda d, t: calls.append(d), **SEED_OPTIONS)
    assert calls == []
    assert_matches(again, reference)


def test_failed_point_is_recorded_with_its_message(dask_client, capsys):
    ds = sweep("seed000", {"radius_factor": [1.0, -1.0]}, client=dask_client, progress=True,
               fixed={"spin_ratio": 20.0}, **SEED_OPTIONS)
    bar = capsys.readouterr().err
    assert "2/2" in bar and "failures=1" in bar  # progress: runs done / total, failures
    assert ds["failed"].values.tolist() == [False, True]
    assert "radius_factor must be > 0" in str(ds["error"].values[1])
    assert ds["fate"].values.tolist() == [0, -1] and bool(ds["completed"].all())
    assert math.isnan(float(ds["min_distance"].values[1]))


def test_killed_worker_costs_only_its_tasks(dask_client, reference, tmp_path):
    pids = dask_client.run(os.getpid)
    victim = max(pids.values())
    killed = []

    def kill_once(done, total):
        if not killed:
            os.kill(victim, signal.SIGKILL)  # the worker process dies mid-sweep
            killed.append(done)

    ds = sweep("seed000", PARAMS, client=dask_client, store=tmp_path / "k.zarr", batch_size=1,
               progress=False, on_batch=kill_once, **SEED_OPTIONS)
    assert killed and killed[0] < 6
    assert victim not in dask_client.run(os.getpid).values()  # it really died
    assert_matches(ds, reference)
    assert_matches(xr.open_zarr(tmp_path / "k.zarr").load(), reference)
    dask_client.wait_for_workers(2, timeout=120)  # the nanny restarted it


def test_existing_store_needs_resume_or_overwrite(dask_client, tmp_path):
    store = tmp_path / "x.zarr"
    sweep("seed000", ["tilt=0"], client=dask_client, store=store, progress=False,
          **SEED_OPTIONS)
    with pytest.raises(InputError, match="resume"):
        sweep("seed000", ["tilt=0"], client=dask_client, store=store, progress=False,
              **SEED_OPTIONS)
    with pytest.raises(InputError, match="design"):
        sweep("seed000", ["tilt=0,0.1"], client=dask_client, store=store, resume=True,
              progress=False, **SEED_OPTIONS)


def test_random_design_through_a_scheduler_address(dask_client, reference):
    # the same sweep through --scheduler tcp://...: a client of its own on the running cluster
    address = dask_client.scheduler.address
    assert address.startswith("tcp://127.0.0.1:")
    ds = sweep("seed000", {"spin_ratio": (0.0, 20.0), "tilt": (0.0, 0.1)}, samples=4, seed=3,
               scheduler=address, progress=False, **SEED_OPTIONS)
    assert ds["fate"].dims == ("sample",) and ds.sizes["sample"] == 4
    assert ds["tilt"].dims == ("sample",) and ds["tilt"].attrs["units"] == "rad"
    scene = SeedScene(**SEED_OPTIONS)
    prep = scene.prepare()
    for k in range(4):
        values = {"spin_ratio": float(ds["spin_ratio"][k]), "tilt": float(ds["tilt"][k])}
        ref = reduce_run(scene.run(prep, values), OUTS)
        assert float(ds["min_distance"][k]) == ref["min_distance"]
        assert int(ds["fate"][k]) == ref["fate"]


@pytest.mark.slow  # compiles the N-body kernels on every worker (about a minute when loaded)
def test_toml_scene_sweep(dask_client):
    root = Path(__file__).resolve().parents[2]
    ds = sweep(root / "poissonkit" / "scene" / "shipped" / "two_magnets.toml",
               {"bodies.right.r.0": [0.025, 0.04]}, client=dask_client, progress=False)
    assert ds["fate"].dims == ("bodies.right.r.0",)
    assert ds["bodies.right.r.0"].attrs["units"] == "m"
    assert bool(ds["completed"].all()) and not bool(ds["failed"].any())
    # released 25 mm apart side by side the magnets snap together within the 50 ms run;
    # at 40 mm (the scene as written) they are still apart at its end
    assert ds["fate"].values.tolist() == [1, 0]
    assert float(ds["min_distance"].values[0]) < 0.025
