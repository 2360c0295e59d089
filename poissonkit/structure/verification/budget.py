"""A wall-clock budget for checks that cannot be interrupted: worker processes killed at a deadline.

sympy cannot be interrupted cooperatively, so each check of a verify report runs in a worker
process (:mod:`multiprocessing`, ``fork``) that is terminated when the budget shared by all
checks of one report runs out; a check that has not finished is then *undecided*.
"""

from __future__ import annotations

import multiprocessing
import os
import time
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

class BoundedChecks:
    """Zero-argument checks run in worker processes that are terminated at a deadline.

    Parameters
    ----------
    tasks
        The checks; each returns a picklable value.
    budget
        Wall-clock seconds for all of them together, from construction; ``<= 0``: no limit
        (the checks then run lazily in this process, as :meth:`result` asks for them).
    workers
        Worker processes (default: the CPU count, at most the number of tasks).

    Notes
    -----
    Uses :class:`multiprocessing.pool.Pool` with the ``fork`` start method (checks are
    closures over sympy objects; a forked worker inherits them). Where ``fork`` is not
    available the checks run in this process without a limit.
    """

    def __init__(self, tasks: Sequence[Callable[[], object]], budget: float,
                 workers: int | None = None) -> None:
        global _TASKS
        _TASKS = list(tasks)
        self._done: dict[int, Outcome] = {}
        self._pool = None
        self.deadline = time.monotonic() + budget if budget > 0 else None
        if self.deadline is not None and "fork" in multiprocessing.get_all_start_methods():
            n = max(1, min(workers or os.cpu_count() or 1, len(_TASKS)))
            self._pool = multiprocessing.get_context("fork").Pool(n)
            # FIFO: the first tasks start first (Jacobi and the claims before the searches)
            self._async = [self._pool.apply_async(_run_task, (i,)) for i in range(len(_TASKS))]

    def result(self, index: int) -> Outcome:
        """``(kind, value)`` of check ``index`` (see :func:`_run_task`), waiting at most until
        the deadline; ``("undecided", "")`` if it did not finish by then."""
        if index not in self._done:
            if self._pool is None:
                self._done[index] = _run_task(index)
            else:
                wait = max(0.0, self.deadline - time.monotonic())
                try:
                    self._done[index] = self._async[index].get(timeout=wait)
                except multiprocessing.TimeoutError:
                    self._done[index] = ("undecided", "")
        return self._done[index]

    def close(self) -> None:
        """Terminate the workers (checks still running are abandoned)."""
        if self._pool is not None:
            self._pool.terminate()
            self._pool.join()
            self._pool = None

    def __enter__(self) -> BoundedChecks:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
