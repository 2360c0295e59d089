"""``sweep``: run a scene over a parameter design on Dask and collect an xarray Dataset."""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.contracts import SweepScene
from poissonkit.errors import InputError
from poissonkit.plugin.contributions import OutcomeEntry
from poissonkit.sweeps.execute import (PointResult, batch_size_for, execute, make_client,
                                       resolve_units, worker_count)
from poissonkit.sweeps.integrity import (StoreRepairWarning, chunk_of, chunk_regions, chunk_shape,
                                         fill_dataset, region_points, repair_message, verify_store)
from poissonkit.sweeps.outcomes import outcome_entries, resolve_outcomes
from poissonkit.sweeps.params import Axis, Design, Range, design_from
from poissonkit.sweeps.targets import sweep_scene
from poissonkit.sweeps.store import (ZarrWriter, check_layout, check_resumable, create_store,
                                     empty_dataset, refresh_coords, store_attrs)

if TYPE_CHECKING:  # dask and xarray are imported where used
    import xarray as xr
    from distributed import Client


def sweep(scene: SweepScene | str | Path,
          params: Sequence[Axis | Range | str] | Mapping[str, object],
          outcomes: Sequence[str] | str | None = None, client: Client | None = None,
          store: str | Path | None = None, *, scheduler: str | None = None,
          workers: int | None = None, samples: int | None = None, seed: int = 0,
          resume: bool = False, overwrite: bool = False, batch_size: int | None = None,
          retries: int = 2, progress: bool = True,
          on_batch: Callable[[int, int], None] | None = None, **scene_options: object
          ) -> xr.Dataset:
    """Run ``scene`` at every point of a parameter design; return the results as a Dataset.

    Parameters
    ----------
    scene
        A registered scene name (e.g. ``"seed000"``, swept through its entry's ``sweep``
        factory), the path of a TOML scene file, or a ready
        :class:`~poissonkit.contracts.SweepScene` (a
        :class:`~poissonkit.sweeps.targets.TomlScene` or a plugin's, e.g.
        ``poissonkit_magnets.seed000_sweep.SeedScene``).
    params
        Swept parameters by path (``docs/sweeps.md``): :func:`~poissonkit.sweeps.params.grid`
        axes, :class:`~poissonkit.sweeps.params.Axis` lists, command-line strings
        (``"tilt=0:0.2:5"``), or a mapping ``{path: values}``; with ``samples``, ranges
        ``{path: (low, high)}`` for a seeded random design.
    outcomes
        Names from :data:`~poissonkit.sweeps.outcomes.OUTCOMES`, built-in or registered by a
        plugin's ``poissonkit_outcomes`` hook (default: the built-in ones but ``megno``).
    client
        A :class:`distributed.Client` of any cluster; otherwise ``scheduler`` (an address) or a
        new local cluster of ``workers`` processes on the loopback interface.
    store
        Zarr store written incrementally as batches finish (``None``: results only in memory).
    samples, seed
        Random design: number of points and the seed of their draw.
    resume
        Continue the sweep in ``store``: only points not completed are run (none if finished).
        Every stored chunk is first checked against its completion record; points whose values
        cannot be trusted (chunk missing, truncated or altered, record missing or damaged) are
        run again, announced by a :class:`~poissonkit.sweeps.integrity.StoreRepairWarning`.
    overwrite
        Replace an existing store instead of refusing.
    batch_size
        Runs per task (default: about 8 tasks per worker, at most 64 runs each); each task
        owns one chunk of the store (a resumed store keeps its chunks).
    retries
        Dask retries of a task that raised (a lost worker's tasks are rescheduled anyway).
    progress
        Show a progress bar (runs done / total, failures).
    on_batch
        Called as ``on_batch(done, total)`` after each finished batch.
    **scene_options
        Options of the scene (seed: ``periods``, ``method``, ``step``, ``escape``, ``fixed``;
        TOML: ``escape``, ``fixed``).

    Returns
    -------
    xarray.Dataset
        One dimension per swept parameter (``sample`` for a random design), coordinates with
        units, one variable per outcome, ``completed``/``failed``/``error`` per point.

    Raises
    ------
    InputError
        Unknown parameter paths or outcomes, a store that exists (without ``resume`` or
        ``overwrite``) or belongs to another sweep, a bad scheduler address.
    """
    from poissonkit._version import __version__

    sc = sweep_scene(scene, **scene_options)
    design = design_from(params, samples=samples, seed=seed)
    names = resolve_outcomes(outcomes)
    chosen = outcome_entries(names)
    units = resolve_units(sc, design.paths)
    attrs = {**sc.settings(), "scene_key": sc.key, "design": json.dumps(design.describe()),
             "outcomes": ",".join(names), "poissonkit_version": __version__,
             "chaos_indicator": "MEGNO from two nearby runs (shadow orbit, renormalised)"}
    ds = empty_dataset(design, names, attrs, units)
    variables = [*names, "completed", "failed", "error"]
    shape = design.shape
    ds, path, chunks = _open_store(store, ds, shape, variables, resume, overwrite)

    completed = np.asarray(ds["completed"].values, dtype=bool).reshape(-1)
    total = design.size
    done = int(completed.sum())
    failures = int(np.asarray(ds["failed"].values).sum())
    if done == total:
        return ds
    arrays = _run_pending(sc, design, ds, chosen, variables, path, chunks, completed, done,
                          failures, client=client, scheduler=scheduler, workers=workers,
                          batch_size=batch_size, retries=retries, progress=progress,
                          on_batch=on_batch)
    for n, v in arrays.items():
        ds[n].values = v
    return ds


def _open_store(store: str | Path | None, ds: xr.Dataset, shape: tuple[int, ...],
                variables: list[str], resume: bool, overwrite: bool
                ) -> tuple[xr.Dataset, Path | None, tuple[int, ...] | None]:
    """``(dataset, path, chunks)``: a resumed store's verified results filled into ``ds`` (its
    chunks kept), or a new store checked to be absent or replaceable (chunks still open)."""
    path = None if store is None else Path(store)
    chunks: tuple[int, ...] | None = None
    if path is not None:
        if path.exists() and resume:
            check_resumable(store_attrs(path), ds)
            chunks, verified = verify_store(path, shape, variables)
            check_layout(path, ds, chunks)
            message = repair_message(path, verified.untrusted)
            if message is not None:
                warnings.warn(message, StoreRepairWarning, stacklevel=3)
            ds = fill_dataset(ds, verified, chunks)
            refresh_coords(path, ds)
        elif path.exists() and not overwrite:
            raise InputError(f"store {str(path)!r} exists: resume it (resume=True, --resume) or "
                             "overwrite it (overwrite=True, --overwrite)")
    elif resume:
        raise InputError("resume needs a store")

    return ds, path, chunks


def _run_pending(sc: SweepScene, design: Design, ds: xr.Dataset,
                 chosen: tuple[OutcomeEntry, ...], variables: list[str],
                 path: Path | None, chunks: tuple[int, ...] | None, completed: np.ndarray,
                 done: int, failures: int, *, client: Client | None, scheduler: str | None,
                 workers: int | None, batch_size: int | None, retries: int, progress: bool,
                 on_batch: Callable[[int, int], None] | None) -> dict[str, np.ndarray]:
    """Run the points not ``completed``, one task per chunk, writing each finished chunk to
    the store at ``path``; the arrays of every variable, completed and new results."""
    shape = design.shape
    total = design.size
    arrays = {n: np.array(ds[n].values) for n in variables}
    count = [done]
    writer: ZarrWriter | None = None
    regions: dict[tuple[int, ...], tuple[slice, ...]] = {}

    def on_results(results: list[PointResult]) -> None:
        flat = np.array([r[0] for r in results], dtype=np.int64)
        index = np.unravel_index(flat, shape)
        values: dict[str, np.ndarray] = {}
        for o in chosen:
            n = o.name
            col = [o.fill if r[1] is None else r[1][n] for r in results]
            values[n] = np.asarray(col, dtype=o.dtype)
        values["failed"] = np.array([r[1] is None for r in results])
        values["error"] = np.array([r[2] for r in results], dtype=object)
        values["completed"] = np.ones(len(results), dtype=bool)
        for n, v in values.items():
            arrays[n][index] = v
        if writer is not None:
            assert chunks is not None
            coords = chunk_of(int(flat[0]), shape, chunks)
            region = regions[coords]
            writer.write_chunk(coords, region, {n: arrays[n][region] for n in variables})
        count[0] += len(results)
        if on_batch is not None:
            on_batch(count[0], total)

    c, close = make_client(client, scheduler, workers)
    try:
        size = batch_size_for(total, worker_count(c), batch_size)
        if chunks is None:  # a new sweep: one batch per chunk of this size
            chunks = chunk_shape(shape, size)
            if path is not None:
                path.parent.mkdir(parents=True, exist_ok=True)
                create_store(path, ds, chunks)
        if path is not None:
            writer = ZarrWriter(path, variables)
        points = dict(design.points())
        parts = []
        for coords, region in chunk_regions(shape, chunks):
            regions[coords] = region
            flat = region_points(shape, region)
            if not completed[flat].all():
                parts.append([(int(k), points[int(k)]) for k in flat])
        todo = [p for part in parts for p in part]
        execute(sc, todo, chosen, c, on_results=on_results, retries=retries,
                progress=progress, total=total, done=done, failures=failures, parts=parts)
    finally:
        close()
    return arrays
