"""Atomic file writes: a file either has its complete new content or is absent/unchanged.

Every writer goes through :func:`atomic_path`: write to a temporary file in the same folder,
``fsync`` it, ``os.replace`` it onto the target (atomic on POSIX and Windows within one file
system), then ``fsync`` the folder so the rename itself survives a power cut. A process killed at
any moment leaves either the old file or the new one, plus at worst a stray ``.*.tmp`` file that
no reader picks up.

(The temporary name is ``.<name>.<random>.tmp<suffix>``.)

API (small on purpose, so every command can use it):

* :func:`atomic_path` — context manager yielding a temporary path for libraries that insist on
  writing to a path themselves (``np.savez``, ``fig.savefig``);
* :func:`write_bytes`, :func:`write_text`, :func:`write_json` — the common cases;
* :func:`remove_stale_temps` — remove what a killed writer left (before resuming in a folder);
* :func:`prepare_output_dir` — refuse to mix a new run's files into a non-empty folder unless
  the caller allows overwriting.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from poissonkit.errors import InputError
from poissonkit.files.killpoints import kill_point

#: The temporary files :func:`atomic_path` makes: ``.<name>.<8 random chars>.tmp<suffix>``.
_TEMP = re.compile(r"^\.(?P<name>.+)\.[a-z0-9_]{8}\.tmp[^/]*$")


class OutputExistsError(InputError):
    """The output folder already holds files of another run (give ``--overwrite``)."""


def _fsync_dir(folder: Path) -> None:
    # the rename is durable only once the folder entry is on disk; not possible on Windows
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _file_mode() -> int:
    """0666 minus the process's umask (read once: setting it back is not thread-safe)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


_FILE_MODE = _file_mode()


@contextlib.contextmanager
def atomic_path(path: str | Path, suffix: str | None = None, phase: str | None = None
                ) -> Iterator[Path]:
    """Yield a temporary path; on normal exit it is fsynced and renamed onto ``path``.

    Parameters
    ----------
    path
        Final file name. Its folder is created if missing.
    suffix
        Suffix of the temporary file (default: ``path``'s, so that libraries choosing a format
        from the extension, e.g. ``savefig``, see the right one).
    phase
        Kill point (:mod:`poissonkit.killpoints`) reached once the temporary file is
        written, before it is renamed (tests only).

    Notes
    -----
    If the body raises, the temporary file is removed and ``path`` is untouched.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # ".<name>.<random>.tmp<suffix>": hidden, and the extension stays last for format sniffing
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.",
                               suffix=".tmp" + (suffix if suffix is not None else path.suffix),
                               dir=path.parent)
    os.close(fd)
    # mkstemp makes the file private (0600); the result is an ordinary output file, with the
    # mode any file the user creates gets (0666 minus the umask), so colleagues can read it
    os.chmod(tmp, _FILE_MODE)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        if phase is not None:
            kill_point(phase)
        with open(tmp_path, "rb+") as fh:
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp_path, path)
        _fsync_dir(path.parent)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp_path.unlink()
        raise


def remove_stale_temps(folder: str | Path) -> list[Path]:
    """Remove the temporary files a killed writer left in ``folder`` (not recursive).

    Only names :func:`atomic_path` makes are touched (``.<name>.<random>.tmp<suffix>``, files,
    or folders of a store written under such a name); call it
    only when no other writer works in ``folder`` (e.g. before resuming a run there).

    Returns
    -------
    list of Path
        The files removed.
    """
    folder = Path(folder)
    if not folder.is_dir():
        return []
    gone = []
    for p in sorted(folder.iterdir()):
        if not _TEMP.match(p.name) or p.is_symlink():
            continue
        if p.is_dir():  # a store written under a temporary folder name (e.g. Zarr)
            shutil.rmtree(p, ignore_errors=True)
            gone.append(p)
        elif p.is_file():
            with contextlib.suppress(FileNotFoundError):
                p.unlink()
                gone.append(p)
    return gone


def write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return ``path``."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; return ``path``."""
    return write_bytes(path, text.encode("utf-8"))


def write_json(path: str | Path, obj: object, indent: int = 2) -> Path:
    """Write ``obj`` as JSON (with a final newline) to ``path`` atomically; return ``path``."""
    return write_text(path, json.dumps(obj, indent=indent) + "\n")


def prepare_output_dir(folder: str | Path, overwrite: bool = False,
                       keep: tuple[str, ...] = ()) -> Path:
    """Create ``folder`` for a new run's files.

    Parameters
    ----------
    folder
        The output folder.
    overwrite
        Remove the folder's current content first instead of refusing.
    keep
        Names inside the folder that are not "another run's files" (e.g. a checkpoint the new
        run resumes from); they are neither counted nor removed.

    Raises
    ------
    OutputExistsError
        If ``folder`` is a non-empty folder (apart from ``keep``) and ``overwrite`` is false.
    InputError
        If ``folder`` exists and is not a folder.
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"--out: {folder} exists and is not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    from poissonkit.files.lock import (
        LOCK_NAME,  # the folder's lock is the running command's
    )

    present = sorted(p for p in folder.iterdir() if p.name not in keep and p.name != LOCK_NAME)
    if present and not overwrite:
        names = ", ".join(p.name for p in present[:5]) + (" ..." if len(present) > 5 else "")
        raise OutputExistsError(f"--out: {folder} already holds files of another run ({names}); "
                                "choose another folder or pass --overwrite")
    for p in present:
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        else:
            p.unlink()
    return folder
