"""Checkpoints of a running integration and the trajectory stream they point into.

A checkpoint file (``checkpoint-<steps>.pkcp``) is written atomically
(:mod:`poissonkit.report.atomic`) and holds a SHA-256 checksum of its payload, so a truncated or
corrupted file is detected and refused (:class:`CheckpointError`), never loaded. Layout:
``b"POISSONKIT-CHECKPOINT 1\\n"``, the hex digest and the payload length on the second line,
then the payload: an ``.npz`` archive (numpy's format, no pickles) with the loop state (state,
time, step counter, event-search history, event records), a JSON ``meta`` entry describing the
problem (method, step, end time, a hash of ``y0``...) and, when the run does not stream, the
trajectory saved so far.

Resuming from a checkpoint of the fixed-step methods (``splitting2/4/6/8`` with a fixed step,
``midpoint``) gives a final state bit-identical to an uninterrupted run: the compiled loops
compute each step from the state and the global step index only, and the checkpoint holds both
exactly. (The adaptive splitting also resumes exactly, since its step depends only on the
state; the scipy methods cannot be checkpointed — their internal step-size controller state is
not exposed.)

:class:`TrajectoryStream` writes saved rows to numbered ``part-NNNNNN.npz`` files in a folder
(each atomic, each recording the global indices of its rows), so a long run keeps only a bounded
number of rows in memory; :func:`read_trajectory` reads them back after checking they form one
sequence (:mod:`poissonkit.numerics.parts`).

Order of writes, so that a kill at any instant leaves a state a resume can finish: a checkpoint
first spills the held rows as a part, then is written itself (its ``stream_parts`` /
``stream_rows`` point just past that part), then older checkpoints are pruned. A resume checks
that parts ``0 .. stream_parts - 1`` hold rows ``0 .. stream_rows - 1`` exactly (else
:class:`~poissonkit.numerics.parts.PartsError`) and only then removes later parts, the newest
first. Kill points (:mod:`poissonkit.killpoints`) mark each boundary for the tests.
"""

from __future__ import annotations

import hashlib
import io
import json
import re
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from poissonkit.errors import InputError
from poissonkit.files import atomic
from poissonkit.files.killpoints import kill_point
from poissonkit.numerics.parts import iter_parts, part_files, part_number, verify_parts

MAGIC = b"POISSONKIT-CHECKPOINT 1\n"
_NAME = re.compile(r"^checkpoint-(\d{12})\.pkcp$")


class CheckpointError(InputError):
    """A checkpoint is missing, corrupted, truncated or belongs to another problem."""


@dataclass(frozen=True)
class Checkpoint:
    """Where and how often to checkpoint.

    Parameters
    ----------
    folder
        Folder of the checkpoint files (created if missing).
    every
        Write a checkpoint every ``every`` steps (and when the run stops early).
    keep
        How many of the newest checkpoints to keep (older ones are removed).
    """

    folder: str | Path
    every: int
    keep: int = 2

    def __post_init__(self) -> None:
        if not isinstance(self.every, (int, np.integer)) or isinstance(self.every, bool) \
                or self.every < 1:
            raise InputError(f"checkpoint every must be a positive int, got {self.every!r}")
        if not isinstance(self.keep, int) or self.keep < 1:
            raise InputError(f"checkpoint keep must be a positive int, got {self.keep!r}")
        object.__setattr__(self, "folder", Path(self.folder))


def fingerprint(**items: Any) -> dict[str, Any]:
    """Plain-data description of a problem, compared on resume (arrays are hashed)."""
    out: dict[str, Any] = {}
    for k, v in items.items():
        if isinstance(v, np.ndarray):
            out[k] = hashlib.sha256(np.ascontiguousarray(v, dtype=float).tobytes()).hexdigest()
        elif isinstance(v, (float, np.floating)):
            out[k] = float(v).hex()
        else:
            out[k] = v
    return out


def write_checkpoint(ck: Checkpoint, steps: int, arrays: Mapping[str, np.ndarray],
                     meta: Mapping[str, Any]) -> Path:
    """Write one checkpoint atomically and prune old ones; return its path."""
    buf = io.BytesIO()
    np.savez(buf, meta=np.array(json.dumps(meta)), **{k: np.asarray(v) for k, v in arrays.items()})
    payload = buf.getvalue()
    digest = hashlib.sha256(payload).hexdigest()
    data = MAGIC + f"{digest} {len(payload)}\n".encode() + payload
    path = Path(ck.folder) / f"checkpoint-{int(steps):012d}.pkcp"
    with atomic.atomic_path(path, phase="checkpoint-tmp") as tmp:
        tmp.write_bytes(data)
    kill_point("checkpoint-written")
    for old in checkpoints(ck.folder)[:-ck.keep]:
        old.unlink(missing_ok=True)
    return path


def checkpoints(folder: str | Path) -> list[Path]:
    """Checkpoint files of ``folder``, oldest first."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if _NAME.match(p.name))


def read_checkpoint(path: str | Path) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """``(arrays, meta)`` of a checkpoint file.

    Raises
    ------
    CheckpointError
        If the file is missing, truncated, or its checksum does not match.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise CheckpointError(f"checkpoint {path}: cannot read ({exc})") from None
    if not data.startswith(MAGIC):
        raise CheckpointError(f"checkpoint {path}: not a poissonkit checkpoint (bad header)")
    rest = data[len(MAGIC):]
    line, sep, payload = rest.partition(b"\n")
    try:
        digest, length = line.decode().split()
        length = int(length)
    except (UnicodeDecodeError, ValueError):
        raise CheckpointError(f"checkpoint {path}: damaged header") from None
    if not sep or len(payload) != length:
        raise CheckpointError(f"checkpoint {path}: truncated ({len(payload)} of {length} "
                              "payload bytes)")
    if hashlib.sha256(payload).hexdigest() != digest:
        raise CheckpointError(f"checkpoint {path}: checksum mismatch (corrupted); refusing it")
    try:
        with np.load(io.BytesIO(payload), allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        meta = json.loads(str(arrays.pop("meta")))
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile, RecursionError):
        raise CheckpointError(f"checkpoint {path}: its payload is not a checkpoint archive "
                              "with a JSON 'meta' entry") from None
    problem = _content_problem(arrays, meta)
    if problem is not None:
        raise CheckpointError(f"checkpoint {path}: {problem}; refusing it")
    return arrays, meta


#: Arrays every checkpoint holds: name -> number of dimensions (0: a scalar).
_ARRAYS = {"y": 1, "prev": 1, "prev2": 1, "hist": 1, "t": 0, "steps": 0}
#: Keys of an event record (:class:`~poissonkit.numerics.events.EventRecord`) and their types.
_RECORD = {"kind": (str,), "step": (int,), "time": (int, float), "value": (int, float),
           "time_error": (int, float), "detail": (dict,)}


def _is_int(v: object) -> bool:
    return isinstance(v, int) and not isinstance(v, bool) and v >= 0


def _content_problem(arrays: Mapping[str, np.ndarray], meta: object) -> str | None:
    """What is wrong with a checkpoint's content (its checksum matched), ``None``: nothing.

    A checksum proves the file is what was written, not that a writer wrote the right types
    (a hand-made or foreign file): every field the resume reads is checked here."""
    for name, ndim in _ARRAYS.items():
        a = arrays.get(name)
        if a is None:
            return f"it has no {name!r} array"
        kind = "iu" if name == "steps" else "f"
        if a.ndim != ndim or a.dtype.kind not in kind:
            return f"its {name!r} array has dtype {a.dtype} and {a.ndim} dimensions"
    if not isinstance(meta, dict):
        return f"its meta is a {type(meta).__name__}, not an object"
    if not isinstance(meta.get("problem"), dict):
        return "its meta has no 'problem' object"
    if not _is_int(meta.get("nfev")) or not isinstance(meta.get("method"), str):
        return "its meta 'nfev' (a count) or 'method' (a name) is missing or mistyped"
    every = meta.get("every")
    if not (_is_int(every) and isinstance(every, int) and every >= 1):
        return f"its meta 'every' must be a positive integer, got {every!r}"
    records = meta.get("records")
    if not isinstance(records, list):
        return f"its meta 'records' must be a list, got {records!r}"[:200]
    for r in records:
        if not isinstance(r, dict) or not {"kind", "step", "time", "value"} <= set(r) \
                or any(k not in _RECORD or not isinstance(v, _RECORD[k])
                       or isinstance(v, bool) for k, v in r.items()):
            return f"its event record {r!r} is malformed"[:200]
    stream = [meta.get(k) for k in ("stream_parts", "stream_rows")]
    if any(v is not None for v in stream) and not all(_is_int(v) for v in stream):
        return f"its meta 'stream_parts'/'stream_rows' must be counts, got {stream!r}"
    return None


def newest_checkpoint(folder: str | Path) -> tuple[Path, dict[str, np.ndarray], dict[str, Any]]:
    """The newest checkpoint of ``folder`` that passes its checksum.

    Damaged newer files are skipped (their names are in the error if none is valid).

    Raises
    ------
    CheckpointError
        If ``folder`` has no valid checkpoint.
    """
    bad: list[str] = []
    for path in reversed(checkpoints(folder)):
        try:
            arrays, meta = read_checkpoint(path)
        except CheckpointError as exc:
            bad.append(str(exc))
            continue
        return path, arrays, meta
    raise CheckpointError(f"no valid checkpoint in {folder}" + (f": {'; '.join(bad)}" if bad
                                                                  else ""))


def check_matches(meta: Mapping[str, Any], expected: Mapping[str, Any]) -> None:
    """:class:`CheckpointError` naming the first field where a checkpoint's problem differs."""
    for k, v in expected.items():
        if meta.get("problem", {}).get(k) != v:
            raise CheckpointError(f"checkpoint belongs to another run: {k} differs "
                                  f"({meta.get('problem', {}).get(k)!r} != {v!r})")


class TrajectoryStream:
    """Saved rows written to ``folder/part-NNNNNN.npz`` (``t``, ``y``), each file atomic.

    Parameters
    ----------
    folder
        Folder of the parts (created if missing).
    max_rows
        Rows held in memory before they are written out as one part.
    """

    def __init__(self, folder: str | Path, max_rows: int = 65536) -> None:
        if not isinstance(max_rows, int) or max_rows < 1:
            raise InputError(f"stream max_rows must be a positive int, got {max_rows!r}")
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.max_rows = max_rows
        self.parts = len(self.part_files())
        self.rows = 0

    def part_files(self) -> list[Path]:
        """Part files written so far, in order."""
        return part_files(self.folder)

    def write(self, t: np.ndarray, y: np.ndarray) -> None:
        """Append rows as the next part (recording their global indices ``rows``)."""
        if len(t) == 0:
            return
        path = self.folder / f"part-{self.parts:06d}.npz"
        with atomic.atomic_path(path, phase="part-tmp") as tmp:
            np.savez(tmp, t=np.asarray(t, dtype=float), y=np.asarray(y, dtype=float),
                     rows=np.array([self.rows, self.rows + len(t)], dtype=np.int64))
        self.parts += 1
        self.rows += len(t)
        kill_point("part-written")

    def truncate(self, parts: int, rows: int) -> None:
        """Continue after a checkpoint: check parts ``0 .. parts - 1`` hold rows
        ``0 .. rows - 1`` exactly, then drop the later parts (newest first).

        Raises
        ------
        PartsError
            If the kept parts have a hole, a gap or a duplicate, or do not hold ``rows`` rows;
            nothing is removed then.
        """
        verify_parts(self.folder, parts=parts, rows=rows)
        for p in reversed(self.part_files()):
            if part_number(p) >= parts:
                p.unlink()
                kill_point("truncate")
        self.parts = parts
        self.rows = rows


def read_trajectory(folder: str | Path, every: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """``(t, y)`` of a streamed trajectory, keeping every ``every``-th row.

    Raises
    ------
    InputError
        If ``folder`` holds no parts.
    PartsError
        If the parts do not form one sequence (a missing part, a gap, a duplicate, damage).
    """
    folder = Path(folder)
    infos = verify_parts(folder)
    if not infos:
        raise InputError(f"no trajectory parts in {folder}")
    ts, ys = [], []
    offset = 0
    for t, y in iter_parts(infos):
        sel = np.arange((-offset) % every, len(t), every)
        ts.append(t[sel])
        ys.append(y[sel])
        offset += len(t)
    return np.concatenate(ts), np.concatenate(ys)
