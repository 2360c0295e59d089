"""Integrity of a sweep store: batches own chunks, each finished chunk has a completion record.

* The grid is chunked so that one batch of points is exactly one chunk of every variable
  (:func:`chunk_shape`, :func:`chunk_regions`): no two batches ever write the same chunk, so a
  batch's chunks can be written whole, checked whole and recomputed whole.
* After a batch's values are written (``completed`` last), a *completion record* is written: a
  small Zarr group ``integrity/<chunk>`` whose attributes hold the SHA-256 of each variable's
  stored block (:func:`digest`). A record therefore exists only for a chunk written in full.
* On resume (:func:`verify_store`) every chunk is read back on its own through Zarr and compared
  with its record. A chunk whose values cannot be trusted -- a chunk file missing, truncated or
  altered, a decode error, a checksum mismatch, a missing or damaged record -- is left out of the
  dataset (its points are not completed) and recomputed; :func:`repair_message` names how many
  points and why. Values read from the store are never taken without their record, so a fill
  value (NaN, 0) standing in for a lost chunk is never presented as data.
"""

from __future__ import annotations

import hashlib
import json
import warnings
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from poissonkit.errors import InputError

if TYPE_CHECKING:  # zarr and xarray are imported where used
    import xarray as xr
    import zarr

#: Sub-group of the store holding one completion record per chunk (not a dataset variable: the
#: store's consolidated metadata does not list it, so xarray does not see it).
RECORDS = "integrity"
#: Version of the record layout (attributes ``format``, ``chunk``, ``points``, ``sha256``).
RECORD_FORMAT = 1

#: Chunk coordinates (index of the chunk along each dimension).
ChunkCoords = tuple[int, ...]
#: The slice of the grid a chunk covers.
Region = tuple[slice, ...]

# Why a chunk's points are recomputed (the words of the warning).
MISSING_CHUNK = "in a missing chunk file"
UNREADABLE_CHUNK = "in an unreadable chunk (truncated or corrupt)"
CHECKSUM = "whose values differ from their checksum"
NO_RECORD = "without a completion record (interrupted write or deleted record)"
BAD_RECORD = "with a damaged completion record"


class StoreRepairWarning(UserWarning):
    """Points of a resumed sweep store could not be trusted and are computed again."""


def chunk_shape(shape: Sequence[int], target: int) -> tuple[int, ...]:
    """Chunk shape of a grid so that one chunk holds at most ``target`` points (at least 1).

    Trailing dimensions are kept whole while they fit, so a chunk is a contiguous run of points
    in C order as far as possible.
    """
    remaining = max(1, int(target))
    out: list[int] = []
    for n in reversed([int(s) for s in shape]):
        c = max(1, min(n, remaining))
        out.append(c)
        remaining = max(1, remaining // c)
    return tuple(reversed(out))


def chunk_regions(shape: Sequence[int], chunks: Sequence[int]
                  ) -> Iterator[tuple[ChunkCoords, Region]]:
    """Every chunk of the grid in C order: its coordinates and the region it covers."""
    counts = [-(-int(n) // int(c)) for n, c in zip(shape, chunks)]
    for coords in np.ndindex(*counts):
        region = tuple(slice(i * c, min((i + 1) * c, n))
                       for i, c, n in zip(coords, chunks, shape))
        yield tuple(int(i) for i in coords), region


def region_points(shape: Sequence[int], region: Region) -> np.ndarray:
    """Flat (C-order) indices of the grid points in ``region``, in C order."""
    axes = [np.arange(s.start, s.stop) for s in region]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.ravel_multi_index([m.ravel() for m in mesh], tuple(shape)).astype(np.int64)


def chunk_of(flat: int, shape: Sequence[int], chunks: Sequence[int]) -> ChunkCoords:
    """Coordinates of the chunk holding the point of flat index ``flat``."""
    idx = np.unravel_index(int(flat), tuple(shape))
    return tuple(int(i) // int(c) for i, c in zip(idx, chunks))


def record_name(coords: ChunkCoords) -> str:
    """Name of a chunk's completion record (Zarr's chunk-key style, ``"2.0"``)."""
    return ".".join(str(i) for i in coords)


def digest(block: np.ndarray, dtype: np.dtype) -> str:
    """SHA-256 of a block of values as stored in an array of ``dtype`` (shape, dtype, bytes)."""
    arr = np.asarray(block)
    h = hashlib.sha256()
    h.update(repr(tuple(arr.shape)).encode())
    if np.dtype(dtype).kind in "OTU" or arr.dtype.kind in "OTU":
        # strings: their text, one JSON list (independent of numpy's string dtype)
        h.update(b"str")
        h.update(json.dumps([str(x) for x in arr.ravel()]).encode("utf-8", "surrogatepass"))
    else:
        dt = np.dtype(dtype).newbyteorder("<")
        h.update(dt.str.encode())
        h.update(np.ascontiguousarray(arr.astype(dt, copy=False)).tobytes())
    return h.hexdigest()


def quiet_zarr() -> warnings.catch_warnings:
    """Enter a warnings context that hides zarr's consolidated-metadata notice (the caller
    exits it)."""
    ctx = warnings.catch_warnings()
    ctx.__enter__()
    # zarr format 3 warns that consolidated metadata is not in its spec yet; xarray reads it
    warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata.*")
    return ctx


def _damaged(path: Path, what: str, exc: BaseException) -> InputError:
    return InputError(f"cannot resume: the sweep store {str(path)!r} is damaged beyond its "
                      f"chunks ({what}: {type(exc).__name__}: {exc}); start it again with "
                      "overwrite (overwrite=True, --overwrite)")


def open_arrays(path: str | Path, variables: Iterable[str], *, mode: str = "r+"
                ) -> tuple[zarr.Group, dict[str, zarr.Array]]:
    """The store's root group and its variables' arrays (every chunk written even if it holds
    only fill values, so a missing chunk file is always a lost chunk).

    Raises
    ------
    InputError
        The group or an array's metadata cannot be read (nothing to recompute into).
    """
    import zarr

    p = Path(path)
    ctx = quiet_zarr()
    try:
        try:
            group = zarr.open_group(str(p), mode=mode)
        except Exception as exc:  # noqa: BLE001 - any failure to read metadata is damage
            raise _damaged(p, "group metadata", exc) from None
        arrays: dict[str, zarr.Array] = {}
        for name in variables:
            try:
                arr = group[name]
            except Exception as exc:  # noqa: BLE001
                raise _damaged(p, f"metadata of {name!r}", exc) from None
            if not isinstance(arr, zarr.Array):
                raise _damaged(p, f"metadata of {name!r}", TypeError("not an array"))
            arrays[name] = arr.with_config({"write_empty_chunks": True})
        return group, arrays
    finally:
        ctx.__exit__(None, None, None)


def ensure_records(path: str | Path) -> None:
    """Make the group of completion records writable: a damaged or missing group document is
    written again (the records under it are kept; each is checked on its own)."""
    import zarr
    from zarr.core.sync import sync

    ctx = quiet_zarr()
    try:
        try:
            zarr.open_group(store=str(path), path=RECORDS, mode="r")
            return
        except Exception:  # noqa: BLE001 - unreadable or missing: write it again below
            pass
        root = zarr.open_group(str(path), mode="r+")
        try:
            sync(root.store.delete(f"{RECORDS}/zarr.json"))
        except Exception:  # noqa: BLE001 - already gone
            pass
        zarr.create_group(store=str(path), path=RECORDS, overwrite=False)
    finally:
        ctx.__exit__(None, None, None)


def write_record(path: str | Path, coords: ChunkCoords, blocks: Mapping[str, np.ndarray],
                 dtypes: Mapping[str, np.dtype]) -> None:
    """Write the completion record of a chunk whose ``blocks`` are now stored in full."""
    import zarr

    n = int(next(iter(blocks.values())).size) if blocks else 0
    attrs = {"format": RECORD_FORMAT, "chunk": list(coords), "points": n,
             "sha256": {k: digest(v, dtypes[k]) for k, v in blocks.items()}}
    ctx = quiet_zarr()
    try:
        zarr.create_group(store=str(path), path=f"{RECORDS}/{record_name(coords)}",
                          attributes=attrs, overwrite=True)
    finally:
        ctx.__exit__(None, None, None)


def _read_record(path: Path, coords: ChunkCoords) -> Mapping[str, object] | None | str:
    """The record of a chunk; ``None`` if there is none; :data:`BAD_RECORD` if unreadable."""
    import zarr
    from zarr.errors import GroupNotFoundError

    try:
        g = zarr.open_group(store=str(path), path=f"{RECORDS}/{record_name(coords)}", mode="r")
        attrs = dict(g.attrs)
    except (GroupNotFoundError, FileNotFoundError):
        return None
    except Exception:  # noqa: BLE001 - an unreadable record vouches for nothing
        return BAD_RECORD
    sums = attrs.get("sha256")
    if (attrs.get("format") != RECORD_FORMAT or list(attrs.get("chunk", [])) != list(coords)
            or not isinstance(sums, dict)):
        return BAD_RECORD
    return attrs


def _stored_chunks(arr: zarr.Array) -> set[str] | None:
    """Keys of the chunks stored for ``arr`` (``None``: the store cannot list them)."""
    from zarr.core.sync import sync

    async def collect() -> set[str]:
        return {k async for k in arr.store.list_prefix(f"{arr.path}/")}

    try:
        return sync(collect())
    except Exception:  # noqa: BLE001 - cannot tell: let the read and the checksum decide
        return None


class _Reader:
    """Reads a variable's chunks: the whole array in one go when it decodes, else chunk by
    chunk (so one damaged chunk costs only its own points)."""

    def __init__(self, arr: zarr.Array) -> None:
        self.arr = arr
        self.keys = _stored_chunks(arr)
        try:
            self.full: np.ndarray | None = _read_block(arr, tuple(slice(None) for _ in arr.shape))
        except Exception:  # noqa: BLE001 - some chunk does not decode: read them one by one
            self.full = None

    def exists(self, coords: ChunkCoords) -> bool:
        if self.keys is None:
            return True
        return f"{self.arr.path}/{self.arr.metadata.encode_chunk_key(coords)}" in self.keys

    def read(self, region: Region) -> np.ndarray:
        if self.full is not None:
            return self.full[region]
        return _read_block(self.arr, region)


@dataclass
class Verified:
    """What a resume may take from a store.

    Attributes
    ----------
    blocks
        ``{chunk coords: {variable: stored block}}`` of every chunk that matches its record.
    untrusted
        Points whose stored values were found but cannot be trusted, by reason.
    pending
        Chunks never written (nothing to warn about: the sweep had not reached them).
    """

    blocks: dict[ChunkCoords, dict[str, np.ndarray]] = field(default_factory=dict)
    untrusted: Counter[str] = field(default_factory=Counter)
    pending: int = 0


def _read_block(arr: zarr.Array, region: Region) -> np.ndarray:
    ctx = quiet_zarr()
    try:
        return np.asarray(arr[region])
    finally:
        ctx.__exit__(None, None, None)


def verify_chunk(path: Path, readers: Mapping[str, _Reader], coords: ChunkCoords,
                 region: Region) -> tuple[dict[str, np.ndarray] | None, str | None]:
    """Check one chunk against its record: ``(blocks, None)`` if trusted, else
    ``(None, reason)``; ``(None, None)`` for a chunk never written."""
    record = _read_record(path, coords)
    if record is None or record == BAD_RECORD:
        # without a record, were values written here (a batch cut short, a deleted record)?
        try:
            written = bool(np.any(readers["completed"].read(region)))
        except Exception:  # noqa: BLE001 - an unreadable chunk was written once
            written = True
        if record == BAD_RECORD:
            return None, BAD_RECORD
        return None, NO_RECORD if written else None
    assert isinstance(record, Mapping)
    sums = record["sha256"]
    assert isinstance(sums, dict)
    blocks: dict[str, np.ndarray] = {}
    for name, reader in readers.items():
        # every written chunk is stored (write_empty_chunks), so a missing file is a lost chunk
        # even when the fill value zarr would return happens to equal the stored values
        if not reader.exists(coords):
            return None, MISSING_CHUNK
        try:
            block = reader.read(region)
        except Exception:  # noqa: BLE001 - a decode error is a damaged chunk, not a crash
            return None, UNREADABLE_CHUNK
        if sums.get(name) != digest(block, reader.arr.dtype):
            return None, CHECKSUM
        blocks[name] = block
    return blocks, None


def verify_store(path: str | Path, shape: Sequence[int], variables: Sequence[str]
                 ) -> tuple[tuple[int, ...], Verified]:
    """Verify every chunk of a store against its completion record.

    Returns
    -------
    chunks, verified
        The store's chunk shape (batches follow it) and what can be trusted.

    Raises
    ------
    InputError
        Metadata damaged, or the store's grid is not ``shape``.
    """
    p = Path(path)
    _, arrays = open_arrays(p, variables, mode="r")
    chunks: tuple[int, ...] | None = None
    for name, arr in arrays.items():
        if tuple(arr.shape) != tuple(shape):
            raise _damaged(p, f"shape of {name!r}",
                           ValueError(f"{tuple(arr.shape)} instead of {tuple(shape)}"))
        if chunks is None:
            chunks = tuple(int(c) for c in arr.chunks)
        elif tuple(arr.chunks) != chunks:
            raise _damaged(p, f"chunks of {name!r}",
                           ValueError(f"{tuple(arr.chunks)} instead of {chunks}"))
    assert chunks is not None
    out = Verified()
    readers = {name: _Reader(arr) for name, arr in arrays.items()}
    for coords, region in chunk_regions(shape, chunks):
        blocks, reason = verify_chunk(p, readers, coords, region)
        if blocks is not None:
            out.blocks[coords] = blocks
        elif reason is None:
            out.pending += 1
        else:
            out.untrusted[reason] += int(np.prod([s.stop - s.start for s in region]))
    return chunks, out


def repair_message(path: str | Path, untrusted: Mapping[str, int]) -> str | None:
    """One line naming how many stored points are recomputed and why (``None``: none)."""
    total = sum(untrusted.values())
    if not total:
        return None
    why = "; ".join(f"{n} {reason}" for reason, n in sorted(untrusted.items()))
    return (f"sweep store {str(path)!r}: {total} stored point{'s' if total != 1 else ''} "
            f"cannot be trusted and will be computed again ({why})")


def fill_dataset(ds: xr.Dataset, verified: Verified, chunks: Sequence[int]) -> xr.Dataset:
    """Copy the trusted chunks' values into ``ds`` (a sweep's empty dataset)."""
    shape = tuple(ds["completed"].shape)
    regions = dict(chunk_regions(shape, chunks))
    for name in ds.data_vars:
        if not any(name in b for b in verified.blocks.values()):
            continue
        values = np.array(ds[name].values)
        for coords, blocks in verified.blocks.items():
            values[regions[coords]] = blocks[name]
        ds[name].values = values
    return ds
