"""The part files of a streamed trajectory, and the check that they form one row sequence.

:class:`~poissonkit.numerics.checkpoint.TrajectoryStream` writes saved rows to numbered files
``part-NNNNNN.npz``; each holds ``t``, ``y`` and ``rows = [first, stop)``, the global indices of
its rows (parts written before ``rows`` was recorded count their rows instead). Whoever
reassembles parts — a resume, the final gather, :func:`read_trajectory` — first calls
:func:`verify_parts`: the parts must be numbered 0, 1, 2 ... without a hole and their rows must
follow each other (no gap, no duplicate), or :class:`PartsError` says where they do not.
"""

from __future__ import annotations

import re
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from poissonkit.errors import InputError

PART = re.compile(r"^part-(\d{6})\.npz$")


class PartsError(InputError):
    """Trajectory parts that are damaged or do not form one gap-free, duplicate-free sequence."""


@dataclass(frozen=True)
class PartInfo:
    """One part file: its number, path and global row range ``[first, stop)``."""

    number: int
    path: Path
    first: int
    stop: int


def part_files(folder: str | Path) -> list[Path]:
    """The ``part-NNNNNN.npz`` files of ``folder`` in order (none if it does not exist)."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if PART.match(p.name))


def part_number(path: Path) -> int:
    """The number ``NNNNNN`` of a part file."""
    m = PART.match(path.name)
    if m is None:
        raise PartsError(f"{path} is not a trajectory part")
    return int(m.group(1))


def _read_range(path: Path, first_guess: int) -> tuple[int, int]:
    try:
        with np.load(path, allow_pickle=False) as z:
            n = len(z["t"])
            if "rows" not in z.files:  # written before parts recorded their rows
                return first_guess, first_guess + n
            first, stop = (int(v) for v in z["rows"])
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        raise PartsError(f"trajectory part {path} is damaged ({exc})") from None
    if stop - first != n:
        raise PartsError(f"trajectory part {path} holds {n} rows but records {stop - first}")
    return first, stop


def verify_parts(folder: str | Path, parts: int | None = None, rows: int | None = None
                 ) -> list[PartInfo]:
    """Check the parts of ``folder`` form one row sequence; return them in order.

    Parameters
    ----------
    folder
        Folder of the parts.
    parts, rows
        If given, only parts numbered below ``parts`` are checked (later ones are a resumed
        run's to discard), and together they must hold exactly rows ``0 .. rows - 1``.

    Raises
    ------
    PartsError
        If a part is missing (a hole in the numbering), damaged, or its rows do not start where
        the previous part's stop (a gap or a duplicate), or the total is not ``rows``.
    """
    files = part_files(folder)
    if parts is not None:
        files = [p for p in files if part_number(p) < parts]
    out: list[PartInfo] = []
    stop = 0
    for expected, path in enumerate(files):
        number = part_number(path)
        if number != expected:
            raise PartsError(f"trajectory parts in {folder}: part {expected:06d} is missing "
                             "(rows lost); cannot reassemble the trajectory")
        first, end = _read_range(path, stop)
        if first != stop:
            kind = "gap" if first > stop else "duplicate"
            raise PartsError(f"trajectory parts in {folder}: {kind} at {path.name} (its rows "
                             f"start at {first}, the previous part stops at {stop})")
        out.append(PartInfo(number, path, first, end))
        stop = end
    if parts is not None and len(out) != parts:
        raise PartsError(f"trajectory parts in {folder}: {len(out)} of the {parts} parts the "
                         "checkpoint points past are present (rows lost); cannot resume")
    if rows is not None and stop != rows:
        raise PartsError(f"trajectory parts in {folder} hold {stop} rows, the checkpoint "
                         f"expects {rows}; cannot resume")
    return out


def iter_parts(infos: list[PartInfo]) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """``(t, y)`` of each verified part in turn (one part in memory at a time)."""
    for info in infos:
        try:
            with np.load(info.path, allow_pickle=False) as z:
                t, y = z["t"], z["y"]
        except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
            raise PartsError(f"trajectory part {info.path} is damaged ({exc})") from None
        yield t, y
