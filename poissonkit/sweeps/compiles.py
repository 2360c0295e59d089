"""Counting numba compilations in a process (a sweep's workers report theirs).

A sweep should compile its kernels once per worker: every later point, whatever its potential
parameters, reuses them (see "Parameters as data" in docs/performance.md). The counter listens
to numba's ``numba:compile`` events, which fire for real compilations only (a function loaded
from the disk cache of :mod:`poissonkit.numerics.jit` is not counted).
"""

from __future__ import annotations

import threading

from numba.core import event

_lock = threading.Lock()


class _Counter(event.Listener):
    """Counts every numba function compiled (callees compiled along with a caller count
    too: numba reports each one)."""

    def __init__(self) -> None:
        self.count = 0

    def on_start(self, ev: event.Event) -> None:
        with _lock:
            self.count += 1

    def on_end(self, ev: event.Event) -> None:
        pass


_counter: _Counter | None = None


def count_compilations() -> None:
    """Start counting numba compilations in this process (idempotent)."""
    global _counter
    with _lock:
        if _counter is None:
            _counter = _Counter()
            event.register("numba:compile", _counter)


def compilations() -> int:
    """Numba functions compiled in this process since :func:`count_compilations` was first
    called (0 before)."""
    return 0 if _counter is None else _counter.count
