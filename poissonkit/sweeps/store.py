"""The sweep's results: an :class:`xarray.Dataset`, mirrored to a Zarr store batch by batch.

Layout: one dimension per swept parameter (or ``sample`` for a random design), a coordinate per
parameter with its ``units``; one variable per outcome (``units``, ``long_name``); ``completed``
(the run finished, successfully or not), ``failed`` and ``error`` (the exception message).
Attributes: the scene, integrator, step or tolerance, the design and the poissonkit version.

The store is created in full at the start (every point ``completed = False``) and each finished
batch is written in place: outcome values first, ``completed`` last, so a client that dies
mid-write leaves those points incomplete and ``resume`` recomputes them.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError
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


def _quiet():
    ctx = warnings.catch_warnings()
    ctx.__enter__()
    # zarr format 3 warns that consolidated metadata is not in its spec yet; xarray reads it
    warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata.*")
    return ctx


def create_store(path: str | Path, ds: xr.Dataset) -> None:
    """Write the (empty) dataset as a new Zarr store, replacing any store at ``path``."""
    ctx = _quiet()
    try:
        ds.to_zarr(str(path), mode="w")
    finally:
        ctx.__exit__(None, None, None)


def open_store(path: str | Path) -> xr.Dataset:
    """The dataset of an existing store, loaded into memory."""
    import xarray as xr

    ctx = _quiet()
    try:
        with xr.open_zarr(str(path)) as ds:
            return ds.load()
    finally:
        ctx.__exit__(None, None, None)


def check_resumable(old: xr.Dataset, new: xr.Dataset) -> None:
    """Raise :class:`InputError` unless ``old`` (on disk) is the same sweep as ``new``."""
    for key in ("scene_key", "design", "outcomes", "method", "step", "tol"):
        a, b = old.attrs.get(key), new.attrs.get(key)
        if a != b:
            raise InputError(f"cannot resume: the store was made with {key} = {a!r}, this sweep "
                             f"has {key} = {b!r} (use a new output folder or overwrite)")


class ZarrWriter:
    """Writes finished points into an existing store (coordinate selection per batch)."""

    def __init__(self, path: str | Path, variables: Iterable[str]) -> None:
        import zarr

        self.group = zarr.open_group(str(path), mode="r+")
        self.variables = tuple(variables)

    def write(self, index: tuple[np.ndarray, ...], values: Mapping[str, np.ndarray]) -> None:
        """Set ``values[name]`` at the points ``index`` (one index array per dimension);
        status variables last."""
        order = [n for n in self.variables if n not in _STATUS] + list(_STATUS)
        for name in order:
            if name in values:
                self.group[name].vindex[index] = values[name]
