"""Gather a streamed trajectory (``trajectory.parts/``) into ``trajectory.npz`` part by part.

The file is the same ``.npz`` :func:`~poissonkit.report.summary.write_trajectory` writes
(``numpy.load`` reads it as before: a zip of ``.npy`` members, deflate-compressed), but each
member is written as a ``.npy`` header followed by the rows of one part at a time, so the peak
memory is one part (``TrajectoryStream.max_rows`` rows), not the whole trajectory. The parts are
checked first (:func:`~poissonkit.numerics.parts.verify_parts`: no hole, gap or duplicate).

:func:`gather_dataset` does the same for the xarray dataset of a long trajectory: a Zarr store
(``trajectory.zarr``) appended one part at a time, since the NetCDF 3 file of scipy's engine can
only be written from arrays held whole in memory.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import zipfile
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.files.atomic import atomic_path
from poissonkit.files.killpoints import kill_point
from poissonkit.numerics.parts import PartInfo, iter_parts, verify_parts

if TYPE_CHECKING:
    import xarray as xr

#: Maps a block of rows ``y`` to the rows of an extra per-row array (e.g. ``r_rel_si``).
RowMap = Callable[[np.ndarray], np.ndarray]


def _member(zf: zipfile.ZipFile, name: str, shape: tuple[int, ...], dtype: np.dtype,
            blocks: Iterable[np.ndarray]) -> None:
    """One ``.npy`` member written block by block (C order: blocks of rows concatenate)."""
    header = {"descr": np.lib.format.dtype_to_descr(dtype), "fortran_order": False,
              "shape": shape}
    with zf.open(name + ".npy", "w", force_zip64=True) as fh:
        np.lib.format.write_array_header_2_0(fh, header) if _needs_v2(header) else \
            np.lib.format.write_array_header_1_0(fh, header)
        written = 0
        for block in blocks:
            block = np.ascontiguousarray(block, dtype=dtype)
            fh.write(block.data)
            written += len(block)
        if written != shape[0]:
            from poissonkit.numerics.parts import PartsError

            raise PartsError(f"trajectory parts changed while being gathered ({name}: "
                             f"{written} of {shape[0]} rows)")


def _small(zf: zipfile.ZipFile, name: str, arr: np.ndarray) -> None:
    with zf.open(name + ".npy", "w", force_zip64=True) as fh:
        np.lib.format.write_array(fh, arr, allow_pickle=False)


def _needs_v2(header: Mapping[str, object]) -> bool:
    # format 1.0 stores the header length in 2 bytes (as numpy.save decides)
    return len(repr(header)) > 60000


def gather_trajectory(path: str | Path, folder: str | Path, *, layout: tuple[str, ...] = (),
                      time_unit: float = 1.0, row_maps: Mapping[str, RowMap] | None = None,
                      **small: np.ndarray) -> int:
    """Write the parts of ``folder`` as ``path`` (``t``, ``t_si``, ``y``, ``layout``, ...),
    atomically and one part in memory at a time; return the number of rows.

    Parameters
    ----------
    path
        The ``.npz`` file to write.
    folder
        Folder of the trajectory parts.
    layout, time_unit
        As for :func:`~poissonkit.report.summary.write_trajectory`.
    row_maps
        Further per-row arrays, each computed from a block of rows ``y`` (e.g. ``r_rel_si``).
    **small
        Further arrays written as they are (e.g. the scales).

    Raises
    ------
    PartsError
        If the parts do not form one sequence, or change while being gathered.
    InputError
        If ``folder`` holds no parts.
    """
    from poissonkit.errors import InputError

    infos: list[PartInfo] = verify_parts(folder)
    if not infos:
        raise InputError(f"no trajectory parts in {folder}")
    rows = infos[-1].stop
    t0, y0 = next(iter_parts(infos[:1]))
    dim = y0.shape[1]
    unit = float(time_unit)
    maps = dict(row_maps or {})
    map_cols = {k: np.asarray(f(y0[:1])).shape[1:] for k, f in maps.items()}
    f8 = np.dtype(float)
    with atomic_path(path) as tmp, \
            zipfile.ZipFile(tmp, mode="w", compression=zipfile.ZIP_DEFLATED,
                            compresslevel=1, allowZip64=True) as zf:
        # deflate level 1: float states shrink ~2 % less than at the default 6, in 2/3 of the
        # time (a 10⁵-body state took about one force evaluation to compress)
        _member(zf, "t", (rows,), f8, (t for t, _ in iter_parts(infos)))
        _member(zf, "t_si", (rows,), f8, (t * unit for t, _ in iter_parts(infos)))
        kill_point("gather-tmp")
        _member(zf, "y", (rows, dim), f8, (y for _, y in iter_parts(infos)))
        _small(zf, "layout", np.array(layout, dtype=str))
        for name, f in maps.items():
            _member(zf, name, (rows, *map_cols[name]), f8,
                    (np.asarray(f(y), dtype=float) for _, y in iter_parts(infos)))
        for name, arr in small.items():
            _small(zf, name, np.asarray(arr))
    kill_point("gather-written")
    return rows


def gather_dataset(path: str | Path, folder: str | Path,
                   build: Callable[[np.ndarray, np.ndarray], xr.Dataset]) -> int:
    """Write the dataset of the parts of ``folder`` as a Zarr store ``path`` (format 2), one
    part at a time; return the number of rows.

    Parameters
    ----------
    path
        The store (a folder) to write; it appears complete or not at all (written under a
        temporary name, then renamed).
    folder
        Folder of the trajectory parts.
    build
        ``build(t, y)``: the dataset of a block of rows (time along dimension ``time``), e.g.
        :func:`~poissonkit.report.trajectory.trajectory_dataset`.

    Raises
    ------
    PartsError
        If the parts do not form one sequence.
    """
    path = Path(path)
    infos = verify_parts(folder)
    # ".<name>.<random>.tmp": the name atomic.remove_stale_temps knows
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent))
    try:
        for k, (t, y) in enumerate(iter_parts(infos)):
            ds = build(t, y)
            if k == 0:
                ds.to_zarr(tmp, mode="w", zarr_format=2, consolidated=True)
            else:
                ds.to_zarr(tmp, append_dim="time", zarr_format=2, consolidated=True)
        shutil.rmtree(path, ignore_errors=True)
        os.replace(tmp, path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return infos[-1].stop if infos else 0
