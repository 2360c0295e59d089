"""What ``poissonkit run --resume`` may do in an output folder: finish what was started, only.

A run's commit record is its ``summary.json`` (written atomically after the trajectory file and
before ``trajectory.parts/`` is removed). :func:`prepare_resume` decides, and it **checks
everything before it removes anything**:

* the folder holds a **finished** run (a summary whose status is not ``interrupted``):
  :class:`RunFinishedError`, a one-line refusal; the summary and the trajectory are left
  untouched (only the remains of an interrupted final clean-up — a leftover
  ``trajectory.parts/`` whose rows ``trajectory.npz`` already holds, temporary files — are
  removed). The message says whether the trajectory is complete; to run it again, use
  ``--overwrite``;
* the summary is missing, unreadable or says ``interrupted``, but the folder's trajectory files
  hold rows that the checkpoint and the parts do not (``trajectory.npz`` longer than the parts,
  unreadable, or a dataset without it): a finished run whose commit record was damaged — also
  :class:`RunFinishedError`, and nothing is removed;
* otherwise (killed, or stopped by SIGINT): the newest valid checkpoint is read, the parts it
  points past are checked (:func:`~poissonkit.numerics.parts.verify_parts`); only then are the
  temporary files a killed writer left and the interrupted attempt's ``summary.json`` /
  ``trajectory.npz`` / ``trajectory.nc`` / ``trajectory.zarr`` removed, and the run continues.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np

from poissonkit.errors import InputError
from poissonkit.files.atomic import remove_stale_temps
from poissonkit.numerics.parts import PartsError, iter_parts, verify_parts

#: Files of an interrupted attempt that the resumed run writes again.
ATTEMPT_FILES = ("summary.json", "trajectory.npz", "trajectory.nc", "trajectory.zarr")
DATASETS = ("trajectory.nc", "trajectory.zarr")
PARTS = "trajectory.parts"
#: What reading a damaged ``.npz`` raises. Any byte of it may be damaged, and the zip and zlib
#: readers under numpy then raise many types (``zlib.error``, ``NotImplementedError`` for a
#: garbled version field, ``struct.error``, ...): every ``Exception`` means "damaged" here.
_UNREADABLE = (Exception,)
CHECKPOINTS = "checkpoints"


class RunFinishedError(InputError):
    """``--resume`` on a run that already finished: refused, its files left untouched."""


def _summary(out: Path) -> dict[str, object] | None:
    try:
        data = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None  # no (readable) commit record: the run did not finish
    return data if isinstance(data, dict) else None


def _npz_problem(path: Path, rows: object, t_reached: object) -> str | None:
    """Why ``path`` is not the complete trajectory the summary describes (``None``: it is)."""
    try:
        with np.load(path, allow_pickle=False) as z:
            t = z["t"]
    except FileNotFoundError:
        return f"{path.name} is missing"
    except _UNREADABLE:
        return f"{path.name} is damaged"
    if isinstance(rows, int) and len(t) != rows:
        return f"{path.name} holds {len(t)} of {rows} rows"
    if not isinstance(rows, int) and isinstance(t_reached, float) and \
            (len(t) == 0 or float(t[-1]) != t_reached):  # summaries without saved_rows
        return f"{path.name} does not reach t = {t_reached!r}"
    return None


def _parts_problem(folder: Path, rows: object, t_reached: object) -> str | None:
    try:
        infos = verify_parts(folder)
    except PartsError as exc:
        return str(exc)
    if not infos:
        return f"{folder.name}/ is missing"
    if isinstance(rows, int) and infos[-1].stop != rows:
        return f"{folder.name}/ holds {infos[-1].stop} of {rows} rows"
    last_t = next(iter_parts(infos[-1:]))[0]
    if not isinstance(rows, int) and isinstance(t_reached, float) and \
            float(last_t[-1]) != t_reached:
        return f"{folder.name}/ does not reach t = {t_reached!r}"
    return None


def finished_problem(out: str | Path) -> tuple[bool, str | None]:
    """``(finished, problem)``: whether ``out``'s summary records a finished run, and what is
    wrong with its trajectory (``None``: complete)."""
    out = Path(out)
    summary = _summary(out)
    if summary is None or summary.get("status") in (None, "interrupted"):
        return False, None
    rows, t_reached = summary.get("saved_rows"), summary.get("t_reached")
    if str(summary.get("trajectory", "")).startswith(PARTS):
        return True, _parts_problem(out / PARTS, rows, t_reached)
    return True, _npz_problem(out / "trajectory.npz", rows, t_reached)


def _refuse_finished(out: Path) -> None:
    """Refuse a folder whose summary records a finished run (see the module docstring)."""
    summary = _summary(out) or {}
    status = summary.get("status")
    _, problem = finished_problem(out)
    if problem is None:
        if not str(summary.get("trajectory", "")).startswith(PARTS):
            shutil.rmtree(out / PARTS, ignore_errors=True)  # rows already in the npz
        remove_stale_temps(out)
        raise RunFinishedError(
            f"--resume: the run in {out} already finished (status {status}, "
            f"{summary.get('saved_rows', '?')} rows); nothing to resume, its files are left "
            "as they are (--overwrite runs it again)")
    raise RunFinishedError(
        f"--resume: the run in {out} already finished (status {status}) but {problem}; "
        "resuming would keep only the rows after the last checkpoint, so it is refused "
        "(--overwrite runs it again)")


def _parts_rows(folder: Path, parts: object, rows: object) -> tuple[int, PartsError | None]:
    """Rows the parts hold, and why they cannot be resumed from (``None``: they can): the
    parts the checkpoint points past must hold exactly its rows; later parts count when they
    continue the sequence (a damaged later part is rewritten by the resume)."""
    if not (isinstance(parts, int) and isinstance(rows, int)):
        return 0, None  # the rows are inside the checkpoint (a run without a stream)
    try:
        verify_parts(folder, parts=parts, rows=rows)
    except PartsError as exc:
        try:
            infos = verify_parts(folder)
        except PartsError:
            infos = []
        return (infos[-1].stop if infos else 0), exc
    try:
        infos = verify_parts(folder)
    except PartsError:
        return rows, None
    return (infos[-1].stop if infos else 0), None


def _unreproduced(out: Path, parts_rows: int) -> str | None:
    """What the folder's trajectory files hold that the parts do not (``None``: nothing).

    A resume writes these files again from the parts and the checkpoint; it may remove them
    only when every row they hold is also in the parts (an interrupted attempt's partial
    result, or a run killed between its gather and its summary)."""
    npz = out / "trajectory.npz"
    if npz.exists():
        try:
            with np.load(npz, allow_pickle=False) as z:
                t = np.asarray(z["t_si"] if "t_si" in z.files else z["t"])
        except _UNREADABLE:
            return "its trajectory.npz cannot be read"
        if len(t) > parts_rows:
            end = f" up to t = {float(t[-1]):.9g} s" if len(t) else ""
            return (f"its trajectory.npz holds {len(t)} rows{end}, the checkpoint and "
                    f"trajectory.parts/ only {parts_rows}")
        return None
    present = [name for name in DATASETS if (out / name).exists()]
    if present:  # written after trajectory.npz: without it they are a finished run's
        return f"it holds {present[0]} but no trajectory.npz"
    return None


def prepare_resume(out: str | Path) -> None:
    """Make ``out`` ready for a resumed run, or refuse (see the module docstring).

    Raises
    ------
    RunFinishedError
        If ``out`` holds a finished run (by its summary, or by trajectory files the
        checkpoints do not account for).
    CheckpointError
        If ``out`` has no valid checkpoint to resume from.
    PartsError
        If the parts the checkpoint points past are not all there.
    """
    from poissonkit.numerics.checkpoint import CheckpointError, checkpoints, newest_checkpoint

    out = Path(out)
    finished, _ = finished_problem(out)
    if finished:
        _refuse_finished(out)
    if not checkpoints(out / CHECKPOINTS):
        raise CheckpointError(f"--resume: {out} has no checkpoint; nothing to resume (a run "
                              "killed before its first checkpoint starts again with --overwrite)")
    try:
        _, _, meta = newest_checkpoint(out / CHECKPOINTS)
    except CheckpointError as exc:
        raise CheckpointError(f"--resume: {exc}") from None
    parts_rows, broken = _parts_rows(out / PARTS, meta.get("stream_parts"),
                                     meta.get("stream_rows"))
    lost = _unreproduced(out, parts_rows)
    if lost is not None:
        raise RunFinishedError(
            f"--resume: {out} has no valid summary.json but {lost}: a finished run whose "
            "summary is damaged; refused, nothing removed (--overwrite runs it again)")
    if broken is not None:
        raise broken
    # every check passed: now, and only now, clear the interrupted attempt's files
    for folder in (out, out / PARTS, out / CHECKPOINTS):
        remove_stale_temps(folder)
    for name in ATTEMPT_FILES:
        if (out / name).is_dir():
            shutil.rmtree(out / name)
        else:
            (out / name).unlink(missing_ok=True)


def finish_parts(out: str | Path, keep: bool) -> None:
    """After the summary is written: remove ``trajectory.parts/`` unless ``keep`` (a stopped,
    checkpointed run keeps it for ``--resume``). Removes the newest part first."""
    from poissonkit.files.killpoints import kill_point
    from poissonkit.numerics.parts import part_files

    folder = Path(out) / PARTS
    if keep or not folder.is_dir():
        return
    for p in reversed(part_files(folder)):
        p.unlink(missing_ok=True)
        kill_point("parts-removing")
    shutil.rmtree(folder, ignore_errors=True)
