"""A wall-clock budget for checks that cannot be interrupted: worker processes killed at a deadline.

sympy cannot be interrupted cooperatively, so each check of a verify report runs in a worker
process (:mod:`multiprocessing`, ``fork``) that is killed when the budget shared by all
checks of one report runs out; a check that has not finished is then *undecided*.
"""

from __future__ import annotations

import multiprocessing
import os
import time
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from collections.abc import Callable, Sequence
from typing import Literal

from poissonkit.errors import PoissonkitError

#: How a check ended: its value, a typed refusal (the check does not apply), a bug, or the
#: budget running out.
Outcome = tuple[Literal["done", "refused", "error", "undecided"], object]

__all__ = ["BoundedChecks", "Outcome", "TimeLimit"]


class TimeLimit(Exception):
    """Raised by a check that gives up within its budget (reported as undecided)."""


#: The checks of the report being built; worker processes forked from this process inherit it
#: (closures cannot be pickled, their index can).
_TASKS: list[Callable[[], object]] = []


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {str(exc).strip()[:200]}"


def _run_task(index: int) -> Outcome:
    """Run one check; ``(kind, value)`` with kind ``done``, ``refused`` (a typed poissonkit
    error: the check does not apply), ``error`` (a bug) or ``undecided``."""
    try:
        return "done", _TASKS[index]()
    except TimeLimit:
        return "undecided", ""
    except PoissonkitError as exc:
        return "refused", _describe(exc)
    except Exception as exc:  # noqa: BLE001 -- a bug: report it, never call the check ok
        return "error", _describe(exc)

def _child(index: int, conn: Connection) -> None:
    """Body of a worker process: run check ``index`` and send its outcome."""
    try:
        conn.send(_run_task(index))
    finally:
        conn.close()


class BoundedChecks:
    """Zero-argument checks run in worker processes that are killed at a deadline.

    Parameters
    ----------
    tasks
        The checks; each returns a picklable value.
    budget
        Wall-clock seconds for all of them together, from construction; ``<= 0``: no limit
        (the checks then run lazily in this process, as :meth:`result` asks for them).
    workers
        Worker processes at a time (default: the CPU count, at most the number of tasks).

    Notes
    -----
    Each check runs in its own process (``fork`` start method: checks are closures over sympy
    objects, which a forked process inherits) and sends its outcome through a pipe; the
    checks start first in, first out. No pool and no helper threads: a
    :class:`multiprocessing.pool.Pool` joins handler threads when it is terminated, which can
    hang for good when a forked worker dies (seen under pytest-xdist); a bare process is
    killed and joined with a time limit. A worker that dies without an answer makes its check
    an ``error``. Where ``fork`` is not available the checks run in this process without a
    limit.
    """

    def __init__(self, tasks: Sequence[Callable[[], object]], budget: float,
                 workers: int | None = None) -> None:
        global _TASKS
        _TASKS = list(tasks)
        self._done: dict[int, Outcome] = {}
        self._running: dict[int, tuple[BaseProcess, Connection]] = {}
        self._pending = list(range(len(_TASKS)))
        self._ctx = None
        self._slots = 1
        self.deadline = time.monotonic() + budget if budget > 0 else None
        if self.deadline is not None and "fork" in multiprocessing.get_all_start_methods():
            self._ctx = multiprocessing.get_context("fork")
            self._slots = max(1, min(workers or os.cpu_count() or 1, len(_TASKS)))
            self._start_pending()

    def _start_pending(self) -> None:
        """Start waiting checks, in order, while there are free slots."""
        assert self._ctx is not None
        while self._pending and len(self._running) < self._slots:
            index = self._pending.pop(0)
            receive, send = self._ctx.Pipe(duplex=False)
            process = self._ctx.Process(target=_child, args=(index, send), daemon=True)
            process.start()
            send.close()  # the child holds the sending end: EOF here when it dies
            self._running[index] = (process, receive)

    def _collect(self, timeout: float) -> None:
        """Wait up to ``timeout`` s for running checks to answer; start the next ones."""
        by_conn = {conn: index for index, (_, conn) in self._running.items()}
        for conn in wait(list(by_conn), timeout):
            index = by_conn[conn]  # type: ignore[index]
            process, receive = self._running.pop(index)
            try:
                self._done[index] = receive.recv()
            except (EOFError, OSError):
                process.join(1.0)
                self._done[index] = ("error", f"the worker process of check {index} ended "
                                               f"without an answer (exit code {process.exitcode})")
            receive.close()
            process.join(1.0)
        self._start_pending()

    def result(self, index: int) -> Outcome:
        """``(kind, value)`` of check ``index`` (see :func:`_run_task`), waiting at most until
        the deadline; ``("undecided", "")`` if it did not finish by then."""
        if index not in self._done:
            if self._ctx is None or self.deadline is None:
                self._done[index] = _run_task(index)
            while index not in self._done:
                left = self.deadline - time.monotonic() if self.deadline is not None else 0.0
                if left <= 0 or not self._running:
                    self._done[index] = ("undecided", "")
                    break
                self._collect(left)
        return self._done[index]

    def close(self) -> None:
        """Kill the workers (checks still running are abandoned)."""
        for process, _ in self._running.values():
            process.kill()
        for process, receive in self._running.values():
            process.join(5.0)
            receive.close()
        self._running.clear()
        self._pending.clear()

    def __enter__(self) -> BoundedChecks:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
