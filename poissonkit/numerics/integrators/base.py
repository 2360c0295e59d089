"""Shared pieces of the integrators: the raw result, status codes, progress bars."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

from poissonkit.contracts import CompiledFunction, CompiledKernels, KernelData
from poissonkit.errors import IntegrationError, MissingStepError, NonFiniteStateError
from poissonkit.numerics.events import EventRecord
from poissonkit.validation import positive_number

# status codes returned by the compiled loops
# GRAZE: the smallest distance has a local minimum between step ends worth a closer look
RUNNING, NONFINITE, COLLISION, ESCAPE, BUFFER_FULL, DONE, NO_CONVERGENCE, GRAZE = range(8)

#: Run status an integrator records in ``RawResult.extra["status"]`` (kept in
#: ``Solution.extra``) when the run left the regime where its method is accurate; the reasons
#: are in ``extra["regime"]`` and appended to the message. The numbers are still computed:
#: this marks them, it does not stop the run.
LEFT_REGIME = "left_regime"

#: ``one_step(y, t, steps_done) -> (status, t_new)``: one step of a loop, in place (replays).
StepFn = Callable[[np.ndarray, float, int], tuple[int, float]]

if TYPE_CHECKING:
    from poissonkit.numerics.checkpoint import TrajectoryStream


class LoopKernels(NamedTuple):
    """Kernels specialised for the compiled time loops, with their own data and scratch.

    A system may offer a leaner form of its kernels for the loops (e.g. the direct-sum kernels
    of :mod:`poissonkit.numerics.nbody.direct`): the same flows with the same numbers bit for
    bit, taking a shorter ``data`` tuple and ``work`` scratch than the system's own.
    """

    #: drift, kick, min_distance, max_radius (and the compensated flows) on ``data``/``work``
    kernels: CompiledKernels
    #: the constant tuple those kernels read
    data: KernelData
    #: fresh scratch arrays for one run
    work: tuple[np.ndarray, ...]


@runtime_checkable
class HasLoopKernels(Protocol):
    """``loop_kernels()``: the system's :class:`LoopKernels`, or ``None`` when it has no
    leaner form than its general kernels."""

    def loop_kernels(self) -> LoopKernels | None: ...


class ProgressBar(Protocol):
    """The part of a tqdm bar the loops use."""

    def update(self, n: float) -> object: ...

    def close(self) -> None: ...


@dataclass
class RawResult:
    """What an integrator returns to :func:`~poissonkit.numerics.solve`."""

    t: np.ndarray
    y: np.ndarray
    steps: int
    nfev: int = 0
    events: list[EventRecord] = field(default_factory=list)
    message: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


def note_left_regime(raw: RawResult, method: str, reasons: list[str]) -> None:
    """Record in ``raw`` that the run left ``method``'s regime (nothing if no ``reasons``):
    ``extra["status"] = LEFT_REGIME``, ``extra["regime"] = reasons``, and the message."""
    if not reasons:
        return
    raw.extra.update(status=LEFT_REGIME, regime=list(reasons))
    note = f"left the {method} regime: " + "; ".join(reasons)
    raw.message = f"{raw.message}; {note}" if raw.message else note


class SaveBuffer:
    """Growable (t, y) storage filled by compiled loops in chunks.

    With a ``sink`` (e.g. :class:`~poissonkit.numerics.checkpoint.TrajectoryStream`) the rows
    are handed over whenever more than ``sink.max_rows`` are held (:meth:`spill`), so memory
    stays bounded however long the run: at most ``2 max_rows + 1`` rows (held rows plus the
    compiled chunk's buffer); :attr:`peak_rows` records the most rows ever held.
    """

    def __init__(self, dim: int, chunk: int, sink: TrajectoryStream | None = None) -> None:
        self.dim = dim
        if sink is not None:  # a compiled chunk never holds more rows than one part
            chunk = min(int(chunk), int(sink.max_rows))
        self.chunk = max(int(chunk), 2)
        self.sink = sink
        self.ts: list[np.ndarray] = []
        self.ys: list[np.ndarray] = []
        self.held = 0
        self.peak_rows = 0
        self.last_t = math.nan  # time of the newest row, held or already handed to the sink
        self.new()

    def new(self) -> None:
        """Start a fresh chunk ``cur_t (chunk,)``, ``cur_y (chunk, dim)`` for the compiled loop."""
        self.cur_t = np.empty(self.chunk)
        self.cur_y = np.empty((self.chunk, self.dim))

    def _note(self, n: int) -> None:
        self.held += n
        self.peak_rows = max(self.peak_rows, self.held + self.chunk)

    def commit(self, n: int) -> None:
        """Keep the first ``n`` rows the compiled loop wrote into the current chunk.

        The chunk arrays are reused (the rows are copied out), so no new allocation per chunk.
        """
        if n:
            self.ts.append(self.cur_t[:n].copy())
            self.ys.append(self.cur_y[:n].copy())
            self.last_t = float(self.cur_t[n - 1])
            self._note(n)

    def add(self, t: float, y: np.ndarray) -> None:
        """Append one saved point ``(t, y)`` directly (e.g. the initial state)."""
        self.ts.append(np.array([t]))
        self.ys.append(np.asarray(y, dtype=float).reshape(1, -1).copy())
        self.last_t = float(t)
        self._note(1)

    def drop_after(self, t: float) -> None:
        """Forget held rows with time > ``t`` (a terminal event was located before them)."""
        if not self.ts:
            return
        ts, ys = self.arrays()
        keep = ts <= t
        self.ts, self.ys = [ts[keep]], [ys[keep]]
        self.held = int(keep.sum())
        self.last_t = float(ts[keep][-1]) if self.held else math.nan

    def spill(self, force: bool = False) -> None:
        """Hand held rows to the sink when there are too many (or always with ``force``)."""
        if self.sink is None or not self.ts or (not force and self.held < self.sink.max_rows):
            return
        ts, ys = self.arrays()
        self.sink.write(ts, ys)
        self.ts, self.ys, self.held = [], [], 0

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """All held points as ``(t (n,), y (n, dim))``."""
        if not self.ts:
            return np.empty(0), np.empty((0, self.dim))
        return np.concatenate(self.ts), np.concatenate(self.ys)


#: ``(scene units per internal time unit, label)`` for the progress bars of runs in this
#: context (``None``: the bar counts internal time, ``t``); set with :func:`progress_in_unit`.
_BAR_UNIT: ContextVar[tuple[float, str] | None] = ContextVar("poissonkit_bar_unit", default=None)


@contextmanager
def progress_in_unit(factor: float, label: str) -> Iterator[None]:
    """Progress bars opened inside this block count time in a unit of the user's (the
    scene's: ``yr``, ``day``, ``s``).

    Parameters
    ----------
    factor
        That unit per internal time unit of the runs made inside the block.
    label
        Its name, shown after the counts (``12.0/100 yr``).
    """
    token = _BAR_UNIT.set((float(factor), str(label)))
    try:
        yield
    finally:
        _BAR_UNIT.reset(token)


def progress_unit_set() -> bool:
    """True inside a :func:`progress_in_unit` block (a caller chose the bars' unit)."""
    return _BAR_UNIT.get() is not None


def progress_in_seconds(time_unit: float) -> AbstractContextManager[None]:
    """Progress bars opened inside this block count physical time in seconds
    (:func:`progress_in_unit` with ``time_unit`` seconds per internal time unit)."""
    return progress_in_unit(time_unit, "s")


class _ScaledBar:
    """A tqdm bar fed in internal time that counts in another unit (``scale`` per unit)."""

    def __init__(self, bar: ProgressBar, scale: float) -> None:
        self._bar = bar
        self._scale = scale

    def update(self, n: float) -> object:
        return self._bar.update(n * self._scale)

    def close(self) -> None:
        self._bar.close()

    def __str__(self) -> str:  # the bar's current line
        return str(self._bar)


def bar_decimals(total: float) -> int:
    """Decimals that show ``total`` to three significant digits (``0.741``, ``1.00``, ``126``;
    none from 100 on)."""
    if not (math.isfinite(total) and total > 0):
        return 0
    return max(0, 2 - math.floor(math.log10(total)))


def progress_bar(enabled: bool, total: float, desc: str) -> ProgressBar | None:
    """A tqdm bar (or a no-op) measuring progress over a run of ``total`` internal time units.

    Inside :func:`progress_in_unit` it counts in that unit (``0.120/0.741 s``, ``12.0/100
    yr``), else internal time (``3.14/126 t``), with about three significant digits of the
    total.
    """
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        from poissonkit.errors import MissingDependencyError

        raise MissingDependencyError("progress bars need tqdm: pip install tqdm") from None
    shown = _BAR_UNIT.get()
    scale, unit = (1.0, "t") if shown is None else shown
    d = bar_decimals(total * scale)
    fmt = ("{desc}: {percentage:3.0f}%|{bar}| "
           f"{{n:.{d}f}}/{{total:.{d}f}} {unit} [{{elapsed}}<{{remaining}}]")
    bar = tqdm(total=total * scale, desc=desc, unit=unit, leave=False, bar_format=fmt)
    return bar if shown is None else _ScaledBar(bar, scale)


def locate_division(name: str, one_step: StepFn, y: np.ndarray, t: float,
                    steps: int) -> IntegrationError:
    """Error for a ``ZeroDivisionError`` raised by a compiled kernel during a chunk of steps.

    The chunk is replayed one step at a time from its start state ``y`` (time ``t``, ``steps``
    steps done) with ``one_step(y, t, steps) -> (status, t_new)``, which advances ``y`` in place
    by one step; the loops are deterministic, so the division recurs at the same step, which the
    returned :class:`~poissonkit.errors.NonFiniteStateError` names.
    """
    y = y.copy()
    while True:
        try:
            status, t_new = one_step(y, t, steps)
        except ZeroDivisionError:
            return NonFiniteStateError(steps + 1, t, f"{name}: division by zero in a compiled "
                                       "kernel (two bodies at the same place?)")
        if status != RUNNING and status != BUFFER_FULL:
            # should not happen (the replay is deterministic); still fail with a typed error
            return IntegrationError(f"{name}: division by zero in a compiled kernel near step "
                                    f"{steps + 1} (t = {t:.6g})")
        steps += 1
        t = t_new


def state_digest(y: np.ndarray) -> str:
    """SHA-256 of a state's float64 bytes: identifies the initial state of a checkpointed run."""
    import hashlib

    return hashlib.sha256(np.ascontiguousarray(y, dtype=float).tobytes()).hexdigest()


def check_step(step: float | None, t_end: float, name: str) -> float:
    """Validate a fixed step size."""
    if step is None:
        raise MissingStepError(name, f"{name} is a fixed-step method: give step=... "
                               "(internal time unit)")
    return positive_number(step, f"{name}: step")


_step_end: dict[tuple[int, int],
                tuple[CompiledFunction, CompiledFunction, CompiledKernels]] = {}


def step_end_kernels(kernels: CompiledKernels) -> tuple[CompiledFunction, CompiledFunction]:
    """Compiled ``(remember, check)`` shared by the compiled time loops (inlined into them).

    ``remember(y, prev, prev2, hist, t)`` shifts the event-search memory before a step: the
    states at the two previous step ends and ``hist = [D_a, D_b, D_c, t_a, t_b]`` (smallest
    centre distances and start times, see :mod:`poissonkit.numerics.locate`).
    ``check(y, data, work, contact, escape, watch, hist) -> (flag, value)`` tests the state at a
    step end: :data:`GRAZE` when the smallest distance has a local minimum between the last step
    ends that may dip below ``watch`` (it takes precedence: its search also covers the step end),
    :data:`COLLISION` below ``contact``, :data:`ESCAPE` beyond ``escape``, else ``(0, 0.0)``.
    """
    from poissonkit.numerics.jit import jit
    from poissonkit.numerics.kernels import copy_into

    key = (id(kernels.min_distance), id(kernels.max_radius))
    hit = _step_end.get(key)
    if hit is not None:
        return hit[0], hit[1]
    min_distance, max_radius = kernels.min_distance, kernels.max_radius

    @jit(inline="always")
    def remember(y, prev, prev2, hist, t):
        copy_into(prev, prev2)
        copy_into(y, prev)
        hist[0] = hist[1]
        hist[1] = hist[2]
        hist[3] = hist[4]
        hist[4] = t

    @jit(inline="always")
    def check(y, data, work, contact, escape, watch, hist):
        flag = RUNNING
        value = 0.0
        if contact > 0.0 or watch > 0.0:
            d = min_distance(y, data, work)
            hist[2] = d
            d0 = hist[0]
            d1 = hist[1]
            if watch > 0.0 and d1 <= d0 and d > d1 and d1 - 2.0 * max(d0 - d1, d - d1) < watch:
                flag = GRAZE
                value = d1
            elif contact > 0.0 and d < contact:
                flag = COLLISION
                value = d
        if flag == RUNNING and escape > 0.0:
            d = max_radius(y, data)
            if d > escape:
                flag = ESCAPE
                value = d
        return flag, value

    _step_end[key] = (remember, check, kernels)  # keep the kernels (and their ids) alive
    return remember, check


_tails: dict[tuple[int, int, bool], tuple[CompiledFunction, CompiledKernels]] = {}


def step_tail(kernels: CompiledKernels, compensated: bool = False) -> CompiledFunction:
    """The end of one step of every compiled fixed-step loop, compiled (inlined into the loop).

    ``tail(y, c, t, fail, last, save, track, data, work, contact, escape, watch, hist, out_t,
    out_y, nsave) -> (status, nsave, value)`` runs, in this order: the NaN/inf test of ``y``
    (:data:`NONFINITE`), the loop's own failure ``fail`` (a status, :data:`RUNNING` for none),
    the event test at the step end when ``track`` (:func:`step_end_kernels`' ``check``: status
    and offending value), saving the row ``(t, y)`` into ``out_t``, ``out_y`` at ``nsave`` when
    ``save`` (``y − c`` for a ``compensated`` loop), then :data:`DONE` when ``last``,
    :data:`BUFFER_FULL` when the buffer is full, else :data:`RUNNING` (go on). A loop returns
    whenever the status is not :data:`RUNNING`.
    """
    from poissonkit.numerics.jit import jit
    from poissonkit.numerics.kernels import all_finite, copy_row, copy_row_compensated

    key = (id(kernels.min_distance), id(kernels.max_radius), bool(compensated))
    hit = _tails.get(key)
    if hit is not None:
        return hit[0]
    check = step_end_kernels(kernels)[1]
    finite = jit(inline="always")(all_finite.py_func)
    comp = bool(compensated)  # a compile-time constant of the closure

    @jit(inline="always")
    def tail(y, c, t, fail, last, save, track, data, work, contact, escape, watch, hist, out_t,
             out_y, nsave):
        if not finite(y):
            return NONFINITE, nsave, 0.0
        if fail != RUNNING:
            return fail, nsave, 0.0
        flag = RUNNING
        value = 0.0
        if track:  # (the check's calls cost even when skipped: keep them off the plain loop)
            flag, value = check(y, data, work, contact, escape, watch, hist)
        if save:
            out_t[nsave] = t
            if comp:
                copy_row_compensated(y, c, out_y, nsave)
            else:
                copy_row(y, out_y, nsave)
            nsave += 1
        if flag != RUNNING:
            return flag, nsave, value
        if last:
            return DONE, nsave, 0.0
        if nsave == out_t.shape[0]:
            return BUFFER_FULL, nsave, 0.0
        return RUNNING, nsave, 0.0

    _tails[key] = (tail, kernels)  # keep the kernels (and their ids) alive
    return tail
