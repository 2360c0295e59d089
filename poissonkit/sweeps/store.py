"""The sweep's results: an :class:`xarray.Dataset`, mirrored to a Zarr store batch by batch.

Layout: one dimension per swept parameter (or ``sample`` for a random design), a coordinate per
parameter with its ``units``; one variable per outcome (``units``, ``long_name``); ``completed``
(the run finished, successfully or not), ``failed`` and ``error`` (the exception message).
Attributes: the scene, integrator, step or tolerance, the design and the poissonkit version.

The store is created in full at the start (every point ``completed = False``), chunked so that
each batch of points owns one chunk of every variable (:mod:`poissonkit.sweeps.integrity`).
Each finished batch is written in place: outcome values first, ``completed`` last, then the
chunk's completion record (a checksum of what was stored). ``resume`` trusts only chunks that
match their record and recomputes the others, saying how many points and why.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError
from poissonkit.sweeps.integrity import (RECORDS, ChunkCoords, Region, ensure_records, quiet_zarr,
                                         open_arrays, write_record)
from poissonkit.sweeps.outcomes import OUTCOMES
from poissonkit.sweeps.params import Design

if TYPE_CHECKING:  # xarray is imported where used
    import xarray as xr

_STATUS = ("completed", "failed", "error")


def _clean_attrs(attrs: Mapping[str, object]) -> dict[str, str | int | float | bool]:
    """JSON-safe attributes (no NaN/None)."""
    out: dict[str, str | int | float | bool] = {}
    for k, v in attrs.items():
        if v is None or (isinstance(v, float) and not math.isfinite(v)):
            continue
        out[k] = v if isinstance(v, (str, int, float, bool)) else json.dumps(v)
    return out


def empty_dataset(design: Design, outcomes: Iterable[str], attrs: Mapping[str, object],
                  units: Mapping[str, str]) -> xr.Dataset:
    """The dataset of a sweep with nothing computed yet."""
    import xarray as xr

    dims = design.dims
    shape = design.shape
    coords: dict[str, tuple[object, ...]] = {}
    if design.axes:
        for a in design.axes:
            coords[a.path] = (a.path, np.array(a.values), {"units": units[a.path],
                                                          "long_name": a.path})
    else:
        coords["sample"] = ("sample", np.arange(design.samples))
        for p, vals in design.sample_values().items():
            coords[p] = ("sample", vals, {"units": units[p], "long_name": p})
    data: dict[str, tuple[object, ...]] = {}
    for name in outcomes:
        o = OUTCOMES[name]
        var_attrs = {"units": o.units, "long_name": o.description}
        if name == "fate":
            var_attrs.update(flag_values=[0, 1, 2], flag_meanings="bounded collision escape")
        data[name] = (dims, np.full(shape, o.fill, dtype=o.dtype), var_attrs)
    data["completed"] = (dims, np.zeros(shape, dtype=bool),
                         {"long_name": "run finished (successfully or not)"})
    data["failed"] = (dims, np.zeros(shape, dtype=bool), {"long_name": "run raised an error"})
    data["error"] = (dims, np.full(shape, "", dtype=object),
                     {"long_name": "error message of a failed run"})
    return xr.Dataset(data, coords=coords, attrs=_clean_attrs(attrs))


def _encoding(ds: xr.Dataset, chunks: Sequence[int] | None) -> dict[str, dict[str, object]]:
    shape = tuple(ds["completed"].shape)
    chunks = tuple(shape) if chunks is None else tuple(int(c) for c in chunks)
    return {name: {"chunks": chunks} for name in ds.data_vars}


#: Attributes that may differ between a store and the sweep resuming it.
_VOLATILE_ATTRS = ("poissonkit_version",)


def check_layout(path: str | Path, ds: xr.Dataset, chunks: Sequence[int]) -> None:
    """Raise :class:`InputError` unless the store's metadata (every variable's shape, dtype,
    codecs, fill value, dimension names, attributes, and the dataset's attributes) is exactly
    what this sweep writes: metadata altered on disk is refused, never read as a layout.

    The expected metadata is made by writing the empty dataset to an in-memory Zarr store with
    the store's chunks, so it is zarr's and xarray's own encoding, not a copy of it.
    """
    import zarr
    from zarr.storage import MemoryStore

    mem = MemoryStore()
    ctx = quiet_zarr()
    try:
        ds.to_zarr(mem, mode="w", encoding=_encoding(ds, chunks))
        expected = zarr.open_group(mem, mode="r")
    finally:
        ctx.__exit__(None, None, None)
    group, arrays = open_arrays(path, [str(v) for v in ds.variables], mode="r")
    for name, arr in arrays.items():
        if arr.metadata.to_dict() != expected[name].metadata.to_dict():
            raise InputError(f"cannot resume: the metadata of {name!r} in the sweep store "
                             f"{str(path)!r} differs from what this sweep writes (altered or "
                             "damaged); start it again with overwrite (overwrite=True, "
                             "--overwrite)")
    have = {k: v for k, v in group.attrs.items() if k not in _VOLATILE_ATTRS}
    want = {k: v for k, v in expected.attrs.items() if k not in _VOLATILE_ATTRS}
    if have != want:
        diff = sorted(k for k in {*have, *want} if have.get(k) != want.get(k))
        raise InputError(f"cannot resume: the attributes {', '.join(diff)} of the sweep store "
                         f"{str(path)!r} differ from this sweep's (altered or damaged); start it "
                         "again with overwrite (overwrite=True, --overwrite)")


def create_store(path: str | Path, ds: xr.Dataset, chunks: Sequence[int] | None = None
                 ) -> None:
    """Write the (empty) dataset as a new Zarr store, replacing any store at ``path``.

    ``chunks``: chunk shape of every data variable (one batch per chunk; default: one chunk).
    """
    import zarr

    ctx = quiet_zarr()
    try:
        ds.to_zarr(str(path), mode="w", encoding=_encoding(ds, chunks))
        # created after the consolidated metadata, so xarray does not list it
        zarr.create_group(store=str(path), path=RECORDS, overwrite=True)
    finally:
        ctx.__exit__(None, None, None)


def refresh_coords(path: str | Path, ds: xr.Dataset) -> None:
    """Rewrite the coordinate values of a resumed store from the design (they never change, so
    a damaged coordinate chunk is simply written again)."""
    _, arrays = open_arrays(path, [str(c) for c in ds.coords])
    ctx = quiet_zarr()
    try:
        for name, arr in arrays.items():
            arr[...] = np.asarray(ds[name].values, dtype=arr.dtype)
    finally:
        ctx.__exit__(None, None, None)


def open_store(path: str | Path) -> xr.Dataset:
    """The dataset of an existing store, loaded into memory."""
    import xarray as xr

    ctx = quiet_zarr()
    try:
        with xr.open_zarr(str(path)) as ds:
            return ds.load()
    finally:
        ctx.__exit__(None, None, None)


def store_attrs(path: str | Path) -> dict[str, object]:
    """The attributes of an existing store (read through Zarr, without loading any chunk).

    Raises
    ------
    InputError
        The store's group metadata cannot be read.
    """
    group, _ = open_arrays(path, (), mode="r")
    return dict(group.attrs)


def check_resumable(old: xr.Dataset | Mapping[str, object], new: xr.Dataset) -> None:
    """Raise :class:`InputError` unless ``old`` (on disk: its dataset or attributes) is the same
    sweep as ``new``."""
    import xarray as xr

    old_attrs = old.attrs if isinstance(old, xr.Dataset) else old
    for key in ("scene_key", "design", "outcomes", "method", "step", "tol"):
        a, b = old_attrs.get(key), new.attrs.get(key)
        if a != b:
            raise InputError(f"cannot resume: the store was made with {key} = {a!r}, this sweep "
                             f"has {key} = {b!r} (use a new output folder or overwrite)")


class ZarrWriter:
    """Writes finished batches into an existing store, one whole chunk per batch."""

    def __init__(self, path: str | Path, variables: Iterable[str]) -> None:
        self.path = Path(path)
        self.variables = tuple(variables)
        _, self.arrays = open_arrays(self.path, self.variables)
        ensure_records(self.path)
        first = self.arrays[self.variables[0]]
        self.chunks = tuple(int(c) for c in first.chunks)

    def write_chunk(self, coords: ChunkCoords, region: Region,
                    blocks: Mapping[str, np.ndarray]) -> None:
        """Store the whole chunk ``coords`` (``blocks[name]`` covers ``region``): values first,
        status variables last, then the completion record of what was stored."""
        order = [n for n in self.variables if n not in _STATUS] + list(_STATUS)
        stored: dict[str, np.ndarray] = {}
        ctx = quiet_zarr()
        try:
            for name in order:
                arr = self.arrays[name]
                block = np.asarray(blocks[name])
                if arr.dtype.kind not in "OTU":
                    block = block.astype(arr.dtype)
                arr[region] = block
                stored[name] = block
        finally:
            ctx.__exit__(None, None, None)
        write_record(self.path, coords, stored, {n: a.dtype for n, a in self.arrays.items()})
