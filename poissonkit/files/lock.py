"""One writer per output folder: an exclusive OS lock on a file inside the folder.

:func:`lock_folder` takes the lock before a command checks or writes anything in the folder
and holds it until the command ends. The lock is the kernel's (``fcntl.flock`` on POSIX,
``msvcrt.locking`` on Windows): a process that dies — killed, crashed — releases it with its
file descriptors, so a stale lock never blocks a later run. A second process asking for a
held lock is refused at once (:class:`FolderLockedError`), never made to wait.

The lock file is ``.poissonkit.lock``. On POSIX it is removed when the lock is released (while
it is still held, and a taker checks that the file it locked is still the one at the path, so
two processes can never both hold "the" lock of a folder).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

from poissonkit.errors import InputError

LOCK_NAME = ".poissonkit.lock"


class FolderLockedError(InputError):
    """Another live process is writing the output folder (its lock is held)."""


def _try_lock(fd: int) -> bool:
    """Take the exclusive lock on ``fd`` without waiting; ``False`` if another holds it."""
    try:
        import fcntl
    except ImportError:  # Windows: a byte-range lock, also released when the process dies
        import msvcrt

        try:
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)  # type: ignore[attr-defined]
        except OSError:
            return False
        return True
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return False
    return True


def _same_file(fd: int, path: Path) -> bool:
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return False
    mine = os.fstat(fd)
    return (st.st_dev, st.st_ino) == (mine.st_dev, mine.st_ino)


def _acquire(path: Path, what: str) -> int:
    for _ in range(100):  # the holder may remove the file between our open and our lock
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        if not _try_lock(fd):
            os.close(fd)
            raise FolderLockedError(f"{what}: {path.parent} is being written by another "
                                    "poissonkit process (its lock is held); wait for it to "
                                    "end, or choose another folder")
        if os.name == "nt" or _same_file(fd, path):
            return fd
        os.close(fd)  # we locked a file its holder had just removed: take the new one
    raise FolderLockedError(f"{what}: could not lock {path.parent} (its lock file keeps "
                            "changing)")


@contextlib.contextmanager
def lock_folder(folder: str | Path, what: str = "--out") -> Iterator[Path]:
    """Hold the exclusive lock of ``folder`` (created if missing) for the ``with`` block.

    Parameters
    ----------
    folder
        The output folder.
    what
        How messages name the folder (the option that gave it).

    Raises
    ------
    FolderLockedError
        If another live process holds the lock.
    InputError
        If ``folder`` exists and is not a folder, or cannot be created.
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{what}: {folder} exists and is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{what}: cannot create {folder} ({exc.strerror})") from None
    path = folder / LOCK_NAME
    fd = _acquire(path, what)
    try:
        yield path
    finally:
        if os.name != "nt":  # removed while still held: no taker can lock a stale file
            with contextlib.suppress(OSError):
                if _same_file(fd, path):
                    path.unlink()
        os.close(fd)  # releases the lock
