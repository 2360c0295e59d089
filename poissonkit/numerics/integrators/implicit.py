"""The fixed-step loop of the implicit one-step methods (implicit midpoint, discrete gradient).

A method is its Newton residual and three small compiled pieces (:class:`ImplicitMethod`): the
scratch its residual reads, the starting guess, and how the solution becomes the new state.
:func:`implicit_loop` compiles the time loop around them (one Newton solve per step,
:func:`~poissonkit.numerics.integrators.newton.newton_solver`; the shared step tail) and
:func:`drive_implicit` runs it through :func:`~poissonkit.numerics.integrators.driver.drive`
(chunks, one-step replays, event location, failures by name).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np

from poissonkit.contracts import CompiledFunction, CompiledKernels, Event, HasCompiledKernels
from poissonkit.errors import IntegrationError
from poissonkit.numerics.events import event_thresholds
from poissonkit.numerics.integrators.base import (NO_CONVERGENCE, RUNNING, RawResult, SaveBuffer,
                                                  step_end_kernels, step_tail)
from poissonkit.numerics.integrators.driver import Control, LoopProblem, LoopState, drive
from poissonkit.numerics.integrators.glue import ChunkResult, Scratch, guard_division
from poissonkit.numerics.integrators.newton import CONVERGED, SINGULAR, newton_solver, no_jacobian
from poissonkit.numerics.jit import jit


class ImplicitMethod(NamedTuple):
    """The compiled pieces of one implicit method.

    Attributes
    ----------
    residual
        ``residual(Z, y, h, mid, G, data, work, args)``: the Newton residual (see
        :func:`~poissonkit.numerics.integrators.newton.newton_solver`).
    converged
        The Newton stopping test (``near_state``, ``near_increment``).
    simplified
        Factorise the Newton matrix once per step.
    scratch
        ``scratch(n, f, c, extra) -> args``: the residual's ``args`` for a state of size ``n``
        (``f`` the field's scratch, ``c`` the compensation, ``extra`` the method's constants).
    guess
        ``guess(Z, y, f, h) -> yn``: writes the starting ``Z`` from ``f = ẏ`` and returns the
        state scale of the stopping test.
    accept
        ``accept(Z, y, c)``: the new state from the solution ``Z`` (``c``: compensation).
    compensated
        The state is ``y − c`` (compensated summation, :class:`LoopState.comp`).
    """

    residual: CompiledFunction
    converged: CompiledFunction
    simplified: bool
    scratch: CompiledFunction
    guess: CompiledFunction
    accept: CompiledFunction
    compensated: bool


def implicit_loop(kernels: CompiledKernels, method: ImplicitMethod) -> CompiledFunction:
    """The compiled time loop ``run(y, c, t0, t_end, h, n_total, tol, maxiter, newton, extra,
    data, work, save_every, step0, max_steps, out_t, out_y, contact, escape, watch, back1, back2,
    hist) -> (status, t, steps, rows, evaluations, value)`` of ``method`` on ``kernels``.

    The last step ends at ``t_end`` itself: ``t0 + n_total h`` may miss it by an ulp, and a
    piece of a sampled run that ends short of its end reads as stopped by an event."""
    rhs = kernels.rhs
    jac = kernels.jac if kernels.jac is not None else no_jacobian
    remember = step_end_kernels(kernels)[0]
    tail = step_tail(kernels, compensated=method.compensated)
    solve = newton_solver(method.residual, jac, method.converged, method.simplified)
    scratch, guess, accept = method.scratch, method.guess, method.accept

    @jit
    def run(y, c, t0, t_end, h, n_total, tol, maxiter, newton, extra, data, work, save_every,
            step0, max_steps, out_t, out_y, contact, escape, watch, back1, back2, hist):
        n = y.shape[0]
        f = np.empty(n)
        Z = np.empty(n)
        mid = np.empty(n)
        G = np.empty(n)
        J = np.empty((n, n))
        A = np.empty((n, n))
        delta = np.empty(n)
        piv = np.empty(n, dtype=np.int64)
        args = scratch(n, f, c, extra)
        nsave = 0
        nfev = 0
        track = contact > 0.0 or escape > 0.0 or watch > 0.0
        for k in range(max_steps):
            gstep = step0 + k + 1
            if track:  # event-search memory, see poissonkit.numerics.locate
                remember(y, back1, back2, hist, t0 + (gstep - 1) * h)
            rhs(y, data, work, f)
            nfev += 1
            yn = guess(Z, y, f, h)
            outcome, nf = solve(Z, y, h, tol, maxiter, newton, yn, data, work, args, mid, G, J,
                                A, piv, delta)
            nfev += nf
            if outcome == SINGULAR:
                return NO_CONVERGENCE, t0 + gstep * h, k + 1, nsave, nfev, 0.0
            ok = outcome == CONVERGED
            last = gstep >= n_total
            t = t_end if last else t0 + gstep * h
            accept(Z, y, c)
            status, nsave, value = tail(y, c, t, RUNNING if ok else NO_CONVERGENCE, last,
                                        last or gstep % save_every == 0, track, data, work,
                                        contact, escape, watch, hist, out_t, out_y, nsave)
            if status != RUNNING:
                return status, t, k + 1, nsave, nfev, value
        return RUNNING, t0 + (step0 + max_steps) * h, max_steps, nsave, nfev, 0.0

    return run


class ImplicitRun(NamedTuple):
    """One run of an implicit loop: the constants ``run`` takes after ``n_total`` and what the
    driver needs to describe and report it."""

    name: str
    solver: str  # "Newton" or "iteration": how failures name the solve
    tol: float
    max_iterations: int
    newton: bool
    extra: tuple[object, ...]
    description: dict[str, object]


def drive_implicit(run: CompiledFunction, spec: ImplicitRun, compensated: bool,
                   system: HasCompiledKernels, y: np.ndarray, t0: float, t_end: float, h: float,
                   n_total: int, events: Sequence[Event], progress: bool, save_every: int,
                   control: Control | None) -> RawResult:
    """Drive the compiled loop ``run`` of :func:`implicit_loop` from ``t0`` to ``t_end`` on the
    grid ``h``, ``n_total`` (chunks, one-step replays, located events, failures by name)."""
    contact, escape, watch = event_thresholds(events)
    data, work = system.data, system.work()
    scratch = Scratch(y.size)
    fixed = (spec.tol, spec.max_iterations, spec.newton, spec.extra, data, work)

    def comp_of(ys: np.ndarray) -> np.ndarray:
        # an uncompensated loop is given the state itself where the compensation goes
        return np.zeros_like(ys) if compensated else ys

    def state(ys: np.ndarray, cs: np.ndarray) -> np.ndarray:
        return ys - cs if compensated else ys

    def chunk(st: LoopState, max_steps: int, buf: SaveBuffer) -> ChunkResult:
        return run(st.y, st.comp if compensated else st.y, t0, t_end, h, n_total, *fixed,
                   save_every, st.steps, max_steps, buf.cur_t, buf.cur_y, contact, escape, watch,
                   st.prev, st.prev2, st.hist)

    def one_step(ys: np.ndarray, ts: float, done: int) -> tuple[int, float]:
        cs = comp_of(ys)
        out = run(ys, cs, t0, t_end, h, n_total, *fixed, save_every, done, 1, scratch.t,
                  scratch.y, 0.0, 0.0, 0.0, ys, ys, scratch.hist)
        if compensated:
            ys -= cs
        return out[0], out[1]

    def advance(ys: np.ndarray, s: float) -> np.ndarray:
        yc = np.array(ys, dtype=float)
        cc = comp_of(yc)
        status = run(yc, cc, 0.0, s, s, 1, *fixed, 1, 0, 1, scratch.t, scratch.y, 0.0, 0.0, 0.0,
                     yc, yc, scratch.hist)[0]
        if status == NO_CONVERGENCE:
            raise IntegrationError(f"{spec.name}: {spec.solver} did not converge while locating "
                                   "an event")
        return state(yc, cc)

    def failure(status: int, st: LoopState) -> Exception | None:
        if status == NO_CONVERGENCE:
            return IntegrationError(
                f"{spec.name}: {spec.solver} did not converge to {spec.tol:g} in "
                f"{spec.max_iterations} iterations at step {st.steps} (t = {st.t:.6g}); "
                "reduce the step")
        return None

    replay: Callable[[LoopState], tuple[Callable[[np.ndarray, float, int], tuple[int, float]],
                                        np.ndarray]]
    replay = (lambda st: (one_step, st.y - st.comp)) if compensated else (
        lambda st: (one_step, st.y.copy()))
    raw = drive(LoopProblem(
        spec.name, system, y, t0, t_end, guard_division(spec.name, chunk, replay), advance,
        lambda st: st.steps >= n_total, spec.description,
        min(n_total // save_every + 2, 4096), events, progress, save_every, control, failure,
        compensated=compensated))
    raw.extra.update(step=h, newton=spec.newton)
    return raw
