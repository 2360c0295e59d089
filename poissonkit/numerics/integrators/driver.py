"""The Python side of the compiled time loops (splittings, midpoint, logh, Wisdom–Holman).

A compiled loop advances the state in place for up to ``max_steps`` steps and returns a status;
:func:`drive` runs it in chunks and, between chunks, does what must not live in compiled code:
locating events (:mod:`poissonkit.numerics.locate`), streaming saved rows to disk,
checkpointing, honouring a stop request (SIGINT), the progress bar. Chunking never changes the
arithmetic: each step depends on the state and the global step index only, so the trajectory is
the same whatever the chunk sizes, and resuming a checkpoint is bit-identical.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from poissonkit.contracts import Event, HasCompiledKernels
from poissonkit.errors import (AbortState, IntegrationError, InterruptedRun, NonFiniteStateError,
                               StepLimitReached)
from poissonkit.numerics.checkpoint import (Checkpoint, TrajectoryStream, check_matches,
                                            newest_checkpoint, write_checkpoint)
from poissonkit.numerics.events import (EventRecord, centre_distance, check_events,
                                        event_thresholds, raise_or_record)
from poissonkit.numerics.fields.contact import chunk_guard
from poissonkit.numerics.fields.regions import (FieldRegionError, explain_nonfinite,
                                                 reads_tables)
from poissonkit.numerics.integrators.base import (BUFFER_FULL, COLLISION, DONE, ESCAPE, GRAZE,
                                                  NONFINITE, RUNNING, RawResult, SaveBuffer,
                                                  progress_bar)
from poissonkit.numerics.locate import Window, locate

#: First chunk (steps) between two looks at a stop request; it then adapts so that a look
#: comes every 0.05–0.2 s, up to MAX_STOP_CHUNK steps (chunking never changes the arithmetic).
STOP_CHUNK = 256
MAX_STOP_CHUNK = 1 << 16


#: The most steps a run of this context may take (``None``: no limit); see :func:`step_limit`.
_STEP_LIMIT: ContextVar[int | None] = ContextVar("poissonkit_step_limit", default=None)


@contextmanager
def step_limit(max_steps: int | None) -> Iterator[None]:
    """Cut the compiled loops run in this context after ``max_steps`` steps.

    A run that reaches the limit before its end time raises
    :class:`~poissonkit.errors.StepLimitReached`, its last state added to the held rows (its
    ``abort``), like any integration error. For runs whose step count is not known up front
    (adaptive steps); fixed-step runs are checked before they start
    (:func:`poissonkit.numerics.workload.plan_run`). Chunking never changes the arithmetic,
    so the steps taken are those of the uncut run.
    """
    token = _STEP_LIMIT.set(max_steps)
    try:
        yield
    finally:
        _STEP_LIMIT.reset(token)


@dataclass
class Control:
    """Long-run controls of :func:`~poissonkit.numerics.solve`.

    Attributes
    ----------
    checkpoint
        Where/how often to checkpoint, or ``None``.
    resume
        Continue from the newest valid checkpoint in ``checkpoint.folder``.
    stream
        Trajectory stream receiving the saved rows, or ``None`` (rows kept in memory).
    stop
        Called between chunks; when it returns true the run stops cleanly ("interrupted").
    """

    checkpoint: Checkpoint | None = None
    resume: bool = False
    stream: TrajectoryStream | None = None
    stop: Callable[[], bool] | None = None


@dataclass
class LoopState:
    """Everything a compiled loop needs to continue: the checkpoint's content."""

    y: np.ndarray
    t: float
    steps: int
    prev: np.ndarray
    prev2: np.ndarray
    #: ``[D_a, D_b, D_c, t_a, t_b]``: smallest centre distance at the two previous step ends and
    #: now, and the start times of the two previous steps (the grazing test's memory)
    hist: np.ndarray
    nfev: int = 0
    records: list[EventRecord] = field(default_factory=list)
    #: compensation array of a compensated loop (the state is ``y − comp``); empty otherwise
    comp: np.ndarray = field(default_factory=lambda: np.empty(0))
    #: further arrays a loop carries from chunk to chunk (e.g. Wisdom–Holman's Jacobi state):
    #: checkpointed with ``y`` and restored in place on resume
    carry: dict[str, np.ndarray] = field(default_factory=dict)
    #: method-specific value of the last status (e.g. the offending value of a failure)
    detail: float = math.nan

    def state(self) -> np.ndarray:
        """The state: ``y`` (a copy), or ``y − comp`` for a compensated loop."""
        return self.y - self.comp if self.comp.size else self.y.copy()


#: Plain-data description of a run (JSON values), checked when resuming.
Problem = Mapping[str, object]

ChunkFn = Callable[[LoopState, int, SaveBuffer], tuple[int, float, int, int, int, float]]


def no_failure(status: int, st: LoopState) -> Exception | None:
    """A loop with no method-specific status: every unknown status is unexpected."""
    return None


@dataclass(frozen=True)
class LoopProblem:
    """What :func:`drive` runs: the problem, the run's options and the compiled loop.

    Attributes
    ----------
    name
        Method name (messages).
    system, y0, t0, t_end
        The problem.
    chunk
        ``chunk(state, max_steps, buf) -> (status, t, steps_done, rows_saved, nfev, value)``.
    advance
        ``advance(y, s)``: one step of length ``s`` from a copy of ``y`` (event location).
    done
        Whether the state has reached the end time.
    description
        Plain-data description checked on resume.
    buffer_rows
        Rows per compiled chunk buffer.
    events, progress, save_every
        As in :func:`~poissonkit.numerics.solve`.
    control
        Checkpoint / resume / stream / stop, or ``None``.
    failure
        Typed error for a method-specific status (e.g. no convergence), else ``None``.
    compensated
        The loop carries a compensation array ``LoopState.comp`` (compensated summation); it is
        part of the state, so it is checkpointed and restored with ``y``.
    carry
        Named arrays the loop keeps beyond ``y`` and reads in ``chunk`` through
        ``LoopState.carry`` (e.g. a state in other coordinates, whose round trip through ``y``
        would not be exact): checkpointed and restored in place, so a resumed run continues
        bit-identically.
    """

    name: str
    system: HasCompiledKernels
    y0: np.ndarray
    t0: float
    t_end: float
    chunk: ChunkFn
    advance: Callable[[np.ndarray, float], np.ndarray]
    done: Callable[[LoopState], bool]
    description: Problem
    buffer_rows: int
    events: Sequence[Event] = ()
    progress: bool = False
    save_every: int = 1
    control: Control | None = None
    failure: Callable[[int, LoopState], Exception | None] = no_failure
    compensated: bool = False
    carry: Mapping[str, np.ndarray] = field(default_factory=dict)


_LEGACY = ("name", "system", "y0", "t0", "t_end")


def drive(problem: LoopProblem | str, *args: Any, **kwargs: Any) -> RawResult:
    """Run ``problem.chunk`` until ``problem.done``; see the module docstring.

    The older call ``drive(name, system, y0, t0, t_end, *, events=…, chunk=…, problem=…, …)``
    (the fields of :class:`LoopProblem` as keywords, ``problem`` for ``description``) still
    works.
    """
    if not isinstance(problem, LoopProblem):
        given = dict(zip(_LEGACY, (problem, *args), strict=False))
        if "problem" in kwargs:
            kwargs["description"] = kwargs.pop("problem")
        if kwargs.get("carry") is None:
            kwargs.pop("carry", None)
        problem = LoopProblem(**given, **kwargs)
    run = _Run(problem)
    try:
        run.loop()
    except IntegrationError as exc:
        exc.abort = run.describe_abort(exc)
        raise
    except InterruptedRun:
        raise
    except KeyboardInterrupt as exc:  # a second Ctrl-C: keep where the loop stood
        raise InterruptedRun(run.describe_abort(exc)) from exc
    finally:
        if run.bar is not None:
            run.bar.close()
    return run.result()


class _Run:
    """One :func:`drive` call: the loop state, the buffer and what happens between chunks."""

    def __init__(self, p: LoopProblem) -> None:
        self.p = p
        self.events = check_events(p.events)
        self.contact, _, self.watch = event_thresholds(self.events)
        self.guard = chunk_guard(p.system, self.events)  # solids, tables that grow
        self.control = p.control or Control()
        self.ck = self.control.checkpoint
        self.stream = self.control.stream
        n = p.y0.size
        self.st = LoopState(y=np.array(p.y0, dtype=float), t=float(p.t0), steps=0,
                            prev=np.zeros(n), prev2=np.zeros(n),
                            hist=np.array([np.inf, np.inf, np.inf, p.t0, p.t0]),
                            comp=np.zeros(n) if p.compensated else np.empty(0),
                            carry=dict(p.carry))
        if self.contact > 0 or self.watch > 0:
            self.st.hist[2] = centre_distance(p.system, self.st.y)
        self.buf = SaveBuffer(n, p.buffer_rows, sink=self.stream)
        self.resumed_from: object = None
        if self.stream is not None and not self.control.resume and self.stream.parts:
            from poissonkit.errors import InputError

            # a fresh run's rows would be numbered after another run's parts: never mix them
            raise InputError(f"stream folder {self.stream.folder} already holds trajectory "
                             "parts; use an empty folder, or resume=True to continue that run")
        if self.control.resume:
            self.resume()
        else:
            self.buf.add(p.t0, self.st.y)
        self.bar = progress_bar(p.progress, p.t_end - p.t0, p.name)
        if self.bar is not None and self.st.t > p.t0:
            self.bar.update(self.st.t - p.t0)
        self.status_msg = "done"
        self.interrupted = False
        # the state at the start of the current chunk (copies), kept only for systems whose
        # non-finite state :func:`explain_nonfinite` may explain (a body leaving a table)
        self.start: LoopState | None = None
        self.keep_start = reads_tables(p.system)

    def resume(self) -> None:
        """Restore the newest checkpoint of the control's folder into the state."""
        from poissonkit.numerics.checkpoint import CheckpointError

        p, st, ck = self.p, self.st, self.ck
        if ck is None:
            from poissonkit.errors import InputError

            raise InputError("resume needs checkpoint=Checkpoint(folder, every)")
        self.resumed_from, arrays, meta = newest_checkpoint(ck.folder)
        check_matches(meta, p.description)
        st.y, st.prev, st.prev2, st.hist = (np.array(arrays[k], dtype=float)
                                            for k in ("y", "prev", "prev2", "hist"))
        if p.compensated:
            if "comp" not in arrays:
                raise CheckpointError("checkpoint has no compensation array; it was not written "
                                      "by a compensated run (compensated=True)")
            st.comp = np.array(arrays["comp"], dtype=float)
        for key, arr in st.carry.items():
            saved = arrays.get(f"carry_{key}")
            if saved is None or saved.shape != arr.shape:
                raise CheckpointError(f"checkpoint has no {key!r} array of shape {arr.shape}; "
                                      f"it was not written by {p.name}")
            arr[...] = saved
        st.t, st.steps, st.nfev = float(arrays["t"]), int(arrays["steps"]), int(meta["nfev"])
        st.records = [EventRecord(**r) for r in meta["records"]]
        if self.stream is not None:
            if "stream_parts" not in meta:
                raise CheckpointError("checkpoint was written without a stream; resume without")
            self.stream.truncate(int(meta["stream_parts"]), int(meta["stream_rows"]))
        if "rows_t" in arrays:
            self.buf.ts, self.buf.ys = [arrays["rows_t"]], [arrays["rows_y"]]
            self.buf.held = len(arrays["rows_t"])

    def save_checkpoint(self) -> None:
        """Write the state, the event records and the held rows (or the stream's position)."""
        p, st, ck, buf = self.p, self.st, self.ck, self.buf
        assert ck is not None
        meta: dict[str, Any] = {"problem": dict(p.description), "nfev": st.nfev,
                                "records": [asdict(r) for r in st.records], "method": p.name,
                                "every": ck.every}
        arrays = {"y": st.y, "prev": st.prev, "prev2": st.prev2, "hist": st.hist,
                  "t": np.float64(st.t), "steps": np.int64(st.steps)}
        if p.compensated:
            arrays["comp"] = st.comp
        arrays.update({f"carry_{key}": arr for key, arr in st.carry.items()})
        if self.stream is not None:
            buf.spill(force=True)
            meta.update(stream_parts=self.stream.parts, stream_rows=self.stream.rows)
        else:
            arrays["rows_t"], arrays["rows_y"] = buf.arrays()
        write_checkpoint(ck, st.steps, arrays, json.loads(json.dumps(meta)))

    def loop(self) -> None:
        """Chunks of compiled steps until the end, a terminal event or a stop request."""
        p, st, ck, control = self.p, self.st, self.ck, self.control
        cap = STOP_CHUNK if control.stop is not None else (1 << 62)
        n_total = int(p.description.get("n_total", 200))  # type: ignore[call-overload]
        prog_chunk = max(1, n_total // 200) if p.progress else (1 << 62)
        next_ck = (st.steps // ck.every + 1) * ck.every if ck is not None else None
        limit = _STEP_LIMIT.get()
        while not p.done(st):
            max_steps = min(cap, prog_chunk)
            if next_ck is not None:
                max_steps = min(max_steps, next_ck - st.steps)
            if limit is not None:
                self.check_limit(limit)
                max_steps = min(max_steps, limit - st.steps)
            if self.guard is not None:
                max_steps = self.guard.limit(st.y, st.t, max_steps)
            t_before = st.t
            if self.keep_start:
                self.start = _copy(st)
            tic = time.perf_counter()
            status, t_new, k, nsave, nf, _ = p.chunk(st, max_steps, self.buf)
            if self.guard is not None and status in (RUNNING, BUFFER_FULL, DONE) \
                    and self.guard.after(st.y, t_new, t_before, k):
                status = COLLISION  # a solid touched: its last step goes to the locator
            if control.stop is not None:  # look at stop requests about 10 times a second
                took = time.perf_counter() - tic
                if took > 0.2 and cap > 1:
                    cap = max(1, cap // 2)
                elif took < 0.05 and k == max_steps:
                    cap = min(2 * cap, MAX_STOP_CHUNK)
            self.buf.commit(nsave)
            st.steps += k
            st.nfev += nf
            st.t = t_new
            if self.bar is not None:
                self.bar.update(t_new - t_before)
            if self.after_chunk(status, k):
                break
            self.buf.spill()
            if next_ck is not None and ck is not None and st.steps >= next_ck \
                    and not p.done(st):
                self.save_checkpoint()
                next_ck += ck.every
            if control.stop is not None and control.stop() and not p.done(st):
                self.interrupted = True
                self.status_msg = f"interrupted at step {st.steps} (t = {st.t:.10g})"
                if ck is not None:
                    self.save_checkpoint()
                if self.buf.last_t != st.t:  # the partial result ends where it stopped
                    self.buf.add(st.t, st.state())
                break

    def check_limit(self, limit: int) -> None:
        """Raise :class:`~poissonkit.errors.StepLimitReached` once ``limit`` steps are done
        (the run is not at its end: the caller asks), the state saved as the last row."""
        st = self.st
        if st.steps < limit:
            return
        if self.buf.last_t != st.t:  # the partial result ends where the run stopped
            self.buf.add(st.t, st.state())
        raise StepLimitReached(limit, st.t, self.p.t_end)

    def after_chunk(self, status: int, k: int = 0) -> bool:
        """Act on a chunk's status (``k`` steps done in the chunk): raise its error, locate its
        events; True at a terminal event (the run ends there)."""
        p, st = self.p, self.st
        if status == NONFINITE:
            error = NonFiniteStateError(st.steps, st.t, f"{p.name} step {st.steps} produced "
                                        "NaN/inf")
            good = self.last_good(k)
            if good is not None:  # name the body and the field it left, where it was
                error = explain_nonfinite(p.system, good.state(), error, span=st.t - good.t,
                                          y_time=good.t)
            raise error
        if status == COLLISION and _all_clear(p.system, self.events, st.y):
            return False  # only a candidate (e.g. bounding spheres of solids overlap); dips
            # inside the step are the grazing test's business
        if status in (COLLISION, ESCAPE, GRAZE):
            segs = [(st.prev, st.hist[4], st.t - st.hist[4])]
            if status == GRAZE:
                segs.insert(0, (st.prev2, st.hist[3], st.hist[4] - st.hist[3]))
            recorded, terminal = locate(p.system, self.events, Window(segs, p.advance),
                                        st.steps, graze=status != ESCAPE)
            st.records.extend(rec for _, rec in recorded)
            if terminal is None:
                return False
            ev, rec, y_hit = terminal
            self.buf.drop_after(rec.time)
            self.buf.add(rec.time, y_hit)
            st.y[:] = y_hit
            st.comp[:] = 0.0
            st.t, st.steps = rec.time, rec.step
            raise_or_record(ev, rec, st.records, p.system, y_hit)
            self.status_msg = "event"
            return True
        if status not in (RUNNING, BUFFER_FULL, DONE):
            exc = p.failure(status, st)
            raise exc if exc is not None else IntegrationError(
                f"{p.name}: unexpected status {status}")
        return False

    def last_good(self, k: int) -> LoopState | None:
        """The state before the chunk's ``k``-th (failing) step, replayed from the chunk's
        start (:attr:`start`; ``None`` without one): chunking never changes the arithmetic,
        so these are the run's own numbers. Costs up to one chunk of steps, once."""
        good, self.start = self.start, None
        if good is None or k < 1:
            return None
        scratch = SaveBuffer(good.y.size, self.p.buffer_rows)
        target = good.steps + k - 1
        while good.steps < target:
            status, t_new, done, _, _, _ = self.p.chunk(good, target - good.steps, scratch)
            good.steps += done
            good.t = t_new
            if status == NONFINITE or done == 0:
                return None  # not the run's path (it cannot happen: the loops are deterministic)
        return good

    def describe_abort(self, exc: BaseException) -> AbortState:
        """What a caller needs to keep the run's partial result when ``exc`` ends the loop
        (:class:`~poissonkit.errors.AbortState`): the held rows, the time and steps reached,
        the non-finite components and the body at fault where the error names one."""
        st = self.st
        bad = np.flatnonzero(~np.isfinite(np.asarray(st.y, dtype=float)))
        return AbortState(held_rows=self.buf.arrays(), time_reached=float(st.t),
                          steps_done=int(st.steps), bad_components=[int(i) for i in bad],
                          body=exc.body if isinstance(exc, FieldRegionError) else None)

    def result(self) -> RawResult:
        """The saved rows (or, streaming, the first and last state) and the run's extras."""
        p, st, buf, stream = self.p, self.st, self.buf, self.stream
        extra: dict[str, Any] = {"peak_rows_in_memory": buf.peak_rows,
                                 "interrupted": self.interrupted}
        if self.guard is not None:
            extra.update(self.guard.report())
        if self.resumed_from is not None:
            extra["resumed_from"] = str(self.resumed_from)
        if stream is not None:
            buf.spill(force=True)
            extra.update(stream=str(stream.folder), streamed_rows=stream.rows)
            ts = np.array([p.t0, st.t])
            ys = np.vstack([np.asarray(p.y0, dtype=float), st.state()])
        else:
            ts, ys = buf.arrays()
        return RawResult(ts, ys, st.steps, nfev=st.nfev, events=st.records,
                         message=self.status_msg, extra=extra)


def _copy(st: LoopState) -> LoopState:
    """A copy of ``st`` that a replay may advance (its arrays copied; no event records)."""
    return LoopState(y=st.y.copy(), t=st.t, steps=st.steps, prev=st.prev.copy(),
                     prev2=st.prev2.copy(), hist=st.hist.copy(), nfev=st.nfev,
                     comp=st.comp.copy(), carry={k: v.copy() for k, v in st.carry.items()},
                     detail=st.detail)


def _all_clear(system: HasCompiledKernels, events: Sequence[Event], y: np.ndarray) -> bool:
    """No terminal event function is negative at ``y``."""
    return all(ev.value(system, y) >= 0 for ev in events if ev.terminal)
